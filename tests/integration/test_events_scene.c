/*
 * test_events_scene.c - Server-Sent Events through a real refractd (docs/api.md "Events",
 * docs/views.md), on the irradiance tests' beam scene (16-voxel light grid, computed in a
 * fraction of a second on llvmpipe) with --lightsim-chunk-steps 2, so a recompute spans
 * a dozen GPU work items:
 *   - GET /v1/events is text/event-stream and opens with a comment;
 *   - creating a scene that needs light simulation publishes scene.created, then
 *     irradiance.progress (queued, then computing with progress rising in (0, 1)), then
 *     irradiance.ready with the light's key, ids one apart on the every-event stream;
 *   - on the scene's stream, a PUT of a light gives scene.updated (what = lights, a newer
 *     generation), then irradiance.progress ... irradiance.ready for the new key that the
 *     PUT answered, and nothing about other scenes;
 *   - uploads give scene.updated with what = volume and what = environment;
 *   - reconnecting with Last-Event-ID (or ?since=) gives exactly the events after that
 *     id, with the same ids, types and data, and then nothing;
 *   - deleting the scene ends its stream after scene.deleted; the every-event stream goes
 *     on;
 *   - a resume point that is not a number is a 400 invalid_field that names the header or
 *     the parameter, a misspelt parameter a 400 unknown_field; an unknown scene is a 404
 *     scene_not_found;
 *   - the daemon stops cleanly with streams open (they end).
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "expect.h"
#include "io/io_image.h"
#include "irradiance_util.h"
#include "sse_util.h"

#define LOG_MAX 256

static const char sun_down[] =
    "[{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0, -1, 0]}]";

/* No receiver, no scattering: needs no light simulation, so it publishes no irradiance
 * events. */
static const char plain_scene[] =
    "{\"name\": \"plain\", \"environment\": {\"type\": \"image\"},"
    " \"objects\": [{\"bounds\": {\"min\": [-0.5, -0.5, -0.5], \"max\": [0.5, 0.5, 0.5]},"
    " \"resolution\": 8, \"ior\": 1.2}],"
    " \"lights\": [{\"name\": \"key\", \"type\": \"directional\", \"direction\": [0, -1, 0]}]}";

static struct sse_event global_log[LOG_MAX], scene_log[LOG_MAX], again_log[LOG_MAX];

/* Checks one recompute as seen on a stream: from log[first], irradiance.progress events
 * (the first queued at 0, then computing with non-decreasing progress in [0, 1)) and then
 * one irradiance.ready, all for scene/light/key. Returns the index after the ready. */
static size_t check_recompute(const struct sse_event *log, size_t count, size_t first,
                              const char *scene, const char *key)
{
    size_t i = first;
    double last = -1;
    int progress_events = 0;
    for (; i < count && strcmp(log[i].type, "irradiance.progress") == 0; i++) {
        cJSON *d = cJSON_Parse(log[i].data);
        const char *state = sse_str(d, "state");
        double p = sse_num(d, "progress");
        CHECK_STR(sse_str(d, "scene"), scene);
        CHECK_STR(sse_str(d, "light"), "sun");
        CHECK_STR(sse_str(d, "key"), key);
        if (progress_events == 0) {
            CHECK_STR(state, "queued");
            CHECK_NEAR(p, 0.0, 0);
        } else {
            CHECK_STR(state, "computing");
            CHECK_MSG(p >= last && p >= 0 && p < 1, "progress %g after %g", p, last);
        }
        last = p;
        progress_events++;
        cJSON_Delete(d);
    }
    CHECK_MSG(progress_events >= 2, "%d irradiance.progress events (queued and computing)",
              progress_events);
    CHECK_MSG(i < count && strcmp(log[i].type, "irradiance.ready") == 0, "after the progress: %s",
              i < count ? log[i].type : "(nothing)");
    if (i >= count)
        return i;
    cJSON *d = cJSON_Parse(log[i].data);
    CHECK_STR(sse_str(d, "scene"), scene);
    CHECK_STR(sse_str(d, "light"), "sun");
    CHECK_STR(sse_str(d, "key"), key);
    CHECK(sse_num(d, "compute_ms") > 0);
    CHECK(cJSON_IsFalse(cJSON_GetObjectItemCaseSensitive(d, "loaded_from_disk")));
    cJSON_Delete(d);
    return i + 1;
}

/* The light's key in an irradiance status body. */
static void status_key(const char *body, char *key)
{
    cJSON *root = cJSON_Parse(body ? body : "");
    snprintf(key, 17, "%s", irr_str(irr_light(root, "sun"), "key"));
    cJSON_Delete(root);
}

static void create_publishes_created_then_irradiance(struct test_daemon *d, struct sse_client *all,
                                                     char *id, double *generation)
{
    CHECK_CONTAINS(all->content_type, "text/event-stream");
    char *doc = beam_scene(sun_down);
    CHECK(test_create_scene(d, doc, id));
    free(doc);
    size_t n = 0;
    struct sse_event ev;
    CHECK(sse_until(all, "irradiance.ready", 60, &ev, global_log, &n, LOG_MAX));
    CHECK_MSG(n >= 4, "%zu events", n);
    if (n < 4)
        return;
    CHECK_STR(global_log[0].type, "scene.created");
    cJSON *data = cJSON_Parse(global_log[0].data);
    CHECK_STR(sse_str(data, "scene"), id);
    *generation = sse_num(data, "generation");
    CHECK(*generation >= 1);
    cJSON_Delete(data);
    for (size_t i = 0; i < n; i++) {
        CHECK(global_log[i].has_id);
        if (i > 0)
            CHECK_MSG(global_log[i].id == global_log[i - 1].id + 1,
                      "every-event stream: id %llu after %llu",
                      (unsigned long long)global_log[i].id,
                      (unsigned long long)global_log[i - 1].id);
    }
    cJSON *st = irr_status(d, id);
    char key[17];
    snprintf(key, sizeof key, "%s", irr_str(irr_light(st, "sun"), "key"));
    cJSON_Delete(st);
    CHECK_INT((int)check_recompute(global_log, n, 1, id, key), (int)n);
}

/* Returns how many events the scene's stream logged. */
static size_t light_put_publishes_update_then_irradiance(struct test_daemon *d,
                                                         struct sse_client *one, const char *id,
                                                         const char *other, double generation)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/lights/sun", id);
    struct irr_answer a =
        irr_http(d, "PUT", path, "{\"type\": \"directional\", \"direction\": [0.3, -1, 0]}");
    CHECK_MSG(a.status == 202, "PUT %s: %ld %s", path, a.status, a.body ? a.body : "");
    char key[17];
    status_key(a.body, key);
    free(a.body);
    size_t n = 0;
    struct sse_event ev;
    CHECK(sse_until(one, "irradiance.ready", 60, &ev, scene_log, &n, LOG_MAX));
    if (n < 3)
        return n;
    CHECK_STR(scene_log[0].type, "scene.updated");
    cJSON *data = cJSON_Parse(scene_log[0].data);
    CHECK_STR(sse_str(data, "scene"), id);
    CHECK_STR(sse_str(data, "what"), "lights");
    CHECK(sse_num(data, "generation") > generation);
    cJSON_Delete(data);
    for (size_t i = 0; i < n; i++) {
        cJSON *di = cJSON_Parse(scene_log[i].data);
        CHECK_MSG(strcmp(sse_str(di, "scene"), id) == 0, "scene stream of %s got %s %s", id,
                  scene_log[i].type, scene_log[i].data);
        CHECK_MSG(strcmp(sse_str(di, "scene"), other) != 0, "an event of the other scene");
        cJSON_Delete(di);
        if (i > 0)
            CHECK(scene_log[i].id > scene_log[i - 1].id);
    }
    CHECK_INT((int)check_recompute(scene_log, n, 1, id, key), (int)n);
    /* Nothing more: the recompute is over. */
    CHECK_INT(sse_next(one, &ev, 0.5), SSE_TIMEOUT);
    return n;
}

static bool same_event(const struct sse_event *a, const struct sse_event *b)
{
    return a->has_id == b->has_id && a->id == b->id && strcmp(a->type, b->type) == 0 &&
           strcmp(a->data, b->data) == 0;
}

/* Reopens the scene's stream after log[0] into c (which the caller closes) and expects
 * exactly log[1..n-1], then nothing. */
static void resume_gives_exactly_the_rest(struct test_daemon *d, const char *id, size_t n,
                                          bool with_header, struct sse_client *c)
{
    char path[160], last[32];
    snprintf(last, sizeof last, "%llu", (unsigned long long)scene_log[0].id);
    if (with_header)
        snprintf(path, sizeof path, "/v1/scenes/%s/events", id);
    else
        snprintf(path, sizeof path, "/v1/scenes/%s/events?since=%s", id, last);
    CHECK_MSG(sse_open(c, d, path, with_header ? last : NULL), "reopen %s: status %ld", path,
              c->status);
    struct sse_event ev;
    size_t got = 0;
    while (sse_next(c, &ev, got + 1 < n ? 10 : 0.5) == SSE_EVENT && got < LOG_MAX)
        again_log[got++] = ev;
    CHECK_INT((int)got, (int)n - 1);
    for (size_t i = 0; i < got && i + 1 < n; i++)
        CHECK_MSG(same_event(&again_log[i], &scene_log[i + 1]),
                  "resumed event %zu: %llu %s %s, expected %llu %s %s", i,
                  (unsigned long long)again_log[i].id, again_log[i].type, again_log[i].data,
                  (unsigned long long)scene_log[i + 1].id, scene_log[i + 1].type,
                  scene_log[i + 1].data);
}

static void uploads_publish_updates(struct test_daemon *d, const char *other)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/events", other);
    struct sse_client c;
    CHECK(sse_open(&c, d, path, NULL));
    static const float ramp[8] = {0, 1, 2, 3, 4, 5, 6, 7};
    CHECK_INT(
        refract_volume_upload(d->client, other, "ramp", (const int[3]){2, 2, 2}, 1, ramp, NULL),
        REFRACT_E_OK);
    static float sky[8 * 4 * 4];
    for (size_t i = 0; i < sizeof sky / sizeof sky[0]; i++)
        sky[i] = 0.5f;
    void *exr = NULL;
    size_t len = 0;
    struct err e = {0};
    CHECK_INT(io_encode_exr(sky, 8, 4, &exr, &len, &e), REFRACT_E_OK);
    CHECK_INT(refract_environment_upload(d->client, other, exr, len, NULL), REFRACT_E_OK);
    free(exr);
    static const char *const what[] = {"volume", "environment"};
    struct sse_event ev;
    for (int k = 0; k < 2; k++) {
        CHECK_INT(sse_next(&c, &ev, 10), SSE_EVENT);
        CHECK_STR(ev.type, "scene.updated");
        cJSON *data = cJSON_Parse(ev.data);
        CHECK_STR(sse_str(data, "scene"), other);
        CHECK_STR(sse_str(data, "what"), what[k]);
        cJSON_Delete(data);
    }
    CHECK_INT(sse_next(&c, &ev, 0.5), SSE_TIMEOUT);
    sse_close(&c);
}

static void delete_ends_the_scene_stream(struct test_daemon *d, struct sse_client *one,
                                         struct sse_client *all, const char *id)
{
    CHECK_INT(refract_scene_delete(d->client, id), REFRACT_E_OK);
    struct sse_event ev;
    CHECK_INT(sse_next(one, &ev, 10), SSE_EVENT);
    CHECK_STR(ev.type, "scene.deleted");
    cJSON *data = cJSON_Parse(ev.data);
    CHECK_STR(sse_str(data, "scene"), id);
    cJSON_Delete(data);
    CHECK_INT(sse_next(one, &ev, 10), SSE_ENDED);
    CHECK_INT((int)one->result, (int)CURLE_OK); /* a proper end, not a reset */
    /* The every-event stream has it too, and goes on. */
    CHECK(sse_until(all, "scene.deleted", 10, &ev, NULL, NULL, 0));
    CHECK_INT(sse_next(all, &ev, 0.3), SSE_TIMEOUT);
}

static void bad_resume_points(struct test_daemon *d)
{
    section("resume points");
    EXPECT_ERROR(d, "GET", "/v1/events?since=abc", NULL, 400, "invalid_field", "since", "abc");
    EXPECT_ERROR(d, "GET", "/v1/events?since=-1", NULL, 400, "invalid_field", "since", "-1");
    EXPECT_ERROR(d, "GET", "/v1/events?since=1.5", NULL, 400, "invalid_field", "since");
    EXPECT_ERROR(d, "GET", "/v1/events?since=", NULL, 400, "invalid_field", "since");
    EXPECT_ERROR(d, "GET", "/v1/events?since", NULL, 400, "invalid_field", "since");
    EXPECT_ERROR(d, "GET", "/v1/events?sinse=3", NULL, 400, "unknown_field", "sinse",
                 "allowed: since");
    EXPECT_ERROR(d, "GET", "/v1/events?since=99999999999999999999999", NULL, 400, "invalid_field",
                 "since");
    EXPECT_ERROR(d, "GET", "/v1/scenes/no_such_scene/events", NULL, 404, "scene_not_found",
                 "no_such_scene");
    EXPECT_ERROR(d, "POST", "/v1/events", NULL, 405, "method_not_allowed", "GET");
    struct sse_client c;
    CHECK(!sse_open(&c, d, "/v1/events", "x42"));
    CHECK_INT((int)c.status, 400);
    CHECK(test_error_is(c.buf, "invalid_field", "Last-Event-ID"));
    sse_close(&c);
    section("");
}

int main(void)
{
    curl_global_init(CURL_GLOBAL_DEFAULT);
    struct test_daemon d;
    const char *args[] = {"--lightsim-chunk-steps", "2", NULL};
    if (!test_daemon_start(&d, args))
        test_setup_failed("test_events_scene", d.why);
    struct sse_client all, one;
    CHECK(sse_open(&all, &d, "/v1/events", NULL));
    char id[REFRACT_ID_SIZE] = "", other[REFRACT_ID_SIZE] = "";
    double generation = 0;
    create_publishes_created_then_irradiance(&d, &all, id, &generation);

    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/events", id);
    CHECK(sse_open(&one, &d, path, NULL));
    CHECK(test_create_scene(&d, plain_scene, other)); /* not on the first scene's stream */
    size_t n = light_put_publishes_update_then_irradiance(&d, &one, id, other, generation);
    sse_close(&one);
    resume_gives_exactly_the_rest(&d, id, n, false, &one);
    sse_close(&one);
    resume_gives_exactly_the_rest(&d, id, n, true, &one);

    uploads_publish_updates(&d, other);
    delete_ends_the_scene_stream(&d, &one, &all, id);
    sse_close(&one);
    bad_resume_points(&d);

    /* Shutdown ends the open stream and still exits cleanly. */
    CHECK_INT(test_daemon_stop(&d), 0);
    struct sse_event ev;
    CHECK_INT(sse_next(&all, &ev, 10), SSE_ENDED);
    sse_close(&all);
    test_daemon_cleanup(&d);
    curl_global_cleanup();
    return test_summary("test_events_scene");
}
