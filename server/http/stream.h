/*
 * stream.h - long-lived streaming responses (MJPEG frame streams, Server-Sent Events)
 * that sleep while there is nothing to send. Internal to server/http/.
 *
 * DESIGN. libmicrohttpd pulls a streaming body through a content-reader callback. When
 * the producer has nothing to send, the stream suspends its connection
 * (MHD_suspend_connection from inside the reader, which libmicrohttpd allows) instead of
 * returning 0 and being polled again: no busy waiting. Whoever makes something new to send
 * (a frame was encoded, an event was published) calls http_stream_wake from any thread,
 * which resumes the connection; libmicrohttpd then calls the reader again.
 *
 * The lost-wake-up race (a wake between "nothing to send" and the suspend) is closed with a
 * flag under the stream's lock: a wake that finds the stream awake sets `pending`, and the
 * reader that is about to sleep sees it and produces again instead.
 *
 * Lifetime: the stream is reference counted. The connection holds one reference until
 * libmicrohttpd frees the response (the client went away, or the producer ended the
 * stream); every waker that may call http_stream_wake later holds its own
 * (http_stream_retain / http_stream_release). Waking a stream whose connection is gone is
 * a no-op. ops->free(ctx) runs when the last reference goes.
 *
 * Thread: produce runs on an HTTP thread, at most one call at a time per stream;
 * http_stream_wake, retain and release from any thread.
 */
#ifndef REFRACT_HTTP_STREAM_H
#define REFRACT_HTTP_STREAM_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/types.h>

#include "http_internal.h"

#define HTTP_STREAM_END ((ssize_t)-1)   /* the body is complete: close normally */
#define HTTP_STREAM_ERROR ((ssize_t)-2) /* abort the connection */

struct http_stream;

struct http_stream_ops {
    /* Writes up to max (> 0) bytes of body into buf and returns how many; 0 = nothing to
     * send now (the stream sleeps until the next http_stream_wake); HTTP_STREAM_END or
     * HTTP_STREAM_ERROR. May keep a partly sent item in ctx and continue it next call. */
    ssize_t (*produce)(void *ctx, struct http_stream *s, char *buf, size_t max);
    /* Called once, when the last reference goes: free ctx. May be NULL. */
    void (*free)(void *ctx);
    /* > 0: a stream asleep this long is woken (produce is called again, and decides
     * whether to send a keep-alive: a comment for SSE, the newest frame again for MJPEG).
     * One timer thread in stream.c serves every stream. 0 = never.
     * http_stream_set_keepalive changes it per stream. */
    int keepalive_ms;
};

/* Answers req with a streaming body (status 200, unknown length, so the body ends when
 * the connection closes) with the content type and extra headers (name, value, ...,
 * NULL), driven by ops/ctx. On success *out (may be NULL) receives a new reference the
 * caller must release (e.g. after handing it to a waker). When the response cannot be
 * made, ops->free(ctx) runs at once, *out is NULL and a 507 error is answered instead. */
enum MHD_Result http_respond_stream(struct http_request *req, const char *content_type,
                                    const char *const *headers, const struct http_stream_ops *ops,
                                    void *ctx, struct http_stream **out);

void http_stream_wake(struct http_stream *s);
/* Changes the stream's keep-alive period (ops->keepalive_ms) from now on, e.g. to be woken
 * sooner once. The keep-alive thread ticks every 250 ms, so periods are that coarse. */
void http_stream_set_keepalive(struct http_stream *s, int keepalive_ms);
void http_stream_retain(struct http_stream *s);
void http_stream_release(struct http_stream *s);
/* True once the client has gone (the response was freed): wakers may drop the stream. */
bool http_stream_closed(struct http_stream *s);

/* ---- the server's set of streams (server.c owns one) ---- */

/* Every open stream of a server, and the one thread that wakes sleeping streams for their
 * keep-alive (it ticks every 250 ms while there are streams, and sleeps otherwise). */
struct http_stream_set;
struct http_stream_set *http_stream_set_create(struct err *e);
/* Ends every open stream: each one's next produce is replaced by HTTP_STREAM_END, and
 * sleeping ones are woken for it; streams opened afterwards end at once. For shutdown,
 * before libmicrohttpd is stopped (it must not be stopped with suspended connections). */
void http_stream_set_end_all(struct http_stream_set *set);
/* Stops the thread and drops the set's references. After MHD_stop_daemon. */
void http_stream_set_destroy(struct http_stream_set *set);
/* Open streams (not yet closed). */
size_t http_stream_set_count(struct http_stream_set *set);

#endif
