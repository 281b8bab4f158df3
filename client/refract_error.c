/*
 * refract_error.c - the error table seen from the client: static descriptions and JSON
 * names of the codes in proto/refract_errors.h, and the per-client message of the last
 * failed call.
 *
 * The descriptions are the table's text, so refractd, librefract and the CLI's --help
 * cannot drift apart. This file does not decide which code a failure gets; the transport
 * (refract_http.c) and the calls (refract_calls.c) do.
 */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "refract_internal.h"

struct code_row {
    int code;
    const char *json;
    const char *text;
};

static const struct code_row code_rows[] = {
#define REFRACT_X_ROW(name, num, http, json, text) {num, json, text},
    REFRACT_ERROR_TABLE(REFRACT_X_ROW)
#undef REFRACT_X_ROW
};

#define CODE_ROW_COUNT (sizeof(code_rows) / sizeof(code_rows[0]))

static const struct code_row *find_row(int code)
{
    for (size_t i = 0; i < CODE_ROW_COUNT; i++) {
        if (code_rows[i].code == code)
            return &code_rows[i];
    }
    return NULL;
}

const char *refract_strerror(int code)
{
    const struct code_row *row = find_row(code);

    return row != NULL ? row->text : "unknown error code";
}

const char *refract_code_name(int code)
{
    const struct code_row *row = find_row(code);

    return row != NULL ? row->json : "unknown";
}

int refract_code_from_name(const char *json_code)
{
    for (size_t i = 0; i < CODE_ROW_COUNT; i++) {
        if (strcmp(code_rows[i].json, json_code) == 0)
            return code_rows[i].code;
    }
    return -1;
}

const char *refract_errmsg(const refract_client *c)
{
    if (c == NULL)
        return "no client (refract_client_create() returned NULL: out of memory, or "
               "libcurl failed to initialise)";
    return c->errmsg;
}

int refract_fail(refract_client *c, int code, const char *fmt, ...)
{
    va_list ap;
    int n;

    va_start(ap, fmt);
    n = vsnprintf(c->errmsg, sizeof(c->errmsg), fmt, ap);
    va_end(ap);
    if (n < 0) {
        snprintf(c->errmsg, sizeof(c->errmsg), "%s", refract_strerror(code));
    } else if ((size_t)n >= sizeof(c->errmsg)) {
        /* Say that the message was cut rather than end it mid-word silently. */
        memcpy(c->errmsg + sizeof(c->errmsg) - 4, "...", 4);
    }
    return code;
}

void refract_clear_error(refract_client *c)
{
    c->errmsg[0] = '\0';
}
