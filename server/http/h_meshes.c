/*
 * h_meshes.c - POST /v1/scenes/{id}/meshes?name=NAME[&format=obj|ply]: a triangle mesh
 * (Wavefront OBJ, or PLY in ascii or binary) that mesh shapes of the scene refer to by
 * name (docs/scenes.md). The body is the file itself; its format is sniffed from its
 * first bytes unless ?format names it. Everything is validated before it is stored
 * (server/mesh: syntax, indices, finite coordinates, header counts against the bytes,
 * --max-mesh-triangles), and the answer says what was stored. Uploading under an
 * existing name replaces that mesh; the scene's GPU data is rebuilt.
 *
 * The body arrives as a file streamed to <data>/tmp (server.c, HTTP_BODY_UPLOAD), never
 * whole in memory; the store parses it mapped and keeps it as a blob (store_mesh.h).
 */
#include <stdio.h>
#include <string.h>

#include "../events/events.h"
#include "../store/store_mesh.h"
#include "http_internal.h"

cJSON *http_mesh_json(const struct store_mesh *m)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", m->name);
    cJSON_AddStringToObject(o, "format", mesh_format_name(m->format));
    cJSON_AddNumberToObject(o, "triangles", (double)m->mesh->triangle_count);
    cJSON_AddNumberToObject(o, "vertices", (double)m->mesh->vertex_count);
    cJSON_AddBoolToObject(o, "closed", m->mesh->closed);
    cJSON *b = cJSON_AddObjectToObject(o, "bounds");
    const double lo[3] = {m->mesh->lo.x, m->mesh->lo.y, m->mesh->lo.z};
    const double hi[3] = {m->mesh->hi.x, m->mesh->hi.y, m->mesh->hi.z};
    cJSON_AddItemToObject(b, "min", cJSON_CreateDoubleArray(lo, 3));
    cJSON_AddItemToObject(b, "max", cJSON_CreateDoubleArray(hi, 3));
    char sum[24];
    snprintf(sum, sizeof sum, "%016llx", (unsigned long long)m->checksum);
    cJSON_AddStringToObject(o, "checksum", sum);
    cJSON_AddNumberToObject(o, "bytes", (double)m->bytes);
    cJSON_AddStringToObject(o, "sha256", m->info.sha256);
    return o;
}

/* Mesh files are sent as raw bytes; these Content-Types (or none) are accepted. */
static bool content_type_ok(struct http_request *req)
{
    static const char *const ok[] = {
        "application/octet-stream", "text/plain",        "model/obj", "model/ply",
        "application/ply",          "application/x-ply", NULL};
    const char *ct =
        MHD_lookup_connection_value(req->conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_TYPE);
    if (ct == NULL)
        return true;
    for (const char *const *t = ok; *t; t++) {
        if (strncmp(ct, *t, strlen(*t)) == 0)
            return true;
    }
    http_respond_error(req, REFRACT_E_UNSUPPORTED_MEDIA_TYPE,
                       "Content-Type \"%s\" is not accepted here; send the OBJ or PLY file's "
                       "bytes as application/octet-stream (or model/obj, model/ply, text/plain)",
                       ct);
    return false;
}

/* Reads ?name and ?format; answers and returns false when they are wrong. */
static bool parse_query(struct http_request *req, const char **name, enum mesh_format *format)
{
    static const char *const allowed[] = {"name", "format", NULL};
    const char *unknown = http_query_unknown(req, allowed);
    if (unknown) {
        http_respond_error(req, REFRACT_E_UNKNOWN_FIELD,
                           "query parameter \"%s\" is not known here; allowed: name, format",
                           unknown);
        return false;
    }
    *name = MHD_lookup_connection_value(req->conn, MHD_GET_ARGUMENT_KIND, "name");
    if (*name == NULL) {
        http_respond_error(req, REFRACT_E_MISSING_FIELD,
                           "query parameter name is required, e.g. ?name=glass; mesh shapes "
                           "refer to the mesh by it");
        return false;
    }
    if (!store_name_valid(*name, true)) {
        http_respond_error(req, REFRACT_E_INVALID_FIELD,
                           "query parameter name: \"%.80s\" is not a mesh name; use 1..63 "
                           "characters of A-Z a-z 0-9 _ -",
                           *name);
        return false;
    }
    const char *f = MHD_lookup_connection_value(req->conn, MHD_GET_ARGUMENT_KIND, "format");
    *format = MESH_FORMAT_UNKNOWN;
    if (f != NULL && strcmp(f, "obj") == 0) {
        *format = MESH_FORMAT_OBJ;
    } else if (f != NULL && strcmp(f, "ply") == 0) {
        *format = MESH_FORMAT_PLY;
    } else if (f != NULL) {
        http_respond_error(req, REFRACT_E_INVALID_FIELD,
                           "query parameter format: expected obj or ply, got \"%.40s\" (leave it "
                           "out to detect the format from the file)",
                           f);
        return false;
    }
    return true;
}

enum MHD_Result http_handle_mesh_post(struct http_request *req)
{
    if (!content_type_ok(req))
        return MHD_YES;
    const char *name;
    enum mesh_format format;
    if (!parse_query(req, &name, &format))
        return MHD_YES;
    enum MHD_Result answer = MHD_NO;
    struct store_scene *v = http_scene_or_404(req, &answer);
    if (v == NULL)
        return answer;
    store_scene_release(v);
    if (req->body_len == 0)
        return http_respond_error(req, REFRACT_E_INVALID_MESH,
                                  "the request body is empty; send the OBJ or PLY file as the "
                                  "body");
    struct store_mesh *m = NULL;
    struct err e = {0};
    enum refract_code rc =
        store_mesh_put_file(req->app->store, req->params[0], name, req->upload_path,
                            req->upload_sha256, format, &m, &e);
    req->upload_path[0] = '\0'; /* consumed by the store */
    if (rc != REFRACT_E_OK)
        return http_respond_err(req, &e);
    cJSON *root = http_mesh_json(m);
    store_mesh_release(m);
    struct store_scene *now = store_scene_get(req->app->store, req->params[0]);
    if (now) {
        http_publish_scene(req->app, EVENT_SCENE_UPDATED, now->id, now, "mesh");
        http_prepare_scene(req->app, now);
        store_scene_release(now);
    }
    return http_respond_json(req, MHD_HTTP_CREATED, root);
}
