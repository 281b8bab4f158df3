/*
 * refract_events.c - refract_events(): refractd's Server-Sent Events (GET /v1/events,
 * GET /v1/scenes/{id}/events) read as events. The transport is refract_stream.c's
 * streaming GET; the bytes go through the SSE parser (sse_parse.c).
 *
 * Resuming: since_id goes out as Last-Event-ID, the header a browser's EventSource sends
 * when it reconnects, so refractd treats both the same way.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "refract_internal.h"
#include "refract_url.h"
#include "sse_parse.h"

struct event_reader {
    struct refract_sse parser;
    refract_event_fn fn;
    void *user;
};

static bool on_event(void *user, const struct refract_sse_event *ev)
{
    struct event_reader *r = user;
    struct refract_event out = {
        .id = ev->id, .type = ev->type, .data = ev->data, .data_len = ev->data_len};

    return r->fn(&out, r->user) == 0;
}

static int events_chunk(void *user, const char *data, size_t len, double now_ms, char *why,
                        size_t why_size)
{
    struct event_reader *r = user;
    enum refract_sse_result result = refract_sse_feed(&r->parser, data, len, on_event, r);

    (void)now_ms;
    if (result == REFRACT_SSE_ERROR) {
        snprintf(why, why_size, "after %ld events: %s", r->parser.events, r->parser.why);
        return -1;
    }
    return result == REFRACT_SSE_STOPPED ? 1 : 0;
}

/* An event cut off by the end of the stream is dropped, as the standard says: the
 * stream ended cleanly as far as the events delivered go. */
static bool events_end(void *user, char *why, size_t why_size)
{
    (void)why;
    (void)why_size;
    return refract_sse_finish(&((struct event_reader *)user)->parser, NULL) != REFRACT_SSE_ERROR;
}

static long events_delivered(void *user)
{
    return ((struct event_reader *)user)->parser.events;
}

int refract_events(refract_client *c, const char *scene_id, const char *since_id,
                   refract_event_fn fn, void *user)
{
    struct event_reader r = {.fn = fn, .user = user};
    const struct refract_stream_sink sink = {
        .content_type = "text/event-stream",
        .chunk = events_chunk,
        .end = events_end,
        .delivered = events_delivered,
        .item = "event",
        .user = &r,
    };
    char last_id[REFRACT_SSE_ID_MAX + 32];
    const char *headers[3] = {"Accept: text/event-stream", NULL, NULL};
    char *path;
    int code = refract_begin(c, NULL);

    if (code != REFRACT_E_OK)
        return code;
    if (fn == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_events: the event callback is NULL");
    if (scene_id != NULL && scene_id[0] == '\0')
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_events: the scene id is empty (NULL means every scene)");
    if (since_id != NULL) {
        if (since_id[0] == '\0' || strlen(since_id) >= REFRACT_SSE_ID_MAX ||
            strpbrk(since_id, "\r\n") != NULL)
            return refract_fail(c, REFRACT_E_USAGE,
                                "refract_events: since_id must be an event id such as \"42\"");
        snprintf(last_id, sizeof(last_id), "Last-Event-ID: %s", since_id);
        headers[1] = last_id;
    }
    path = scene_id != NULL ? refract_scene_path(scene_id, "/events")
                            : refract_path_printf("/v1/events");
    if (path == NULL)
        return refract_out_of_memory(c, "building the events path");
    refract_sse_init(&r.parser, 0);
    code = refract_stream_get(c, path, headers, &sink);
    refract_sse_fini(&r.parser);
    free(path);
    return code;
}
