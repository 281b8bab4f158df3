/*
 * stream.c - streaming responses that suspend their connection while idle (stream.h),
 * and the server's set of them with its keep-alive thread.
 */
#include "stream.h"

#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <time.h>

#include "../core/log.h"

struct http_stream {
    atomic_int refs;
    pthread_mutex_t lock;
    struct MHD_Connection *conn;
    struct http_stream_ops ops;
    void *ctx;
    struct http_stream_set *set;
    /* under lock */
    bool sleeping; /* the reader suspended the connection; a wake resumes it */
    bool pending;  /* a wake came while awake: produce again before sleeping */
    bool closed;   /* libmicrohttpd freed the response: the connection is gone */
    bool ending;   /* http_stream_set_end_all: the next read ends the body */
    int64_t slept_ms;
    int keepalive_ms; /* starts as ops.keepalive_ms */
    /* under set->lock */
    struct http_stream *next;
};

struct http_stream_set {
    pthread_mutex_t lock;
    pthread_cond_t changed;
    struct http_stream *head; /* one reference each */
    size_t open;
    bool ending, stopping;
    pthread_t thread;
};

static int64_t now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

void http_stream_retain(struct http_stream *s)
{
    atomic_fetch_add(&s->refs, 1);
}

void http_stream_release(struct http_stream *s)
{
    if (s == NULL || atomic_fetch_sub(&s->refs, 1) != 1)
        return;
    if (s->ops.free)
        s->ops.free(s->ctx);
    pthread_mutex_destroy(&s->lock);
    free(s);
}

bool http_stream_closed(struct http_stream *s)
{
    pthread_mutex_lock(&s->lock);
    bool closed = s->closed;
    pthread_mutex_unlock(&s->lock);
    return closed;
}

/* Caller holds s->lock. */
static void wake_locked(struct http_stream *s)
{
    if (s->closed)
        return;
    if (s->sleeping) {
        s->sleeping = false;
        MHD_resume_connection(s->conn);
    } else {
        s->pending = true;
    }
}

void http_stream_set_keepalive(struct http_stream *s, int keepalive_ms)
{
    pthread_mutex_lock(&s->lock);
    s->keepalive_ms = keepalive_ms;
    pthread_mutex_unlock(&s->lock);
}

void http_stream_wake(struct http_stream *s)
{
    pthread_mutex_lock(&s->lock);
    wake_locked(s);
    pthread_mutex_unlock(&s->lock);
}

/* libmicrohttpd's content reader. */
static ssize_t stream_read(void *cls, uint64_t pos, char *buf, size_t max)
{
    (void)pos;
    struct http_stream *s = cls;
    pthread_mutex_lock(&s->lock);
    bool ending = s->ending;
    pthread_mutex_unlock(&s->lock);
    if (ending)
        return MHD_CONTENT_READER_END_OF_STREAM;
    ssize_t n = s->ops.produce(s->ctx, s, buf, max);
    if (n == HTTP_STREAM_END)
        return MHD_CONTENT_READER_END_OF_STREAM;
    if (n < 0)
        return MHD_CONTENT_READER_END_WITH_ERROR;
    if (n > 0)
        return n;
    pthread_mutex_lock(&s->lock);
    if (s->pending || s->ending) {
        /* Something arrived between produce and now: libmicrohttpd calls again. */
        s->pending = false;
    } else {
        /* Suspending from inside the reader is allowed (microhttpd.h); a wake on any
         * thread resumes, and libmicrohttpd then calls this reader again. */
        s->sleeping = true;
        s->slept_ms = now_ms();
        MHD_suspend_connection(s->conn);
    }
    pthread_mutex_unlock(&s->lock);
    return 0;
}

/* libmicrohttpd is done with the response: the connection has gone. */
static void stream_response_freed(void *cls)
{
    struct http_stream *s = cls;
    pthread_mutex_lock(&s->lock);
    s->closed = true;
    s->sleeping = false;
    pthread_mutex_unlock(&s->lock);
    struct http_stream_set *set = s->set;
    pthread_mutex_lock(&set->lock);
    set->open--;
    pthread_mutex_unlock(&set->lock);
    http_stream_release(s);
}

enum MHD_Result http_respond_stream(struct http_request *req, const char *content_type,
                                    const char *const *headers, const struct http_stream_ops *ops,
                                    void *ctx, struct http_stream **out)
{
    if (out)
        *out = NULL;
    struct http_stream_set *set = http_server_streams(req->server);
    struct http_stream *s = calloc(1, sizeof *s);
    if (s == NULL) {
        if (ops->free)
            ops->free(ctx);
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory opening a stream");
    }
    /* References: the response's (released when libmicrohttpd frees it), the set's, and
     * the caller's (when asked for). */
    atomic_init(&s->refs, 2 + (out != NULL));
    pthread_mutex_init(&s->lock, NULL);
    s->conn = req->conn;
    s->ops = *ops;
    s->keepalive_ms = ops->keepalive_ms;
    s->ctx = ctx;
    s->set = set;
    struct MHD_Response *resp = MHD_create_response_from_callback(
        MHD_SIZE_UNKNOWN, 64 * 1024, stream_read, s, stream_response_freed);
    if (resp == NULL) {
        s->ops.free = NULL;
        free(s);
        if (ops->free)
            ops->free(ctx);
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory opening a stream");
    }
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, content_type);
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CACHE_CONTROL, "no-store");
    http_response_common_headers(resp);
    for (size_t i = 0; headers && headers[i] && headers[i + 1]; i += 2)
        MHD_add_response_header(resp, headers[i], headers[i + 1]);

    pthread_mutex_lock(&set->lock);
    s->next = set->head;
    set->head = s;
    set->open++;
    s->ending = set->ending;
    pthread_cond_signal(&set->changed);
    pthread_mutex_unlock(&set->lock);

    enum MHD_Result r = MHD_queue_response(req->conn, MHD_HTTP_OK, resp);
    req->status = MHD_HTTP_OK;
    /* On failure libmicrohttpd frees the response (and calls stream_response_freed) when
     * the connection closes; the set drops its reference on its next pass. */
    MHD_destroy_response(resp);
    req->phase = HTTP_PHASE_ANSWERED;
    if (out)
        *out = s;
    return r;
}

/* ---- the set and its keep-alive thread ---------------------------------------------- */

/* Drops closed streams, wakes sleepers whose keep-alive is due. Caller holds set->lock. */
static void set_pass_locked(struct http_stream_set *set)
{
    int64_t now = now_ms();
    struct http_stream **link = &set->head;
    while (*link) {
        struct http_stream *s = *link;
        pthread_mutex_lock(&s->lock);
        bool closed = s->closed;
        if (!closed && s->sleeping && s->keepalive_ms > 0 && now - s->slept_ms >= s->keepalive_ms)
            wake_locked(s);
        pthread_mutex_unlock(&s->lock);
        if (closed) {
            *link = s->next;
            http_stream_release(s);
        } else {
            link = &s->next;
        }
    }
}

static void *set_thread(void *arg)
{
    struct http_stream_set *set = arg;
    pthread_mutex_lock(&set->lock);
    while (!set->stopping) {
        set_pass_locked(set);
        if (set->head == NULL) {
            pthread_cond_wait(&set->changed, &set->lock);
        } else {
            struct timespec ts;
            clock_gettime(CLOCK_REALTIME, &ts);
            ts.tv_nsec += 250 * 1000 * 1000;
            if (ts.tv_nsec >= 1000 * 1000 * 1000) {
                ts.tv_sec += 1;
                ts.tv_nsec -= 1000 * 1000 * 1000;
            }
            pthread_cond_timedwait(&set->changed, &set->lock, &ts);
        }
    }
    pthread_mutex_unlock(&set->lock);
    return NULL;
}

struct http_stream_set *http_stream_set_create(struct err *e)
{
    struct http_stream_set *set = calloc(1, sizeof *set);
    if (set == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the stream set");
        return NULL;
    }
    pthread_mutex_init(&set->lock, NULL);
    pthread_cond_init(&set->changed, NULL);
    if (pthread_create(&set->thread, NULL, set_thread, set) != 0) {
        pthread_cond_destroy(&set->changed);
        pthread_mutex_destroy(&set->lock);
        free(set);
        err_set(e, REFRACT_E_INTERNAL, "cannot start the stream keep-alive thread");
        return NULL;
    }
    return set;
}

void http_stream_set_end_all(struct http_stream_set *set)
{
    pthread_mutex_lock(&set->lock);
    set->ending = true;
    for (struct http_stream *s = set->head; s; s = s->next) {
        pthread_mutex_lock(&s->lock);
        s->ending = true;
        wake_locked(s);
        pthread_mutex_unlock(&s->lock);
    }
    pthread_mutex_unlock(&set->lock);
}

size_t http_stream_set_count(struct http_stream_set *set)
{
    pthread_mutex_lock(&set->lock);
    size_t n = set->open;
    pthread_mutex_unlock(&set->lock);
    return n;
}

void http_stream_set_destroy(struct http_stream_set *set)
{
    if (set == NULL)
        return;
    pthread_mutex_lock(&set->lock);
    set->stopping = true;
    pthread_cond_signal(&set->changed);
    pthread_mutex_unlock(&set->lock);
    pthread_join(set->thread, NULL);
    struct http_stream *s = set->head;
    while (s) {
        struct http_stream *next = s->next;
        if (!http_stream_closed(s))
            log_warn("http", "a stream was still open when the server stopped");
        http_stream_release(s);
        s = next;
    }
    pthread_cond_destroy(&set->changed);
    pthread_mutex_destroy(&set->lock);
    free(set);
}
