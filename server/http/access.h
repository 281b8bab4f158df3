/*
 * access.h - the access checks server.c applies to every request (access.c explains
 * each): Host allow-list, bearer token, Content-Type of JSON bodies. Pure functions of the
 * config and the header values; no libmicrohttpd here, so they are unit-testable.
 */
#ifndef REFRACT_HTTP_ACCESS_H
#define REFRACT_HTTP_ACCESS_H

#include <stdbool.h>
#include <stddef.h>

#include "http.h"

/* True when host (the Host header's value; NULL when absent) names a host cfg serves. */
bool http_access_host_allowed(const struct http_config *cfg, const char *host);
/* The 421 message for host (printable ASCII only; says which flag to use). */
void http_access_host_message(const char *host, char *out, size_t size);

/* True for the routes that need no token: GET /v1/health and the viewer's static pages. */
bool http_access_token_exempt(const char *method, const char *pattern);

enum http_token_verdict {
    HTTP_TOKEN_OK = 0,     /* no token configured, or the right one */
    HTTP_TOKEN_MISSING,    /* no Authorization header */
    HTTP_TOKEN_NOT_BEARER, /* an Authorization header of another scheme */
    HTTP_TOKEN_WRONG,      /* a bearer token, not the right one */
};
/* Checks the Authorization header's value (NULL when absent) in constant time. */
enum http_token_verdict http_access_token_check(const struct http_config *cfg,
                                                const char *authorization);

/* True when content_type is application/json (any case, parameters allowed). */
bool http_access_json_type(const char *content_type);
/* The 415 message of a JSON route (method, pattern) sent content_type (NULL: none). */
void http_access_type_message(const char *method, const char *pattern, const char *content_type,
                              char *out, size_t size);

#endif
