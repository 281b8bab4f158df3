/*
 * h_uploads.c - PUT /v1/scenes/{id}/volumes/{name} (raw, NRRD or OpenEXR; decoded and
 * validated by upload_volume.c) and PUT /v1/scenes/{id}/environment (an EXR, Radiance
 * HDR, PNG or JPEG image). Everything is validated before it is stored. Both bodies
 * arrive as a file streamed to <data>/tmp (server.c), never whole in memory.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../events/events.h"
#include "http_internal.h"

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

enum MHD_Result http_handle_volume_put(struct http_request *req)
{
    if (!octet_stream_or_415(req))
        return MHD_YES;
    const char *name = req->params[1];
    if (!store_name_valid(name, true))
        return http_respond_error(req, REFRACT_E_INVALID_FIELD,
                                  "volume name \"%s\": use 1..63 characters of A-Z a-z 0-9 _ -",
                                  name);
    struct store_volume *vol = NULL;
    enum MHD_Result answer = MHD_YES;
    if (!http_volume_upload(req, name, &vol, &answer))
        return answer;
    cJSON *root = http_volume_json(vol);
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
    enum refract_code rc = store_env_put_file(req->app->store, req->params[0], req->upload_path,
                                              req->upload_sha256, &w, &h, &e);
    req->upload_path[0] = '\0'; /* consumed by the store */
    if (rc != REFRACT_E_OK)
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
    cJSON_AddStringToObject(root, "sha256", req->upload_sha256);
    return http_respond_json(req, MHD_HTTP_CREATED, root);
}
