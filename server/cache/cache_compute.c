/*
 * cache_compute.c - recomputing irradiance volumes: the cache's worker thread (input
 * fields on the CPU, once per transport hash; writing finished volumes to disk) and the
 * GPU chunks (GPU_PRIORITY_LIGHTSIM work items that each advance a run by a bounded
 * number of wavefront steps and resubmit themselves; docs/ARCHITECTURE.md, "One thread
 * owns the GPU"). Locking rules in cache_internal.h.
 */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/log.h"
#include "../core/metrics.h"
#include "cache_internal.h"

void irr_fields_release(struct irr_fields *f)
{
    if (f == NULL || atomic_fetch_sub(&f->refs, 1) != 1)
        return;
    lightsim_fields_free(&f->f);
    free(f);
}

/* ---- GPU chunks ------------------------------------------------------------------------ */

void irr_fail_locked(struct irr_entry *en, const struct err *e)
{
    en->phase = IRR_FAILED;
    snprintf(en->message, sizeof en->message, "%s", e->msg);
    en->cache->counters.failed++;
    irr_note_failed_locked(en->cache, en);
    log_warn("irradiance", "volume %016" PRIx64 " (light %s): %s", en->key, en->light.name, e->msg);
}

/* The run ended: results out of the run into the entry. */
static void finish_run(struct irr_entry *en, struct err *e)
{
    struct irradiance_cache *c = en->cache;
    struct irradiance_volume host = {0};
    struct irradiance_gpu tex = {0};
    struct lightsim_stats stats;
    lightsim_gpu_stats(en->run, &stats);
    enum refract_code rc = lightsim_gpu_read(en->run, &host, e);
    if (rc == REFRACT_E_OK)
        rc = lightsim_gpu_take_textures(en->run, &tex, e);
    lightsim_gpu_run_destroy(en->run);
    en->run = NULL;
    en->finished = true;
    double ms = gpu_time_ms() - en->started_ms;
    pthread_mutex_lock(&c->lock);
    /* Cancelled after this chunk began: the volume is still right for its key, so keep it
     * unless the key was asked for again meanwhile (a new entry computes it). */
    if (rc == REFRACT_E_OK && en->cancelled && irr_find_locked(c, en->key) == NULL) {
        en->cancelled = false;
        c->counters.superseded--;
    }
    if (rc == REFRACT_E_OK && en->cancelled) {
        irradiance_volume_free(&host);
        irradiance_gpu_free(&tex);
    } else if (rc != REFRACT_E_OK) {
        irradiance_volume_free(&host);
        irradiance_gpu_free(&tex);
        irr_fail_locked(en, e);
    } else {
        host.stats = stats;
        en->host.volume = host;
        en->has_host = true;
        en->gpu = tex;
        en->has_gpu = true;
        en->stats = stats;
        en->has_stats = true;
        en->progress = 1.0;
        en->patches_live = 0;
        en->compute_ms = ms;
        metrics_lightsim(ms * 1e-3);
        en->phase = IRR_READY;
        en->last_use = ++c->tick;
        irr_note_ready_locked(c, en);
        c->counters.computed++;
        en->persisting = true;
        irr_push_task_locked(c, IRR_TASK_PERSIST, en);
        irr_evict_gpu_locked(c, en->last_use);
        log_info("irradiance", "volume %016" PRIx64 " (light %s) ready in %.1f ms, %lld steps",
                 en->key, en->light.name, ms, stats.steps);
    }
    pthread_mutex_unlock(&c->lock);
}

static void chunk_run(struct gpu_work *w, struct gpu *gpu)
{
    struct irr_entry *en = w->user;
    struct irradiance_cache *c = en->cache;
    pthread_mutex_lock(&c->lock);
    bool cancelled = en->cancelled;
    pthread_mutex_unlock(&c->lock);
    if (cancelled) {
        lightsim_gpu_run_destroy(en->run); /* superseded by a newer pose */
        en->run = NULL;
        en->finished = true;
        return;
    }
    if (en->run == NULL) {
        en->started_ms = gpu_time_ms();
        enum refract_code rc =
            lightsim_gpu_begin(gpu, &en->fields->f, &en->light, &en->set, &en->run, &w->err);
        irr_fields_release(en->fields); /* the run has its own copy on the GPU */
        en->fields = NULL;
        if (rc != REFRACT_E_OK) {
            en->finished = true;
            return;
        }
        pthread_mutex_lock(&c->lock);
        en->phase = IRR_COMPUTING;
        pthread_mutex_unlock(&c->lock);
    }
    bool done = false;
    if (lightsim_gpu_advance(en->run, c->desc.chunk_steps, &done, &w->err) != REFRACT_E_OK) {
        lightsim_gpu_run_destroy(en->run);
        en->run = NULL;
        en->finished = true;
        return;
    }
    if (done) {
        finish_run(en, &w->err);
        if (w->err.code != REFRACT_E_OK)
            err_clear(&w->err); /* recorded in the entry already */
        return;
    }
    struct lightsim_stats stats;
    lightsim_gpu_stats(en->run, &stats);
    pthread_mutex_lock(&c->lock);
    en->phase = IRR_COMPUTING;
    en->progress = stats.progress;
    en->patches_live = stats.patches_live;
    en->stats = stats;
    en->has_stats = true;
    irr_note_progress_locked(c, en); /* throttled */
    pthread_mutex_unlock(&c->lock);
}

/* After a chunk: resubmits the run, or records how it ended. */
static void chunk_settle(struct gpu_work *w)
{
    struct irr_entry *en = w->user;
    struct irradiance_cache *c = en->cache;
    if (w->err.code != REFRACT_E_OK) {
        /* A failed chunk, or the queue's TIMEOUT/SHUTTING_DOWN instead of a run. */
        lightsim_gpu_run_destroy(en->run);
        en->run = NULL;
        en->finished = true;
        pthread_mutex_lock(&c->lock);
        if (!en->cancelled)
            irr_fail_locked(en, &w->err);
        pthread_mutex_unlock(&c->lock);
    }
    if (!en->finished) {
        struct err e = {0};
        if (gpu_submit(c->gpu, &en->work, &e) == REFRACT_E_OK)
            return;
        lightsim_gpu_run_destroy(en->run);
        en->run = NULL;
        en->finished = true;
        pthread_mutex_lock(&c->lock);
        irr_fail_locked(en, &e);
        pthread_mutex_unlock(&c->lock);
    }
    if (en->fields) {
        irr_fields_release(en->fields);
        en->fields = NULL;
    }
    pthread_mutex_lock(&c->lock);
    en->busy = false;
    pthread_mutex_unlock(&c->lock);
}

static void chunk_done(struct gpu_work *w)
{
    struct irradiance_cache *c = ((struct irr_entry *)w->user)->cache;
    chunk_settle(w); /* the entry may be gone after this */
    irr_events_flush(c);
}

void irr_release_gpu_entry(struct irr_entry *en)
{
    if (en->run)
        lightsim_gpu_run_destroy(en->run);
    en->run = NULL;
    if (en->has_gpu)
        irradiance_gpu_free(&en->gpu);
    en->has_gpu = false;
}

/* ---- the worker ------------------------------------------------------------------------ */

static bool same_grid(const struct light_grid *a, const struct light_grid *b)
{
    return a->dims[0] == b->dims[0] && a->dims[1] == b->dims[1] && a->dims[2] == b->dims[2] &&
           a->voxel == b->voxel && a->bmin.x == b->bmin.x && a->bmin.y == b->bmin.y &&
           a->bmin.z == b->bmin.z;
}

/* The fields of a transport hash on the entry's light grid (with a receiver the grid
 * depends on the light: docs/lightsim.md "Domain"): kept ones first, else built now (CPU,
 * slow-ish). Returns a new reference or NULL with e filled. Worker thread only. */
static struct irr_fields *fields_for(struct irradiance_cache *c, struct irr_entry *en,
                                     struct err *e)
{
    struct light_grid grid;
    lightsim_domain_light(en->scene, &en->light, en->lookup, en->lookup_ctx, &grid);
    for (int i = 0; i < IRR_FIELDS_KEPT; i++) {
        struct irr_fields *f = c->fields[i];
        if (f && f->transport == en->transport && same_grid(&f->f.grid, &grid)) {
            memmove(&c->fields[1], &c->fields[0], (size_t)i * sizeof c->fields[0]);
            c->fields[0] = f;
            atomic_fetch_add(&f->refs, 1);
            return f;
        }
    }
    struct irr_fields *f = calloc(1, sizeof *f);
    if (f == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the light simulation's fields");
        return NULL;
    }
    double t0 = gpu_time_ms();
    if (lightsim_fields_build_light(en->scene, &en->light, en->lookup, en->lookup_ctx, &f->f, e) !=
        REFRACT_E_OK) {
        free(f);
        return NULL;
    }
    log_info("irradiance", "light fields %d x %d x %d built in %.1f ms", f->f.grid.dims[0],
             f->f.grid.dims[1], f->f.grid.dims[2], gpu_time_ms() - t0);
    atomic_init(&f->refs, 2); /* the kept list's and the caller's */
    f->transport = en->transport;
    irr_fields_release(c->fields[IRR_FIELDS_KEPT - 1]);
    memmove(&c->fields[1], &c->fields[0], (IRR_FIELDS_KEPT - 1) * sizeof c->fields[0]);
    c->fields[0] = f;
    return f;
}

static void run_build(struct irradiance_cache *c, struct irr_entry *en)
{
    if (en->kind == IRR_KIND_PHOTONS) {
        irr_photons_pass(c, en);
        return;
    }
    pthread_mutex_lock(&c->lock);
    bool cancelled = en->cancelled;
    pthread_mutex_unlock(&c->lock);
    struct err e = {0};
    struct irr_fields *f = cancelled ? NULL : fields_for(c, en, &e);
    pthread_mutex_lock(&c->lock);
    irr_drop_source(en); /* the fields no longer need the scene version */
    if (cancelled || en->cancelled || f == NULL) {
        if (!cancelled && !en->cancelled)
            irr_fail_locked(en, &e);
        en->busy = false;
        pthread_mutex_unlock(&c->lock);
        irr_fields_release(f);
        return;
    }
    en->fields = f;
    en->work = (struct gpu_work){.priority = GPU_PRIORITY_LIGHTSIM,
                                 .label = "light simulation",
                                 .run = chunk_run,
                                 .done = chunk_done,
                                 .user = en};
    pthread_mutex_unlock(&c->lock);
    if (gpu_submit(c->gpu, &en->work, &e) != REFRACT_E_OK) {
        irr_fields_release(f);
        pthread_mutex_lock(&c->lock);
        en->fields = NULL;
        irr_fail_locked(en, &e);
        en->busy = false;
        pthread_mutex_unlock(&c->lock);
    }
}

static void run_persist(struct irradiance_cache *c, struct irr_entry *en)
{
    struct err e = {0};
    enum refract_code rc = irr_disk_write(c, en, &e); /* host copy pinned by persisting */
    pthread_mutex_lock(&c->lock);
    en->on_disk = rc == REFRACT_E_OK;
    if (rc != REFRACT_E_OK) {
        log_warn("irradiance", "volume %016" PRIx64 " not persisted: %s", en->key, e.msg);
        en->persisting = false;
        irr_evict_host_locked(c);
        pthread_mutex_unlock(&c->lock);
        return;
    }
    pthread_mutex_unlock(&c->lock);
    /* Still pinned by persisting: its row is recorded before it may leave memory. */
    irr_index_recorded(c, en);
    pthread_mutex_lock(&c->lock);
    en->persisting = false;
    irr_evict_host_locked(c);
    pthread_mutex_unlock(&c->lock);
}

void *irr_worker_main(void *arg)
{
    struct irradiance_cache *c = arg;
    pthread_mutex_lock(&c->lock);
    for (;;) {
        while (!c->stop && c->task_head == NULL && c->touch_count == 0)
            pthread_cond_wait(&c->wake, &c->lock);
        if (c->stop)
            break;
        if (c->task_head == NULL) { /* only uses to record */
            pthread_mutex_unlock(&c->lock);
            irr_index_flush_touches(c);
            pthread_mutex_lock(&c->lock);
            continue;
        }
        struct irr_task *t = c->task_head;
        c->task_head = t->next;
        if (c->task_head == NULL)
            c->task_tail = NULL;
        pthread_mutex_unlock(&c->lock);
        if (t->kind == IRR_TASK_BUILD)
            run_build(c, t->entry);
        else
            run_persist(c, t->entry);
        free(t);
        irr_events_flush(c);
        pthread_mutex_lock(&c->lock);
    }
    /* Stopping: finished volumes still reach the disk; unbuilt entries let go of their
     * scene versions. */
    while (c->task_head) {
        struct irr_task *t = c->task_head;
        c->task_head = t->next;
        if (t->kind == IRR_TASK_BUILD) {
            irr_drop_source(t->entry);
            t->entry->busy = false;
        } else {
            pthread_mutex_unlock(&c->lock);
            run_persist(c, t->entry);
            pthread_mutex_lock(&c->lock);
        }
        free(t);
    }
    c->task_tail = NULL;
    pthread_mutex_unlock(&c->lock);
    if (c->has_index)
        irr_index_flush_touches(c);
    return NULL;
}
