/*
 * test_events_keepalive.c - an idle Server-Sent Events stream sends the comment
 * `: keep-alive` every 15 s (docs/api.md "Events"), so a client (and refractd) notices a
 * connection that went away; and it sends nothing else: no event while nothing happens.
 * (About 16 s of waiting; nothing else runs meanwhile.)
 */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "sse_util.h"

int main(void)
{
    curl_global_init(CURL_GLOBAL_DEFAULT);
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_events_keepalive", d.why);
    struct sse_client c;
    CHECK(sse_open(&c, &d, "/v1/events", NULL));
    int opening = c.comments;
    double t0 = sse_now();
    struct sse_event ev;
    /* Up to 20 s: the keep-alive thread ticks once a second after the 15 s. */
    while (c.comments == opening && sse_now() - t0 < 20 && !c.ended) {
        CHECK_INT(sse_next(&c, &ev, 0.5), SSE_TIMEOUT);
    }
    double waited = sse_now() - t0;
    CHECK_INT(c.comments, opening + 1);
    CHECK_STR(c.last_comment, "keep-alive");
    CHECK_MSG(waited > 13 && waited < 18, "the keep-alive came after %.1f s", waited);
    printf("keep-alive after %.1f s\n", waited);
    /* The stream is still good afterwards: an event arrives. */
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d,
                            "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, "
                            "1]}, \"resolution\": 4, \"ior\": 1.1}]}",
                            id));
    CHECK_INT(sse_next(&c, &ev, 10), SSE_EVENT);
    CHECK_STR(ev.type, "scene.created");
    sse_close(&c);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    curl_global_cleanup();
    return test_summary("test_events_keepalive");
}
