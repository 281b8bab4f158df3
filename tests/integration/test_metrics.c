/*
 * test_metrics.c - GET /metrics (docs/api.md "Metrics"; issue 13, part 7):
 *   - metrics_need_the_token: with --token-file, /metrics without the token is 401 like
 *     every route but /v1/health, and 200 text/plain with it;
 *   - the_text_is_prometheus_exposition_format: every family has HELP and TYPE, every
 *     sample line is `name{labels} value` of a declared family, histogram buckets are
 *     cumulative and end in +Inf = _count;
 *   - counters_follow_what_happened: after two renders of one scene, a 404 and an upload,
 *     the request counter of each route and status grew by what was sent, the render
 *     histogram by 2, the GPU scene cache saw at least one miss then a hit, the GPU busy
 *     time grew, stored bytes equal GET /v1/storage's used_bytes, and the jobs and
 *     streams gauges are present; then an open view session shows as 1;
 *   - light_simulation_and_irradiance_lookups_are_counted: a scene with a light is
 *     simulated once (refractd_lightsim_seconds_count + 1, lightsim GPU busy time), its
 *     first lookup missed and the render's lookup hit.
 * Every item the issue lists has a family here: requests by route and status, latency
 * histograms, GPU queue length and busy time, render and light-simulation times, cache
 * hits/misses/evictions, bytes stored, open views and streams, jobs by state.
 */
#include <regex.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "daemon.h"
#include "test.h"
#include "upload_util.h"

#define TOKEN "metrics-token-0123456789abcdef"
#define SCENE                                                                                      \
    "{\"name\": \"m\", \"camera\": {\"eye\": [0, 0, 4], \"width\": 16, \"height\": 12}, "          \
    "\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "  \
    "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}}]}"

/* GET /metrics; returns the status, *text the body (new, caller frees). */
static long get_metrics(struct test_daemon *d, char **text, char *content_type, size_t size)
{
    struct refract_response r;
    *text = NULL;
    if (refract_request(d->client, "GET", "/metrics", NULL, 0, NULL, &r) != REFRACT_E_OK)
        return -1;
    long status = r.status;
    snprintf(content_type, size, "%s", r.content_type);
    *text = r.body;
    r.body = NULL;
    refract_response_free(&r);
    return status;
}

/* The value of the sample line that starts with `series` followed by a space (exact name
 * and labels), or -1 when absent. */
static double sample(const char *text, const char *series)
{
    size_t n = strlen(series);
    for (const char *p = text; p && *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : NULL) {
        if (strncmp(p, series, n) == 0 && p[n] == ' ')
            return strtod(p + n + 1, NULL);
    }
    return -1.0;
}

static void metrics_need_the_token(struct test_daemon *d)
{
    char *text = NULL, type[128];
    CHECK_INT(get_metrics(d, &text, type, sizeof type), 401);
    CHECK(test_error_is(text, "unauthorized", "--token-file"));
    free(text);
    CHECK_INT(refract_set_token(d->client, TOKEN), 0);
    CHECK_INT(get_metrics(d, &text, type, sizeof type), 200);
    CHECK(strncmp(type, "text/plain; version=0.0.4", 25) == 0);
    free(text);
}

static void the_text_is_prometheus_exposition_format(const char *text)
{
    regex_t line_re;
    CHECK_INT(regcomp(&line_re,
                      "^([a-z_]+)(\\{[a-z_]+=\"[^\"]*\"(,[a-z_]+=\"[^\"]*\")*\\})? "
                      "([0-9.e+-]+)$",
                      REG_EXTENDED),
              0);
    char declared[64][64];
    size_t families = 0;
    int bad_lines = 0, undeclared = 0, samples = 0;
    char *copy = strdup(text), *save = NULL;
    for (char *line = strtok_r(copy, "\n", &save); line; line = strtok_r(NULL, "\n", &save)) {
        char name[64];
        if (sscanf(line, "# TYPE %63s", name) == 1) {
            if (families < 64)
                snprintf(declared[families++], sizeof declared[0], "%s", name);
            continue;
        }
        if (line[0] == '#')
            continue;
        regmatch_t m[5];
        if (regexec(&line_re, line, 5, m, 0) != 0) {
            bad_lines++;
            fprintf(stderr, "not an exposition line: %s\n", line);
            continue;
        }
        samples++;
        bool known = false;
        for (size_t f = 0; f < families && !known; f++) {
            size_t len = strlen(declared[f]);
            known = strncmp(line, declared[f], len) == 0 &&
                    (line[len] == '{' || line[len] == ' ' || line[len] == '_');
        }
        undeclared += !known;
    }
    free(copy);
    regfree(&line_re);
    CHECK_INT(bad_lines, 0);
    CHECK_INT(undeclared, 0);
    CHECK(samples > 50);
    CHECK_INT((long)families, 15);
    /* The render histogram: cumulative buckets ending in +Inf == _count. */
    double previous = 0, inf = sample(text, "refractd_render_seconds_bucket{le=\"+Inf\"}");
    const char *p = text;
    int buckets = 0, decreasing = 0;
    while ((p = strstr(p, "refractd_render_seconds_bucket{le=\"")) != NULL) {
        const char *v = strchr(p, ' ');
        double x = strtod(v + 1, NULL);
        decreasing += x < previous;
        previous = x;
        buckets++;
        p = v;
    }
    CHECK_INT(buckets, 17);
    CHECK_INT(decreasing, 0);
    CHECK_NEAR(inf, sample(text, "refractd_render_seconds_count"), 0);
}

static void counters_follow_what_happened(struct test_daemon *d)
{
    char *before = NULL, *after = NULL, *body = NULL, type[128];
    CHECK_INT(get_metrics(d, &before, type, sizeof type), 200);
    char id[REFRACT_ID_SIZE], path[256];
    CHECK(test_create_scene(d, SCENE, id));
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    for (int i = 0; i < 2; i++) {
        CHECK_INT(test_request(d, "POST", path, "{}", &body), 200);
        free(body);
    }
    CHECK_INT(test_request(d, "GET", "/v1/nothing-here", NULL, &body), 404);
    free(body);
    static float voxels[8 * 8 * 8];
    for (size_t i = 0; i < 8 * 8 * 8; i++)
        voxels[i] = 1.0f + (float)i * 1e-3f;
    snprintf(path, sizeof path, "/v1/scenes/%s/volumes/v?dims=8,8,8&type=float32", id);
    CHECK_INT(upload_put(d, path, voxels, sizeof voxels, &body), 201);
    free(body);
    CHECK_INT(test_request(d, "GET", "/v1/storage", NULL, &body), 200);
    double used = upload_json_number(body, "used_bytes");
    free(body);
    CHECK_INT(get_metrics(d, &after, type, sizeof type), 200);
    if (before == NULL || after == NULL) {
        free(before);
        free(after);
        return;
    }
    the_text_is_prometheus_exposition_format(after);
    static const char *const grew_by[][2] = {
        {"refractd_http_requests_total{method=\"POST\",route=\"/v1/scenes/{id}/render\","
         "status=\"200\"}",
         "2"},
        {"refractd_http_requests_total{method=\"POST\",route=\"/v1/scenes\",status=\"201\"}", "1"},
        {"refractd_http_requests_total{method=\"\",route=\"none\",status=\"404\"}", "1"},
        {"refractd_http_request_duration_seconds_count{method=\"POST\",route=\"/v1/scenes/{id}/"
         "render\"}",
         "2"},
        {"refractd_render_seconds_count", "2"},
    };
    for (size_t i = 0; i < sizeof grew_by / sizeof grew_by[0]; i++) {
        double b = sample(before, grew_by[i][0]), a = sample(after, grew_by[i][0]);
        CHECK_MSG(a - (b < 0 ? 0 : b) == atof(grew_by[i][1]), "%s: %g before, %g after",
                  grew_by[i][0], b, a);
    }
    CHECK(sample(after, "refractd_cache_events_total{cache=\"gpu_scene\",event=\"miss\"}") >= 1);
    CHECK(sample(after, "refractd_cache_events_total{cache=\"gpu_scene\",event=\"hit\"}") >= 1);
    CHECK(sample(after, "refractd_cache_events_total{cache=\"irradiance\",event=\"eviction\"}") >=
          0);
    CHECK(sample(after, "refractd_gpu_busy_seconds_total{kind=\"interactive\"}") >
          sample(before, "refractd_gpu_busy_seconds_total{kind=\"interactive\"}"));
    CHECK(sample(after, "refractd_render_seconds_sum") > 0);
    CHECK_NEAR(sample(after, "refractd_stored_bytes"), used, 0);
    CHECK(used >= sizeof voxels);
    CHECK_NEAR(sample(after, "refractd_storage_limit_bytes"), 10737418240.0, 0);
    CHECK(sample(after, "refractd_gpu_queue_length") >= 0);
    CHECK(sample(after, "refractd_streams_open") == 0);
    CHECK(sample(after, "refractd_jobs{state=\"queued\"}") == 0);
    CHECK(sample(after, "refractd_lightsim_seconds_count") >= 0);
    CHECK(sample(after, "refractd_gpu_queue_wait_seconds_total{kind=\"lightsim\"}") >= 0);
    CHECK(sample(after, "refractd_views_open") == 0);
    free(after);
    /* A view session (it renders frames of its own, so it comes after the render counts). */
    snprintf(path, sizeof path, "/v1/scenes/%s/views", id);
    CHECK_INT(test_request(d, "POST", path, "{}", &body), 201);
    free(body);
    CHECK_INT(get_metrics(d, &after, type, sizeof type), 200);
    CHECK(after != NULL && sample(after, "refractd_views_open") == 1);
    free(before);
    free(after);
}

/* A scene that needs light simulation: the beam of tests/integration/irradiance_util.h
 * (a 16-voxel light grid, a fraction of a second on llvmpipe). */
#define LIT_SCENE                                                                                  \
    "{\"name\": \"beam\", \"camera\": {\"eye\": [0, 0.5, 4], \"look_at\": [0, -1, 0], "            \
    "\"width\": 16, \"height\": 12}, \"environment\": {\"intensity\": 0}, \"objects\": "           \
    "[{\"bounds\": {\"min\": [-0.5, -0.5, -0.5], \"max\": [0.5, 0.5, 0.5]}, \"resolution\": 8, "   \
    "\"ior\": 1.0}], \"receiver\": {\"height\": -1, \"half_size\": 1, \"albedo\": 0.8}, "          \
    "\"lights\": [{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0, -1, 0]}], "    \
    "\"lightsim\": {\"resolution\": 16, \"initial_patches\": 8}}"

/* Polls GET .../irradiance until every light is ready (true) or 60 s pass. */
static bool wait_irradiance_ready(struct test_daemon *d, const char *id)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/irradiance", id);
    for (int i = 0; i < 3000; i++) {
        char *body = NULL;
        bool ready = false;
        if (test_request(d, "GET", path, NULL, &body) == 200) {
            cJSON *st = cJSON_Parse(body);
            const cJSON *l = NULL;
            ready = st != NULL;
            int lights = 0;
            cJSON_ArrayForEach(l, cJSON_GetObjectItemCaseSensitive(st, "lights"))
            {
                const cJSON *state = cJSON_GetObjectItemCaseSensitive(l, "state");
                ready = ready && cJSON_IsString(state) && strcmp(state->valuestring, "ready") == 0;
                lights++;
            }
            ready = ready && lights > 0;
            cJSON_Delete(st);
        }
        free(body);
        if (ready)
            return true;
        usleep(20000);
    }
    return false;
}

static void light_simulation_and_irradiance_lookups_are_counted(struct test_daemon *d)
{
    char *before = NULL, *after = NULL, *body = NULL, type[128], id[REFRACT_ID_SIZE];
    CHECK_INT(get_metrics(d, &before, type, sizeof type), 200);
    CHECK(test_create_scene(d, LIT_SCENE, id));
    CHECK(wait_irradiance_ready(d, id));
    char path[256];
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    CHECK_INT(test_request(d, "POST", path, "{}", &body), 200);
    free(body);
    CHECK_INT(get_metrics(d, &after, type, sizeof type), 200);
    if (before && after) {
        CHECK_NEAR(sample(after, "refractd_lightsim_seconds_count") -
                       sample(before, "refractd_lightsim_seconds_count"),
                   1, 0);
        CHECK(sample(after, "refractd_lightsim_seconds_sum") > 0);
        CHECK(sample(after, "refractd_gpu_busy_seconds_total{kind=\"lightsim\"}") > 0);
        const char *miss = "refractd_cache_events_total{cache=\"irradiance\",event=\"miss\"}";
        const char *hit = "refractd_cache_events_total{cache=\"irradiance\",event=\"hit\"}";
        CHECK(sample(after, miss) - sample(before, miss) >= 1);
        CHECK(sample(after, hit) - sample(before, hit) >= 1);
        CHECK(sample(after, "refractd_irradiance_cache_bytes{tier=\"gpu\"}") > 0);
    }
    free(before);
    free(after);
}

int main(void)
{
    char token_file[512];
    test_temp_template(token_file, sizeof token_file, "refract-token");
    int fd = mkstemp(token_file);
    if (fd < 0 || write(fd, TOKEN "\n", strlen(TOKEN) + 1) < 0)
        test_setup_failed("test_metrics", "cannot write the token file");
    close(fd);
    struct test_daemon d;
    if (!test_daemon_start(&d, (const char *[]){"--token-file", token_file, NULL})) {
        unlink(token_file);
        test_setup_failed("test_metrics", d.why);
    }
    metrics_need_the_token(&d);
    counters_follow_what_happened(&d);
    light_simulation_and_irradiance_lookups_are_counted(&d);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    unlink(token_file);
    return test_summary("test_metrics");
}
