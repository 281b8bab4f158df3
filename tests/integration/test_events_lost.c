/*
 * test_events_lost.c - what a Server-Sent Events client that was away for longer than the
 * hub's history gets (docs/api.md "Events"), with --event-history 4 and a scene that
 * needs no light simulation (so each lights PUT publishes exactly one event):
 *   - reconnecting after id L when the ring holds only the newest 4 events gives first
 *     `event: lost` with data {"missed": N} (no id: the client's Last-Event-ID stays the
 *     last event it saw), N = the events after L that left the ring, then exactly the 4
 *     held, with the ids and data the every-event stream had;
 *   - the same on the scene's stream (missed counts every event, the hub keeps no
 *     per-scene history) and with ?since=0;
 *   - an id newer than the newest (the daemon restarted since the client's last event)
 *     gives the history the hub holds, after a comment that says so;
 *   - a reader that is not lost gets no `lost`.
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sse_util.h"

#define HISTORY 4
#define PUTS 7

static const char plain_scene[] =
    "{\"name\": \"plain\", \"objects\": [{\"bounds\": {\"min\": [-0.5, -0.5, -0.5],"
    " \"max\": [0.5, 0.5, 0.5]}, \"resolution\": 8, \"ior\": 1.2}],"
    " \"lights\": [{\"name\": \"key\", \"type\": \"directional\", \"direction\": [0, -1, 0]}]}";

static struct sse_event seen[PUTS + 1];

/* Opens path (after `last`, by header when not NULL), expects `lost` with `missed` (none
 * when missed is 0) and then exactly the events seen[first..PUTS], then nothing. */
static void expect_lost_then(const struct test_daemon *d, const char *path, const char *last,
                             unsigned long long missed, size_t first)
{
    struct sse_client c;
    CHECK_MSG(sse_open(&c, d, path, last), "%s: status %ld", path, c.status);
    struct sse_event ev;
    if (missed > 0) {
        CHECK_INT(sse_next(&c, &ev, 10), SSE_EVENT);
        CHECK_STR(ev.type, "lost");
        CHECK(!ev.has_id);
        cJSON *data = cJSON_Parse(ev.data);
        CHECK_MSG(sse_num(data, "missed") == (double)missed, "%s: lost %s, expected missed %llu",
                  path, ev.data, missed);
        cJSON_Delete(data);
    }
    for (size_t i = first; i <= PUTS; i++) {
        bool got = sse_next(&c, &ev, 10) == SSE_EVENT;
        CHECK_MSG(got, "%s: event %zu missing", path, i);
        if (!got)
            break;
        CHECK_MSG(ev.id == seen[i].id && strcmp(ev.data, seen[i].data) == 0 &&
                      strcmp(ev.type, seen[i].type) == 0,
                  "%s: got %llu %s %s, expected %llu %s %s", path, (unsigned long long)ev.id,
                  ev.type, ev.data, (unsigned long long)seen[i].id, seen[i].type, seen[i].data);
    }
    CHECK_INT(sse_next(&c, &ev, 0.3), SSE_TIMEOUT);
    sse_close(&c);
}

int main(void)
{
    curl_global_init(CURL_GLOBAL_DEFAULT);
    struct test_daemon d;
    const char *args[] = {"--event-history", "4", NULL};
    if (!test_daemon_start(&d, args))
        test_setup_failed("test_events_lost", d.why);
    struct sse_client all;
    CHECK(sse_open(&all, &d, "/v1/events", NULL));
    char id[REFRACT_ID_SIZE] = "";
    CHECK(test_create_scene(&d, plain_scene, id));
    CHECK_INT(sse_next(&all, &seen[0], 10), SSE_EVENT);
    CHECK_STR(seen[0].type, "scene.created");
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/lights/key", id);
    for (int k = 1; k <= PUTS; k++) {
        char light[128];
        snprintf(light, sizeof light, "{\"type\": \"directional\", \"direction\": [0.%d, -1, 0]}",
                 k);
        char *body = NULL;
        CHECK_INT((int)test_request(&d, "PUT", path, light, &body), 200);
        free(body);
        CHECK_INT(sse_next(&all, &seen[k], 10), SSE_EVENT);
        CHECK_STR(seen[k].type, "scene.updated");
        CHECK_MSG(seen[k].id == seen[k - 1].id + 1, "id %llu after %llu",
                  (unsigned long long)seen[k].id, (unsigned long long)seen[k - 1].id);
    }
    /* The ring holds seen[PUTS - 3 .. PUTS]. */
    unsigned long long last = seen[0].id, newest = seen[PUTS].id;
    unsigned long long oldest_held = newest - HISTORY + 1;
    char last_text[32], since_path[160], scene_path[160];
    snprintf(last_text, sizeof last_text, "%llu", last);
    expect_lost_then(&d, "/v1/events", last_text, oldest_held - 1 - last, PUTS - HISTORY + 1);
    snprintf(scene_path, sizeof scene_path, "/v1/scenes/%s/events?since=%llu", id, last);
    expect_lost_then(&d, scene_path, NULL, oldest_held - 1 - last, PUTS - HISTORY + 1);
    expect_lost_then(&d, "/v1/events?since=0", NULL, oldest_held - 1, PUTS - HISTORY + 1);
    /* Not lost: after the oldest held event's predecessor, nothing is missing. */
    snprintf(since_path, sizeof since_path, "/v1/events?since=%llu", oldest_held - 1);
    expect_lost_then(&d, since_path, NULL, 0, PUTS - HISTORY + 1);
    snprintf(since_path, sizeof since_path, "/v1/events?since=%llu", newest - 1);
    expect_lost_then(&d, since_path, NULL, 0, PUTS);

    /* From a previous life of the daemon: its history, after a comment saying so. */
    struct sse_client c;
    CHECK(sse_open(&c, &d, "/v1/events", "1000000"));
    CHECK_CONTAINS(c.last_comment, "restarted");
    sse_close(&c);
    expect_lost_then(&d, "/v1/events", "1000000", oldest_held - 1, PUTS - HISTORY + 1);

    /* The every-event stream kept up: nothing lost, nothing more. */
    struct sse_event ev;
    CHECK_INT(sse_next(&all, &ev, 0.3), SSE_TIMEOUT);
    sse_close(&all);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    curl_global_cleanup();
    return test_summary("test_events_lost");
}
