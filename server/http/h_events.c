/*
 * h_events.c - Server-Sent Events: GET /v1/events and GET /v1/scenes/{id}/events
 * (docs/api.md "Events", docs/views.md), and http_publish_scene, the one place the
 * handlers publish scene.created / scene.updated / scene.deleted from.
 *
 * DESIGN. An SSE stream is a streaming response (stream.h) whose producer reads the event
 * hub (events.h) from a cursor: the id of the last event it has seen. It holds at most one
 * batch of SSE_BATCH events at a time and reads the next batch only once the last one has
 * been written to the connection, so a slow client holds nothing but its cursor
 * (backpressure by cursor); a client that falls behind the hub's ring learns how many
 * events it missed (`event: lost`). While there is nothing to send the connection is
 * suspended. One hub listener per server (struct http_sse) keeps the list of open streams,
 * each with a reference, and wakes those an event is about; it drops closed streams as it
 * goes. No polling: the only timer is the keep-alive of stream.c.
 *
 * Resume: `Last-Event-ID` (what EventSource sends when it reconnects) wins over `?since=`
 * (a URL the client wrote), since the header is the newer of the two. An id newer than the
 * newest event means the daemon restarted (ids begin again at 1): the stream then sends
 * the whole history the hub still holds.
 *
 * Thread: handlers and produce on HTTP threads, the listener on publishing threads.
 */
#include <errno.h>
#include <inttypes.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/log.h"
#include "../events/events.h"
#include "http_internal.h"
#include "stream.h"

#define SSE_BATCH 16           /* events a stream holds at most */
#define SSE_KEEPALIVE_MS 15000 /* docs/views.md: a comment every 15 s */
#define SSE_ITEM_MAX (EVENT_DATA_MAX + 256)

/* ---- one stream --------------------------------------------------------------------- */

struct sse_stream {
    struct event_hub *hub;
    char scene[EVENT_SCENE_MAX]; /* "" = every event */
    uint64_t cursor;             /* the hub's id of the last event read or skipped */
    struct event batch[SSE_BATCH];
    size_t batch_len, batch_next;
    char item[SSE_ITEM_MAX]; /* the text being written: one event, or a comment */
    size_t item_len, item_sent;
    bool ending;           /* the scene was deleted: end once the item is written */
    int64_t last_write_ms; /* gpu_now_ms() of the last bytes produced */
};

static void item_set(struct sse_stream *st, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

static void item_set(struct sse_stream *st, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(st->item, sizeof st->item, fmt, ap);
    va_end(ap);
    st->item_len = n < 0 ? 0 : (size_t)n < sizeof st->item ? (size_t)n : sizeof st->item - 1;
    st->item_sent = 0;
}

/* An event as SSE lines. The data is one JSON object; a line break in it can only be
 * whitespace between tokens (JSON strings escape theirs), so it becomes a space and the
 * event keeps one `data:` line. */
static void item_event(struct sse_stream *st, const struct event *ev)
{
    item_set(st, "id: %" PRIu64 "\nevent: %s\ndata: ", ev->id, ev->type);
    size_t n = st->item_len;
    for (const char *p = ev->data; *p && n + 3 < sizeof st->item; p++)
        st->item[n++] = *p == '\n' || *p == '\r' ? ' ' : *p;
    memcpy(st->item + n, "\n\n", 3);
    st->item_len = n + 2;
}

/* The next event (or `lost`) into st->item; false when there is nothing new. */
static bool next_event_item(struct sse_stream *st)
{
    if (st->batch_next == st->batch_len) {
        uint64_t lost = 0;
        st->batch_len = event_read(st->hub, st->cursor, st->scene[0] ? st->scene : NULL, false,
                                   st->batch, SSE_BATCH, &lost, &st->cursor);
        st->batch_next = 0;
        if (lost > 0) {
            /* No id: the client's Last-Event-ID stays the last event it really saw. */
            item_set(st, "event: lost\ndata: {\"missed\":%" PRIu64 "}\n\n", lost);
            return true;
        }
        if (st->batch_len == 0)
            return false;
    }
    const struct event *ev = &st->batch[st->batch_next++];
    item_event(st, ev);
    if (st->scene[0] && strcmp(ev->type, EVENT_SCENE_DELETED) == 0) {
        st->ending = true; /* the scene's stream ends with its deletion */
        st->batch_next = st->batch_len;
    }
    return true;
}

static ssize_t sse_produce(void *ctx, struct http_stream *s, char *buf, size_t max)
{
    (void)s;
    struct sse_stream *st = ctx;
    int64_t now = gpu_now_ms();
    size_t used = 0;
    while (used < max) {
        if (st->item_sent < st->item_len) {
            size_t n = st->item_len - st->item_sent;
            n = n < max - used ? n : max - used;
            memcpy(buf + used, st->item + st->item_sent, n);
            st->item_sent += n;
            used += n;
            continue;
        }
        if (st->ending)
            break;
        if (next_event_item(st))
            continue;
        /* Nothing new: woken by the keep-alive timer (asleep SSE_KEEPALIVE_MS; the
         * margin allows for its one-second tick) or by the wake that follows the opening,
         * and only the first sends the comment. */
        if (used == 0 && now - st->last_write_ms >= SSE_KEEPALIVE_MS * 9 / 10) {
            item_set(st, ": keep-alive\n\n");
            continue;
        }
        break;
    }
    if (used > 0)
        st->last_write_ms = now;
    else if (st->ending)
        return HTTP_STREAM_END;
    return (ssize_t)used;
}

static void sse_free(void *ctx)
{
    free(ctx);
}

static const struct http_stream_ops sse_ops = {
    .produce = sse_produce,
    .free = sse_free,
    .keepalive_ms = SSE_KEEPALIVE_MS,
};

/* ---- the server's streams and its one hub listener ---------------------------------- */

struct sse_entry {
    struct http_stream *stream;  /* a reference */
    char scene[EVENT_SCENE_MAX]; /* "" = every event */
};

struct http_sse {
    struct event_hub *hub; /* borrowed; NULL = no events */
    int listener;          /* event_listen token; 0 = none */
    pthread_mutex_t lock;  /* guards list, count, cap */
    struct sse_entry *list;
    size_t count, cap;
};

/* Drops the closed streams (their connections are gone). Called with the lock held. */
static void sweep_locked(struct http_sse *sse)
{
    size_t j = 0;
    for (size_t i = 0; i < sse->count; i++) {
        if (http_stream_closed(sse->list[i].stream)) {
            http_stream_release(sse->list[i].stream);
            continue;
        }
        sse->list[j++] = sse->list[i];
    }
    sse->count = j;
}

/* The hub's listener (publishing thread, quick, never blocks on more than the list). */
static void on_event(void *ctx, const struct event *ev)
{
    struct http_sse *sse = ctx;
    pthread_mutex_lock(&sse->lock);
    sweep_locked(sse);
    for (size_t i = 0; i < sse->count; i++) {
        const struct sse_entry *en = &sse->list[i];
        if (en->scene[0] == '\0' || strcmp(en->scene, ev->scene) == 0)
            http_stream_wake(en->stream);
    }
    pthread_mutex_unlock(&sse->lock);
}

struct http_sse *http_sse_create(struct event_hub *hub, struct err *e)
{
    struct http_sse *sse = calloc(1, sizeof *sse);
    if (sse == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the event streams");
        return NULL;
    }
    pthread_mutex_init(&sse->lock, NULL);
    sse->hub = hub;
    if (hub) {
        sse->listener = event_listen(hub, on_event, sse);
        if (sse->listener == 0) {
            err_set(e, REFRACT_E_INTERNAL,
                    "the event hub's listener table is full; the HTTP server cannot follow "
                    "events (a bug: report it)");
            http_sse_destroy(sse);
            return NULL;
        }
    }
    return sse;
}

void http_sse_destroy(struct http_sse *sse)
{
    if (sse == NULL)
        return;
    if (sse->listener)
        event_unlisten(sse->hub, sse->listener); /* on_event no longer runs after this */
    for (size_t i = 0; i < sse->count; i++)
        http_stream_release(sse->list[i].stream);
    free(sse->list);
    pthread_mutex_destroy(&sse->lock);
    free(sse);
}

/* Adds a stream (consuming the reference s). False when out of memory. */
static bool sse_add(struct http_sse *sse, struct http_stream *s, const char *scene)
{
    pthread_mutex_lock(&sse->lock);
    sweep_locked(sse);
    if (sse->count == sse->cap) {
        size_t cap = sse->cap ? sse->cap * 2 : 16;
        struct sse_entry *grown = realloc(sse->list, cap * sizeof *grown);
        if (grown == NULL) {
            pthread_mutex_unlock(&sse->lock);
            return false;
        }
        sse->list = grown;
        sse->cap = cap;
    }
    struct sse_entry *en = &sse->list[sse->count++];
    en->stream = s;
    snprintf(en->scene, sizeof en->scene, "%s", scene ? scene : "");
    pthread_mutex_unlock(&sse->lock);
    return true;
}

/* ---- the handlers ------------------------------------------------------------------- */

/* A decimal event id (no sign, no blanks, fits 64 bits). */
static bool parse_event_id(const char *text, uint64_t *out)
{
    if (text == NULL || text[0] < '0' || text[0] > '9')
        return false;
    errno = 0;
    char *end = NULL;
    unsigned long long v = strtoull(text, &end, 10);
    if (errno != 0 || *end != '\0')
        return false;
    *out = (uint64_t)v;
    return true;
}

/* Where the client wants to resume: *has false when it did not say. Answers 400 and returns
 * false for an id that is not a number. */
static bool resume_point(struct http_request *req, uint64_t *since, bool *has,
                         enum MHD_Result *answer)
{
    static const char *const allowed[] = {"since", NULL};
    const char *unknown = http_query_unknown(req, allowed);
    if (unknown) {
        *answer = http_respond_error(req, REFRACT_E_UNKNOWN_FIELD,
                                     "query parameter \"%.64s\" is not known here; allowed: since",
                                     unknown);
        return false;
    }
    const char *header = MHD_lookup_connection_value(req->conn, MHD_HEADER_KIND, "Last-Event-ID");
    const char *query = NULL;
    size_t query_len = 0;
    bool has_query = MHD_lookup_connection_value_n(req->conn, MHD_GET_ARGUMENT_KIND, "since", 5,
                                                   &query, &query_len) == MHD_YES;
    if (has_query && query == NULL)
        query = ""; /* "?since" without a value */
    *has = header != NULL || has_query;
    if (header) {
        if (parse_event_id(header, since))
            return true;
        *answer = http_respond_error(req, REFRACT_E_INVALID_FIELD,
                                     "Last-Event-ID: \"%.64s\" is not an event id; send the "
                                     "number of the last `id:` line received (a whole number "
                                     ">= 0), or leave the header out",
                                     header);
        return false;
    }
    if (query == NULL || parse_event_id(query, since))
        return true;
    *answer = http_respond_error(req, REFRACT_E_INVALID_FIELD,
                                 "since: \"%.64s\" is not an event id; give the number of the "
                                 "last `id:` line received (a whole number >= 0, e.g. "
                                 "?since=42), or leave it out to begin with the next event",
                                 query);
    return false;
}

/* Answers with the stream of `scene`'s events (NULL: every event). */
static enum MHD_Result open_stream(struct http_request *req, const char *scene)
{
    struct event_hub *hub = req->app->events;
    if (hub == NULL || req->sse == NULL)
        return http_respond_error(req, REFRACT_E_INTERNAL,
                                  "this refractd was started without an event hub (a bug: "
                                  "report it)");
    uint64_t since = 0;
    bool has_since = false;
    enum MHD_Result answer = MHD_NO;
    if (!resume_point(req, &since, &has_since, &answer))
        return answer;
    struct sse_stream *st = calloc(1, sizeof *st);
    if (st == NULL)
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY,
                                  "out of memory opening an event stream");
    uint64_t newest = event_last_id(hub);
    st->hub = hub;
    snprintf(st->scene, sizeof st->scene, "%s", scene ? scene : "");
    st->cursor = has_since ? since : newest;
    st->last_write_ms = gpu_now_ms();
    /* A first comment, so the client sees the stream open before the first event. */
    if (has_since && since > newest) {
        st->cursor = 0;
        item_set(st,
                 ": event %" PRIu64 " is newer than this refractd's newest (%" PRIu64
                 "): it restarted; here is the history it holds\n\n",
                 since, newest);
    } else {
        item_set(st, ": events of %s%s after id %" PRIu64 "\n\n", scene ? "scene " : "refractd",
                 scene ? scene : "", st->cursor);
    }
    /* stream.c sends Cache-Control: no-store; a proxy must not buffer the events. */
    static const char *const headers[] = {"X-Accel-Buffering", "no", NULL};
    struct http_stream *s = NULL;
    enum MHD_Result r = http_respond_stream(req, "text/event-stream", headers, &sse_ops, st, &s);
    if (s == NULL)
        return r;
    http_stream_retain(s); /* one reference for the list, ours released below */
    if (!sse_add(req->sse, s, scene)) {
        http_stream_release(s);
        log_warn("http", "out of memory listing an event stream; it is woken only by its "
                         "keep-alive");
    }
    /* The producer may have gone to sleep before the stream was listed. */
    http_stream_wake(s);
    http_stream_release(s);
    return r;
}

enum MHD_Result http_handle_events(struct http_request *req)
{
    return open_stream(req, NULL);
}

enum MHD_Result http_handle_scene_events(struct http_request *req)
{
    enum MHD_Result answer = MHD_NO;
    struct store_scene *v = http_scene_or_404(req, &answer);
    if (v == NULL)
        return answer;
    store_scene_release(v);
    return open_stream(req, req->params[0]);
}

/* ---- publishing --------------------------------------------------------------------- */

void http_publish_scene(const struct http_app *app, const char *type, const char *scene_id,
                        const struct store_scene *version, const char *what)
{
    if (app->events == NULL)
        return;
    cJSON *data = cJSON_CreateObject();
    if (data == NULL)
        return;
    cJSON_AddStringToObject(data, "scene", scene_id);
    if (version)
        cJSON_AddNumberToObject(data, "generation", (double)version->generation);
    if (what)
        cJSON_AddStringToObject(data, "what", what);
    event_publish_json(app->events, scene_id, type, data);
}
