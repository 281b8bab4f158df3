/*
 * job_batch.c - `refractd --batch JOB.json (--frames A-B | --task I/N) --out DIR`: one
 * array task of a batch job, run once without HTTP (docs/slurm.md).
 *
 * DESIGN. A scheduler we do not own (Slurm job arrays, Kubernetes Indexed Jobs) runs N
 * copies of refractd, each with its own GPU context and a private data directory, each
 * given its share of the job's frames. The specification is the one POST /v1/jobs takes,
 * expanded by the same job_spec_expand, and every frame goes through the runner's own path
 * (job_frame.c, drawn in tiles by render_tiles.h like the daemon's), so a task's frame is
 * byte-identical to the same frame of a daemon's job. What makes each frame exist exactly
 * once is the shared output directory (job_batch_dir.c): a frame file appears only by
 * rename, complete; a task skips the frames it finds there, so a requeued task renders
 * only what its killed run had not finished. Progress lives in that directory too
 * (progress.json).
 *
 * The caller's thread runs the loop and waits for each frame (gpu_run_sync); lights are
 * waited for by polling the irradiance cache every JOB_BATCH_RETRY_MS, as the runner does.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cjson/cJSON.h>

#include "../cache/irradiance_cache.h"
#include "../core/log.h"
#include "../gpu/queue.h"
#include "../render/render.h"
#include "../request/render_request.h"
#include "../request/render_tiles.h"
#include "../scene/json_read.h"
#include "jobs.h"

#define JOB_BATCH_RETRY_MS 200
#define JOB_BATCH_MAX_SPEC_BYTES (64 << 20)
/* The irradiance slot and inline scene name of a batch task (its data dir is private). */
#define JOB_BATCH_SLOT "job:batch"

static bool parse_int(const char *text, const char **end, int *out)
{
    char *stop = NULL;
    long v = strtol(text, &stop, 10);
    if (stop == text || v < 0 || v > 100000000 || (*text < '0' || *text > '9'))
        return false;
    *out = (int)v;
    *end = stop;
    return true;
}

enum refract_code job_batch_range(const char *frames, const char *task, int total, int *first,
                                  int *last, struct err *e)
{
    const char *end = NULL;
    if ((frames == NULL) == (task == NULL))
        return err_set(e, REFRACT_E_USAGE,
                       "--batch: give exactly one of --frames A-B (a frame range, 0-based, "
                       "inclusive) or --task I/N (task I of N, 0-based)");
    if (frames) {
        if (!parse_int(frames, &end, first) || *end != '-' || !parse_int(end + 1, &end, last) ||
            *end != '\0' || *last < *first)
            return err_set(e, REFRACT_E_USAGE,
                           "--frames %.60s: expected A-B with 0 <= A <= B (0-based, inclusive), "
                           "e.g. 0-5",
                           frames);
        if (*last >= total)
            return err_set(e, REFRACT_E_USAGE,
                           "--frames %.60s: the job has %d frames (0..%d); give a range inside it",
                           frames, total, total - 1);
        return REFRACT_E_OK;
    }
    int index = 0, count = 0;
    if (!parse_int(task, &end, &index) || *end != '/' || !parse_int(end + 1, &end, &count) ||
        *end != '\0' || count < 1 || index >= count)
        return err_set(e, REFRACT_E_USAGE,
                       "--task %.60s: expected I/N with 0 <= I < N, e.g. "
                       "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT",
                       task);
    *first = (int)((long long)index * total / count);
    *last = (int)((long long)(index + 1) * total / count) - 1;
    return REFRACT_E_OK;
}

/* The specification file's text, NUL-terminated: new (caller frees). */
static enum refract_code read_spec(const char *path, char **out, size_t *len, struct err *e)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return err_set(e, REFRACT_E_IO, "--batch %s: cannot open it: %s", path, strerror(errno));
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap + 1);
    while (buf) {
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (n < cap || n >= JOB_BATCH_MAX_SPEC_BYTES)
            break;
        char *grown = realloc(buf, cap * 2 + 1);
        if (grown == NULL) {
            free(buf);
            buf = NULL;
            break;
        }
        buf = grown;
        cap *= 2;
    }
    fclose(f);
    if (buf == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "--batch %s: out of memory reading it", path);
    if (n >= JOB_BATCH_MAX_SPEC_BYTES) {
        free(buf);
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED, "--batch %s: larger than %d MiB", path,
                       JOB_BATCH_MAX_SPEC_BYTES >> 20);
    }
    buf[n] = '\0';
    *out = buf;
    *len = n;
    return REFRACT_E_OK;
}

/* Expands the specification: *base is a new reference to the scene version (an inline
 * scene's private version, or the store's scene, e.g. from --scene-dir). */
static enum refract_code expand(const struct job_batch_desc *d, struct store_scene **base,
                                struct job_frame **frames, int *count, struct err *e)
{
    char *text = NULL;
    size_t len = 0;
    enum refract_code rc = read_spec(d->spec_path, &text, &len, e);
    if (rc != REFRACT_E_OK)
        return rc;
    cJSON *root = NULL;
    const cJSON *doc = NULL;
    char scene[STORE_ID_MAX] = "";
    rc = jr_parse(text, len, &root, e);
    free(text);
    if (rc == REFRACT_E_OK && !cJSON_IsObject(root))
        rc = err_set(e, REFRACT_E_INVALID_FIELD, "a job is a JSON object; see docs/api.md");
    if (rc == REFRACT_E_OK)
        rc = job_spec_scene(root, scene, &doc, e);
    *base = NULL;
    if (rc == REFRACT_E_OK && doc) {
        char *json = cJSON_PrintUnformatted(doc);
        rc = json ? store_scene_private(d->store, JOB_BATCH_SLOT, json, strlen(json), base, e)
                  : err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory reading the scene");
        free(json);
        if (rc != REFRACT_E_OK)
            job_spec_inline_error(e);
        else
            rc = job_spec_inline_check((*base)->scene, e);
    } else if (rc == REFRACT_E_OK) {
        *base = store_scene_get(d->store, scene);
        if (*base == NULL)
            rc = err_set(e, REFRACT_E_SCENE_NOT_FOUND,
                         "scene: no scene \"%s\"; put %s.json in a --scene-dir, or send the "
                         "whole scene document as \"scene\"",
                         scene, scene);
    }
    if (rc == REFRACT_E_OK)
        rc = job_spec_expand(root, (*base)->scene, &d->limits, frames, count, e);
    if (rc != REFRACT_E_OK) {
        store_scene_release(*base);
        *base = NULL;
    }
    cJSON_Delete(root);
    return rc;
}

/* One frame on the GPU thread. */
struct batch_work {
    struct gpu_work work;
    const struct job_batch_desc *d;
    struct store_scene *version;
    struct render_view_request request;
    struct render_light lights[SCENE_MAX_LIGHTS];
    struct render_view_result result;
    const char *irradiance;
    struct render_tiles tiles;
};

static void batch_frame_run(struct gpu_work *w, struct gpu *gpu)
{
    (void)gpu;
    struct batch_work *b = w->user;
    bool more = false;
    if (render_tiles_step(&b->tiles, b->d->render, b->d->irradiance, b->d->store, b->version,
                          &b->request, b->lights, &b->result, &b->irradiance, &more,
                          &w->err) == REFRACT_E_OK)
        w->again = more;
}

static bool stopping(const struct job_batch_desc *d)
{
    return d->stop && d->stop(d->stop_user);
}

/* Before each tile: a task told to stop drops the frame it is drawing (a large frame's
 * tiles could outlast the scheduler's grace time); its requeued run draws it again. */
static bool batch_abandoned(struct gpu_work *w)
{
    const struct batch_work *b = w->user;
    return stopping(b->d);
}

static void sleep_ms(int ms)
{
    struct timespec ts = {.tv_sec = ms / 1000, .tv_nsec = (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

enum frame_outcome { FRAME_DONE, FRAME_STOPPED };

/* Renders frame n (f) of base and writes it to the output directory. Waits for its lights
 * first; a busy queue or a volume that went away meanwhile is tried again. */
static enum refract_code render_frame(const struct job_batch_desc *d, struct store_scene *base,
                                      int n, const struct job_frame *f, enum frame_outcome *out,
                                      struct err *e)
{
    struct store_scene *v = NULL;
    enum refract_code rc = job_frame_version(d->store, base, f, &v, e);
    if (rc != REFRACT_E_OK)
        return err_prefix(e, "frame %d: ", n);
    struct irradiance_source isrc;
    job_frame_source(v, f, JOB_BATCH_SLOT, &isrc);
    struct batch_work b = {.d = d, .version = v};
    *out = FRAME_DONE;
    for (;;) {
        if (stopping(d)) {
            *out = FRAME_STOPPED;
            break;
        }
        if (f->reference_samples > 0) { /* the path tracer on this task's CPUs */
            memset(&b.result, 0, sizeof b.result);
            rc = job_frame_reference(v, f, &b.result, e);
            if (rc == REFRACT_E_OK) {
                void *bytes = NULL;
                size_t len = 0;
                rc = job_frame_encode(&b.result, f, v->scene->render.tonemap, &bytes, &len, e);
                if (rc == REFRACT_E_OK)
                    rc = job_batch_frame_write(d->out_dir, n, f->format, bytes, len, e);
                free(bytes);
            }
            free(b.result.rgba);
            if (rc != REFRACT_E_OK)
                err_prefix(e, "frame %d: ", n);
            break;
        }
        if (!irradiance_cache_request(d->irradiance, &isrc, false)) {
            char msg[ERR_MSG_MAX];
            if (job_frame_lights_failed(d->irradiance, &isrc, msg, sizeof msg)) {
                rc = err_set(e, REFRACT_E_GPU_ERROR, "frame %d: %s", n, msg);
                break;
            }
            sleep_ms(JOB_BATCH_RETRY_MS); /* not lit yet */
            continue;
        }
        memset(&b.request, 0, sizeof b.request);
        memset(&b.result, 0, sizeof b.result);
        b.request.camera = f->camera;
        b.request.settings = v->scene->render;
        b.irradiance = NULL;
        render_tiles_init(&b.tiles, d->tile_pixels, f->camera.width, f->camera.height);
        b.work = (struct gpu_work){.priority = GPU_PRIORITY_BATCH,
                                   .label = "batch frame",
                                   .run = batch_frame_run,
                                   .abandoned = batch_abandoned,
                                   .abandoned_why = "the task was told to stop",
                                   .user = &b};
        rc = gpu_run_sync(d->gpu, &b.work);
        if (rc != REFRACT_E_OK && stopping(d)) {
            /* Told to stop between two tiles: the frame was abandoned or the queue is
             * shutting down. The frame is not written; the task stops, it did not fail. */
            free(b.result.rgba);
            rc = REFRACT_E_OK;
            *out = FRAME_STOPPED;
            break;
        }
        bool unlit = rc == REFRACT_E_OK && b.irradiance &&
                     (!strcmp(b.irradiance, "missing") || !strcmp(b.irradiance, "stale"));
        if (rc == REFRACT_E_BUSY || rc == REFRACT_E_TIMEOUT || unlit) {
            free(b.result.rgba);
            sleep_ms(JOB_BATCH_RETRY_MS);
            continue;
        }
        if (rc != REFRACT_E_OK) {
            free(b.result.rgba); /* a tile failed: the rows before it are of no use */
            rc = err_set(e, rc, "frame %d: %s", n, b.work.err.msg);
            break;
        }
        void *bytes = NULL;
        size_t len = 0;
        rc = job_frame_encode(&b.result, f, v->scene->render.tonemap, &bytes, &len, e);
        free(b.result.rgba);
        if (rc == REFRACT_E_OK)
            rc = job_batch_frame_write(d->out_dir, n, f->format, bytes, len, e);
        else
            err_prefix(e, "frame %d: ", n);
        free(bytes);
        break;
    }
    store_scene_release(v);
    return rc;
}

static int frames_present(const char *dir, const struct job_frame *frames, int first, int last)
{
    int done = 0;
    for (int n = first; n <= last; n++)
        done += job_batch_frame_exists(dir, n, frames[n].format);
    return done;
}

/* Writes the task record and progress.json; a failure is logged, not fatal: the frames
 * are what matters, and the next frame writes progress again. */
static void progress(const struct job_batch_desc *d, const struct job_frame *frames, int total,
                     int first, int last, const char *state, const char *message)
{
    struct job_batch_task t = {.first = first,
                               .last = last,
                               .done = frames_present(d->out_dir, frames, first, last),
                               .state = state,
                               .message = message};
    struct err e = {0};
    if (job_batch_progress_write(d->out_dir, &t, frames, total, &e) != REFRACT_E_OK)
        log_warn("batch", "progress: %s", e.msg);
}

enum refract_code job_batch_run(const struct job_batch_desc *d, struct job_batch_report *report,
                                struct err *e)
{
    memset(report, 0, sizeof *report);
    struct store_scene *base = NULL;
    struct job_frame *frames = NULL;
    int total = 0, first = 0, last = -1;
    enum refract_code rc = expand(d, &base, &frames, &total, e);
    if (rc == REFRACT_E_OK)
        rc = job_batch_range(d->frames, d->task, total, &first, &last, e);
    if (rc == REFRACT_E_OK)
        rc = job_batch_dir_prepare(d->out_dir, e);
    if (rc != REFRACT_E_OK) {
        free(frames);
        store_scene_release(base);
        return rc;
    }
    report->frames_total = total;
    report->first = first;
    report->last = last;
    report->temps_removed = job_batch_clean_temps(d->out_dir, first, last);
    log_info("batch", "frames %d-%d of %d into %s (%d partial files of an earlier run removed)",
             first, last, total, d->out_dir, report->temps_removed);
    progress(d, frames, total, first, last, "running", NULL);
    for (int n = first; n <= last && rc == REFRACT_E_OK; n++) {
        if (stopping(d)) {
            report->stopped = true;
            break;
        }
        if (job_batch_frame_exists(d->out_dir, n, frames[n].format)) {
            report->skipped++;
            continue;
        }
        double start = gpu_time_ms();
        enum frame_outcome out = FRAME_DONE;
        rc = render_frame(d, base, n, &frames[n], &out, e);
        if (rc == REFRACT_E_OK && out == FRAME_STOPPED) {
            report->stopped = true;
            break;
        }
        if (rc == REFRACT_E_OK) {
            report->rendered++;
            log_info("batch", "frame %d written (%.0f ms)", n, gpu_time_ms() - start);
            progress(d, frames, total, first, last, "running", NULL);
        }
    }
    const char *state = rc != REFRACT_E_OK ? "failed" : report->stopped ? "stopped" : "done";
    progress(d, frames, total, first, last, state, rc != REFRACT_E_OK ? e->msg : NULL);
    free(frames);
    store_scene_release(base);
    return rc;
}
