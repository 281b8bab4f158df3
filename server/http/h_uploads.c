/*
 * h_uploads.c - PUT /v1/scenes/{id}/volumes/{name} (raw little-endian float32 with the
 * dimensions in the query) and PUT /v1/scenes/{id}/environment (an EXR, Radiance HDR,
 * PNG or JPEG image). Everything is validated before it is stored: names, dimensions
 * against the body's size and the limits, finite values.
 *
 * Known limit: the body is held in memory while it is checked (up to
 * --max-upload-bytes); streaming to disk comes with the durable store (issue 5).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../events/events.h"
#include "http_internal.h"

static bool parse_dims(const char *text, int dims[3])
{
    char *end = NULL;
    for (int a = 0; a < 3; a++) {
        long v = strtol(text, &end, 10);
        if (end == text || v < 1 || v > 1000000)
            return false;
        dims[a] = (int)v;
        if (a < 2) {
            if (*end != ',')
                return false;
            text = end + 1;
        }
    }
    return *end == '\0';
}

static bool host_is_little_endian(void)
{
    const uint16_t probe = 1;
    return *(const uint8_t *)&probe == 1;
}

/* Copies the body into floats (swapping on big-endian hosts) and finds the first non-finite
 * value; returns its index or -1. */
static long long decode_floats(const char *body, float *out, size_t count)
{
    memcpy(out, body, count * sizeof(float));
    if (!host_is_little_endian()) {
        for (size_t i = 0; i < count; i++) {
            uint32_t u;
            memcpy(&u, &out[i], 4);
            u = __builtin_bswap32(u);
            memcpy(&out[i], &u, 4);
        }
    }
    for (size_t i = 0; i < count; i++) {
        if (!isfinite(out[i]))
            return (long long)i;
    }
    return -1;
}

/* True when the Content-Type is absent or application/octet-stream; otherwise answers 415
 * and returns false. */
static bool octet_stream_or_415(struct http_request *req)
{
    const char *ct =
        MHD_lookup_connection_value(req->conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_TYPE);
    if (ct == NULL || strncmp(ct, "application/octet-stream", 24) == 0)
        return true;
    http_respond_error(req, REFRACT_E_UNSUPPORTED_MEDIA_TYPE,
                       "Content-Type \"%s\" is not accepted here; send the raw bytes as "
                       "application/octet-stream",
                       ct);
    return false;
}

struct volume_query {
    int dims[3];
    int components;
};

/* Validates the query; answers and returns false on error. A misspelt parameter
 * (?component=3) is an error, not silently the default. */
static bool parse_volume_query(struct http_request *req, struct volume_query *q)
{
    static const char *const allowed[] = {"dims", "components", NULL};
    const char *unknown = http_query_unknown(req, allowed);
    if (unknown) {
        http_respond_error(req, REFRACT_E_UNKNOWN_FIELD,
                           "query parameter \"%s\" is not known here; allowed: dims, components",
                           unknown);
        return false;
    }
    const char *dims = MHD_lookup_connection_value(req->conn, MHD_GET_ARGUMENT_KIND, "dims");
    const char *comps = MHD_lookup_connection_value(req->conn, MHD_GET_ARGUMENT_KIND, "components");
    if (dims == NULL) {
        http_respond_error(req, REFRACT_E_MISSING_FIELD,
                           "query parameter dims is required, e.g. ?dims=64,64,64");
        return false;
    }
    if (!parse_dims(dims, q->dims)) {
        http_respond_error(req, REFRACT_E_INVALID_FIELD,
                           "query parameter dims: expected three positive integers X,Y,Z, got "
                           "\"%s\"",
                           dims);
        return false;
    }
    q->components = 1;
    if (comps && (strcmp(comps, "1") == 0 || strcmp(comps, "3") == 0)) {
        q->components = comps[0] - '0';
    } else if (comps) {
        http_respond_error(req, REFRACT_E_INVALID_FIELD,
                           "query parameter components: expected 1 (scalar) or 3 (RGB), got "
                           "\"%s\"",
                           comps);
        return false;
    }
    const struct scene_limits *lim = &req->cfg->limits;
    for (int a = 0; a < 3; a++) {
        if (q->dims[a] > lim->max_resolution) {
            http_respond_error(req, REFRACT_E_LIMIT_EXCEEDED,
                               "query parameter dims: %d voxels along %c exceed the limit of %d "
                               "(refractd --max-resolution)",
                               q->dims[a], "xyz"[a], lim -> max_resolution);
            return false;
        }
    }
    long long voxels = (long long)q->dims[0] * q->dims[1] * q->dims[2];
    if (voxels > lim->max_voxels) {
        http_respond_error(req, REFRACT_E_LIMIT_EXCEEDED,
                           "query parameter dims: %lld voxels exceed the limit of %lld "
                           "(refractd --max-voxels)",
                           voxels, (long long)lim->max_voxels);
        return false;
    }
    return true;
}

enum MHD_Result http_handle_volume_put(struct http_request *req)
{
    if (!octet_stream_or_415(req))
        return MHD_YES;
    const char *name = req->params[1];
    if (!store_name_valid(name, true))
        return http_respond_error(req, REFRACT_E_INVALID_FIELD,
                                  "volume name \"%s\": use 1..63 characters of A-Z a-z 0-9 _ -",
                                  name);
    struct volume_query q;
    if (!parse_volume_query(req, &q))
        return MHD_YES;
    enum MHD_Result answer = MHD_NO;
    struct store_scene *v = http_scene_or_404(req, &answer);
    if (v == NULL)
        return answer;
    store_scene_release(v);
    size_t count = (size_t)q.dims[0] * q.dims[1] * q.dims[2] * (size_t)q.components;
    if (req->body_len != count * sizeof(float))
        return http_respond_error(req, REFRACT_E_INVALID_VOLUME,
                                  "the body has %zu bytes but dims=%d,%d,%d with %d component(s) "
                                  "of float32 need %zu; check dims, components and the file",
                                  req->body_len, q.dims[0], q.dims[1], q.dims[2], q.components,
                                  count * sizeof(float));
    float *data = malloc(count * sizeof(float));
    if (data == NULL)
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory for the volume");
    long long bad = decode_floats(req->body, data, count);
    if (bad >= 0) {
        long long voxel = bad / q.components;
        int x = (int)(voxel % q.dims[0]), y = (int)((voxel / q.dims[0]) % q.dims[1]),
            z = (int)(voxel / ((long long)q.dims[0] * q.dims[1]));
        free(data);
        return http_respond_error(req, REFRACT_E_INVALID_VOLUME,
                                  "value %lld (voxel x=%d y=%d z=%d) is not a finite number; "
                                  "volumes must hold finite float32 values",
                                  bad, x, y, z);
    }
    struct store_volume *vol = NULL;
    struct err e = {0};
    if (store_volume_put(req->app->store, req->params[0], name, q.dims, q.components, data, count,
                         &vol, &e) != REFRACT_E_OK)
        return http_respond_err(req, &e);
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "name", vol->name);
    cJSON_AddItemToObject(root, "dims", cJSON_CreateIntArray(q.dims, 3));
    cJSON_AddNumberToObject(root, "components", q.components);
    cJSON_AddNumberToObject(root, "bytes", (double)(count * sizeof(float)));
    cJSON_AddNumberToObject(root, "min", vol->min);
    cJSON_AddNumberToObject(root, "max", vol->max);
    char sum[24];
    snprintf(sum, sizeof sum, "%016llx", (unsigned long long)vol->checksum);
    cJSON_AddStringToObject(root, "checksum_fnv1a64", sum);
    store_volume_release(vol);
    struct store_scene *now = store_scene_get(req->app->store, req->params[0]);
    if (now) {
        http_publish_scene(req->app, EVENT_SCENE_UPDATED, now->id, now, "volume");
        http_prepare_scene(req->app, now);
        store_scene_release(now);
    }
    return http_respond_json(req, MHD_HTTP_CREATED, root);
}

enum MHD_Result http_handle_environment_put(struct http_request *req)
{
    if (!octet_stream_or_415(req))
        return MHD_YES;
    enum MHD_Result answer = MHD_NO;
    struct store_scene *v = http_scene_or_404(req, &answer);
    if (v == NULL)
        return answer;
    store_scene_release(v);
    int w = 0, h = 0;
    struct err e = {0};
    if (store_env_put(req->app->store, req->params[0], req->body, req->body_len, &w, &h, &e) !=
        REFRACT_E_OK)
        return http_respond_err(req, &e);
    struct store_scene *now = store_scene_get(req->app->store, req->params[0]);
    if (now) {
        http_publish_scene(req->app, EVENT_SCENE_UPDATED, now->id, now, "environment");
        http_prepare_scene(req->app, now);
        store_scene_release(now);
    }
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "width", w);
    cJSON_AddNumberToObject(root, "height", h);
    cJSON_AddNumberToObject(root, "bytes", (double)req->body_len);
    return http_respond_json(req, MHD_HTTP_CREATED, root);
}
