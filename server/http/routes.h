/*
 * routes.h - route lookup (internal to server/http/).
 */
#ifndef REFRACT_HTTP_ROUTES_H
#define REFRACT_HTTP_ROUTES_H

#include <stdbool.h>
#include <stddef.h>

#include "http_internal.h"

/* The route for method + url, with its path parameters, or NULL. *path_known tells
 * whether some other method serves this path (405 rather than 404). */
const struct http_route *http_route_find(const char *method, const char *url,
                                         char params[][HTTP_PARAM_MAX], int *param_count,
                                         bool *path_known);
/* The route's position in the table (http_routes), or METRICS_NO_ROUTE for NULL: the
 * label index of GET /metrics. */
size_t http_route_index(const struct http_route *route);
/* Comma-separated methods that serve url (for 405 messages and the Allow header): as many
 * whole names as fit in size bytes with the NUL; returns strlen(out). */
size_t http_route_methods(const char *url, char *out, size_t size);

#endif
