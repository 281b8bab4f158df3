/*
 * http.h - refractd's HTTP/JSON API v1 (proto/openapi.yaml) on libmicrohttpd.
 *
 * THREADING MODEL: libmicrohttpd runs its own polling threads (epoll, a thread pool of
 * `threads`), with suspend/resume allowed. Handlers run on those threads and never call
 * GL. A handler that needs the GPU builds a gpu_work item, submits it to the GPU queue
 * (server/gpu/queue.h) and suspends its connection; the item's `done` callback, on the GPU
 * thread, resumes the connection, and the handler runs once more on an HTTP thread to
 * encode the result (PNG/JPEG/EXR encoding happens there, off the GPU thread) and answer.
 * Every queued item carries the request deadline, because a suspended connection does
 * not notice that its client has gone.
 *
 * Ownership: the server borrows the store, gpu and render for its lifetime; the caller
 * stops the server before destroying them (main.c writes the shutdown order).
 */
#ifndef REFRACT_HTTP_H
#define REFRACT_HTTP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"
#include "../gpu/queue.h"
#include "../render/render.h"
#include "../scene/scene.h"
#include "../store/store.h"

struct http_config {
    const char *bind_address;   /* "127.0.0.1" */
    int port;                   /* 0 = an ephemeral port (see http_server_port) */
    int threads;                /* libmicrohttpd thread pool size; 0 = 4 */
    size_t max_json_bytes;      /* JSON request bodies; 0 = 8 MiB */
    size_t max_upload_bytes;    /* volume and image uploads; 0 = 1 GiB */
    int max_rays;               /* per trace request; 0 = 65536 */
    long long max_image_pixels; /* width * height of a render; 0 = 4096 * 4096 */
    int request_timeout_ms;     /* deadline of a request's GPU work (every tile of a render
                                   must start before it); 0 = 120000 */
    /* Fair sharing (docs/api.md "Fair sharing"); each refusal is a JSON error naming its
     * flag. A client is an IP address. */
    int max_connections;          /* open connections; 0 = 2048 (503 busy beyond) */
    int max_connections_per_ip;   /* open connections of one client; 0 = no limit (429) */
    int max_queued_per_client;    /* renders and traces of one client queued or running
                                     on the GPU; 0 = no limit (429) */
    int header_timeout_s;         /* idle seconds allowed before a request's headers and
                                     body are in (and between keep-alive requests); 0 = 10 */
    int header_deadline_s;        /* seconds a request's headers and body (not an upload's
                                     body) may take to arrive in all, however they trickle;
                                     0 = no deadline (server/http/deadline.h) */
    long long upload_min_rate;    /* bytes per second an upload's body must average once
                                     header_deadline_s is spent; 0 = none */
    int connection_timeout_s;     /* idle seconds allowed while answering; 0 = 300 */
    long long render_tile_pixels; /* pixels a render draws per GPU turn: larger renders are
                                     drawn in tiles of rows, other work between; 0 = 65536 */
    int max_reference_samples;  /* "mode": "reference" samples per pixel; 0 = 65536 */
    int max_reference_ms;       /* "mode": "reference" time per render; 0 = 120000 */
    struct scene_limits limits;
    /* Access control (access.c; docs/api.md "Security"). All borrowed for the server's
     * life. token: the bearer token every route except GET /v1/health and the viewer's
     * static pages requires; NULL or "" = none. allow_hosts: Host names served besides
     * the loopback names and bind_address ("*" = any). */
    const char *token;
    const char *const *allow_hosts;
    size_t allow_host_count;
    /* TLS (PEM text, not paths): both set = https only; both NULL = plain http. */
    const char *tls_cert_pem;
    const char *tls_key_pem;
};

struct http_server;
struct irradiance_cache;
struct event_hub;
struct view_registry;
struct job_runner;

/* Where the server gets its state. All borrowed. */
struct http_app {
    struct store *store;
    struct gpu *gpu;
    struct render *render; /* used on the GPU thread only */
    struct irradiance_cache *irradiance;
    struct event_hub *events;    /* what changed (server/events/events.h); may be NULL */
    struct view_registry *views; /* view sessions (server/view/, docs/views.md) */
    struct job_runner *jobs;     /* batch jobs (server/jobs/jobs.h) */
};

/* Starts listening. Returns a new server (stop with http_server_stop) or NULL with e
 * filled (e.g. the port is taken: says which and how to pick another). */
struct http_server *http_server_start(const struct http_config *cfg, const struct http_app *app,
                                      struct err *e);
/* The port actually bound (useful with port 0). */
int http_server_port(const struct http_server *s);
/* From now on every new request is answered 503 shutting_down (the listening socket
 * closes in http_server_stop); requests in progress continue. */
void http_server_quiesce(struct http_server *s);
/* Ends every open stream (frame streams, event streams), so that no connection stays
 * suspended by a stream; requests waiting for the GPU are not affected. For shutdown,
 * after quiesce. */
void http_server_end_streams(struct http_server *s);
/* Waits up to timeout_ms until no request is in progress (answered or not). Returns true
 * when idle. Used at shutdown so connections resumed with "shutting_down" get answered. */
bool http_server_wait_idle(struct http_server *s, int timeout_ms);
/* Ends the reference renders in progress (they answer 503 shutting_down at once). For
 * shutdown, after quiesce and before waiting for idle. Any thread. */
void http_reference_cancel_all(void);
/* Stops the daemon. Call after the GPU queue has been drained (so no connection is
 * suspended). NULL is a no-op. */
void http_server_stop(struct http_server *s);

/* Queues a background build of a scene's GPU data (maintenance priority) and records the
 * outcome in the store's GPU status, and asks the irradiance cache for the volumes of the
 * scene's lights (which starts their recompute when they are not cached). Used after
 * create/upload/lights changes and at start-up. */
void http_prepare_scene(const struct http_app *app, struct store_scene *version);

/* The route table, for the contract test (tests/integration/test_openapi_contract.c). */
struct http_route_info {
    const char *method;
    const char *pattern; /* "/v1/scenes/{id}/render" */
};
size_t http_routes(const struct http_route_info **out);

#endif
