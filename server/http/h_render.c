/*
 * h_render.c - POST /v1/scenes/{id}/render and POST /v1/scenes/{id}/trace.
 *
 * Both parse and validate on the HTTP thread, take a reference to the scene's current
 * version, and hand a job to the GPU thread (http_suspend_for_gpu). The GPU thread runs
 * render_view / render_trace; back on an HTTP thread the result is encoded (tone mapping
 * and PNG/JPEG, or linear EXR) or written as JSON.
 *
 * A render first asks the irradiance cache for its lights' volumes (HTTP thread: queues
 * what is missing, reads back what is on disk), then, on the GPU thread, gathers the best
 * volume of each light: the current pose's, else the previous pose's while the new one is
 * computed. It never waits for a recompute; X-Refract-Irradiance says what it used.
 *
 * A render larger than --render-tile-pixels is drawn in tiles of whole rows, one per turn
 * of its GPU work item (render_tiles.h, shared with view frames and job frames), so that
 * work queued behind it runs between its tiles: a small render waits for one tile, not for
 * the whole large one. The tiles equal a render made at once. Before each turn the queue
 * drops the render when its client has gone, or when its deadline (--request-timeout-ms)
 * has passed.
 * Renders drawn in tiles are in progress together, each holding its whole image, so
 * together they may hold at most --max-image-pixels pixels: one that does not fit waits
 * (its turns pass without drawing) until renders in progress finish. One always fits.
 */
#include <math.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../cache/irradiance_cache.h"
#include "../core/ray_status.h"
#include "../io/io_image.h"
#include "../request/render_tiles.h"
#include "http_internal.h"

/* ---- render ---------------------------------------------------------------------------- */

struct render_job {
    struct store_scene *version; /* owned reference */
    struct http_render_request request;
    struct render_view_result result;
    struct render_light lights[SCENE_MAX_LIGHTS];
    const char *irradiance;    /* X-Refract-Irradiance: ready|stale|missing|not-needed */
    struct render_tiles tiles; /* GPU thread: the tile loop (render_tiles.h) */
    long long pixels_held;     /* counted in tiled_pixels while drawing */
};

/* Pixels of the tiled renders in progress (begun, not finished), every client's. */
static atomic_llong tiled_pixels;

static void release_pixels(struct render_job *job)
{
    if (job->pixels_held > 0)
        atomic_fetch_sub(&tiled_pixels, job->pixels_held);
    job->pixels_held = 0;
}

/* GPU thread, first turn of a render drawn in tiles: counts its pixels unless that would
 * pass the limit while others are in progress (then it waits; false). */
static bool take_pixels(struct render_job *job, long long limit)
{
    const struct scene_camera *cam = &job->request.view.camera;
    long long pixels = (long long)cam->width * cam->height;
    if (render_tiles_at_once(&job->tiles))
        return true; /* one turn: drawn at once, like any small render */
    long long held = atomic_load(&tiled_pixels);
    if (held > 0 && held + pixels > limit)
        return false;
    atomic_fetch_add(&tiled_pixels, pixels);
    job->pixels_held = pixels;
    return true;
}

static void render_job_free(void *p)
{
    struct render_job *job = p;
    release_pixels(job); /* a render dropped or failed between two tiles */
    store_scene_release(job->version);
    free(job->result.rgba);
    free(job);
}

/* One tile per turn; asks for another turn until every row is drawn. */
static void render_run(struct gpu_work *w, struct gpu *gpu)
{
    (void)gpu;
    struct http_request *req = w->user;
    struct render_job *job = req->job;
    /* The image is made on the first turn, not when queued: a render waiting in line holds
     * none. */
    if (job->result.rgba == NULL && !take_pixels(job, req->cfg->max_image_pixels)) {
        w->again = true; /* no room: let the renders in progress go on */
        return;
    }
    bool more = false;
    if (render_tiles_step(&job->tiles, req->app->render, req->app->irradiance, req->app->store,
                          job->version, &job->request.view, job->lights, &job->result,
                          &job->irradiance, &more, &w->err) != REFRACT_E_OK)
        return;
    w->again = more;
    if (!more)
        release_pixels(job);
}

static enum refract_code encode(const struct render_job *job, void **bytes, size_t *len,
                                const char **content_type, struct err *e)
{
    const struct render_view_result *r = &job->result;
    const struct http_render_request *rq = &job->request;
    enum io_frame_format format = rq->format == HTTP_FORMAT_EXR    ? IO_FRAME_EXR
                                  : rq->format == HTTP_FORMAT_JPEG ? IO_FRAME_JPEG
                                                                   : IO_FRAME_PNG;
    *content_type = format == IO_FRAME_EXR    ? "image/x-exr"
                    : format == IO_FRAME_JPEG ? "image/jpeg"
                                              : "image/png";
    return io_encode_frame(r->rgba, r->width, r->height, format, rq->exposure_ev,
                           rq->tonemap == SCENE_TONEMAP_FILMIC ? IO_TONEMAP_FILMIC
                                                               : IO_TONEMAP_CLAMP,
                           rq->jpeg_quality, bytes, len, e);
}

static enum MHD_Result render_answer(struct http_request *req)
{
    struct render_job *job = req->job;
    if (req->work.err.code != REFRACT_E_OK)
        return http_respond_err(req, &req->work.err);
    void *bytes = NULL;
    size_t len = 0;
    const char *content_type = NULL;
    struct err e = {0};
    double t0 = gpu_time_ms();
    if (encode(job, &bytes, &len, &content_type, &e) != REFRACT_E_OK)
        return http_respond_err(req, &e);
    char gpu_ms[32], total_ms[32], encode_ms[32], size[32], generation[32];
    snprintf(gpu_ms, sizeof gpu_ms, "%.3f", job->result.gpu_ms);
    snprintf(total_ms, sizeof total_ms, "%.3f", gpu_time_ms() - req->started_ms);
    snprintf(encode_ms, sizeof encode_ms, "%.3f", gpu_time_ms() - t0);
    snprintf(size, sizeof size, "%dx%d", job->result.width, job->result.height);
    snprintf(generation, sizeof generation, "%llu", (unsigned long long)job->version->generation);
    const char *headers[] = {"X-Render-Time-Ms",
                             gpu_ms,
                             "X-Request-Time-Ms",
                             total_ms,
                             "X-Encode-Time-Ms",
                             encode_ms,
                             "X-Renderer",
                             gpu_info(req->app->gpu)->renderer,
                             "X-Image-Size",
                             size,
                             "X-Scene-Generation",
                             generation,
                             "X-Refract-Irradiance",
                             job->irradiance ? job->irradiance : "missing",
                             NULL};
    return http_respond_bytes(req, MHD_HTTP_OK, bytes, len, content_type, headers);
}

enum MHD_Result http_handle_render(struct http_request *req)
{
    if (http_render_is_reference(req->body, req->body_len))
        return http_handle_render_reference(req);
    enum MHD_Result answer = MHD_NO;
    struct store_scene *v = http_scene_or_404(req, &answer);
    if (v == NULL)
        return answer;
    struct render_job *job = calloc(1, sizeof *job);
    if (job == NULL) {
        store_scene_release(v);
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory");
    }
    job->version = v;
    req->job = job;
    req->job_free = render_job_free;
    struct err e = {0};
    if (http_parse_render_request(req->body, req->body_len, v->scene, req->cfg, &job->request,
                                  &e) != REFRACT_E_OK)
        return http_respond_err(req, &e);
    const struct scene_camera *cam = &job->request.view.camera;
    render_tiles_init(&job->tiles, req->cfg->render_tile_pixels, cam->width, cam->height);
    struct irradiance_source isrc;
    render_request_irradiance_source(v, &isrc);
    irradiance_cache_request(req->app->irradiance, &isrc, false);
    req->work.label = "render";
    req->work.run = render_run;
    return http_suspend_for_gpu(req, render_answer);
}

/* ---- trace ----------------------------------------------------------------------------- */

struct trace_job {
    struct store_scene *version; /* owned reference */
    struct scene_render_settings settings;
    struct render_trace_ray *rays;
    struct render_trace_hit *hits;
    struct render_trace_event *events; /* "events": true; RENDER_TRACE_MAX_EVENTS per ray */
    size_t count;
    double gpu_ms;
};

static void trace_job_free(void *p)
{
    struct trace_job *job = p;
    store_scene_release(job->version);
    free(job->rays);
    free(job->hits);
    free(job->events);
    free(job);
}

static void trace_run(struct gpu_work *w, struct gpu *gpu)
{
    (void)gpu;
    struct http_request *req = w->user;
    struct trace_job *job = req->job;
    struct render_scene_source src = render_request_scene_source(job->version);
    render_trace_events(req->app->render, &src, &job->settings, job->rays, job->count, job->hits,
                        job->events, &job->gpu_ms, &w->err);
}

static cJSON *vec3_json(const double v[3])
{
    return cJSON_CreateDoubleArray(v, 3);
}

static const char *medium_name(const struct scene *s, int medium)
{
    return medium >= 0 && (size_t)medium < s->surface_count ? s->surfaces[medium].name : "ambient";
}

/* The ray's surface events ("events": true; docs/api.md "Trace"). */
static void add_events(cJSON *o, const struct scene *s, const struct render_trace_hit *h,
                       const struct render_trace_event *ev)
{
    cJSON *arr = cJSON_AddArrayToObject(o, "events");
    int n = h->event_count < RENDER_TRACE_MAX_EVENTS ? h->event_count : RENDER_TRACE_MAX_EVENTS;
    for (int k = 0; k < n; k++) {
        const struct render_trace_event *e = &ev[k];
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "kind",
                                e->kind == TRACE_EVENT_REFLECTED ? "reflected" : "refracted");
        cJSON_AddStringToObject(j, "surface", medium_name(s, e->surface));
        cJSON_AddItemToObject(j, "point", vec3_json(e->point));
        cJSON_AddItemToObject(j, "normal", vec3_json(e->normal));
        cJSON_AddStringToObject(j, "medium_before", medium_name(s, e->medium_from));
        cJSON_AddStringToObject(j, "medium_after", medium_name(s, e->medium_to));
        cJSON_AddNumberToObject(j, "n_before", e->n_from);
        cJSON_AddNumberToObject(j, "n_after", e->n_to);
        cJSON_AddNumberToObject(j, "fresnel_reflectance", e->fresnel_R);
        cJSON_AddItemToArray(arr, j);
    }
    cJSON_AddNumberToObject(o, "event_count", h->event_count);
}

static enum MHD_Result trace_answer(struct http_request *req)
{
    struct trace_job *job = req->job;
    if (req->work.err.code != REFRACT_E_OK)
        return http_respond_err(req, &req->work.err);
    cJSON *root = cJSON_CreateObject();
    cJSON *arr = cJSON_AddArrayToObject(root, "rays");
    for (size_t i = 0; i < job->count; i++) {
        const struct render_trace_hit *h = &job->hits[i];
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "status", ray_status_json(h->status));
        cJSON_AddItemToObject(o, "exit_origin", vec3_json(h->exit_origin));
        cJSON_AddItemToObject(o, "exit_direction", vec3_json(h->exit_direction));
        cJSON_AddItemToObject(o, "transmittance", vec3_json(h->transmittance));
        cJSON_AddNumberToObject(o, "optical_path_length", h->optical_path_length);
        cJSON_AddNumberToObject(o, "steps", h->steps);
        if (job->events != NULL)
            add_events(o, job->version->scene, h, &job->events[i * RENDER_TRACE_MAX_EVENTS]);
        cJSON_AddItemToArray(arr, o);
    }
    cJSON_AddNumberToObject(root, "gpu_ms", job->gpu_ms);
    cJSON_AddStringToObject(root, "renderer", gpu_info(req->app->gpu)->renderer);
    return http_respond_json(req, MHD_HTTP_OK, root);
}

enum MHD_Result http_handle_trace(struct http_request *req)
{
    enum MHD_Result answer = MHD_NO;
    struct store_scene *v = http_scene_or_404(req, &answer);
    if (v == NULL)
        return answer;
    struct trace_job *job = calloc(1, sizeof *job);
    if (job == NULL) {
        store_scene_release(v);
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory");
    }
    job->version = v;
    req->job = job;
    req->job_free = trace_job_free;
    struct err e = {0};
    bool events = false;
    if (http_parse_trace_request(req->body, req->body_len, v->scene, req->cfg, &job->settings,
                                 &job->rays, &job->count, &events, &e) != REFRACT_E_OK)
        return http_respond_err(req, &e);
    job->hits = calloc(job->count, sizeof *job->hits);
    if (job->hits == NULL)
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory for the hits");
    /* Each origin's inside set here, on the HTTP thread, not on the GPU thread. */
    struct render_scene_source src = render_request_scene_source(v);
    for (size_t i = 0; i < job->count; i++) {
        struct render_trace_ray *r = &job->rays[i];
        vec3 o = {r->origin[0], r->origin[1], r->origin[2]};
        r->inside = scene_surfaces_inside(v->scene, src.lookup, src.lookup_ctx, o);
        r->inside_known = true;
    }
    if (events) {
        job->events = calloc(job->count * RENDER_TRACE_MAX_EVENTS, sizeof *job->events);
        if (job->events == NULL)
            return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY,
                                      "out of memory for the events; trace fewer rays at a time");
    }
    req->work.label = "trace";
    req->work.run = trace_run;
    return http_suspend_for_gpu(req, trace_answer);
}
