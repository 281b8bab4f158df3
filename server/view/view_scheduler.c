/*
 * view_scheduler.c - when each view session renders (docs/views.md "Frames: when and
 * how"), and the life of one frame job: scheduler -> GPU thread -> encoder -> newest frame.
 *
 * DESIGN. One thread. It scans the table under the registry lock and, for each session,
 * starts a frame when the session needs one (change_gen != full_gen), has none in flight
 * and its max_fps spacing has passed; it ends sessions that have had no request and no
 * stream for the idle timeout. Then it sleeps on the registry's condition variable until
 * the earliest of those times, or until it is signalled (a PATCH, an event, a finished
 * frame, a stream leaving). A scan that started frames or ended sessions is followed by
 * another before sleeping, so a signal sent while the lock was released is never lost.
 * The scan is O(sessions): at most --max-views, a few microseconds.
 *
 * Progressive refinement: with `progressive` on, the first frame after a change is a
 * half-size preview when the last full frame took longer than 20 ms (render_ms); the
 * full frame follows at once (a preview and its full frame are one frame for the max_fps
 * spacing) unless another change came in, in which case that change gets its own preview
 * first.
 */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../core/log.h"
#include "view_internal.h"
#include "../request/render_request.h"

#define PREVIEW_AFTER_MS 20.0  /* docs/views.md: previews only when full frames are slower */
#define RETRY_BUSY_MS 200      /* a full GPU queue (BUSY) or a missed deadline: try again */
#define SLEEP_MAX_MS 3600000LL /* nothing due: sleep until signalled (or an hour) */

/* A new job for s (caller holds s->mu), or NULL when out of memory. */
static struct view_job *job_make_locked(struct view_session *s, int64_t now)
{
    struct view_job *job = calloc(1, sizeof *job);
    if (job == NULL)
        return NULL;
    view_session_retain(s);
    job->session = s;
    job->settings = s->settings;
    job->change_gen = s->change_gen;
    if (s->hdr != NULL && s->hdr_gen == s->change_gen && !s->settings.reference) {
        /* Encode-only change: the newest full frame's image goes straight to an encoder,
         * borrowed, not copied: only a finished render replaces s->hdr, and this job is
         * the session's one frame in flight until it finishes. */
        job->result.rgba = s->hdr;
        job->result.width = s->hdr_width;
        job->result.height = s->hdr_height;
        job->result.gpu_ms = s->hdr_render_ms;
        job->irradiance = s->hdr_irradiance;
        job->reencode = true;
    }
    bool preview = !job->reencode && !s->settings.reference && s->settings.progressive &&
                   s->last_full_render_ms > PREVIEW_AFTER_MS && s->preview_gen != s->change_gen;
    job->kind = preview ? VIEW_FRAME_PREVIEW : VIEW_FRAME_FULL;
    s->in_flight = true;
    s->next_start_ms = now + (int64_t)(1000.0 / s->settings.max_fps);
    return job;
}

static void job_free(struct view_job *job)
{
    store_scene_release(job->version);
    if (!job->reencode)
        free(job->result.rgba); /* a re-encode borrowed the session's image */
    view_session_release(job->session);
    free(job);
}

void view_job_finish(struct view_registry *r, struct view_job *job, struct view_frame *frame,
                     const struct err *e)
{
    struct view_session *s = job->session;
    int64_t now = gpu_now_ms();
    pthread_mutex_lock(&s->mu);
    s->in_flight = false;
    if (frame) {
        frame->seq = ++s->seq;
        frame->made_ms = now;
        frame->reencoded = job->reencode;
        if (job->reencode) {
            s->frames_reencoded++;
        } else {
            s->frames_rendered++;
            if (job->kind == VIEW_FRAME_FULL && job->result.rgba != NULL) {
                /* Kept for encode-only changes; the job no longer owns it. */
                free(s->hdr);
                s->hdr = job->result.rgba;
                job->result.rgba = NULL;
                s->hdr_width = job->result.width;
                s->hdr_height = job->result.height;
                s->hdr_render_ms = frame->render_ms;
                s->hdr_irradiance = frame->irradiance;
                s->hdr_gen = job->change_gen;
            }
        }
        view_frame_release(s->frame);
        s->frame = frame;
        if (job->kind == VIEW_FRAME_FULL) {
            s->full_gen = job->change_gen;
            s->last_full_render_ms = frame->render_ms;
            /* Reference mode: another slice while the image is short of its target. */
            s->ref_samples = job->settings.reference ? job->ref_samples : 0;
            s->ref_refining = job->settings.reference && job->change_gen == s->change_gen &&
                              job->ref_samples < (uint32_t)job->settings.reference_samples;
        } else {
            s->preview_gen = job->change_gen;
            s->next_start_ms = now; /* the full frame follows at once (docs/views.md) */
        }
        err_clear(&s->last_error);
    } else if (e->code == REFRACT_E_BUSY || e->code == REFRACT_E_TIMEOUT) {
        s->next_start_ms = now + RETRY_BUSY_MS; /* the same change, a little later */
    } else {
        /* Give up on this change (a bad combination of settings, GPU memory): the status
         * says why, and the next change tries again. Never retry in a loop. */
        s->last_error = *e;
        s->full_gen = job->change_gen;
        s->ref_refining = false;
    }
    pthread_mutex_unlock(&s->mu);
    if (frame)
        view_session_wake_watchers(s);
    else if (e->code != REFRACT_E_SHUTTING_DOWN)
        log_warn("view", "%s (scene %s): frame failed: %s", s->id, s->scene, e->msg);
    job_free(job);
    pthread_mutex_lock(&r->mu);
    r->in_flight--;
    pthread_cond_signal(&r->wake);
    pthread_cond_broadcast(&r->idle);
    pthread_mutex_unlock(&r->mu);
}

/* One tile per turn (a frame no larger than a tile: the whole frame), asking for another
 * turn until every row is drawn (render_tiles.h, as renders and job frames do). */
static void job_run(struct gpu_work *w, struct gpu *gpu)
{
    (void)gpu;
    struct view_job *job = w->user;
    const struct view_registry_desc *d = view_registry_settings(job->session->reg);
    bool more = false;
    if (render_tiles_step(&job->tiles, d->render, d->irradiance, d->store, job->version,
                          &job->request, job->lights, &job->result, &job->irradiance, &more,
                          &w->err) != REFRACT_E_OK)
        return;
    w->again = more;
}

/* GPU thread, must not block: the encoder takes it from here (failures too). */
static void job_done(struct gpu_work *w)
{
    struct view_job *job = w->user;
    view_encoder_submit(job->session->reg->encoder, job);
}

/* Outside every lock: fetches the scene's current version, resolves the settings, asks
 * the irradiance cache for the lights' volumes and submits the GPU work. */
static void job_start(struct view_registry *r, struct view_job *job)
{
    struct view_session *s = job->session;
    struct err e = {0};
    job->version = store_scene_get(r->desc.store, s->scene);
    if (job->version == NULL) {
        /* Deleted without an event reaching us (no hub): the session ends with it. */
        char id[VIEW_ID_LEN + 1];
        memcpy(id, s->id, sizeof id);
        err_set(&e, REFRACT_E_SCENE_NOT_FOUND, "scene %s no longer exists", s->scene);
        view_job_finish(r, job, NULL, &e); /* releases the job's reference to s */
        view_session_end(r, id);
        return;
    }
    if (job->reencode) {
        view_encoder_submit(r->encoder, job); /* nothing to render */
        return;
    }
    if (job->settings.reference) {
        view_reference_start(r, job); /* CPU threads, not the GPU */
        return;
    }
    struct render_view_request *rq = &job->request;
    rq->camera = job->settings.camera;
    if (job->kind == VIEW_FRAME_PREVIEW) {
        rq->camera.width = rq->camera.width / 2 > 0 ? rq->camera.width / 2 : 1;
        rq->camera.height = rq->camera.height / 2 > 0 ? rq->camera.height / 2 : 1;
    }
    view_settings_render(&job->settings, job->version->scene, &rq->settings);
    pthread_mutex_lock(&s->mu);
    s->last_render = rq->settings;
    pthread_mutex_unlock(&s->mu);
    render_tiles_init(&job->tiles, r->desc.tile_pixels, rq->camera.width, rq->camera.height);
    struct irradiance_source isrc;
    render_request_irradiance_source(job->version, &isrc);
    irradiance_cache_request(r->desc.irradiance, &isrc, false);
    job->work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE,
                                  .deadline_ms = gpu_now_ms() + r->desc.request_timeout_ms,
                                  .label = "view frame",
                                  .run = job_run,
                                  .done = job_done,
                                  .user = job};
    if (gpu_submit(r->desc.gpu, &job->work, &e) != REFRACT_E_OK)
        view_job_finish(r, job, NULL, &e);
}

/* One scan (caller holds r->mu): fills jobs to start and sessions that expired, returns
 * the time of the next due event. */
static int64_t scan_locked(struct view_registry *r, int64_t now, struct view_job **jobs,
                           size_t *job_count, struct view_session **expired, size_t *expired_count)
{
    int64_t next = now + SLEEP_MAX_MS;
    int64_t timeout_ms = (int64_t)(r->desc.idle_timeout_s * 1000.0);
    for (int i = r->count - 1; i >= 0; i--) {
        struct view_session *s = r->sessions[i];
        pthread_mutex_lock(&s->mu);
        if (s->watcher_count == 0) {
            int64_t expire_at = s->last_activity_ms + timeout_ms;
            if (now >= expire_at) {
                pthread_mutex_unlock(&s->mu);
                expired[(*expired_count)++] = view_registry_unlist_locked(r, s);
                continue;
            }
            next = expire_at < next ? expire_at : next;
        }
        if (!s->in_flight && (s->change_gen != s->full_gen || s->ref_refining)) {
            struct view_job *job = now >= s->next_start_ms ? job_make_locked(s, now) : NULL;
            if (job) {
                jobs[(*job_count)++] = job;
                r->in_flight++;
            } else {
                int64_t at = s->next_start_ms > now ? s->next_start_ms : now + RETRY_BUSY_MS;
                next = at < next ? at : next;
            }
        }
        pthread_mutex_unlock(&s->mu);
    }
    return next;
}

static void sleep_until_locked(struct view_registry *r, int64_t at_ms)
{
    struct timespec ts = {.tv_sec = (time_t)(at_ms / 1000),
                          .tv_nsec = (long)(at_ms % 1000) * 1000000};
    pthread_cond_timedwait(&r->wake, &r->mu, &ts);
}

void *view_scheduler_main(void *arg)
{
    struct view_registry *r = arg;
    size_t cap = (size_t)r->desc.max_views;
    struct view_job **jobs = calloc(cap, sizeof *jobs);
    struct view_session **expired = calloc(cap, sizeof *expired);
    if (jobs == NULL || expired == NULL) {
        log_error("view", "out of memory: the view scheduler cannot run");
        free(jobs);
        free(expired);
        return NULL;
    }
    pthread_mutex_lock(&r->mu);
    while (!r->stopping) {
        size_t job_count = 0, expired_count = 0;
        int64_t next = scan_locked(r, gpu_now_ms(), jobs, &job_count, expired, &expired_count);
        if (job_count == 0 && expired_count == 0) {
            sleep_until_locked(r, next);
            continue;
        }
        pthread_mutex_unlock(&r->mu);
        for (size_t i = 0; i < expired_count; i++) {
            log_info("view", "%s (scene %s): no request and no stream for %g s: ended",
                     expired[i]->id, expired[i]->scene, r->desc.idle_timeout_s);
            view_session_mark_ended(expired[i]);
            view_session_release(expired[i]);
        }
        for (size_t i = 0; i < job_count; i++)
            job_start(r, jobs[i]);
        pthread_mutex_lock(&r->mu);
    }
    pthread_mutex_unlock(&r->mu);
    free(jobs);
    free(expired);
    return NULL;
}
