/*
 * refract_internal.h - what librefract's own files share; not installed, not public API.
 *
 * The library is files of one concept each:
 *   refract_client.c  the handle: create/destroy, options, refract_free
 *   refract_error.c   the code table (strerror, code names) and the per-client message
 *   refract_http.c    the curl transport: one exchange, reply headers, error replies
 *   refract_calls.c   the typed calls built on the transport, and their shared helpers
 *   refract_lights.c  the calls of lights and irradiance volumes (issue 3)
 *   refract_wait.c    waiting for irradiance volumes, polling their status
 *   refract_views.c   view sessions: create, patch, status, delete (issue 4)
 *   refract_stream.c  the curl transport of long-lived streaming GETs
 *   refract_view_stream.c  frame streams: multipart parts -> JPEG frames
 *   refract_events.c  Server-Sent Events
 *   refract_upload.c  uploads of files, streamed from disk with progress (issue 5)
 * plus refract_url.c, refract_status.c and refract_view_json.c (pure string and JSON work,
 * no curl), which the CLI's unit test also compiles, and multipart_parse.c and sse_parse.c
 * (pure byte parsers, unit-tested on their own).
 *
 * Names here carry the refract_ prefix of the library but are not declared in refract.h;
 * nothing outside the .c files in client/ may call them.
 */
#ifndef REFRACT_INTERNAL_H
#define REFRACT_INTERNAL_H

#include <curl/curl.h>
#include <stdbool.h>

#include "refract.h"

/* Room for the message of one failed call: the server's message plus our context. */
#define REFRACT_ERRMSG_SIZE 2048

/* Connect timeout in milliseconds. Short on purpose: refractd is usually on loopback or
 * the same network, so a connect that takes longer than this will not succeed. */
#define REFRACT_CONNECT_TIMEOUT_MS 10000L

/* Default request timeout (refract.h documents it): long enough for a large render on
 * Mesa's software rasterizer. */
#define REFRACT_DEFAULT_TIMEOUT_MS 120000L

/*
 * One client. INVARIANT: errmsg is always NUL-terminated; it is "" after a call that
 * succeeded and holds the message of the call that failed otherwise.
 */
struct refract_client {
    CURL *curl;                       /* owned; reused so the TCP connection stays open */
    char *base_url;                   /* owned; "http://host:port", no trailing '/' */
    long timeout_ms;                  /* whole request; 0 = none */
    char *token;                      /* owned; bearer token, NULL = none (never logged) */
    char *cacert;                     /* owned; CURLOPT_CAINFO, NULL = the system's */
    char curl_error[CURL_ERROR_SIZE]; /* CURLOPT_ERRORBUFFER of the current exchange */
    char errmsg[REFRACT_ERRMSG_SIZE]; /* what refract_errmsg() returns */
};

/* refract_error.c */

/* Sets c's message from a printf format and returns code, so a failing path reads
 * `return refract_fail(c, REFRACT_E_IO, "...", ...);`. A message longer than the buffer
 * is cut and ends with "...". */
int refract_fail(refract_client *c, int code, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Empties c's message at the start of a call, so refract_errmsg() never shows a stale one. */
void refract_clear_error(refract_client *c);
/* The code whose JSON name is json_code ("scene_not_found" -> REFRACT_E_SCENE_NOT_FOUND),
 * or -1 when the table has no such name. */
int refract_code_from_name(const char *json_code);

/* refract_http.c */

/* One HTTP exchange (the body of refract_request(), without clearing the message).
 * On failure out is zeroed and c's message says why. */
int refract_http_exchange(refract_client *c, const char *method, const char *path, const void *body,
                          size_t body_len, const char *content_type, struct refract_response *out);
/* A request body that libcurl reads as it sends it (refract_upload.c), instead of a
 * buffer; every member is borrowed for the exchange. */
struct refract_http_body_source {
    curl_read_callback read; /* CURLOPT_READFUNCTION */
    curl_seek_callback seek; /* CURLOPT_SEEKFUNCTION; NULL: the body cannot be rewound */
    void *user;              /* READDATA and SEEKDATA */
    long long size;          /* bytes; -1 = unknown, sent with chunked encoding */
    /* CURLOPT_XFERINFOFUNCTION: progress, and the bound on silences, since the exchange
     * sets no whole-request timeout for a source (an upload may take long); may be NULL */
    curl_xferinfo_callback xferinfo;
    void *xferinfo_user;
};
/* refract_http_exchange() with the body read from src. */
int refract_http_exchange_source(refract_client *c, const char *method, const char *path,
                                 const struct refract_http_body_source *src,
                                 const char *content_type, struct refract_response *out);
/* Turns a reply into a result: REFRACT_E_OK for a 2xx status; otherwise the code of the
 * JSON error body with the server's message as c's message, or REFRACT_E_PROTOCOL when
 * the body is not a refractd error. method and path only name the request in messages. */
int refract_http_check(refract_client *c, const char *method, const char *path,
                       const struct refract_response *r);

/* Maps a failed curl_easy_perform onto the code table (refract_http.c's header lists the
 * mapping) and sets c's message; method and path name the request. */
int refract_http_transport_failure(refract_client *c, CURLcode rc, const char *method,
                                   const char *path, bool out_of_memory);

/* refract_stream.c: a streaming GET whose body is handed on chunk by chunk */

/* Where a streaming GET's body goes. Each callback fills why (why_size bytes) when it
 * fails; the transport prefixes "GET <path>: ". */
struct refract_stream_sink {
    /* the Content-Type a 2xx reply must start with ("multipart/", "text/event-stream") */
    const char *content_type;
    /* the 2xx reply began with this Content-Type: false = protocol error; may be NULL */
    bool (*begin)(void *user, const char *content_type, char *why, size_t why_size);
    /* the next bytes, now_ms = refract_monotonic_ms() when they came: 0 = go on,
     * 1 = stop (the caller has what it wanted), -1 = protocol error */
    int (*chunk)(void *user, const char *data, size_t len, double now_ms, char *why,
                 size_t why_size);
    /* refractd closed the stream: false = it closed in the middle of something */
    bool (*end)(void *user, char *why, size_t why_size);
    /* how many items (frames, events) the sink has delivered, for messages */
    long (*delivered)(void *user);
    const char *item; /* "frame", "event": names the items in messages */
    void *user;
};

/* GETs path with extra request headers (NULL-terminated "Name: value" lines; may be NULL)
 * and hands a 2xx body to sink. c->timeout_ms bounds the silence (no byte for that long
 * -> REFRACT_E_TIMEOUT), not the whole stream. A non-2xx reply gives its error code
 * (refract_http_check). Returns REFRACT_E_OK when sink stopped the stream or refractd
 * ended it cleanly. */
int refract_stream_get(refract_client *c, const char *path, const char *const *headers,
                       const struct refract_stream_sink *sink);

/* CLOCK_MONOTONIC in milliseconds (struct refract_frame.arrival_ms's clock). */
double refract_monotonic_ms(void);

/* refract_calls.c: the steps every typed call shares */

/* Starts a typed call: c must exist; its message is cleared; *json_out is NULLed (when
 * json_out is not NULL). Returns REFRACT_E_USAGE for a NULL c. */
int refract_begin(refract_client *c, char **json_out);
/* Checks a scene id, volume or light name argument: present and not empty. call and what
 * name it in the message ("refract_light_put", "light name"). */
int refract_check_segment(refract_client *c, const char *call, const char *what, const char *value);
/* Returns a new string made from fmt, or NULL when out of memory; free() it. */
char *refract_path_printf(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Returns a new path "/v1/scenes/<escaped id><suffix>", or NULL when out of memory. */
char *refract_scene_path(const char *scene_id, const char *suffix);
/* refract_check_segment of the scene id (named by call), then refract_scene_path into
 * *path_out (caller frees; NULL on failure). Returns the code with c's message set. */
int refract_scene_route(refract_client *c, const char *call, const char *scene_id,
                        const char *suffix, char **path_out);
/* Sets c's message to "out of memory while <what>"; returns REFRACT_E_OUT_OF_MEMORY. */
int refract_out_of_memory(refract_client *c, const char *what);
/* The common tail of every JSON call: exchange, check the status, check that a non-empty
 * reply is JSON, and hand the body to *json_out (when json_out is not NULL) or free it.
 * Borrows body until return. */
int refract_call_json(refract_client *c, const char *method, const char *path, const void *body,
                      size_t body_len, const char *content_type, char **json_out);
/* The rest of a JSON call on one scene's resource, after refract_begin() and the call's
 * own argument checks: checks scene_id, builds "/v1/scenes/<escaped id><suffix>" and
 * makes the call with refract_call_json(). call names the function in messages. */
int refract_scene_call_json(refract_client *c, const char *call, const char *method,
                            const char *scene_id, const char *suffix, const void *body,
                            size_t body_len, const char *content_type, char **json_out);
/* The tail of refract_call_json_status() after its exchange: checks r's status and that a
 * non-empty body is JSON, and moves the body to *json_out (when json_out is not NULL).
 * Releases r in every case. */
int refract_take_json(refract_client *c, const char *method, const char *path,
                      struct refract_response *r, char **json_out);
/* refract_call_json() that also gives the reply's HTTP status (200 or 202, say) through
 * *http_status (when not NULL; 0 when no reply came). */
int refract_call_json_status(refract_client *c, const char *method, const char *path,
                             const void *body, size_t body_len, const char *content_type,
                             char **json_out, long *http_status);
/* Reads a JSON reply (one of refractd's status objects) into the struct out, or writes why
 * not into why. */
typedef bool (*refract_reply_reader)(const char *json, size_t len, void *out, char *why,
                                     size_t why_size);
/* Reads the reply body (owned; taken) of method path with reader into out and hands the body
 * to *json_slot (out's copy of the JSON); when out is NULL the body is freed. what names
 * the reply in the error ("a view status"). */
int refract_take_reply(refract_client *c, const char *method, const char *path, char *body,
                       const char *what, refract_reply_reader reader, void *out, char **json_slot);
/* refract_call_json_status() with body (NULL: none; else JSON) whose reply is read with
 * refract_take_reply(). */
int refract_call_reply(refract_client *c, const char *method, const char *path, const char *body,
                       const char *what, refract_reply_reader reader, void *out, char **json_slot,
                       long *http_status);
/* The options every request of c sets on c->curl (URL, protocols, paths as they are, error
 * buffer, no signals, connect timeout, user agent, headers); the caller adds the rest. */
void refract_http_set_common(refract_client *c, const char *url, struct curl_slist *headers);
/* Copies src into dst (dst_size bytes), cutting it if needed; dst is NUL-terminated. */
void refract_copy_string(char *dst, size_t dst_size, const char *src);

#endif
