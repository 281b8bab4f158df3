/*
 * h_scenes.c - GET /v1/health and the scene resource: create, list, show, delete; and the
 * background build of a scene's GPU data that follows a create or an upload.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../cache/irradiance_cache.h"
#include "../core/log.h"
#include "../events/events.h"
#include "../gpu/resources.h"
#include "../store/store_mesh.h"
#include "http_internal.h"

static time_t started_at;

__attribute__((constructor)) static void note_start_time(void)
{
    started_at = time(NULL);
}

enum MHD_Result http_handle_health(struct http_request *req)
{
    const struct gpu_context_info *info = gpu_info(req->app->gpu);
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "status", "ok");
    cJSON_AddStringToObject(root, "version", REFRACT_VERSION);
    cJSON *gpu = cJSON_AddObjectToObject(root, "gpu");
    cJSON_AddStringToObject(gpu, "vendor", info->vendor);
    cJSON_AddStringToObject(gpu, "renderer", info->renderer);
    cJSON_AddStringToObject(gpu, "version", info->version);
    cJSON_AddStringToObject(gpu, "device", info->device_kind);
    cJSON_AddNumberToObject(gpu, "egl_device_index", info->device_index);
    cJSON_AddNumberToObject(gpu, "egl_device_count", info->device_count);
    cJSON_AddNumberToObject(gpu, "max_3d_texture_size", info->max_3d_texture_size);
    cJSON_AddNumberToObject(gpu, "memory_in_use_bytes", (double)gpu_memory_in_use());
    cJSON_AddNumberToObject(root, "queue_length", (double)gpu_queue_length(req->app->gpu));
    cJSON_AddNumberToObject(root, "uptime_s", (double)(time(NULL) - started_at));
    struct store_scene **list = NULL;
    size_t n = store_scene_list(req->app->store, &list);
    store_list_free(list, n);
    cJSON_AddNumberToObject(root, "scenes", (double)n);
    const struct http_config *c = req->cfg;
    cJSON *lim = cJSON_AddObjectToObject(root, "limits");
    cJSON_AddNumberToObject(lim, "max_resolution", c->limits.max_resolution);
    cJSON_AddNumberToObject(lim, "max_voxels", (double)c->limits.max_voxels);
    cJSON_AddNumberToObject(lim, "max_upload_voxels", (double)c->limits.max_upload_voxels);
    cJSON_AddNumberToObject(lim, "max_objects", c->limits.max_objects);
    cJSON_AddNumberToObject(lim, "max_image_dim", c->limits.max_image_dim);
    cJSON_AddNumberToObject(lim, "max_image_pixels", (double)c->max_image_pixels);
    cJSON_AddNumberToObject(lim, "max_steps", c->limits.max_steps);
    cJSON_AddNumberToObject(lim, "max_rays", c->max_rays);
    cJSON_AddNumberToObject(lim, "max_json_bytes", (double)c->max_json_bytes);
    cJSON_AddNumberToObject(lim, "max_upload_bytes", (double)c->max_upload_bytes);
    cJSON_AddNumberToObject(lim, "request_timeout_ms", c->request_timeout_ms);
    /* docs/api.md "Fair sharing", as in force (--max-connections may have been lowered to
     * fit the descriptor limit at start). */
    cJSON *fair = cJSON_AddObjectToObject(root, "fair_sharing");
    cJSON_AddNumberToObject(fair, "max_connections", c->max_connections);
    cJSON_AddNumberToObject(fair, "max_connections_per_ip", c->max_connections_per_ip);
    cJSON_AddNumberToObject(fair, "max_queued_per_client", c->max_queued_per_client);
    cJSON_AddNumberToObject(fair, "header_timeout_s", c->header_timeout_s);
    cJSON_AddNumberToObject(fair, "header_deadline_s", c->header_deadline_s);
    cJSON_AddNumberToObject(fair, "upload_min_rate", (double)c->upload_min_rate);
    cJSON_AddNumberToObject(fair, "connection_timeout_s", c->connection_timeout_s);
    cJSON_AddNumberToObject(fair, "render_tile_pixels", (double)c->render_tile_pixels);
    cJSON_AddNumberToObject(fair, "max_image_pixels", (double)c->max_image_pixels);
    cJSON_AddNumberToObject(fair, "request_timeout_ms", c->request_timeout_ms);
    const struct irradiance_cache_desc *ic = irradiance_cache_settings(req->app->irradiance);
    struct irradiance_cache_counters k;
    irradiance_cache_counters(req->app->irradiance, &k);
    cJSON *irr = cJSON_AddObjectToObject(root, "irradiance");
    cJSON_AddNumberToObject(irr, "gpu_budget_bytes", (double)ic->gpu_budget_bytes);
    cJSON_AddNumberToObject(irr, "host_budget_bytes", (double)ic->host_budget_bytes);
    cJSON_AddNumberToObject(irr, "position_tolerance", ic->position_tolerance);
    cJSON_AddNumberToObject(irr, "direction_tolerance", ic->direction_tolerance);
    cJSON_AddNumberToObject(irr, "chunk_steps", ic->chunk_steps);
    cJSON_AddNumberToObject(irr, "entries", k.entries);
    cJSON_AddNumberToObject(irr, "gpu_bytes", (double)k.gpu_bytes);
    cJSON_AddNumberToObject(irr, "host_bytes", (double)k.host_bytes);
    return http_respond_json(req, MHD_HTTP_OK, root);
}

/* ---- background scene builds -------------------------------------------------------- */

struct prepare_job {
    struct gpu_work work;
    const struct http_app *app;
    struct store_scene *version; /* owned reference */
};

static void prepare_run(struct gpu_work *w, struct gpu *gpu)
{
    (void)gpu;
    struct prepare_job *job = w->user;
    struct store_scene *v = job->version;
    struct store_gpu_status st = {.generation = v->generation};
    /* A newer version supersedes this one: skip the build, the newer job will do it. */
    struct store_scene *current = store_scene_get(job->app->store, v->id);
    bool stale = current == NULL || current->generation != v->generation;
    store_scene_release(current);
    if (stale)
        return;
    struct render_scene_source src = render_request_scene_source(v);
    struct render_scene_status rs;
    struct err e = {0};
    if (render_scene_prepare(job->app->render, &src, &rs, &e) == REFRACT_E_OK) {
        snprintf(st.state, sizeof st.state, "ready");
        st.gpu_bytes = rs.gpu_bytes;
        st.build_ms = rs.build_ms;
    } else {
        snprintf(st.state, sizeof st.state, "failed");
        snprintf(st.message, sizeof st.message, "%s", e.msg);
        log_warn("render", "scene %s: %s", v->id, e.msg);
    }
    store_gpu_status_set(job->app->store, v->id, &st);
}

static void prepare_done(struct gpu_work *w)
{
    struct prepare_job *job = w->user;
    store_scene_release(job->version);
    free(job);
}

void http_prepare_scene(const struct http_app *app, struct store_scene *version)
{
    struct irradiance_source isrc;
    render_request_irradiance_source(version, &isrc);
    irradiance_cache_request(app->irradiance, &isrc, false);
    struct prepare_job *job = calloc(1, sizeof *job);
    if (job == NULL)
        return;
    atomic_fetch_add(&version->refs, 1);
    job->app = app;
    job->version = version;
    job->work = (struct gpu_work){.priority = GPU_PRIORITY_MAINTENANCE,
                                  .skip_on_shutdown = true,
                                  .label = "scene build",
                                  .run = prepare_run,
                                  .done = prepare_done,
                                  .user = job};
    struct store_gpu_status st = {.generation = version->generation};
    snprintf(st.state, sizeof st.state, "pending");
    store_gpu_status_set(app->store, version->id, &st);
    struct err e;
    if (gpu_submit(app->gpu, &job->work, &e) != REFRACT_E_OK) {
        store_scene_release(version);
        free(job);
    }
}

struct forget_job {
    struct gpu_work work;
    const struct http_app *app;
    char id[STORE_ID_MAX];
};

static void forget_run(struct gpu_work *w, struct gpu *gpu)
{
    (void)gpu;
    struct forget_job *job = w->user;
    render_scene_forget(job->app->render, job->id);
}

static void forget_done(struct gpu_work *w)
{
    free(w->user);
}

static void forget_scene(const struct http_app *app, const char *id)
{
    struct forget_job *job = calloc(1, sizeof *job);
    if (job == NULL)
        return;
    job->app = app;
    snprintf(job->id, sizeof job->id, "%.*s", STORE_ID_MAX - 1, id);
    job->work = (struct gpu_work){.priority = GPU_PRIORITY_MAINTENANCE,
                                  .label = "scene free",
                                  .run = forget_run,
                                  .done = forget_done,
                                  .user = job};
    struct err e;
    if (gpu_submit(app->gpu, &job->work, &e) != REFRACT_E_OK)
        free(job);
}

/* ---- the scene resource --------------------------------------------------------------- */

struct store_scene *http_scene_or_404(struct http_request *req, enum MHD_Result *answer)
{
    struct store_scene *v = store_scene_get(req->app->store, req->params[0]);
    if (v == NULL)
        *answer = http_respond_error(req, REFRACT_E_SCENE_NOT_FOUND,
                                     "no scene with id \"%s\"; GET /v1/scenes lists the scenes",
                                     req->params[0]);
    return v;
}

static void add_volumes(const struct store_scene *v, cJSON *obj)
{
    cJSON *vols = cJSON_AddArrayToObject(obj, "volumes");
    for (size_t i = 0; i < v->volume_count; i++) {
        const struct store_volume *vol = v->volumes[i];
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", vol->name);
        int dims[3] = {vol->view.dims[0], vol->view.dims[1], vol->view.dims[2]};
        cJSON_AddItemToObject(o, "dims", cJSON_CreateIntArray(dims, 3));
        cJSON_AddNumberToObject(o, "components", vol->view.components);
        cJSON_AddNumberToObject(o, "bytes", (double)(vol->count * sizeof(float)));
        char sum[24];
        snprintf(sum, sizeof sum, "%016llx", (unsigned long long)vol->checksum);
        cJSON_AddStringToObject(o, "checksum_fnv1a64", sum);
        cJSON_AddStringToObject(o, "sha256", vol->info.sha256);
        cJSON_AddItemToArray(vols, o);
    }
}

void http_scene_summary(const struct http_app *app, const struct store_scene *v, cJSON *obj,
                        bool detailed)
{
    cJSON_AddStringToObject(obj, "id", v->id);
    cJSON_AddStringToObject(obj, "name", v->scene->name);
    cJSON_AddNumberToObject(obj, "generation", (double)v->generation);
    cJSON_AddNumberToObject(obj, "objects", (double)v->scene->object_count);
    struct store_gpu_status st;
    cJSON *gpu = cJSON_AddObjectToObject(obj, "gpu");
    if (store_gpu_status_get(app->store, v->id, &st)) {
        cJSON_AddStringToObject(gpu, "state", st.state);
        cJSON_AddNumberToObject(gpu, "generation", (double)st.generation);
        cJSON_AddNumberToObject(gpu, "memory_bytes", (double)st.gpu_bytes);
        cJSON_AddNumberToObject(gpu, "build_ms", st.build_ms);
        if (st.message[0])
            cJSON_AddStringToObject(gpu, "message", st.message);
    } else {
        cJSON_AddStringToObject(gpu, "state", "pending");
    }
    if (!detailed)
        return;
    add_volumes(v, obj);
    cJSON *env = cJSON_AddObjectToObject(obj, "environment");
    cJSON_AddStringToObject(env, "type",
                            v->scene->environment.kind == SCENE_ENV_IMAGE ? "image" : "procedural");
    cJSON_AddBoolToObject(env, "image_uploaded", v->env != NULL);
    if (v->env) {
        cJSON_AddNumberToObject(env, "width", v->env->width);
        cJSON_AddNumberToObject(env, "height", v->env->height);
    }
    char missing[256];
    int n =
        scene_missing_volumes(v->scene, store_volume_lookup, (void *)v, missing, sizeof missing);
    if (n > 0)
        cJSON_AddStringToObject(obj, "missing_volumes", missing);
    cJSON *meshes = cJSON_AddArrayToObject(obj, "meshes");
    for (size_t i = 0; i < v->mesh_count; i++)
        cJSON_AddItemToArray(meshes, http_mesh_json(v->meshes[i]));
    if (scene_missing_meshes(v->scene, store_volume_lookup, (void *)v, missing, sizeof missing) > 0)
        cJSON_AddStringToObject(obj, "missing_meshes", missing);
    cJSON *doc = cJSON_ParseWithLength(v->json, v->json_len);
    if (doc)
        cJSON_AddItemToObject(obj, "document", doc);
}

enum MHD_Result http_handle_scene_create(struct http_request *req)
{
    struct store_scene *v = NULL;
    struct err e = {0};
    if (req->body_len == 0)
        return http_respond_error(req, REFRACT_E_INVALID_JSON,
                                  "the request body is empty; send a scene document (see "
                                  "proto/scene.schema.json and proto/examples/)");
    if (store_scene_create(req->app->store, NULL, req->body, req->body_len, &v, &e) != REFRACT_E_OK)
        return http_respond_err(req, &e);
    http_publish_scene(req->app, EVENT_SCENE_CREATED, v->id, v, NULL);
    http_prepare_scene(req->app, v);
    cJSON *root = cJSON_CreateObject();
    http_scene_summary(req->app, v, root, false);
    char location[128];
    snprintf(location, sizeof location, "/v1/scenes/%s", v->id);
    store_scene_release(v);
    char *text = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    if (text == NULL)
        return MHD_NO;
    const char *headers[] = {"Location", location, NULL};
    return http_respond_bytes(req, MHD_HTTP_CREATED, text, strlen(text), "application/json",
                              headers);
}

enum MHD_Result http_handle_scene_list(struct http_request *req)
{
    struct store_scene **list = NULL;
    size_t n = store_scene_list(req->app->store, &list);
    cJSON *root = cJSON_CreateObject();
    cJSON *arr = cJSON_AddArrayToObject(root, "scenes");
    for (size_t i = 0; i < n; i++) {
        cJSON *o = cJSON_CreateObject();
        http_scene_summary(req->app, list[i], o, false);
        cJSON_AddItemToArray(arr, o);
    }
    store_list_free(list, n);
    return http_respond_json(req, MHD_HTTP_OK, root);
}

enum MHD_Result http_handle_scene_get(struct http_request *req)
{
    enum MHD_Result answer = MHD_NO;
    struct store_scene *v = http_scene_or_404(req, &answer);
    if (v == NULL)
        return answer;
    cJSON *root = cJSON_CreateObject();
    http_scene_summary(req->app, v, root, true);
    store_scene_release(v);
    return http_respond_json(req, MHD_HTTP_OK, root);
}

enum MHD_Result http_handle_scene_delete(struct http_request *req)
{
    struct err e = {0};
    if (store_scene_delete(req->app->store, req->params[0], &e) != REFRACT_E_OK)
        return http_respond_err(req, &e);
    http_publish_scene(req->app, EVENT_SCENE_DELETED, req->params[0], NULL, NULL);
    forget_scene(req->app, req->params[0]);
    irradiance_cache_forget_scene(req->app->irradiance, req->params[0]);
    return http_respond_empty(req, MHD_HTTP_NO_CONTENT);
}
