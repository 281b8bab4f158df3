/*
 * fuzz_router.c - libFuzzer harness of refractd's request router (server/http/routes.c:
 * http_route_find, http_route_methods, http_route_index over the real route table), which
 * sees every request line any client sends. docs/fuzzing.md.
 *
 * Input layout: a request line as "METHOD URL": the method up to the first space, the
 * URL after it up to the first NUL (libmicrohttpd hands the router a NUL-terminated
 * URL); byte 0's low 6 bits also size the Allow buffer of http_route_methods (1..64
 * bytes, refractd uses 64) so that truncation runs too.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "http/http.h"
#include "http/routes.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    size_t allow_size = (size_t)(data[0] & 63) + 1;
    char *line = malloc(size + 1);
    if (line == NULL)
        return 0;
    memcpy(line, data, size);
    line[size] = '\0';
    char *space = strchr(line, ' ');
    const char *method = line, *url = "";
    if (space != NULL) {
        *space = '\0';
        url = space + 1;
    }
    char params[HTTP_MAX_PARAMS][HTTP_PARAM_MAX];
    int param_count = -1;
    bool path_known = false;
    const struct http_route *route =
        http_route_find(method, url, params, &param_count, &path_known);
    const struct http_route_info *table;
    size_t routes = http_routes(&table);
    if (route != NULL) {
        size_t i = http_route_index(route);
        if (i >= routes || !path_known || strcmp(table[i].method, method) != 0)
            abort(); /* the route found serves this method */
        if (param_count < 0 || param_count > HTTP_MAX_PARAMS)
            abort();
        for (int p = 0; p < param_count; p++) {
            size_t n = strnlen(params[p], HTTP_PARAM_MAX);
            /* a parameter is a non-empty part of the URL without '/' */
            if (n == 0 || n >= HTTP_PARAM_MAX || strchr(params[p], '/') != NULL ||
                strstr(url, params[p]) == NULL)
                abort();
        }
    }
    char *allow = malloc(allow_size);
    if (allow != NULL) {
        size_t used = http_route_methods(url, allow, allow_size);
        if (used >= allow_size || strlen(allow) != used)
            abort();
        if (path_known && allow_size == 64 && used == 0)
            abort(); /* some method serves a known path, and 64 bytes hold its name */
        free(allow);
    }
    free(line);
    return 0;
}
