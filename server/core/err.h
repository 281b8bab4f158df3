/*
 * err.h - errors as values.
 *
 * A function that can fail returns an enum refract_code (0 = REFRACT_E_OK) and fills
 * a caller-provided struct err with the same code and a message written for the person
 * who will read it: what was wrong, where (a JSON path first when there is one), what
 * is allowed and how to fix it. Nothing both prints and returns; logging happens once,
 * at the edge (the HTTP layer or main).
 *
 * Thread: any. Ownership: struct err is a plain value held by the caller.
 */
#ifndef REFRACT_ERR_H
#define REFRACT_ERR_H

#include "refract_errors.h"

#define ERR_MSG_MAX 512

struct err {
    enum refract_code code;
    char msg[ERR_MSG_MAX];
};

/* Sets e->code and formats e->msg (truncated to ERR_MSG_MAX-1). e may be NULL.
 * Returns code, so callers can write `return err_set(e, ...)`. */
enum refract_code err_set(struct err *e, enum refract_code code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Prepends "prefix" to an existing message ("objects[2].": "ior: ..." ->
 * "objects[2].ior: ..."). Keeps the code. Returns e->code. */
enum refract_code err_prefix(struct err *e, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* Clears e to REFRACT_E_OK with an empty message. */
void err_clear(struct err *e);

/* Static strings from the table in proto/refract_errors.h; unknown codes give
 * "internal"/500/"unknown error code". */
const char *err_code_json(enum refract_code code);
int err_code_http_status(enum refract_code code);
const char *err_code_text(enum refract_code code);

/* Looks up a code by its JSON string; returns REFRACT_E_COUNT_ when unknown. */
enum refract_code err_code_from_json(const char *json_code);

#endif
