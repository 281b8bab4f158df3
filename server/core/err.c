/*
 * err.c - struct err helpers and lookups in the error table.
 *
 * The table itself lives in proto/refract_errors.h so the client and the server
 * share it; this file only indexes it.
 */
#include "err.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

struct code_row {
    enum refract_code code;
    int http_status;
    const char *json;
    const char *text;
};

static const struct code_row code_rows[] = {
#define ROW(name, num, http, json, text) {REFRACT_E_##name, http, json, text},
    REFRACT_ERROR_TABLE(ROW)
#undef ROW
};

static const struct code_row *find_row(enum refract_code code)
{
    for (size_t i = 0; i < sizeof code_rows / sizeof code_rows[0]; i++) {
        if (code_rows[i].code == code)
            return &code_rows[i];
    }
    return NULL;
}

enum refract_code err_set(struct err *e, enum refract_code code, const char *fmt, ...)
{
    if (e == NULL)
        return code;
    e->code = code;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->msg, sizeof e->msg, fmt, ap);
    va_end(ap);
    return code;
}

enum refract_code err_prefix(struct err *e, const char *fmt, ...)
{
    if (e == NULL)
        return REFRACT_E_INTERNAL;
    char prefix[ERR_MSG_MAX];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(prefix, sizeof prefix, fmt, ap);
    va_end(ap);
    /* Truncation keeps the start of the message, which carries the path. */
    size_t plen = strnlen(prefix, sizeof prefix - 1);
    size_t mlen = strnlen(e->msg, sizeof e->msg - 1);
    if (plen + mlen > sizeof e->msg - 1)
        mlen = sizeof e->msg - 1 - plen;
    memmove(e->msg + plen, e->msg, mlen);
    memcpy(e->msg, prefix, plen);
    e->msg[plen + mlen] = '\0';
    return e->code;
}

void err_clear(struct err *e)
{
    if (e == NULL)
        return;
    e->code = REFRACT_E_OK;
    e->msg[0] = '\0';
}

const char *err_code_json(enum refract_code code)
{
    const struct code_row *r = find_row(code);
    return r ? r->json : "internal";
}

int err_code_http_status(enum refract_code code)
{
    const struct code_row *r = find_row(code);
    return (r && r->http_status) ? r->http_status : 500;
}

const char *err_code_text(enum refract_code code)
{
    const struct code_row *r = find_row(code);
    return r ? r->text : "unknown error code";
}

enum refract_code err_code_from_json(const char *json_code)
{
    for (size_t i = 0; i < sizeof code_rows / sizeof code_rows[0]; i++) {
        if (strcmp(code_rows[i].json, json_code) == 0)
            return code_rows[i].code;
    }
    return REFRACT_E_COUNT_;
}
