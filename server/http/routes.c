/*
 * routes.c - the route table of API v1 and of the web viewer, and path matching. proto/openapi.yaml
 * documents exactly these routes; tests/integration/test_openapi_contract.c checks both ways.
 */
#include <stdio.h>
#include <string.h>

#include "../core/metrics.h"
#include "http_internal.h"
#include "routes.h"

static const struct http_route routes[] = {
    /* The web viewer (h_web.c): pages and their assets, outside /v1. */
    {"GET", "/", http_handle_web_index, HTTP_BODY_NONE},
    {"GET", "/viewer/{id}", http_handle_web_viewer, HTTP_BODY_NONE},
    {"GET", "/assets/{file}", http_handle_web_asset, HTTP_BODY_NONE},
    /* API v1. */
    {"GET", "/v1/health", http_handle_health, HTTP_BODY_NONE},
    {"GET", "/v1/storage", http_handle_storage, HTTP_BODY_NONE},
    {"GET", "/metrics", http_handle_metrics, HTTP_BODY_NONE},
    {"GET", "/v1/scenes", http_handle_scene_list, HTTP_BODY_NONE},
    {"POST", "/v1/scenes", http_handle_scene_create, HTTP_BODY_JSON},
    {"GET", "/v1/scenes/{id}", http_handle_scene_get, HTTP_BODY_NONE},
    {"DELETE", "/v1/scenes/{id}", http_handle_scene_delete, HTTP_BODY_NONE},
    {"PUT", "/v1/scenes/{id}/volumes/{name}", http_handle_volume_put, HTTP_BODY_UPLOAD},
    {"PUT", "/v1/scenes/{id}/environment", http_handle_environment_put, HTTP_BODY_UPLOAD},
    {"POST", "/v1/scenes/{id}/meshes", http_handle_mesh_post, HTTP_BODY_UPLOAD},
    {"POST", "/v1/scenes/{id}/render", http_handle_render, HTTP_BODY_JSON},
    {"POST", "/v1/scenes/{id}/trace", http_handle_trace, HTTP_BODY_JSON},
    {"GET", "/v1/scenes/{id}/lights", http_handle_lights_get, HTTP_BODY_NONE},
    {"PUT", "/v1/scenes/{id}/lights", http_handle_lights_put, HTTP_BODY_JSON},
    {"PUT", "/v1/scenes/{id}/lights/{name}", http_handle_light_put, HTTP_BODY_JSON},
    {"GET", "/v1/scenes/{id}/irradiance", http_handle_irradiance_get, HTTP_BODY_NONE},
    {"GET", "/v1/scenes/{id}/irradiance/{light}.exr", http_handle_irradiance_exr, HTTP_BODY_NONE},
    {"POST", "/v1/scenes/{id}/views", http_handle_view_create, HTTP_BODY_JSON},
    {"GET", "/v1/views", http_handle_view_list, HTTP_BODY_NONE},
    {"GET", "/v1/views/{vid}", http_handle_view_get, HTTP_BODY_NONE},
    {"PATCH", "/v1/views/{vid}", http_handle_view_patch, HTTP_BODY_JSON},
    {"DELETE", "/v1/views/{vid}", http_handle_view_delete, HTTP_BODY_NONE},
    {"GET", "/v1/views/{vid}/stream", http_handle_view_stream, HTTP_BODY_NONE},
    {"POST", "/v1/jobs", http_handle_job_create, HTTP_BODY_JSON},
    {"GET", "/v1/jobs", http_handle_job_list, HTTP_BODY_NONE},
    {"GET", "/v1/jobs/{jid}", http_handle_job_get, HTTP_BODY_NONE},
    {"DELETE", "/v1/jobs/{jid}", http_handle_job_delete, HTTP_BODY_NONE},
    {"GET", "/v1/jobs/{jid}/frames/{n}", http_handle_job_frame, HTTP_BODY_NONE},
    {"GET", "/v1/jobs/{jid}/archive", http_handle_job_archive, HTTP_BODY_NONE},
    {"GET", "/v1/scenes/{id}/events", http_handle_scene_events, HTTP_BODY_NONE},
    {"GET", "/v1/events", http_handle_events, HTTP_BODY_NONE},
};

#define ROUTE_COUNT (sizeof routes / sizeof routes[0])
_Static_assert(ROUTE_COUNT < METRICS_NO_ROUTE, "GET /metrics counts requests per route index");

size_t http_route_index(const struct http_route *route)
{
    return route != NULL ? (size_t)(route - routes) : METRICS_NO_ROUTE;
}

size_t http_routes(const struct http_route_info **out)
{
    static struct http_route_info infos[ROUTE_COUNT];
    for (size_t i = 0; i < ROUTE_COUNT; i++) {
        infos[i].method = routes[i].method;
        infos[i].pattern = routes[i].pattern;
    }
    *out = infos;
    return ROUTE_COUNT;
}

/* Matches url against pattern segment by segment; {x} captures one non-empty segment, or
 * the part of it before a literal suffix ({light}.exr captures "sun" of "sun.exr"). */
static bool match(const char *pattern, const char *url, char params[][HTTP_PARAM_MAX],
                  int *param_count)
{
    int n = 0;
    const char *p = pattern, *u = url;
    while (*p && *u) {
        if (*p == '{') {
            const char *close = strchr(p, '}');
            const char *seg_end = strchr(u, '/');
            size_t len = seg_end ? (size_t)(seg_end - u) : strlen(u);
            if (close == NULL)
                return false;
            const char *suffix_end = strchr(close + 1, '/');
            size_t suffix = suffix_end ? (size_t)(suffix_end - close - 1) : strlen(close + 1);
            if (suffix > 0) {
                if (len <= suffix || memcmp(u + len - suffix, close + 1, suffix) != 0)
                    return false;
                len -= suffix;
            }
            if (len == 0 || len >= HTTP_PARAM_MAX || n >= HTTP_MAX_PARAMS)
                return false;
            memcpy(params[n], u, len);
            params[n][len] = '\0';
            n++;
            p = close + 1;
            u += len;
            continue;
        }
        if (*p != *u)
            return false;
        p++;
        u++;
    }
    if (*p != '\0' || *u != '\0')
        return false;
    *param_count = n;
    return true;
}

const struct http_route *http_route_find(const char *method, const char *url,
                                         char params[][HTTP_PARAM_MAX], int *param_count,
                                         bool *path_known)
{
    *path_known = false;
    for (size_t i = 0; i < ROUTE_COUNT; i++) {
        int n = 0;
        if (!match(routes[i].pattern, url, params, &n))
            continue;
        *path_known = true;
        if (strcmp(routes[i].method, method) == 0) {
            *param_count = n;
            return &routes[i];
        }
    }
    return NULL;
}

size_t http_route_methods(const char *url, char *out, size_t size)
{
    char params[HTTP_MAX_PARAMS][HTTP_PARAM_MAX];
    size_t used = 0;
    out[0] = '\0';
    for (size_t i = 0; i < ROUTE_COUNT; i++) {
        int n = 0;
        if (!match(routes[i].pattern, url, params, &n))
            continue;
        int w = snprintf(out + used, size - used, "%s%s", used ? ", " : "", routes[i].method);
        if (w < 0 || (size_t)w >= size - used) {
            /* Whole names only: snprintf left a cut one ("GET, DE") behind the list. */
            out[used] = '\0';
            break;
        }
        used += (size_t)w;
    }
    return used;
}
