/*
 * refract_calls.c - the typed calls of refract.h: one function per route of refractd's
 * API, built on refract_http_exchange() and refract_http_check().
 *
 * Each call checks its arguments, builds the path (scene ids and volume names are
 * percent-encoded as single path segments), exchanges, turns a non-2xx reply into its
 * code, and hands the reply body to the caller without copying it. A JSON reply is
 * parsed once to make sure it is JSON, so a caller never receives an HTML error page
 * from a proxy as if refractd had sent it. This file never touches libcurl directly.
 * The helpers every call uses (refract_begin, refract_call_json, ...) are declared in
 * refract_internal.h, because refract_lights.c builds its calls the same way.
 */
#include <cjson/cJSON.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "refract_internal.h"
#include "refract_url.h"

char *refract_path_printf(const char *fmt, ...)
{
    va_list ap;
    int n;
    char *out;

    va_start(ap, fmt);
    n = vsnprintf(NULL, 0, fmt, ap);
    va_end(ap);
    if (n < 0)
        return NULL;
    out = malloc((size_t)n + 1);
    if (out == NULL)
        return NULL;
    va_start(ap, fmt);
    vsnprintf(out, (size_t)n + 1, fmt, ap);
    va_end(ap);
    return out;
}

int refract_out_of_memory(refract_client *c, const char *what)
{
    return refract_fail(c, REFRACT_E_OUT_OF_MEMORY, "out of memory while %s", what);
}

int refract_check_segment(refract_client *c, const char *call, const char *what, const char *value)
{
    if (value == NULL || value[0] == '\0')
        return refract_fail(c, REFRACT_E_USAGE, "%s: the %s is %s", call, what,
                            value == NULL ? "NULL" : "empty");
    return REFRACT_E_OK;
}

char *refract_scene_path(const char *scene_id, const char *suffix)
{
    char *id = refract_url_escape_dup(scene_id);
    char *path = id != NULL ? refract_path_printf("/v1/scenes/%s%s", id, suffix) : NULL;

    free(id);
    return path;
}

int refract_scene_route(refract_client *c, const char *call, const char *scene_id,
                        const char *suffix, char **path_out)
{
    int code = refract_check_segment(c, call, "scene id", scene_id);

    *path_out = NULL;
    if (code != REFRACT_E_OK)
        return code;
    *path_out = refract_scene_path(scene_id, suffix);
    if (*path_out == NULL)
        return refract_out_of_memory(c, "building the request path");
    return REFRACT_E_OK;
}

int refract_call_json_status(refract_client *c, const char *method, const char *path,
                             const void *body, size_t body_len, const char *content_type,
                             char **json_out, long *http_status)
{
    struct refract_response r;
    int code = refract_http_exchange(c, method, path, body, body_len, content_type, &r);

    if (http_status != NULL)
        *http_status = code == REFRACT_E_OK ? r.status : 0;
    if (code != REFRACT_E_OK)
        return code;
    return refract_take_json(c, method, path, &r, json_out);
}

int refract_take_json(refract_client *c, const char *method, const char *path,
                      struct refract_response *r, char **json_out)
{
    int code = refract_http_check(c, method, path, r);

    if (code == REFRACT_E_OK && r->body_len > 0) {
        cJSON *root = cJSON_ParseWithLengthOpts(r->body, r->body_len, NULL, 0);

        if (root == NULL)
            code = refract_fail(c, REFRACT_E_PROTOCOL,
                                "%s %s: refractd answered HTTP %ld "
                                "with a body that is not JSON (Content-Type \"%s\")",
                                method, path, r->status, r->content_type);
        cJSON_Delete(root);
    }
    if (code == REFRACT_E_OK && json_out != NULL) {
        *json_out = r->body; /* ownership moves to the caller */
        r->body = NULL;
    }
    refract_response_free(r);
    return code;
}

int refract_call_json(refract_client *c, const char *method, const char *path, const void *body,
                      size_t body_len, const char *content_type, char **json_out)
{
    return refract_call_json_status(c, method, path, body, body_len, content_type, json_out, NULL);
}

int refract_take_reply(refract_client *c, const char *method, const char *path, char *body,
                       const char *what, refract_reply_reader reader, void *out, char **json_slot)
{
    char why[256] = "";

    if (out == NULL) {
        free(body);
        return REFRACT_E_OK;
    }
    if (!reader(body, body != NULL ? strlen(body) : 0, out, why, sizeof(why))) {
        free(body);
        return refract_fail(c, REFRACT_E_PROTOCOL, "%s %s: refractd's reply is not %s: %s", method,
                            path, what, why);
    }
    *json_slot = body; /* ownership moves to the caller */
    return REFRACT_E_OK;
}

/* refractd's JSON routes take POST, PUT and PATCH, and want Content-Type: application/json
 * even with an empty body (docs/api.md "Security"). */
static bool sends_json(const char *method)
{
    return strcmp(method, "POST") == 0 || strcmp(method, "PUT") == 0 ||
           strcmp(method, "PATCH") == 0;
}

int refract_call_reply(refract_client *c, const char *method, const char *path, const char *body,
                       const char *what, refract_reply_reader reader, void *out, char **json_slot,
                       long *http_status)
{
    char *reply = NULL;
    int code =
        refract_call_json_status(c, method, path, body, body != NULL ? strlen(body) : 0,
                                 body != NULL || sends_json(method) ? "application/json" : NULL,
                                 &reply, http_status);

    if (code != REFRACT_E_OK) {
        free(reply);
        return code;
    }
    return refract_take_reply(c, method, path, reply, what, reader, out, json_slot);
}

int refract_scene_call_json(refract_client *c, const char *call, const char *method,
                            const char *scene_id, const char *suffix, const void *body,
                            size_t body_len, const char *content_type, char **json_out)
{
    char *path;
    int code = refract_scene_route(c, call, scene_id, suffix, &path);

    if (code != REFRACT_E_OK)
        return code;
    code = refract_call_json(c, method, path, body, body_len, content_type, json_out);
    free(path);
    return code;
}

int refract_begin(refract_client *c, char **json_out)
{
    if (json_out != NULL)
        *json_out = NULL;
    if (c == NULL)
        return REFRACT_E_USAGE;
    refract_clear_error(c);
    return REFRACT_E_OK;
}

int refract_health(refract_client *c, char **json_out)
{
    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (json_out == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_health: json_out is NULL");
    return refract_call_json(c, "GET", "/v1/health", NULL, 0, NULL, json_out);
}

int refract_scene_list(refract_client *c, char **json_out)
{
    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (json_out == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_scene_list: json_out is NULL");
    return refract_call_json(c, "GET", "/v1/scenes", NULL, 0, NULL, json_out);
}

/* Copies the "id" of a POST /v1/scenes reply into id_out. */
static int copy_new_id(refract_client *c, const char *reply, char *id_out, size_t id_size)
{
    cJSON *root = cJSON_ParseWithLengthOpts(reply, strlen(reply), NULL, 0);
    const cJSON *id = cJSON_GetObjectItemCaseSensitive(root, "id");
    int code = REFRACT_E_OK;

    if (!cJSON_IsString(id) || id->valuestring[0] == '\0') {
        code = refract_fail(c, REFRACT_E_PROTOCOL,
                            "POST /v1/scenes: refractd's reply has no "
                            "\"id\" string");
    } else if (strlen(id->valuestring) >= id_size) {
        /* The scene exists now, so the message must carry its id. */
        code = refract_fail(c, REFRACT_E_USAGE,
                            "refract_scene_create: the new scene's id "
                            "\"%s\" does not fit id_out (id_size %zu; use REFRACT_ID_SIZE); "
                            "the scene was created",
                            id->valuestring, id_size);
    } else {
        strcpy(id_out, id->valuestring);
    }
    cJSON_Delete(root);
    return code;
}

int refract_scene_create(refract_client *c, const char *scene_json, size_t len, char *id_out,
                         size_t id_size)
{
    char *reply = NULL;
    int code;

    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (scene_json == NULL || id_out == NULL || id_size == 0)
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_scene_create: scene_json and id_out "
                            "must not be NULL and id_size must not be 0");
    id_out[0] = '\0';
    code = refract_call_json(c, "POST", "/v1/scenes", scene_json, len, "application/json", &reply);
    if (code == REFRACT_E_OK)
        code = copy_new_id(c, reply != NULL ? reply : "", id_out, id_size);
    free(reply);
    return code;
}

int refract_scene_get(refract_client *c, const char *scene_id, char **json_out)
{
    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (json_out == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_scene_get: json_out is NULL");
    return refract_scene_call_json(c, "refract_scene_get", "GET", scene_id, "", NULL, 0, NULL,
                                   json_out);
}

int refract_scene_delete(refract_client *c, const char *scene_id)
{
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    return refract_scene_call_json(c, "refract_scene_delete", "DELETE", scene_id, "", NULL, 0, NULL,
                                   NULL);
}

/* Runtime check rather than a macro: compilers disagree on how to spell the byte-order
 * test, and this folds to a constant anyway. */
static bool host_is_little_endian(void)
{
    const uint32_t one = 1;
    unsigned char first;

    memcpy(&first, &one, 1);
    return first == 1;
}

/* Returns a new buffer holding count floats as little-endian float32, or NULL when out
 * of memory; free() it. Used on big-endian hosts only. */
static void *floats_to_le(const float *data, size_t count)
{
    unsigned char *out = malloc(count * 4);

    if (out == NULL)
        return NULL;
    for (size_t i = 0; i < count; i++) {
        uint32_t bits;

        memcpy(&bits, &data[i], 4);
        out[4 * i + 0] = (unsigned char)(bits & 0xFF);
        out[4 * i + 1] = (unsigned char)((bits >> 8) & 0xFF);
        out[4 * i + 2] = (unsigned char)((bits >> 16) & 0xFF);
        out[4 * i + 3] = (unsigned char)((bits >> 24) & 0xFF);
    }
    return out;
}

/* Checks dims and components and returns the number of float values through *count. */
static int volume_count(refract_client *c, const int dims[3], int components, size_t *count)
{
    size_t n = 1;

    if (dims == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_volume_upload: dims is NULL");
    for (int i = 0; i < 3; i++) {
        if (dims[i] <= 0)
            return refract_fail(c, REFRACT_E_USAGE,
                                "refract_volume_upload: dims[%d] is %d; "
                                "each dimension must be at least 1",
                                i, dims[i]);
    }
    if (components <= 0)
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_volume_upload: components is %d; it "
                            "must be at least 1",
                            components);
    for (int i = 0; i < 4; i++) {
        size_t f = (size_t)(i < 3 ? dims[i] : components);

        if (n > SIZE_MAX / 4 / f)
            return refract_fail(c, REFRACT_E_USAGE,
                                "refract_volume_upload: %dx%dx%d voxels "
                                "of %d components do not fit in memory",
                                dims[0], dims[1], dims[2], components);
        n *= f;
    }
    *count = n;
    return REFRACT_E_OK;
}

int refract_volume_upload(refract_client *c, const char *scene_id, const char *name,
                          const int dims[3], int components, const float *data, char **json_out)
{
    const char *call = "refract_volume_upload";
    void *swapped = NULL;
    char *esc_id = NULL;
    char *esc_name = NULL;
    char *path = NULL;
    size_t count = 0;
    int code;

    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    code = refract_check_segment(c, call, "scene id", scene_id);
    if (code == REFRACT_E_OK)
        code = refract_check_segment(c, call, "volume name", name);
    if (code == REFRACT_E_OK)
        code = volume_count(c, dims, components, &count);
    if (code == REFRACT_E_OK && data == NULL)
        code = refract_fail(c, REFRACT_E_USAGE, "%s: data is NULL", call);
    if (code != REFRACT_E_OK)
        return code;

    esc_id = refract_url_escape_dup(scene_id);
    esc_name = refract_url_escape_dup(name);
    if (esc_id != NULL && esc_name != NULL)
        path = refract_path_printf("/v1/scenes/%s/volumes/%s?dims=%d,%d,%d&components=%d", esc_id,
                                   esc_name, dims[0], dims[1], dims[2], components);
    /* The wire format is little-endian float32; only a big-endian host needs a copy. */
    if (!host_is_little_endian())
        swapped = floats_to_le(data, count);
    if (path == NULL || (!host_is_little_endian() && swapped == NULL))
        code = refract_out_of_memory(c, "preparing the volume upload");
    else
        code = refract_call_json(c, "PUT", path, swapped != NULL ? swapped : (const void *)data,
                                 count * 4, "application/octet-stream", json_out);
    free(swapped);
    free(path);
    free(esc_name);
    free(esc_id);
    return code;
}

int refract_environment_upload(refract_client *c, const char *scene_id, const void *bytes,
                               size_t len, char **json_out)
{
    char *path;
    int code;

    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    code = refract_check_segment(c, "refract_environment_upload", "scene id", scene_id);
    if (code != REFRACT_E_OK)
        return code;
    if (bytes == NULL && len > 0)
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_environment_upload: bytes is NULL "
                            "but len is %zu",
                            len);
    path = refract_scene_path(scene_id, "/environment");
    if (path == NULL)
        return refract_out_of_memory(c, "building the request path");
    code = refract_call_json(c, "PUT", path, bytes != NULL ? bytes : "", len,
                             "application/octet-stream", json_out);
    free(path);
    return code;
}

void refract_image_free(struct refract_image *img)
{
    if (img == NULL)
        return;
    free(img->bytes);
    memset(img, 0, sizeof(*img));
    img->render_ms = -1.0;
}

void refract_copy_string(char *dst, size_t dst_size, const char *src)
{
    size_t n = strnlen(src, dst_size - 1);

    memcpy(dst, src, n);
    dst[n] = '\0';
}

/* Moves an image reply into out; the reply must carry an image/ Content-Type. */
static int take_image(refract_client *c, const char *path, struct refract_response *r,
                      struct refract_image *out)
{
    if (strncmp(r->content_type, "image/", 6) != 0 || r->body_len == 0)
        return refract_fail(c, REFRACT_E_PROTOCOL,
                            "POST %s: expected an image, got HTTP %ld "
                            "with Content-Type \"%s\" and %zu bytes",
                            path, r->status, r->content_type, r->body_len);
    out->bytes = r->body; /* ownership moves to the caller */
    out->len = r->body_len;
    r->body = NULL;
    refract_copy_string(out->content_type, sizeof(out->content_type), r->content_type);
    refract_copy_string(out->renderer, sizeof(out->renderer), r->renderer);
    refract_copy_string(out->irradiance, sizeof(out->irradiance), r->irradiance);
    out->render_ms = r->render_ms;
    return REFRACT_E_OK;
}

int refract_render(refract_client *c, const char *scene_id, const char *request_json,
                   struct refract_image *out)
{
    const char *body = request_json != NULL ? request_json : "{}";
    struct refract_response r;
    char *path;
    int code;

    if (out != NULL) {
        memset(out, 0, sizeof(*out)); /* the contract allows an uninitialised out */
        out->render_ms = -1.0;
    }
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (out == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_render: out is NULL");
    code = refract_scene_route(c, "refract_render", scene_id, "/render", &path);
    if (code != REFRACT_E_OK)
        return code;
    code = refract_http_exchange(c, "POST", path, body, strlen(body), "application/json", &r);
    if (code == REFRACT_E_OK)
        code = refract_http_check(c, "POST", path, &r);
    if (code == REFRACT_E_OK)
        code = take_image(c, path, &r, out);
    refract_response_free(&r);
    free(path);
    return code;
}

int refract_trace(refract_client *c, const char *scene_id, const char *request_json,
                  char **json_out)
{
    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (json_out == NULL || request_json == NULL)
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_trace: request_json and json_out "
                            "must not be NULL");
    return refract_scene_call_json(c, "refract_trace", "POST", scene_id, "/trace", request_json,
                                   strlen(request_json), "application/json", json_out);
}
