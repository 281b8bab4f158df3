/*
 * cache_photons.c - lights' photon maps in the irradiance cache (docs/photons.md "The
 * cache"; issue 15 item 3). A scene whose receiver has "photons" caustics keeps one map per
 * light, like a volume: keyed by the scene's transport and the light's pose (not its colour
 * or intensity: the map is traced at unit intensity and scaled at render time), made
 * ahead on the cache's worker thread, used as soon as its first pass is done, refined in
 * PHOTON_LEVELS passes of count / 16, count / 4 and count photons (each a whole map with the
 * radius of its photon count, replacing the last: the caustic sharpens and its noise falls),
 * and persisted as <key>.pmap once the last pass is in.
 *
 * Passes are worker tasks, one at a time, so other scenes' work interleaves; a pass traces
 * on every online CPU (photon_map.c), never on the GPU thread, so renders go on meanwhile.
 * A map whose pose is no longer wanted (the light moved on) stops after its current pass
 * and stays usable; it goes on when the pose is asked for again, and memory may drop it
 * (it is not on disk yet). Locking rules in cache_internal.h.
 */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../core/log.h"
#include "../io/io_files.h"
#include "cache_internal.h"

struct irr_photon_scene {
    struct scene_pathtrace sp;  /* the scene's surfaces (sp.scene.surfaces points into sp) */
    struct pathtrace_scene one; /* the same with the entry's light alone, unit intensity */
    /* Passes past `photons` accumulate (receiver.photons_max): every landed photon so far,
     * weighted as one list of acc_count photons; 0 before the pass of `photons`. */
    struct photon_list acc;
    long acc_count;
    int next_pass; /* the pass to trace next (the entry's passes, unless replaying) */
};

/* ---- host copies ----------------------------------------------------------------------- */

void irr_pmap_unref(struct irr_pmap *m)
{
    if (m == NULL || --m->refs > 0)
        return;
    photon_grid_free(&m->grid);
    free(m);
}

size_t irr_host_bytes(const struct irr_host *h)
{
    if (h->photons) /* keys, E in double and float per slot */
        return (size_t)h->photons->grid.capacity * (2 * sizeof(int32_t) + 3 * sizeof(double) +
                                                     4 * sizeof(float));
    return irradiance_volume_bytes(&h->volume);
}

void irr_host_free(struct irr_host *h)
{
    irradiance_volume_free(&h->volume);
    irr_pmap_unref(h->photons);
    h->photons = NULL;
}

void irr_photon_scene_free(struct irr_entry *en)
{
    if (en->pt)
        photon_list_free(&en->pt->acc);
    free(en->pt);
    en->pt = NULL;
}

/* ---- keys ------------------------------------------------------------------------------ */

uint64_t irr_photons_key(const struct irradiance_cache *c, uint64_t transport,
                         const struct scene *s, const struct scene_light *l)
{
    uint64_t h = irradiance_cache_key(c, transport, l);
    h = irr_mix(h, "photons", 7);
    int64_t radius = llround(l->radius / c->desc.position_tolerance);
    h = irr_mix(h, &radius, sizeof radius);
    int64_t count[2] = {s->receiver.photons, s->receiver.photons_max};
    h = irr_mix(h, count, sizeof count);
    double r = s->receiver.photon_radius;
    return irr_mix(h, &r, sizeof r);
}

/* ---- passes (worker) ------------------------------------------------------------------- */

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* The geometry and the light of a photon entry, made at its first pass. */
static enum refract_code photon_scene(struct irr_entry *en, struct err *e)
{
    if (en->pt != NULL)
        return REFRACT_E_OK;
    en->pt = calloc(1, sizeof *en->pt);
    if (en->pt == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a photon map's scene");
    enum refract_code rc =
        scene_pathtrace_geometry(en->scene, en->lookup, en->lookup_ctx, &en->pt->sp, e);
    if (rc != REFRACT_E_OK) {
        irr_photon_scene_free(en);
        return rc;
    }
    struct pathtrace_light pl;
    scene_pathtrace_light_unit(&en->light, &pl);
    photon_scene_one_light(&en->pt->sp.scene, &pl, &en->pt->one);
    return REFRACT_E_OK;
}

static bool wanted_locked(const struct irradiance_cache *c, uint64_t key)
{
    for (size_t i = 0; i < c->slot_count; i++) {
        if (c->slots[i].current == key)
            return true;
    }
    return false;
}

/* The share of a map's photons traced after `passes` passes, over all its passes. */
static double progress_of(long count, long count_max, int passes)
{
    double done = 0.0, all = 0.0;
    int n = photon_pass_count(count, count_max);
    for (int k = 0; k < n; k++) {
        double b = (double)photon_pass_batch(count, count_max, k);
        all += b;
        done += k < passes ? b : 0.0;
    }
    return all > 0.0 ? done / all : 1.0;
}

/* One pass's map (photon.h "A light's map is made in passes"): traced and gathered into
 * m->grid; the pass of `count` photons keeps its list for the passes after it, which add
 * theirs to it. */
static enum refract_code trace_pass(struct irr_photon_scene *pt, const struct scene_receiver *rc,
                                    int pass, struct irr_pmap *m, struct photon_map_stats *st,
                                    struct err *e)
{
    long count = rc->photons, count_max = rc->photons_max > count ? rc->photons_max : count;
    int first = photon_initial_passes(count);
    long batch = photon_pass_batch(count, count_max, pass);
    long cpus = sysconf(_SC_NPROCESSORS_ONLN);
    int threads = cpus > 0 ? (int)cpus : 1;
    long total = photon_pass_total(count, count_max, pass);
    memset(st, 0, sizeof *st);
    struct photon_list l;
    double t0 = now_ms();
    enum refract_code r =
        photon_map_trace(&pt->one, batch, photon_level_seed(pass), threads, &l, e);
    st->trace_ms = now_ms() - t0;
    if (r != REFRACT_E_OK)
        return r;
    const struct photon_list *gathered = &l;
    if (pass == first - 1 && count_max > count) {
        photon_list_free(&pt->acc);
        pt->acc = l; /* the passes after it add to it */
        pt->acc_count = batch;
        memset(&l, 0, sizeof l);
        gathered = &pt->acc;
    } else if (pass >= first) {
        r = photon_list_accumulate(&pt->acc, pt->acc_count, &l, batch, e);
        pt->acc_count += batch;
        gathered = &pt->acc;
    }
    st->emitted = gathered->emitted;
    st->landed = gathered->count;
    st->radius = photon_radius(&pt->one, total, rc->photon_radius);
    double t1 = now_ms();
    if (r == REFRACT_E_OK)
        r = photon_grid_build(gathered, st->radius, &m->grid, e);
    st->grid_ms = now_ms() - t1;
    m->emitted = st->emitted;
    m->landed = st->landed;
    photon_list_free(&l);
    return r;
}

void irr_photons_pass(struct irradiance_cache *c, struct irr_entry *en)
{
    struct err e = {0};
    pthread_mutex_lock(&c->lock);
    bool cancelled = en->cancelled;
    int passes_done = en->passes;
    if (!cancelled && en->phase == IRR_READY && !wanted_locked(c, en->key)) {
        /* A refining pass queued before the light moved on: not run (it goes on when the
         * pose is asked for again). */
        en->busy = false;
        irr_drop_source(en);
        irr_photon_scene_free(en);
        pthread_mutex_unlock(&c->lock);
        return;
    }
    if (!cancelled && en->phase == IRR_QUEUED) {
        en->phase = IRR_COMPUTING;
        irr_note_progress_locked(c, en);
    }
    pthread_mutex_unlock(&c->lock);
    irr_events_flush(c);

    bool fresh = en->pt == NULL;
    enum refract_code rc = cancelled ? REFRACT_E_OK : photon_scene(en, &e);
    /* Resumed past the pass of `photons` (the pose was left, which dropped the accumulated
     * list): the passes from that one on are traced again (the same seeds, the same
     * photons), their maps not shown until one has more photons than the map in use. */
    int first = photon_initial_passes(en->receiver.photons);
    if (!cancelled && rc == REFRACT_E_OK && fresh)
        en->pt->next_pass = passes_done >= first ? first - 1 : passes_done;
    int pass = rc == REFRACT_E_OK && en->pt ? en->pt->next_pass : passes_done;
    struct irr_pmap *m = NULL;
    double t0 = now_ms();
    struct photon_map_stats st = {0};
    if (!cancelled && rc == REFRACT_E_OK) {
        m = calloc(1, sizeof *m);
        if (m == NULL)
            rc = err_set(&e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a photon map");
        else
            m->refs = 1;
        if (rc == REFRACT_E_OK)
            rc = trace_pass(en->pt, &en->receiver, pass, m, &st, &e);
        if (rc == REFRACT_E_OK)
            en->pt->next_pass = pass + 1;
    }
    double ms = now_ms() - t0;

    pthread_mutex_lock(&c->lock);
    bool go_on = false;
    if (cancelled || en->cancelled || rc != REFRACT_E_OK) {
        irr_pmap_unref(m);
        if (!cancelled && !en->cancelled && rc != REFRACT_E_OK)
            irr_fail_locked(en, &e);
    } else if (en->has_host && en->host.photons && m->emitted <= en->host.photons->emitted) {
        irr_pmap_unref(m); /* replayed: the map in use has as many photons; the list goes on */
        en->compute_ms += ms;
        go_on = wanted_locked(c, en->key);
    } else {
        if (en->has_host)
            irr_host_free(&en->host);
        en->host.photons = m;
        en->has_host = true;
        en->passes = pass + 1;
        long count_max = en->receiver.photons_max > en->receiver.photons
                             ? en->receiver.photons_max
                             : en->receiver.photons;
        int passes_all = photon_pass_count(en->receiver.photons, count_max);
        bool last = en->passes >= passes_all;
        en->refining = !last;
        en->progress =
            last ? 1.0 : progress_of(en->receiver.photons, count_max, en->passes);
        en->compute_ms += ms;
        if (en->phase != IRR_READY) {
            en->phase = IRR_READY;
            en->last_use = ++c->tick;
        }
        /* Every pass is news to the views showing this pose: irradiance.ready again. */
        for (size_t i = 0; i < c->slot_count; i++) {
            if (c->slots[i].current == en->key)
                c->slots[i].announced = false;
        }
        irr_note_ready_locked(c, en);
        if (last) {
            c->counters.computed++;
            en->persisting = true;
            irr_push_task_locked(c, IRR_TASK_PERSIST, en);
        } else {
            go_on = wanted_locked(c, en->key);
        }
        log_info("irradiance",
                 "photon map %016" PRIx64 " (light %s) pass %d of %d: %ld photons (%zu landed), "
                 "radius %.4g, %u lattice points, %.0f ms (trace %.0f, gather %.0f)%s",
                 en->key, en->light.name, en->passes, passes_all, st.emitted, st.landed,
                 st.radius, m->grid.used, ms, st.trace_ms, st.grid_ms,
                 last    ? ""
                 : go_on ? "; refining"
                         : "; its pose is no longer wanted: stopped");
    }
    if (go_on) {
        irr_push_task_locked(c, IRR_TASK_BUILD, en); /* still busy */
    } else {
        en->busy = false;
        irr_drop_source(en);
        irr_photon_scene_free(en);
    }
    irr_evict_host_locked(c);
    pthread_mutex_unlock(&c->lock);
    irr_events_flush(c);
}

/* ---- files ----------------------------------------------------------------------------- */

/* <key>.pmap: a header (magic, point count, spacing, radius), then per stored lattice point
 * i, j (int32) and E rgb (double), in the host's byte order: a data directory is read by the
 * machine that wrote it. */
static const char pmap_magic[16] = "REFRACT-PMAP-1\n";
#define PMAP_HEADER (16 + 8 + 16)
#define PMAP_POINT (8 + 24)

enum refract_code irr_photons_write(const char *path, const struct irr_host *h, struct err *e)
{
    const struct photon_grid *g = &h->photons->grid;
    size_t len = PMAP_HEADER + (size_t)g->used * PMAP_POINT;
    unsigned char *b = malloc(len);
    if (b == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory writing a photon map");
    uint32_t head[2] = {g->used, 0};
    double grid[2] = {g->cell, g->radius};
    memcpy(b, pmap_magic, 16);
    memcpy(b + 16, head, 8);
    memcpy(b + 24, grid, 16);
    unsigned char *p = b + PMAP_HEADER;
    for (uint32_t s = 0; s < g->capacity; s++) {
        if (g->keys[2 * s] == PHOTON_EMPTY_KEY)
            continue;
        memcpy(p, &g->keys[2 * s], 8);
        memcpy(p + 8, &g->E_double[3 * s], 24);
        p += PMAP_POINT;
    }
    enum refract_code rc = io_write_atomic(path, b, len, e);
    free(b);
    return rc;
}

enum refract_code irr_photons_read(const char *path, struct irr_host *h, struct err *e)
{
    char *b = NULL;
    size_t len = 0;
    enum refract_code rc =
        io_read_file(path, PMAP_HEADER + (size_t)PHOTON_LATTICE_MAX * PMAP_POINT, &b, &len, e);
    if (rc != REFRACT_E_OK)
        return rc;
    uint32_t head[2] = {0, 0};
    double grid[2] = {0.0, 0.0};
    if (len >= PMAP_HEADER) {
        memcpy(head, b + 16, 8);
        memcpy(grid, b + 24, 16);
    }
    if (len < PMAP_HEADER || memcmp(b, pmap_magic, 16) != 0 || head[0] > PHOTON_LATTICE_MAX ||
        len != PMAP_HEADER + (size_t)head[0] * PMAP_POINT) {
        free(b);
        return err_set(e, REFRACT_E_STORAGE, "%s is not a photon map this build wrote", path);
    }
    int32_t *ij = malloc((size_t)head[0] * 2 * sizeof *ij + 8);
    double *E = malloc((size_t)head[0] * 3 * sizeof *E + 8);
    struct irr_pmap *m = calloc(1, sizeof *m);
    if (ij == NULL || E == NULL || m == NULL)
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory reading a photon map");
    for (uint32_t p = 0; rc == REFRACT_E_OK && p < head[0]; p++) {
        memcpy(&ij[2 * p], b + PMAP_HEADER + (size_t)p * PMAP_POINT, 8);
        memcpy(&E[3 * p], b + PMAP_HEADER + (size_t)p * PMAP_POINT + 8, 24);
    }
    if (rc == REFRACT_E_OK)
        rc = photon_grid_from_points(grid[0], grid[1], head[0], ij, E, &m->grid, e);
    free(b);
    free(ij);
    free(E);
    if (rc != REFRACT_E_OK) {
        free(m);
        return rc;
    }
    m->refs = 1;
    h->photons = m;
    return REFRACT_E_OK;
}
