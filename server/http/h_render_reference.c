/*
 * h_render_reference.c - POST /v1/scenes/{id}/render with "mode": "reference": the CPU
 * reference path tracer (core/pathtrace.h, docs/pathtracer.md) renders the scene's
 * current version to a sample count per pixel and/or a time budget, and answers linear
 * EXR (R, G, B, A and the variance of each pixel's mean, variance.R/G/B) or a tone-mapped
 * PNG/JPEG of the mean.
 *
 * DESIGN: the render runs on CPU threads, never on the GPU thread (a reference render
 * takes seconds to minutes and would stall every view). The handler parses and validates
 * on the HTTP thread, suspends the connection and starts one detached coordinator
 * thread, which renders (request/reference_render.h: one worker per online CPU over
 * interleaved rows, until the sample count, the time budget or the daemon's stop), then
 * resumes the connection; the answer is encoded back on an HTTP thread. One reference
 * render runs at a time in refractd, this or a job's frame (it uses every core); another
 * request is answered 503 busy.
 * REALITY: the workers are started per request rather than kept in a pool: their start
 * costs microseconds against renders of seconds.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../core/pathtrace_image.h"
#include "../io/io_exr.h"
#include "../request/reference_render.h"
#include "../io/io_image.h"
#include "../scene/json_read.h"
#include "../scene/scene_pathtrace.h"
#include "http_internal.h"

#define REFERENCE_MAX_SAMPLES 65536 /* http_config.max_reference_samples 0 */
#define REFERENCE_MAX_MS 120000     /* http_config.max_reference_ms 0 */

struct reference_job {
    struct store_scene *version; /* owned reference */
    struct http_request *req;    /* borrowed: the suspended connection outlives the job */
    struct scene_pathtrace pt;   /* borrows version->scene */
    struct pathtrace_camera cam;
    struct pathtrace_image img;
    int samples;        /* target per pixel */
    double deadline_ms; /* gpu_time_ms() clock */
    uint64_t seed;
    int threads;
    enum { REF_PNG, REF_JPEG, REF_EXR } format;
    double exposure_ev;
    enum scene_tonemap tonemap;
    int jpeg_quality;
    double render_ms;
    bool cancelled;    /* the daemon is stopping */
    bool start_failed; /* no coordinator thread could be started */
};

static void reference_job_free(void *p)
{
    struct reference_job *job = p;
    store_scene_release(job->version);
    pathtrace_image_fini(&job->img);
    free(job);
}

void http_reference_cancel_all(void)
{
    reference_cancel_all();
}

static void *coordinator_main(void *arg)
{
    struct reference_job *job = arg;
    struct http_request *req = job->req;
    job->render_ms = reference_render(&job->pt.scene, &job->cam, &job->img, job->samples,
                                      job->deadline_ms, job->seed, job->threads, &job->cancelled);
    reference_end();
    req->phase = HTTP_PHASE_RESUMED;
    MHD_resume_connection(req->conn);
    return NULL;
}

static enum MHD_Result reference_answer(struct http_request *req)
{
    struct reference_job *job = req->job;
    if (job->start_failed)
        return http_respond_error(req, REFRACT_E_INTERNAL,
                                  "could not start a reference render thread (out of threads?)");
    if (job->cancelled)
        return http_respond_error(req, REFRACT_E_SHUTTING_DOWN,
                                  "refractd is stopping; the reference render was cancelled");
    float *rgba = NULL, *exr = NULL;
    uint32_t min_n, max_n;
    double rel_noise;
    if (!reference_image_floats(&job->img, &rgba, &exr, &min_n, &max_n, &rel_noise))
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory encoding %dx%d",
                                  job->img.width, job->img.height);
    char samples[32], samples_max[32], noise[32], render_ms[32], size[32], spp_s[32];
    snprintf(samples, sizeof samples, "%u", min_n);
    snprintf(samples_max, sizeof samples_max, "%u", max_n);
    snprintf(noise, sizeof noise, "%.6g", rel_noise);
    snprintf(render_ms, sizeof render_ms, "%.3f", job->render_ms);
    snprintf(size, sizeof size, "%dx%d", job->img.width, job->img.height);
    double total = 0.0;
    for (int64_t i = 0; i < (int64_t)job->img.width * job->img.height; i++)
        total += job->img.samples[i];
    snprintf(spp_s, sizeof spp_s, "%.0f", job->render_ms > 0 ? total / job->render_ms * 1e3 : 0.0);
    void *bytes = NULL;
    size_t len = 0;
    struct err e = {0};
    enum refract_code rc;
    const char *type;
    if (job->format == REF_EXR) {
        static const char *const names[] = {"R",          "G",          "B",         "A",
                                            "variance.R", "variance.G", "variance.B"};
        const char *attrs[] = {"refract.mode", "reference", "refract.samples", samples, NULL};
        rc = io_encode_exr_channels(exr, job->img.width, job->img.height, 7, names, attrs, &bytes,
                                    &len, &e);
        type = "image/x-exr";
    } else {
        rc = io_encode_frame(
            rgba, job->img.width, job->img.height,
            job->format == REF_JPEG ? IO_FRAME_JPEG : IO_FRAME_PNG, job->exposure_ev,
            job->tonemap == SCENE_TONEMAP_FILMIC ? IO_TONEMAP_FILMIC : IO_TONEMAP_CLAMP,
            job->jpeg_quality, &bytes, &len, &e);
        type = job->format == REF_JPEG ? "image/jpeg" : "image/png";
    }
    free(rgba);
    free(exr);
    if (rc != REFRACT_E_OK)
        return http_respond_err(req, &e);
    const char *headers[] = {"X-Render-Time-Ms",
                             render_ms,
                             "X-Image-Size",
                             size,
                             "X-Render-Mode",
                             "reference",
                             "X-Reference-Samples",
                             samples,
                             "X-Reference-Samples-Max",
                             samples_max,
                             "X-Reference-Noise",
                             noise,
                             "X-Reference-Samples-Per-Second",
                             spp_s,
                             NULL};
    return http_respond_bytes(req, MHD_HTTP_OK, bytes, len, type, headers);
}

static enum refract_code parse_reference(const char *body, size_t len, const struct scene *scene,
                                         const struct http_config *cfg, struct reference_job *job,
                                         struct err *e)
{
    static const char *const keys[] = {"mode",    "camera",         "width",   "height",
                                       "format",  "exposure",       "tonemap", "jpeg_quality",
                                       "samples", "time_budget_ms", "seed",    NULL};
    static const char *const formats[] = {"png", "jpeg", "exr", NULL};
    cJSON *root = NULL;
    enum refract_code rc = http_parse_body(body, len, &root, e);
    if (rc != REFRACT_E_OK)
        return rc;
    struct scene_camera camera;
    rc = jr_check_object(root, "", keys, e);
    if (rc == REFRACT_E_OK)
        rc = http_parse_camera(root, &scene->camera, cfg, &camera, e);
    int format = REF_PNG;
    if (rc == REFRACT_E_OK)
        rc = jr_enum(root, "", "format", false, REF_PNG, formats, &format, e);
    job->exposure_ev = scene->render.exposure_ev;
    job->tonemap = scene->render.tonemap;
    job->jpeg_quality = 90;
    if (rc == REFRACT_E_OK)
        rc =
            http_parse_image_options(root, &job->exposure_ev, &job->tonemap, &job->jpeg_quality, e);
    int max_samples =
        cfg->max_reference_samples > 0 ? cfg->max_reference_samples : REFERENCE_MAX_SAMPLES;
    int max_ms = cfg->max_reference_ms > 0 ? cfg->max_reference_ms : REFERENCE_MAX_MS;
    /* Only a budget: as many samples as it allows. Neither: REFERENCE_DEFAULT_SAMPLES. */
    bool has_budget = cJSON_GetObjectItemCaseSensitive(root, "time_budget_ms") != NULL;
    int budget = max_ms;
    if (rc == REFRACT_E_OK)
        rc = jr_int(root, "", "time_budget_ms", false, budget, 1, max_ms, &budget, e);
    int def_samples = has_budget                                ? max_samples
                      : REFERENCE_DEFAULT_SAMPLES < max_samples ? REFERENCE_DEFAULT_SAMPLES
                                                                : max_samples;
    if (rc == REFRACT_E_OK)
        rc = jr_int(root, "", "samples", false, def_samples, 1, max_samples, &job->samples, e);
    double seed = 1.0;
    if (rc == REFRACT_E_OK)
        rc = jr_number(root, "", "seed", false, 1.0, 0.0, 4294967295.0, &seed, e);
    if (rc == REFRACT_E_OK && seed != floor(seed))
        rc = err_set(e, REFRACT_E_INVALID_FIELD,
                     "seed: expected an integer in 0..4294967295, got %g", seed);
    cJSON_Delete(root);
    if (rc != REFRACT_E_OK) {
        if (e->code == REFRACT_E_INVALID_FIELD &&
            (strstr(e->msg, "samples") == e->msg || strstr(e->msg, "time_budget_ms") == e->msg))
            strncat(e->msg,
                    " (refractd's --max-reference-samples and --max-reference-ms set "
                    "the limits)",
                    sizeof e->msg - strlen(e->msg) - 1);
        return rc;
    }
    job->format = format;
    job->seed = (uint64_t)seed;
    job->deadline_ms = gpu_time_ms() + budget;
    job->cam = (struct pathtrace_camera){camera.eye,       camera.look_at, camera.up,
                                         camera.fov_y_deg, camera.width,   camera.height};
    return REFRACT_E_OK;
}

bool http_render_is_reference(const char *body, size_t len)
{
    cJSON *root = NULL;
    struct err e = {0};
    if (len == 0 || jr_parse(body, len, &root, &e) != REFRACT_E_OK)
        return false;
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(root, "mode");
    bool yes = cJSON_IsString(m) && strcmp(m->valuestring, "reference") == 0;
    cJSON_Delete(root);
    return yes;
}

enum MHD_Result http_handle_render_reference(struct http_request *req)
{
    enum MHD_Result answer = MHD_NO;
    struct store_scene *v = http_scene_or_404(req, &answer);
    if (v == NULL)
        return answer;
    struct reference_job *job = calloc(1, sizeof *job);
    if (job == NULL) {
        store_scene_release(v);
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory");
    }
    job->version = v;
    job->req = req;
    req->job = job;
    req->job_free = reference_job_free;
    struct err e = {0};
    if (parse_reference(req->body, req->body_len, v->scene, req->cfg, job, &e) != REFRACT_E_OK)
        return http_respond_err(req, &e);
    struct render_scene_source src = render_request_scene_source(v);
    if (scene_pathtrace_init(v->scene, src.lookup, src.lookup_ctx, &job->pt, &e) != REFRACT_E_OK)
        return http_respond_err(req, &e);
    if (pathtrace_image_init(&job->img, job->cam.width, job->cam.height) != 0)
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY,
                                  "out of memory for a %dx%d reference image (52 bytes a pixel); "
                                  "render a smaller image",
                                  job->cam.width, job->cam.height);
    if (!reference_begin())
        return http_respond_error(req, REFRACT_E_BUSY,
                                  "a reference render is running (one at a time: it uses every "
                                  "CPU); retry when it has finished");
    job->threads = reference_threads();
    req->on_resume = reference_answer;
    req->phase = HTTP_PHASE_SUSPENDED;
    MHD_suspend_connection(req->conn);
    if (!reference_start_detached(coordinator_main, job)) {
        /* answered by reference_answer, as a failed GPU submission is */
        reference_end();
        job->start_failed = true;
        req->phase = HTTP_PHASE_RESUMED;
        MHD_resume_connection(req->conn);
    }
    return MHD_YES;
}
