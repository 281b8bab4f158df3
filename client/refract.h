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

/* A rendered image. */
struct refract_image {
    void *bytes; /* encoded PNG, JPEG or EXR; owned */
    size_t len;
    char content_type[64]; /* image/png, image/jpeg or image/x-exr */
    double render_ms;      /* GPU time reported by refractd (X-Render-Time-Ms) */
    char renderer[256];    /* GL_RENDERER reported by refractd (X-Renderer) */
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

#ifdef __cplusplus
}
#endif

#endif
