/*
 * deadline.h - the total time a request may take to arrive (--header-deadline; docs/api.md
 * "Fair sharing"). --header-timeout closes a connection that stays silent, but a client
 * that sends one header byte every few seconds is never silent for long and would hold
 * its connection forever ("slowloris"). libmicrohttpd has no total deadline for a
 * request's headers, only the idle timeout, so refractd keeps its own: each connection is
 * an entry, armed with a due time when the connection opens (and again after each answer
 * on a kept-alive connection), disarmed once the request's headers and body are in. An
 * upload's body streams to a file and may be large, so it is held to a rate instead
 * (--upload-min-rate, as Apache's mod_reqtimeout MinRate): every byte received moves its
 * due time on by 1/rate seconds, so it must arrive, on average, at least that fast once
 * the deadline's time is spent. A reaper thread closes the connections whose entries are due, with
 * shutdown(SHUT_RDWR) on their socket: libmicrohttpd then sees its client gone and closes
 * the connection itself, through its usual path (the request's completion callback frees
 * what it held, an unfinished body's file included).
 *
 * RACES. The reaper touches a socket only under the lock, and only while its entry is
 * listed. libmicrohttpd calls the connection callback's CLOSED notification, which removes
 * the entry under the same lock, before it closes the socket, so the reaper never shuts
 * down a descriptor that was closed, or reused by another connection since.
 *
 * Thread: any; one mutex guards the list.
 */
#ifndef REFRACT_HTTP_DEADLINE_H
#define REFRACT_HTTP_DEADLINE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"

/* One connection (embedded in the server's connection state). Zeroed before _add. */
struct http_deadline_entry {
    int fd;
    int64_t due_ms;  /* gpu_now_ms() clock; 0 = disarmed */
    int64_t base_ms; /* when the request's time began (opened, or the previous answer) */
    long long bytes; /* upload body bytes received (upload mode) */
    bool upload;     /* due = base + deadline + bytes / min rate */
    const char *ip;  /* the client, for the log (borrowed for the entry's life) */
    struct http_deadline_entry *prev, *next;
    bool listed;
};

struct http_deadlines;

/* The list and its reaper thread, for a deadline of seconds (> 0) and an upload body's
 * minimum rate in bytes per second (0 = none: an upload's entry is disarmed once its
 * headers are in), or NULL with e filled. seconds <= 0 (no deadline) gives NULL with e
 * untouched: every function below takes NULL as "no deadline" and does nothing. */
struct http_deadlines *http_deadlines_create(int seconds, long long min_rate, struct err *e);
/* Stops the reaper and frees the list. Call it after libmicrohttpd has stopped (every
 * entry removed). NULL is a no-op. */
void http_deadlines_destroy(struct http_deadlines *d);

/* A connection opened with socket fd: lists its entry, armed. */
void http_deadlines_add(struct http_deadlines *d, struct http_deadline_entry *en, int fd,
                        const char *ip);
/* Arms the entry again from now (a kept-alive connection waits for its next request). */
void http_deadlines_arm(struct http_deadlines *d, struct http_deadline_entry *en);
/* The request's headers are in and its body is an upload: from now on the entry is due
 * when the body falls behind the minimum rate (disarmed when there is none). */
void http_deadlines_upload(struct http_deadlines *d, struct http_deadline_entry *en);
/* An upload's body received `bytes` more: its due time moves on. */
void http_deadlines_received(struct http_deadlines *d, struct http_deadline_entry *en,
                             size_t bytes);
/* The request is in: the entry is not due any more. */
void http_deadlines_disarm(struct http_deadlines *d, struct http_deadline_entry *en);
/* The connection closes (before its socket does): unlists the entry. */
void http_deadlines_remove(struct http_deadlines *d, struct http_deadline_entry *en);

#endif
