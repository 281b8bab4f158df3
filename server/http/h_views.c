/*
 * h_views.c - the view session resource (docs/views.md): POST /v1/scenes/{id}/views,
 * GET /v1/views, GET/PATCH/DELETE /v1/views/{vid}, and GET /v1/views/{vid}/stream, the
 * MJPEG frame stream (multipart/x-mixed-replace; boundary=refract-frame).
 *
 * The sessions themselves (scheduling, rendering, encoding) live in server/view/; this
 * file validates bodies (view_request.c), answers with view status objects, and adapts a
 * session's newest frame to a streaming response (stream.h).
 *
 * A frame stream holds at most one frame: the one it is sending. Between frames it asks
 * the session for its newest frame; when that is the one it sent last, it sleeps (its
 * connection suspended) until the session wakes it (a new frame, or the end), or until the
 * keep-alive period passed, when it sends the same frame again. A slow client therefore
 * skips frames instead of queueing them.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stream.h"

#define FRAME_BOUNDARY "refract-frame"
#define FRAME_KEEPALIVE_MS 15000 /* docs/views.md: the newest frame again after 15 s */
/* docs/views.md: once a stream has gone quiet after a new frame, that frame is sent once
 * more after about a second. Chromium shows a part of a multipart <img> only when the
 * headers of the part after it arrive, so without the repeat a plain <img> would show
 * each change only with the next one (or the keep-alive). */
#define FRAME_REPEAT_MS 1000

/* Answers 404 naming the id, for a session that does not exist (any more). */
static enum MHD_Result view_not_found(struct http_request *req, const char *id)
{
    return http_respond_error(
        req, REFRACT_E_NOT_FOUND,
        "no view session \"%s\": it was ended (DELETE), expired after %g s without a request or "
        "a stream (refractd --view-idle-timeout), its scene was deleted, or it never existed; "
        "GET /v1/views lists the open ones, POST /v1/scenes/{id}/views opens one",
        id, view_registry_settings(req->app->views)->idle_timeout_s);
}

/* The session named by the first path parameter as a new reference, or NULL after
 * answering 404. */
static struct view_session *view_or_404(struct http_request *req, enum MHD_Result *answer)
{
    struct view_session *s = view_session_find(req->app->views, req->params[0]);
    if (s == NULL)
        *answer = view_not_found(req, req->params[0]);
    return s;
}

/* The status of s, resolving its quality preset with the scene's current settings. */
static cJSON *status_json(struct http_request *req, struct view_session *s)
{
    struct store_scene *v = store_scene_get(req->app->store, view_session_scene(s));
    cJSON *o = view_session_status_json(s, v ? v->scene : NULL);
    store_scene_release(v);
    return o;
}

static enum MHD_Result answer_status(struct http_request *req, unsigned status,
                                     struct view_session *s)
{
    cJSON *o = status_json(req, s);
    view_session_release(s);
    if (o == NULL)
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory");
    return http_respond_json(req, status, o);
}

enum MHD_Result http_handle_view_create(struct http_request *req)
{
    enum MHD_Result answer = MHD_NO;
    struct store_scene *v = http_scene_or_404(req, &answer);
    if (v == NULL)
        return answer;
    struct view_settings defaults, st;
    view_settings_defaults(v->scene, &defaults);
    struct err e = {0};
    struct view_session *s = NULL;
    enum refract_code rc =
        http_parse_view_settings(req->body, req->body_len, v->scene, req->cfg, &defaults, &st, &e);
    if (rc == REFRACT_E_OK)
        rc = view_session_open(req->app->views, v, &st, &s, &e);
    store_scene_release(v);
    if (rc != REFRACT_E_OK)
        return http_respond_err(req, &e);
    return answer_status(req, MHD_HTTP_CREATED, s);
}

enum MHD_Result http_handle_view_list(struct http_request *req)
{
    struct view_session **list = NULL;
    size_t n = view_session_list(req->app->views, &list);
    cJSON *root = cJSON_CreateObject();
    cJSON *arr = cJSON_AddArrayToObject(root, "views");
    for (size_t i = 0; i < n; i++)
        cJSON_AddItemToArray(arr, status_json(req, list[i]));
    view_session_list_free(list, n);
    return http_respond_json(req, MHD_HTTP_OK, root);
}

enum MHD_Result http_handle_view_get(struct http_request *req)
{
    enum MHD_Result answer = MHD_NO;
    struct view_session *s = view_or_404(req, &answer);
    if (s == NULL)
        return answer;
    return answer_status(req, MHD_HTTP_OK, s);
}

enum MHD_Result http_handle_view_patch(struct http_request *req)
{
    enum MHD_Result answer = MHD_NO;
    struct view_session *s = view_or_404(req, &answer);
    if (s == NULL)
        return answer;
    struct store_scene *v = store_scene_get(req->app->store, view_session_scene(s));
    if (v == NULL) {
        enum MHD_Result r = http_respond_error(
            req, REFRACT_E_SCENE_NOT_FOUND,
            "view session %s: its scene \"%s\" no longer exists; the session is ending",
            view_session_id(s), view_session_scene(s));
        view_session_release(s);
        return r;
    }
    struct view_settings current, st;
    view_session_settings(s, &current);
    struct err e = {0};
    enum refract_code rc =
        http_parse_view_settings(req->body, req->body_len, v->scene, req->cfg, &current, &st, &e);
    store_scene_release(v);
    if (rc != REFRACT_E_OK) {
        view_session_release(s);
        return http_respond_err(req, &e);
    }
    view_session_update(s, &st);
    return answer_status(req, MHD_HTTP_OK, s);
}

enum MHD_Result http_handle_view_delete(struct http_request *req)
{
    if (!view_session_end(req->app->views, req->params[0]))
        return view_not_found(req, req->params[0]);
    return http_respond_empty(req, MHD_HTTP_NO_CONTENT);
}

/* ---- the frame stream ------------------------------------------------------------------ */

struct frame_stream {
    struct view_session *session; /* owned reference */
    struct view_watcher watcher;
    bool watching;
    struct http_stream *stream; /* borrowed: valid until frame_stream_free */
    /* The part being sent: its headers (the first part opens with the boundary line),
     * then the JPEG, then the next boundary line at once. Sending the delimiter right
     * after the image, not with the next frame, matters: a browser shows a part of an
     * <img>'s multipart/x-mixed-replace stream only once it sees the delimiter after it,
     * and with on-change streams the next frame may be long in coming. */
    struct view_frame *sending; /* owned reference, or NULL between parts */
    char head[320];
    const char *trailer; /* "\r\n--" FRAME_BOUNDARY "\r\n", or the closing delimiter */
    size_t head_len, trailer_len, offset;
    bool opened; /* the opening boundary line has been sent */
    uint64_t sent_seq;
    int64_t sent_ms;
    bool sending_repeat;   /* the part being sent repeats the last one */
    bool repeat_due;       /* a new frame went and has not been repeated yet */
    long long frames_left; /* ?frames=N: the parts still to send; -1 = no end */
};

static void frame_stream_wake(void *ctx)
{
    struct frame_stream *fs = ctx;
    http_stream_wake(fs->stream);
}

static void frame_stream_free(void *ctx)
{
    struct frame_stream *fs = ctx;
    if (fs->watching)
        view_session_unwatch(fs->session, &fs->watcher);
    view_frame_release(fs->sending);
    view_session_release(fs->session);
    free(fs);
}

static void part_begin(struct frame_stream *fs, struct view_frame *f)
{
    fs->sending_repeat = f->seq == fs->sent_seq;
    int n = snprintf(fs->head, sizeof fs->head,
                     "%sContent-Type: image/jpeg\r\nContent-Length: %zu\r\n"
                     "X-Frame-Seq: %llu\r\nX-Frame-Kind: %s\r\nX-Render-Time-Ms: %.3f\r\n"
                     "X-Refract-Irradiance: %s\r\n%s\r\n",
                     fs->opened ? "" : "--" FRAME_BOUNDARY "\r\n", f->len,
                     (unsigned long long)f->seq, view_frame_kind_name(f->kind), f->render_ms,
                     f->irradiance, fs->sending_repeat ? "X-Frame-Repeat: 1\r\n" : "");
    fs->head_len = n > 0 && (size_t)n < sizeof fs->head ? (size_t)n : 0;
    fs->opened = true;
    /* The last part of a ?frames=N stream ends with the closing delimiter. */
    fs->trailer =
        fs->frames_left == 1 ? "\r\n--" FRAME_BOUNDARY "--\r\n" : "\r\n--" FRAME_BOUNDARY "\r\n";
    fs->trailer_len = strlen(fs->trailer);
    fs->offset = 0;
    fs->sending = f;
}

/* Copies what fits of the part being sent; finishes the part when all of it went. */
static size_t part_copy(struct frame_stream *fs, char *buf, size_t max)
{
    const struct view_frame *f = fs->sending;
    size_t total = fs->head_len + f->len + fs->trailer_len, n = 0;
    while (n < max && fs->offset < total) {
        size_t at = fs->offset, chunk;
        const char *src;
        if (at < fs->head_len) {
            src = fs->head + at;
            chunk = fs->head_len - at;
        } else if (at < fs->head_len + f->len) {
            src = (const char *)f->jpeg + (at - fs->head_len);
            chunk = f->len - (at - fs->head_len);
        } else {
            src = fs->trailer + (at - fs->head_len - f->len);
            chunk = total - at;
        }
        if (chunk > max - n)
            chunk = max - n;
        memcpy(buf + n, src, chunk);
        n += chunk;
        fs->offset += chunk;
    }
    if (fs->offset == total) {
        if (fs->frames_left > 0)
            fs->frames_left--;
        fs->sent_seq = f->seq;
        fs->sent_ms = gpu_now_ms();
        /* Streams with an end (?frames=N) are for programs: no repeats there. */
        fs->repeat_due = !fs->sending_repeat && fs->frames_left < 0;
        view_frame_release(fs->sending);
        fs->sending = NULL;
    }
    return n;
}

static ssize_t frame_stream_produce(void *ctx, struct http_stream *s, char *buf, size_t max)
{
    struct frame_stream *fs = ctx;
    if (fs->sending == NULL) {
        if (fs->frames_left == 0)
            return HTTP_STREAM_END; /* ?frames=N sent */
        bool ended = false;
        struct view_frame *f = view_session_frame(fs->session, &ended);
        /* Woken by the keep-alive timer (it sleeps the stream's keep-alive period before
         * waking us; the margins absorb its 250 ms tick). */
        int64_t quiet_ms = gpu_now_ms() - fs->sent_ms;
        bool keepalive = quiet_ms >= FRAME_KEEPALIVE_MS - 500;
        bool repeat = fs->repeat_due && quiet_ms >= FRAME_REPEAT_MS - 300;
        if (ended || f == NULL || (f->seq == fs->sent_seq && !keepalive && !repeat)) {
            view_frame_release(f);
            http_stream_set_keepalive(s, fs->repeat_due ? FRAME_REPEAT_MS : FRAME_KEEPALIVE_MS);
            return ended ? HTTP_STREAM_END : 0;
        }
        part_begin(fs, f);
    }
    return (ssize_t)part_copy(fs, buf, max);
}

/* ?frames=N (1..1000000): the stream ends after N frames (a snapshot, a test); absent:
 * it runs until the session ends or the client leaves. Answers and returns false when the
 * query is wrong. */
static bool parse_stream_query(struct http_request *req, long long *frames)
{
    static const char *const allowed[] = {"frames", NULL};
    const char *unknown = http_query_unknown(req, allowed);
    if (unknown) {
        http_respond_error(req, REFRACT_E_UNKNOWN_FIELD,
                           "query parameter \"%s\" is not known here; allowed: frames", unknown);
        return false;
    }
    const char *text = MHD_lookup_connection_value(req->conn, MHD_GET_ARGUMENT_KIND, "frames");
    *frames = -1;
    if (text == NULL)
        return true;
    char *end = NULL;
    long long n = strtoll(text, &end, 10);
    if (end == text || *end != '\0' || n < 1 || n > 1000000) {
        http_respond_error(req, REFRACT_E_INVALID_FIELD,
                           "query parameter frames: expected an integer in 1..1000000 (the "
                           "frames to send before the stream ends), got \"%s\"",
                           text);
        return false;
    }
    *frames = n;
    return true;
}

enum MHD_Result http_handle_view_stream(struct http_request *req)
{
    long long frames = -1;
    if (!parse_stream_query(req, &frames))
        return MHD_YES;
    enum MHD_Result answer = MHD_NO;
    struct view_session *s = view_or_404(req, &answer);
    if (s == NULL)
        return answer;
    struct frame_stream *fs = calloc(1, sizeof *fs);
    if (fs == NULL) {
        view_session_release(s);
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory opening a stream");
    }
    fs->session = s;
    fs->frames_left = frames;
    static const struct http_stream_ops ops = {.produce = frame_stream_produce,
                                               .free = frame_stream_free,
                                               .keepalive_ms = FRAME_KEEPALIVE_MS};
    struct http_stream *stream = NULL;
    answer = http_respond_stream(req, "multipart/x-mixed-replace; boundary=" FRAME_BOUNDARY, NULL,
                                 &ops, fs, &stream);
    if (stream == NULL)
        return answer; /* fs was freed */
    /* Our reference keeps fs alive while it starts watching; a frame that became the
     * newest before the watch began is sent by the wake below. */
    fs->stream = stream;
    fs->watcher = (struct view_watcher){.wake = frame_stream_wake, .ctx = fs};
    fs->watching = view_session_watch(s, &fs->watcher);
    http_stream_wake(stream);
    http_stream_release(stream);
    return answer;
}
