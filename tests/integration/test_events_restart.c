/*
 * test_events_restart.c - irradiance.ready for volumes that are not computed (docs/api.md
 * "Events"), on the beam scene (16-voxel light grid):
 *   - after a restart, the volume read back from the data directory for the scene's light
 *     is announced with irradiance.ready, loaded_from_disk true and the key it had, and
 *     no irradiance.progress (nothing is recomputed): the events of the start-up are in
 *     the history, so ?since=0 shows them;
 *   - turning a light back to a pose whose volume is cached gives scene.updated and then
 *     irradiance.ready at once, with no irradiance.progress in between;
 *   - a render (which asks the cache again) publishes nothing: ready is announced once
 *     per pose change.
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "irradiance_util.h"
#include "sse_util.h"

static const char sun_down[] =
    "[{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0, -1, 0]}]";

static void light_key(const struct test_daemon *d, const char *id, char *key)
{
    cJSON *st = irr_status(d, id);
    snprintf(key, 17, "%s", irr_str(irr_light(st, "sun"), "key"));
    cJSON_Delete(st);
}

/* PUT the sun with `light`; expects `status`. */
static void put_sun(const struct test_daemon *d, const char *id, const char *light, long status)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/lights/sun", id);
    struct irr_answer a = irr_http(d, "PUT", path, light);
    CHECK_MSG(a.status == status, "PUT %s: %ld %s", path, a.status, a.body ? a.body : "");
    free(a.body);
}

/* Reads until irradiance.ready; checks it is about id/key with loaded_from_disk `disk`, and
 * counts the irradiance.progress events on the way into *progress. */
static void expect_ready(struct sse_client *c, const char *id, const char *key, bool disk,
                         int *progress)
{
    struct sse_event ev;
    *progress = 0;
    for (;;) {
        bool got = sse_next(c, &ev, 30) == SSE_EVENT;
        CHECK_MSG(got, "no irradiance.ready for %s", key);
        if (!got)
            return;
        if (strcmp(ev.type, "irradiance.progress") == 0)
            (*progress)++;
        if (strcmp(ev.type, "irradiance.ready") == 0)
            break;
    }
    cJSON *data = cJSON_Parse(ev.data);
    CHECK_STR(sse_str(data, "scene"), id);
    CHECK_STR(sse_str(data, "key"), key);
    CHECK(cJSON_IsBool(cJSON_GetObjectItemCaseSensitive(data, "loaded_from_disk")));
    CHECK_INT(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(data, "loaded_from_disk")), disk);
    CHECK(sse_num(data, "compute_ms") > 0);
    cJSON_Delete(data);
}

int main(void)
{
    curl_global_init(CURL_GLOBAL_DEFAULT);
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_events_restart", d.why);
    char id[REFRACT_ID_SIZE] = "", key[17] = "", moved[17] = "";
    char *doc = beam_scene(sun_down);
    CHECK(test_create_scene(&d, doc, id));
    free(doc);
    cJSON_Delete(irr_wait_ready(&d, id, 60));
    light_key(&d, id, key);
    CHECK_INT(test_daemon_stop(&d), 0);

    struct test_daemon again;
    char data_dir[sizeof d.data_dir];
    snprintf(data_dir, sizeof data_dir, "%s", d.data_dir);
    if (!test_daemon_start_in(&again, data_dir, NULL))
        test_setup_failed("test_events_restart", again.why);
    struct sse_client c;
    CHECK(sse_open(&c, &again, "/v1/events?since=0", NULL));
    int progress = 0;
    expect_ready(&c, id, key, true, &progress);
    CHECK_INT(progress, 0);

    /* A new pose is computed; back to the first pose is a hit, announced at once. */
    put_sun(&again, id, "{\"type\": \"directional\", \"direction\": [0.2, -1, 0]}", 202);
    light_key(&again, id, moved);
    expect_ready(&c, id, moved, false, &progress);
    CHECK(progress >= 1);
    put_sun(&again, id, "{\"type\": \"directional\", \"direction\": [0, -1, 0]}", 200);
    struct sse_event ev;
    CHECK_INT(sse_next(&c, &ev, 10), SSE_EVENT);
    CHECK_STR(ev.type, "scene.updated");
    expect_ready(&c, id, key, true, &progress);
    CHECK_INT(progress, 0);

    /* A render asks the cache again: no new event. */
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    struct irr_answer a = irr_http(&again, "POST", path, "{\"format\": \"png\"}");
    CHECK_INT((int)a.status, 200);
    CHECK_STR(a.irradiance, "ready");
    free(a.body);
    CHECK_INT(sse_next(&c, &ev, 0.5), SSE_TIMEOUT);

    sse_close(&c);
    CHECK_INT(test_daemon_stop(&again), 0);
    test_daemon_cleanup(&again);
    test_daemon_cleanup(&d);
    curl_global_cleanup();
    return test_summary("test_events_restart");
}
