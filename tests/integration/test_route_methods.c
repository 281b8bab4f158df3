/*
 * test_route_methods.c - http_route_methods (the Allow header of a 405 answer) over every
 * path of the route table and every buffer size: the answer is always a list of whole
 * method names that the full answer starts with, and the return value is its length.
 * A buffer too short for the next name once left that name cut behind the list
 * ("GET, DE"), found by tests/fuzz/fuzz_router.c (regression input
 * tests/fuzz/corpus/router/regress_allow_cut_name). Pure C over the real route table; in
 * this folder because it links refract_http, as the daemon does.
 */
#include <stdio.h>
#include <string.h>

#include "http/http.h"
#include "http/routes.h"
#include "test.h"

/* The pattern with each {param} replaced by "p1" (a literal suffix such as ".exr" kept). */
static void concrete_path(const char *pattern, char *out, size_t size)
{
    size_t n = 0;
    for (const char *p = pattern; *p && n + 3 < size; p++) {
        if (*p == '{') {
            const char *close = strchr(p, '}');
            out[n++] = 'p';
            out[n++] = '1';
            p = close;
            continue;
        }
        out[n++] = *p;
    }
    out[n] = '\0';
}

int main(void)
{
    const struct http_route_info *routes;
    size_t count = http_routes(&routes);
    CHECK(count > 0);
    int multi_method_paths = 0;
    for (size_t r = 0; r < count; r++) {
        char url[256];
        concrete_path(routes[r].pattern, url, sizeof url);
        char full[256];
        size_t full_len = http_route_methods(url, full, sizeof full);
        CHECK_INT((long long)full_len, (long long)strlen(full));
        CHECK_CONTAINS(full, routes[r].method);
        if (strchr(full, ',') != NULL)
            multi_method_paths++;
        for (size_t size = 1; size <= full_len + 1; size++) {
            char out[256];
            memset(out, 'X', sizeof out);
            size_t used = http_route_methods(url, out, size);
            CHECK_MSG(used < size && strlen(out) == used, "%s in %zu bytes: %zu, \"%s\"", url, size,
                      used, out);
            /* A prefix of the full list that ends at a whole name (or holds none). */
            CHECK_MSG(strncmp(out, full, used) == 0 &&
                          (used == 0 || full[used] == '\0' || strncmp(full + used, ", ", 2) == 0),
                      "%s in %zu bytes: \"%s\" is not whole names of \"%s\"", url, size, out, full);
        }
        /* The route itself is found for its method, with its path known. */
        char params[HTTP_MAX_PARAMS][HTTP_PARAM_MAX];
        int n = 0;
        bool known = false;
        const struct http_route *found = http_route_find(routes[r].method, url, params, &n, &known);
        CHECK(found != NULL && known);
        CHECK_INT((long long)http_route_index(found), (long long)r);
    }
    /* Paths with several methods exist (GET and DELETE /v1/scenes/{id}): the cut case ran. */
    CHECK(multi_method_paths > 0);
    return test_summary("test_route_methods");
}
