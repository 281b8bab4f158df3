/*
 * refract.h - librefract, the C client of refractd's HTTP/JSON API (proto/openapi.yaml).
 *
 * The shape follows libcurl's easy interface: an opaque handle, calls that return an
 * int code from the shared table (proto/refract_errors.h, REFRACT_E_*), a message for
 * the last failed call from refract_errmsg(), and static text from refract_strerror().
 *
 *     refract_client *c = refract_client_create("http://127.0.0.1:8750");
 *     char *health = NULL;
 *     if (refract_health(c, &health) != REFRACT_E_OK)
 *         fprintf(stderr, "refract: %s\n", refract_errmsg(c));
 *     refract_free(health);
 *     refract_client_destroy(c);
 *
 * When refractd answers with an error, the call returns the code named in its JSON
 * error body ("error": {"code", "message"}) and refract_errmsg() holds the server's
 * message. Transport failures give REFRACT_E_CONNECT_FAILED or REFRACT_E_PROTOCOL;
 * REFRACT_E_TIMEOUT when refractd accepted the connection but no complete reply came
 * within the client's timeout; REFRACT_E_OUT_OF_MEMORY when an allocation failed; and
 * REFRACT_E_USAGE when the call's own arguments are wrong (NULL, empty id, bad dims).
 *
 * Ownership: strings and buffers returned through out-parameters are new allocations
 * that the caller releases with refract_free() (or refract_response_free()).
 * Thread: one client per thread; different clients may be used concurrently.
 */
#ifndef REFRACT_H
#define REFRACT_H

#include <stddef.h>
#include <stdio.h>

#include "refract_errors.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct refract_client refract_client;

/* The address refractd listens on by default. */
#define REFRACT_DEFAULT_URL "http://127.0.0.1:8750"
/* Room for a scene id and its NUL: ids are at most 63 characters of [a-z0-9_-]. */
#define REFRACT_ID_SIZE 64

/* Returns a new client for base_url ("http://host:port", no trailing slash needed;
 * NULL means REFRACT_DEFAULT_URL), or NULL when out of memory. Destroy it with
 * refract_client_destroy(). */
refract_client *refract_client_create(const char *base_url);
/* Destroys the client; NULL is a no-op. */
void refract_client_destroy(refract_client *c);

/* Request timeout in milliseconds for later calls (default 120000; 0 = none). */
void refract_set_timeout_ms(refract_client *c, long timeout_ms);

/* The bearer token of a refractd started with --token-file, sent with every later request
 * as "Authorization: Bearer TOKEN". refract_client_create() takes it from the environment
 * variable REFRACT_TOKEN when that is set and valid; token NULL or "" sends none. Returns
 * REFRACT_E_OK, REFRACT_E_USAGE (a token with spaces or control characters; c's message
 * says so, never showing the token) or REFRACT_E_OUT_OF_MEMORY. */
int refract_set_token(refract_client *c, const char *token);
/* refract_set_token() with the first line of the file at path (as refractd reads its
 * --token-file). REFRACT_E_IO when the file cannot be read. */
int refract_set_token_file(refract_client *c, const char *path);
/* A PEM file of CA certificates that verifies an https refractd's certificate instead of
 * the system's store (libcurl's CURLOPT_CAINFO); NULL restores the system's. Returns
 * REFRACT_E_OK, REFRACT_E_IO (the file cannot be read) or REFRACT_E_OUT_OF_MEMORY. */
int refract_set_cacert(refract_client *c, const char *path);

/* The message of the last failed call on c; valid until the next call on c. Never NULL. */
const char *refract_errmsg(const refract_client *c);
/* Static description of a code ("the request body is not valid JSON"). */
const char *refract_strerror(int code);
/* The JSON error code string of a code ("invalid_json"). */
const char *refract_code_name(int code);

/* Frees memory returned by librefract; NULL is a no-op. */
void refract_free(void *p);

/* A raw HTTP exchange, for anything the typed calls below do not cover and for tests
 * that send malformed input on purpose. */
struct refract_response {
    long status;            /* HTTP status */
    char *body;             /* response body, NUL-terminated for convenience; owned */
    size_t body_len;        /* without the terminating NUL */
    char content_type[128]; /* Content-Type header, "" if absent */
    double render_ms;       /* X-Render-Time-Ms header, -1 if absent */
    char renderer[256];     /* X-Renderer header, "" if absent */
    char irradiance[32];    /* X-Refract-Irradiance header, "" if absent */
};
void refract_response_free(struct refract_response *r);

/* Sends method (GET, POST, PUT, DELETE, PATCH) to path ("/v1/health") with an optional
 * body. Succeeds (REFRACT_E_OK) whenever an HTTP response arrived, whatever its status;
 * the caller inspects out->status. out is filled on success and must be released with
 * refract_response_free(). */
int refract_request(refract_client *c, const char *method, const char *path, const void *body,
                    size_t body_len, const char *content_type, struct refract_response *out);

/*
 * Typed calls. Each returns REFRACT_E_OK, or the error code of refractd's reply (see
 * refract_errmsg()), or a transport code.
 */

/* GET /v1/health -> *json_out (new string). */
int refract_health(refract_client *c, char **json_out);

/* POST /v1/scenes with a scene JSON document; writes the new id into id_out, which
 * should have REFRACT_ID_SIZE bytes. (If the id does not fit, the call returns
 * REFRACT_E_USAGE and its message names the id of the scene that was created.) */
int refract_scene_create(refract_client *c, const char *scene_json, size_t len, char *id_out,
                         size_t id_size);
/* GET /v1/scenes -> JSON list. */
int refract_scene_list(refract_client *c, char **json_out);
/* GET /v1/scenes/{id} -> JSON. */
int refract_scene_get(refract_client *c, const char *scene_id, char **json_out);
/* DELETE /v1/scenes/{id}. */
int refract_scene_delete(refract_client *c, const char *scene_id);

/* PUT /v1/scenes/{id}/volumes/{name}?dims=X,Y,Z&components=C with raw little-endian
 * float32 data (dims[0]*dims[1]*dims[2]*components values, x fastest). json_out
 * (optional, may be NULL) receives the server's description of what it stored. */
int refract_volume_upload(refract_client *c, const char *scene_id, const char *name,
                          const int dims[3], int components, const float *data, char **json_out);

/* PUT /v1/scenes/{id}/environment with an EXR, Radiance HDR, PNG or JPEG file's bytes.
 * json_out (optional, may be NULL) receives the server's description of what it stored. */
int refract_environment_upload(refract_client *c, const char *scene_id, const void *bytes,
                               size_t len, char **json_out);

/*
 * Uploads streamed from a file (docs/api.md "Upload a volume", "Upload a mesh", "Upload
 * an environment image"). libcurl reads the file piece by piece as it sends it, so an
 * upload of any size costs a few kilobytes of memory here (refractd, too, streams the
 * body to disk). The call returns when refractd has validated and stored the upload
 * and answered with what it stored (json_out), or with its error (the code of its
 * reply, and its message in refract_errmsg()).
 *
 *     static void on_progress(long long sent, long long total, void *user)
 *     {
 *         fprintf(stderr, "\r%lld of %lld bytes", sent, total);
 *     }
 *     struct refract_upload_desc up = {.kind = REFRACT_UPLOAD_VOLUME, .name = "ior",
 *                                      .dims = {64, 64, 64}, .type = "uint8",
 *                                      .has_scale = 1, .scale = 1.0 / 255,
 *                                      .progress = on_progress};
 *     char *stored = NULL;
 *     if (refract_upload_file(c, scene, "ior_64.u8", &up, &stored) == REFRACT_E_OK)
 *         puts(stored);   // {"name":"ior","dims":[64,64,64],...,"sha256":"..."}
 *     refract_free(stored);
 *
 * Timeout: refract_set_timeout_ms() bounds how long nothing may move (no byte sent
 * and none received), not the whole upload, which may take long for a large file; the
 * wait for refractd's answer after the last byte counts as silence.
 */
enum refract_upload_kind {
    REFRACT_UPLOAD_VOLUME = 1,     /* PUT /v1/scenes/{id}/volumes/{name}: raw, NRRD, OpenEXR */
    REFRACT_UPLOAD_MESH = 2,       /* POST /v1/scenes/{id}/meshes?name={name}: OBJ, PLY */
    REFRACT_UPLOAD_ENVIRONMENT = 3 /* PUT /v1/scenes/{id}/environment: EXR, HDR, PNG, JPEG */
};

/* Called as the body goes out, from the calling thread: once with sent_bytes 0 before
 * the first byte, then whenever more went (sent_bytes never decreases), and, when the
 * whole body went, last with sent_bytes equal to its size. total_bytes is the body's
 * size, or -1 when it is not known (refract_upload_stream of a pipe). */
typedef void (*refract_upload_progress_fn)(long long sent_bytes, long long total_bytes, void *user);

/* What an upload is. Zero means "not sent": refractd's default, or what the file says. */
struct refract_upload_desc {
    enum refract_upload_kind kind;
    const char *name;   /* the volume's or the mesh's name; NULL for the environment */
    const char *format; /* ?format=: volumes "raw", "nrrd", "exr"; meshes "obj", "ply";
                           NULL = refractd recognises the file by its first bytes */
    /* volumes only (REFRACT_E_USAGE for another kind): */
    int dims[3];      /* ?dims=X,Y,Z: required for raw and for an EXR slice atlas */
    const char *type; /* ?type= for raw: "float32" (refractd's default), "float16",
                         "uint8", "uint16" */
    int components;   /* ?components=: 1 (scalar) or 3 (RGB) */
    int has_scale, has_offset;
    double scale, offset; /* ?scale= and ?offset=: stored value = offset + scale * sample */
    refract_upload_progress_fn progress; /* optional */
    void *user;                          /* passed to progress */
};

/* Uploads the file at path (opened and read here, never whole in memory) as desc
 * says; json_out (optional, may be NULL) receives refractd's 201 answer: for a volume
 * name, format, type, dims, components, bytes, min, max, component_min/max,
 * checksum_fnv1a64 and sha256 (of the float32 data stored); for a mesh name, format,
 * triangles, vertices, closed, bounds, checksum, bytes and sha256 (of the file); for
 * the environment width, height, bytes and sha256 (of the file). A file that cannot be
 * opened or read, or that changes size while it is sent, gives REFRACT_E_IO. */
int refract_upload_file(refract_client *c, const char *scene_id, const char *path,
                        const struct refract_upload_desc *desc, char **json_out);

/* The same from an open stream (a pipe, stdin), read from its current position: size
 * bytes when size >= 0 (fewer is REFRACT_E_IO), else up to its end, sent with chunked
 * encoding. f stays open; the caller closes it. */
int refract_upload_stream(refract_client *c, const char *scene_id, FILE *f, long long size,
                          const struct refract_upload_desc *desc, char **json_out);

/* A rendered image. */
struct refract_image {
    void *bytes; /* encoded PNG, JPEG or EXR; owned */
    size_t len;
    char content_type[64]; /* image/png, image/jpeg or image/x-exr */
    double render_ms;      /* GPU time reported by refractd (X-Render-Time-Ms) */
    char renderer[256];    /* GL_RENDERER reported by refractd (X-Renderer) */
    /* X-Refract-Irradiance: "ready", "stale" (some light used the volume of its previous
     * pose: a recompute is under way), "missing" (some light had no volume yet and was
     * left out), "not-needed" (the scene has no light-dependent terms); "" if absent. */
    char irradiance[32];
};
void refract_image_free(struct refract_image *img);

/* POST /v1/scenes/{id}/render with a render request JSON ("{}" or NULL for the scene's
 * defaults; see proto/openapi.yaml RenderRequest). out is overwritten (it need not be
 * initialised) and on success must be released with refract_image_free(). */
int refract_render(refract_client *c, const char *scene_id, const char *request_json,
                   struct refract_image *out);

/* POST /v1/scenes/{id}/trace with a trace request JSON -> *json_out. */
int refract_trace(refract_client *c, const char *scene_id, const char *request_json,
                  char **json_out);

/*
 * Lights and their irradiance volumes (docs/lightsim.md, docs/api.md).
 *
 * A light is a JSON object {"name", "type": "directional"|"point"|"spot", "direction",
 * "position", "angle_deg", "color", "intensity"}. Changing lights makes refractd look up
 * each light's irradiance volume in its cache by scene transport and light pose; a miss
 * starts a recompute on the GPU in the background. The status of every light's volume
 * is read into a struct refract_irradiance.
 */

/* Room for a light name and its NUL. */
#define REFRACT_NAME_SIZE 64

/* One light's irradiance volume, as GET /v1/scenes/{id}/irradiance describes it. Numbers
 * that the reply does not carry are -1; strings it does not carry are "". */
struct refract_light_status {
    char name[REFRACT_NAME_SIZE];
    /* "ready", "queued", "computing", "stale" (the current pose has no volume yet; renders
     * use the previous one), "failed" or "not_needed", as refractd sent it */
    char state[16];
    double progress;        /* 0..1: the fraction of the volume the wavefront swept */
    long long patches_live; /* wavefront patches alive in the simulation */
    char key[24];           /* the cache key, 16 hex digits */
    long long gpu_bytes;    /* GPU memory the volume takes */
    long long host_bytes;   /* host memory the volume takes */
    double compute_ms;      /* how long the simulation took (or has taken so far) */
    char using_volume[16];  /* JSON "using": which volume renders use now: "current",
                               "previous" or "none" */
    char message[512];      /* "failed": why */
    int code;               /* "failed": the REFRACT_E_* code of a "code" member when the
                               reply has one and the table knows it, else 0 */
    int photon_map;         /* 1: the light's entry is a photon map (receiver.caustics
                               "photons", docs/photons.md "The cache"), not a volume */
    int refining;           /* such a map "ready" from its first pass and still refining:
                               progress is the share of its photons traced; not settled */
    long long photons;      /* that map's photons now (0 before its first pass) */
};

/* The irradiance status of a scene. */
struct refract_irradiance {
    char *json;       /* the reply as refractd sent it; owned */
    long http_status; /* 200 or 202 for a light change; 200 for a status read */
    char scene[REFRACT_ID_SIZE];
    int needed;              /* 0 when the scene needs no light simulation at all */
    char transport_hash[24]; /* 16 hex digits */
    size_t light_count;
    struct refract_light_status *lights; /* owned; light_count of them */
};
/* Releases what out owns and zeroes it; NULL is a no-op. */
void refract_irradiance_free(struct refract_irradiance *status);

/* Reads an irradiance status JSON document (the reply of the calls below) into out
 * (overwritten; release it with refract_irradiance_free()). Returns REFRACT_E_PROTOCOL,
 * with a message naming the member, when json is not such a document. */
int refract_irradiance_parse(refract_client *c, const char *json, struct refract_irradiance *out);

/* 1 when no light's volume or photon map is still to come: every light is "ready" (and not
 * refining), "failed" or "not_needed" (a scene without lights is settled); else 0. */
int refract_irradiance_settled(const struct refract_irradiance *status);

/* PUT /v1/scenes/{id}/lights/{name} with one light object (light_json): adds the light
 * or replaces the one of that name. status_out (optional, may be NULL) receives the
 * irradiance status of the reply: http_status 200 when every light's volume was ready
 * (cache hits), 202 when a recompute started. */
int refract_light_put(refract_client *c, const char *scene_id, const char *name,
                      const char *light_json, struct refract_irradiance *status_out);

/* PUT /v1/scenes/{id}/lights with {"lights": [...]}: replaces all lights of the scene.
 * status_out as for refract_light_put(). */
int refract_lights_put(refract_client *c, const char *scene_id, const char *lights_json,
                       struct refract_irradiance *status_out);

/* GET /v1/scenes/{id}/lights -> *json_out, a new string {"scene", "lights": [...]} with
 * every light's defaults written out. */
int refract_lights_get(refract_client *c, const char *scene_id, char **json_out);

/* GET /v1/scenes/{id}/irradiance -> *out (overwritten; release it with
 * refract_irradiance_free()). */
int refract_irradiance_status(refract_client *c, const char *scene_id,
                              struct refract_irradiance *out);

/* GET /v1/scenes/{id}/irradiance/{light}.exr: the light's irradiance volume as an
 * OpenEXR file (layout in docs/api.md) in out (overwritten; on success release it with
 * refract_image_free()): content_type "image/x-exr", and irradiance "stale" when the
 * light's current pose has no volume yet and this is the previous pose's. A reply that
 * is not an OpenEXR file gives REFRACT_E_PROTOCOL. */
int refract_irradiance_get_exr(refract_client *c, const char *scene_id, const char *light,
                               struct refract_image *out);

/* Called by refract_irradiance_wait() with every status it reads, the first included. */
typedef void (*refract_progress_fn)(const struct refract_irradiance *status, void *user);

struct refract_wait_options {
    long timeout_ms;  /* give up after this long with REFRACT_E_TIMEOUT; 0 = never */
    long interval_ms; /* between two reads of the status; clamped to 100..250; 0 = 200 */
    refract_progress_fn progress; /* optional */
    void *user;                   /* passed to progress */
};

/* Polls GET /v1/scenes/{id}/irradiance until the status is settled (see
 * refract_irradiance_settled()) and returns REFRACT_E_OK; the final status goes to
 * final_out (optional, may be NULL; release it with refract_irradiance_free()). A light
 * that "failed" ends the wait too: the caller reads its state and message. After
 * timeout_ms without settling, returns REFRACT_E_TIMEOUT with a message naming the
 * lights still to come (final_out then holds the last status read). opts NULL means
 * the defaults: no timeout, 200 ms, no callback. */
int refract_irradiance_wait(refract_client *c, const char *scene_id,
                            const struct refract_wait_options *opts,
                            struct refract_irradiance *final_out);

/*
 * View sessions and their frame streams (docs/views.md, issue 4).
 *
 * A view session is a camera, an image size and render settings that refractd keeps; its
 * stream (multipart/x-mixed-replace JPEG) gets a new frame whenever something the view
 * shows changed: a PATCH of the session, the scene, a light, an irradiance volume that
 * became ready. Nothing changes -> nothing is rendered or sent (but the newest frame is
 * sent again every 15 s, so a client that went away is noticed).
 *
 *     struct refract_view v;
 *     struct refract_view_options o = {.width = 640, .height = 480};
 *     if (refract_view_create_opts(c, "wine_glass", &o, &v) == REFRACT_E_OK) {
 *         refract_view_stream(c, v.id, on_frame, &state);   // until on_frame returns 1
 *         refract_view_delete(c, v.id);
 *         refract_view_free(&v);
 *     }
 */

/* The newest frame of a session, as its status describes it. */
struct refract_view_frame {
    long long seq;       /* 1, 2, ... per session */
    char kind[16];       /* "full" or "preview" (half size, right after a change) */
    int width, height;   /* pixels */
    double render_ms;    /* GPU time */
    double encode_ms;    /* JPEG encoding, off the GPU thread */
    long long bytes;     /* JPEG size */
    double age_ms;       /* how long ago it was made */
    char irradiance[32]; /* "ready", "stale", "missing", "not-needed" */
    long long scene_generation;
};

/* A view session's status (GET /v1/views/{vid}). Numbers the reply lacks are -1 and
 * strings "". */
struct refract_view {
    char *json;               /* the reply as refractd sent it; owned */
    char id[REFRACT_ID_SIZE]; /* "v" + 16 hex digits */
    char scene[REFRACT_ID_SIZE];
    int width, height;
    char quality[16]; /* "draft", "normal", "final" */
    char state[16];   /* "rendering" or "idle" */
    int streams;      /* open stream connections */
    double max_fps;
    double expires_in_s; /* until the idle session ends */
    char renderer[256];  /* GL_RENDERER of the daemon */
    char stream[256];    /* the stream's path, "/v1/views/<id>/stream" */
    char viewer[256];    /* the web viewer's path, "/viewer/<scene>?view=<id>" */
    int has_frame;       /* 0 before the first frame; then frame is filled */
    struct refract_view_frame frame;
};
/* Releases what v owns and zeroes it; NULL is a no-op. */
void refract_view_free(struct refract_view *v);

/* The small way to describe a session. Zero means "refractd's default" everywhere
 * (the scene's camera, size and exposure; quality "normal"; JPEG quality 80; 30 fps;
 * progressive on); a vector is sent only when its has_ flag is set. */
struct refract_view_options {
    int width, height; /* pixels */
    int has_eye, has_look_at, has_up;
    double eye[3], look_at[3], up[3]; /* world space */
    double fov_y_deg;                 /* vertical field of view */
    int has_exposure;
    double exposure;     /* stops */
    const char *quality; /* "draft", "normal", "final"; NULL = default */
    int jpeg_quality;    /* 1..100 */
    double max_fps;      /* 0.1..120 */
    int progressive;     /* 0 = default (on), 1 = on, -1 = off */
};

/* The JSON body that opts describe (a new string; refract_free() it), or NULL when out of
 * memory. opts NULL gives "{}". */
char *refract_view_options_json(const struct refract_view_options *opts);

/* POST /v1/scenes/{id}/views with a create body (docs/views.md; NULL or "{}" for every
 * default). out (overwritten) receives the new session's status; release it with
 * refract_view_free(). A scene that does not exist gives REFRACT_E_SCENE_NOT_FOUND. */
int refract_view_create(refract_client *c, const char *scene_id, const char *request_json,
                        struct refract_view *out);
/* The same with an options struct (opts NULL = every default). */
int refract_view_create_opts(refract_client *c, const char *scene_id,
                             const struct refract_view_options *opts, struct refract_view *out);

/* PATCH /v1/views/{vid}: changes what patch_json names ("camera" merges into the current
 * camera). out (optional, may be NULL) receives the new status.
 *
 *     refract_view_patch(c, v.id, "{\"camera\": {\"eye\": [0, 1, 4]}}", NULL);
 */
int refract_view_patch(refract_client *c, const char *view_id, const char *patch_json,
                       struct refract_view *out);
/* GET /v1/views/{vid} -> *out (overwritten; refract_view_free() it). An ended or expired
 * session gives REFRACT_E_NOT_FOUND. */
int refract_view_status(refract_client *c, const char *view_id, struct refract_view *out);
/* DELETE /v1/views/{vid}: the session ends, and so do its streams. */
int refract_view_delete(refract_client *c, const char *view_id);
/* GET /v1/views -> *json_out, {"views": [...]}. */
int refract_view_list(refract_client *c, char **json_out);

/* Reads a view status JSON document into out (overwritten; refract_view_free() it).
 * REFRACT_E_PROTOCOL, with a message naming the member, when it is not one. */
int refract_view_parse(refract_client *c, const char *json, struct refract_view *out);

/* One frame of a stream; everything borrowed, valid only during the callback. */
struct refract_frame {
    const void *bytes; /* a complete JPEG (it starts with SOI and ends with EOI) */
    size_t len;
    long index;            /* 0 for the first frame this stream delivered */
    long long seq;         /* X-Frame-Seq; -1 when absent. A resent frame (the 15 s
                              keep-alive, or the one repeat after a stream goes quiet)
                              has the seq it had before. */
    int repeat;            /* X-Frame-Repeat: the quiet-stream repeat (docs/views.md) */
    char kind[16];         /* X-Frame-Kind: "full", "preview"; "" when absent */
    double render_ms;      /* X-Render-Time-Ms; -1 when absent */
    char irradiance[32];   /* X-Refract-Irradiance; "" when absent */
    char content_type[64]; /* "image/jpeg" */
    double arrival_ms;     /* CLOCK_MONOTONIC in ms when the frame's first byte (its
                              first header line; the boundary line before it comes
                              with the previous frame) arrived, for latency
                              measurements */
};

/* Called with each frame; return 0 to go on, non-zero to stop the stream. */
typedef int (*refract_frame_fn)(const struct refract_frame *frame, void *user);

/*
 * GET /v1/views/{vid}/stream: reads frames until fn returns non-zero (REFRACT_E_OK), or
 * refractd ends the stream between two frames (REFRACT_E_OK: the session was deleted or
 * expired; the caller counts the frames it got), or something goes wrong:
 * REFRACT_E_NOT_FOUND for an unknown session; REFRACT_E_PROTOCOL when the stream is not
 * a frame stream, is malformed (a Content-Length that lied, a part that is not a whole
 * JPEG) or ends in the middle of a frame, with a message saying which frame and how far
 * it got; REFRACT_E_TIMEOUT when no byte came for the client's timeout
 * (refract_set_timeout_ms: for streams it bounds the silence, not the whole stream; 0 =
 * wait for ever). Blocks the calling thread; use another client to PATCH meanwhile (from
 * fn too).
 */
int refract_view_stream(refract_client *c, const char *view_id, refract_frame_fn fn, void *user);

/* One Server-Sent Event; borrowed, valid only during the callback. */
struct refract_event {
    const char *id;   /* "42"; "" when refractd sent none */
    const char *type; /* "scene.updated", "irradiance.ready", "lost", ... */
    const char *data; /* one JSON object, NUL-terminated */
    size_t data_len;
};

/* Called with each event; return 0 to go on, non-zero to stop. */
typedef int (*refract_event_fn)(const struct refract_event *ev, void *user);

/*
 * GET /v1/scenes/{id}/events (scene_id not NULL) or GET /v1/events (NULL): reads events
 * until fn returns non-zero or refractd ends the stream (both REFRACT_E_OK; a scene's
 * stream ends after its scene.deleted). since_id (optional, may be NULL) asks for the
 * events after that id still in refractd's history (sent as Last-Event-ID); when some
 * are gone the first event is "lost" with {"missed": N}. Errors as for
 * refract_view_stream (REFRACT_E_SCENE_NOT_FOUND for an unknown scene; the client's
 * timeout bounds the silence, and refractd sends a keep-alive comment every 15 s).
 *
 *     static int on_event(const struct refract_event *ev, void *user)
 *     {
 *         printf("%s %s %s\n", ev->id, ev->type, ev->data);
 *         return strcmp(ev->type, "irradiance.ready") == 0; // stop there
 *     }
 *     refract_events(c, "wine_glass", NULL, on_event, NULL);
 */
int refract_events(refract_client *c, const char *scene_id, const char *since_id,
                   refract_event_fn fn, void *user);

#ifdef __cplusplus
}
#endif

/* ---- batch jobs (docs/api.md "Batch jobs") ---- */

/* POST /v1/jobs with a job specification -> *json_out: the 202 status ({"id", ...}). */
int refract_job_submit(refract_client *c, const char *spec_json, size_t len, char **json_out);
/* GET /v1/jobs/{id} -> *json_out (state, frames_done, frames_total, progress, eta_s, ...). */
int refract_job_get(refract_client *c, const char *job_id, char **json_out);
/* GET /v1/jobs, filtered by state and scene (NULL = any) -> *json_out ({"jobs": [...]}). */
int refract_job_list(refract_client *c, const char *state, const char *scene, char **json_out);
/* DELETE /v1/jobs/{id}: cancels an unfinished job (*json_out, may be NULL, gets its
 * status) or deletes a finished one (*json_out stays NULL). */
int refract_job_cancel(refract_client *c, const char *job_id, char **json_out);
/* GET /v1/jobs/{id}/frames/{n} -> out (release with refract_image_free). */
int refract_job_frame(refract_client *c, const char *job_id, int n, struct refract_image *out);

#endif
