/*
 * http_internal.h - what the HTTP module's files share: the per-request state, the route
 * table's handler type, and the response helpers. Not used outside server/http/.
 */
#ifndef REFRACT_HTTP_INTERNAL_H
#define REFRACT_HTTP_INTERNAL_H

#include <stdbool.h>
#include <stddef.h>

#include <cjson/cJSON.h>
#include <microhttpd.h>

#include "../view/view.h"
#include "../request/render_request.h"
#include "../core/sha256.h"
#include "clients.h"
#include "deadline.h"
#include "http.h"

#define HTTP_MAX_PARAMS 3
#define HTTP_PARAM_MAX 256 /* longer than any valid id or name: handlers say why */

struct http_request;

/* A route handler runs on an HTTP thread once the whole body has arrived. It answers
 * (http_respond_*) or suspends the connection (http_suspend_for_gpu). */
typedef enum MHD_Result (*http_handler_fn)(struct http_request *req);

enum http_body_kind {
    HTTP_BODY_NONE = 0,   /* no body expected (a body is drained and ignored) */
    HTTP_BODY_JSON = 1,   /* limited by max_json_bytes */
    HTTP_BODY_UPLOAD = 2, /* limited by max_upload_bytes */
};

struct http_route {
    const char *method;
    const char *pattern;
    http_handler_fn handler;
    enum http_body_kind body;
};

enum http_phase {
    HTTP_PHASE_NEW = 0,       /* handler not run yet */
    HTTP_PHASE_SUSPENDED = 1, /* waiting for the GPU */
    HTTP_PHASE_RESUMED = 2,   /* GPU done; on_resume answers */
    HTTP_PHASE_ANSWERED = 3,
};

/* Per-request state: allocated on the first handler call, freed only in the completion
 * callback (server.c). One owner: the connection. */
struct http_request {
    struct MHD_Connection *conn;
    const struct http_server *server;
    const struct http_config *cfg;
    const struct http_app *app;
    const struct http_route *route;
    char params[HTTP_MAX_PARAMS][HTTP_PARAM_MAX];
    int param_count;
    char *body; /* owned; NUL-terminated; NULL for HTTP_BODY_UPLOAD routes */
    size_t body_len, body_cap, body_limit;
    bool body_too_large;
    /* HTTP_BODY_UPLOAD routes: the body streams to a temporary file under <data>/tmp
     * as it arrives, hashed on the way (server.c). When the handler runs, the file is
     * complete and closed, upload_path names it and upload_sha256 is its SHA-256. A
     * handler that hands the file on (renamed into the blob store) clears upload_path;
     * otherwise the completion callback removes the file. A kill -9 leaves it for the
     * start-up sweep. */
    int upload_fd; /* -1 when not open */
    char upload_path[1024];
    struct sha256 upload_hash;
    char upload_sha256[SHA256_HEX_SIZE];
    struct err upload_err;  /* code != OK when writing the file failed (answered at the end) */
    size_t upload_reserved; /* bytes of the file counted against --max-storage-bytes */
    enum http_phase phase;
    int status; /* the status answered with (0 = none yet); GET /metrics counts it */
    double started_ms;
    /* Asynchronous GPU work (handler-specific). */
    struct gpu_work work;
    void *job; /* owned; freed by job_free */
    void (*job_free)(void *job);
    http_handler_fn on_resume; /* answers after the GPU finished */
    /* Fair sharing (server.c): the connection's client, whether this request counts
     * against its --max-queued-per-client, and the socket polled to notice that the client
     * left while the request waits for the GPU (-1: unknown). */
    const struct http_client_key *client;
    bool gpu_counted;
    int client_fd;
    /* The connection's --header-deadline entry (deadline.h; NULL: not tracked). */
    struct http_deadline_entry *deadline;
    struct http_sse *sse;      /* the server's event streams (h_events.c) */
};

/* ---- responses (respond.c) ---- */

/* The headers every response carries (X-Content-Type-Options: nosniff); respond.c adds
 * them to its own, a handler that builds an MHD_Response itself calls this. */
void http_response_common_headers(struct MHD_Response *resp);

/* {"error": {"code", "message"}} with the code's HTTP status. */
enum MHD_Result http_respond_error(struct http_request *req, enum refract_code code,
                                   const char *fmt, ...) __attribute__((format(printf, 3, 4)));
enum MHD_Result http_respond_err(struct http_request *req, const struct err *e);
/* The same with extra response headers (name, value, ..., NULL). */
enum MHD_Result http_respond_error_with(struct http_request *req, const char *const *headers,
                                        enum refract_code code, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* Serialises and consumes json. */
enum MHD_Result http_respond_json(struct http_request *req, unsigned status, cJSON *json);
/* Consumes bytes (malloc'd). */
enum MHD_Result http_respond_bytes(struct http_request *req, unsigned status, void *bytes,
                                   size_t len, const char *content_type,
                                   const char *const *headers /* name, value, ..., NULL */);
enum MHD_Result http_respond_empty(struct http_request *req, unsigned status);

/* The server's open streams (stream.h). */
struct http_stream_set *http_server_streams(const struct http_server *srv);

/* ---- GPU hand-off (server.c) ---- */

/* Submits req->work (its run set by the caller) with the request deadline and suspends
 * the connection; when the work is done, on_resume answers. On submission failure
 * answers the error at once. */
enum MHD_Result http_suspend_for_gpu(struct http_request *req, http_handler_fn on_resume);

/* ---- reference renders (h_render_reference.c; docs/pathtracer.md) ---- */

/* True when body is a JSON object with "mode": "reference" (anything else, including
 * invalid JSON, is for the fast renderer's parser to judge). */
bool http_render_is_reference(const char *body, size_t len);
/* POST /v1/scenes/{id}/render with "mode": "reference": the CPU path tracer on worker
 * threads; suspends the connection until the image is done. */
enum MHD_Result http_handle_render_reference(struct http_request *req);

/* ---- request parsing (request_parse.c) ---- */

struct http_render_request {
    struct render_view_request view;
    enum { HTTP_FORMAT_PNG, HTTP_FORMAT_JPEG, HTTP_FORMAT_EXR } format;
    int jpeg_quality;
    double exposure_ev;
    enum scene_tonemap tonemap;
};

/* An empty or all-space body means {}; otherwise jr_parse. *root is a new tree. */
enum refract_code http_parse_body(const char *body, size_t len, cJSON **root, struct err *e);
/* The readers shared by render requests and view sessions. Each starts from its default
 * (def, or the values *exposure_ev, *tonemap, *jpeg_quality hold on entry) and changes
 * only what root names; limits are the cfg's, with messages naming the flag.
 *   camera: "camera" {eye, look_at, up, fov_y_deg} (merged into def), "width", "height";
 *   settings: "stepper", "step", "max_steps", "boundary_threshold";
 *   image options: "exposure", "tonemap", "jpeg_quality". */
enum refract_code http_parse_camera(const cJSON *root, const struct scene_camera *def,
                                    const struct http_config *cfg, struct scene_camera *out,
                                    struct err *e);
enum refract_code http_parse_settings(const cJSON *root, const struct scene_render_settings *def,
                                      const struct http_config *cfg,
                                      struct scene_render_settings *out, struct err *e);
enum refract_code http_parse_image_options(const cJSON *root, double *exposure_ev,
                                           enum scene_tonemap *tonemap, int *jpeg_quality,
                                           struct err *e);

/* Parses a render request against the scene's defaults. An empty body means "{}". */
enum refract_code http_parse_render_request(const char *body, size_t len, const struct scene *scene,
                                            const struct http_config *cfg,
                                            struct http_render_request *out, struct err *e);

/* Parses a view session's body (create or PATCH; view_request.c) on top of `current`
 * (the session's settings, or view_settings_defaults for a new one); scene resolves the
 * quality preset. Every field is optional. */
enum refract_code http_parse_view_settings(const char *body, size_t len, const struct scene *scene,
                                           const struct http_config *cfg,
                                           const struct view_settings *current,
                                           struct view_settings *out, struct err *e);

/* Parses a trace request; *rays is a new array (caller frees) of *count rays. */
enum refract_code http_parse_trace_request(const char *body, size_t len, const struct scene *scene,
                                           const struct http_config *cfg,
                                           struct scene_render_settings *settings,
                                           struct render_trace_ray **rays, size_t *count,
                                           bool *events, struct err *e);

/* ---- volume uploads (upload_volume.c) ---- */

/* Decodes the upload of req (query: format, dims, type, components, scale, offset;
 * docs/api.md "Volume uploads") as volume `name` of the scene in params[0], checks its
 * values against the channels the scene uses it for, and stores it. Answers errors
 * itself (returns false; *answer holds the result); on success *out is a new
 * reference the caller releases. */
bool http_volume_upload(struct http_request *req, const char *name, struct store_volume **out,
                        enum MHD_Result *answer);
/* The 201 body describing a stored volume. */
cJSON *http_volume_json(const struct store_volume *vol);
/* The first query parameter of req that is not in `allowed` (NULL-terminated), or NULL:
 * a misspelt parameter is an error, never silently its default. */
const char *http_query_unknown(struct http_request *req, const char *const *allowed);

/* ---- handlers ---- */
enum MHD_Result http_handle_health(struct http_request *req);
enum MHD_Result http_handle_scene_create(struct http_request *req);
enum MHD_Result http_handle_scene_list(struct http_request *req);
enum MHD_Result http_handle_scene_get(struct http_request *req);
enum MHD_Result http_handle_scene_delete(struct http_request *req);
enum MHD_Result http_handle_volume_put(struct http_request *req);
enum MHD_Result http_handle_environment_put(struct http_request *req);
enum MHD_Result http_handle_mesh_post(struct http_request *req);
enum MHD_Result http_handle_render(struct http_request *req);
enum MHD_Result http_handle_trace(struct http_request *req);
enum MHD_Result http_handle_lights_get(struct http_request *req);
enum MHD_Result http_handle_lights_put(struct http_request *req);
enum MHD_Result http_handle_light_put(struct http_request *req);
enum MHD_Result http_handle_irradiance_get(struct http_request *req);
enum MHD_Result http_handle_irradiance_exr(struct http_request *req);
enum MHD_Result http_handle_view_create(struct http_request *req);
enum MHD_Result http_handle_view_list(struct http_request *req);
enum MHD_Result http_handle_view_get(struct http_request *req);
enum MHD_Result http_handle_view_patch(struct http_request *req);
enum MHD_Result http_handle_view_delete(struct http_request *req);
enum MHD_Result http_handle_view_stream(struct http_request *req);
/* The web viewer (h_web.c). */
enum MHD_Result http_handle_web_index(struct http_request *req);
enum MHD_Result http_handle_web_viewer(struct http_request *req);
enum MHD_Result http_handle_web_asset(struct http_request *req);
enum MHD_Result http_handle_storage(struct http_request *req);
enum MHD_Result http_handle_metrics(struct http_request *req);
/* Batch jobs (h_jobs.c). */
enum MHD_Result http_handle_job_create(struct http_request *req);
enum MHD_Result http_handle_job_list(struct http_request *req);
enum MHD_Result http_handle_job_get(struct http_request *req);
enum MHD_Result http_handle_job_delete(struct http_request *req);
enum MHD_Result http_handle_job_frame(struct http_request *req);
enum MHD_Result http_handle_job_archive(struct http_request *req);
enum MHD_Result http_handle_events(struct http_request *req);
enum MHD_Result http_handle_scene_events(struct http_request *req);

/* ---- events (h_events.c) ---- */
struct http_sse;
/* The server's Server-Sent Events streams and its one listener on hub (NULL: none; the
 * event routes then answer 500). NULL with e filled on failure. */
struct http_sse *http_sse_create(struct event_hub *hub, struct err *e);
/* After MHD_stop_daemon: stops listening, releases the streams. NULL is a no-op. */
void http_sse_destroy(struct http_sse *sse);
/* Publishes a scene event (EVENT_SCENE_CREATED, _UPDATED, _DELETED) with data {"scene",
 * "generation" (of version, when not NULL), "what" (when not NULL: "document", "volume",
 * "environment", "mesh", "lights")}. A no-op without a hub. */
void http_publish_scene(const struct http_app *app, const char *type, const char *scene_id,
                        const struct store_scene *version, const char *what);

/* ---- irradiance (h_irradiance.c) ---- */
/* The irradiance status body (docs/api.md) of a version. */
cJSON *http_irradiance_status(const struct http_app *app, struct store_scene *v);
/* A version as render and irradiance source: render_request_scene_source and
 * render_request_irradiance_source (server/request/render_request.h, shared with the view
 * sessions). */

/* Looks up the scene named by the first path parameter; answers 404 and returns NULL when
 * it does not exist. Returns a new reference. */
struct store_scene *http_scene_or_404(struct http_request *req, enum MHD_Result *answer);

/* The description of an uploaded mesh (h_meshes.c): name, format, triangles, vertices,
 * closed, bounds, checksum, bytes. Returns a new cJSON object. */
struct store_mesh;
cJSON *http_mesh_json(const struct store_mesh *m);

/* Adds the scene's version, GPU status and uploads to a JSON object. */
void http_scene_summary(const struct http_app *app, const struct store_scene *v, cJSON *obj,
                        bool detailed);

#endif
