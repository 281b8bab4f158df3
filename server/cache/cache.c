/*
 * cache.c - the irradiance cache's table: keys, slots, requests (hit, miss, supersession),
 * status, the GPU thread's gather for renders, copies for downloads, and LRU eviction
 * under the GPU and host budgets. Design and threads in irradiance_cache.h; locking in
 * cache_internal.h.
 */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/log.h"
#include "../core/metrics.h"
#include "../io/io_files.h"
#include "cache_internal.h"

/* ---- keys ------------------------------------------------------------------------------ */

uint64_t irr_mix(uint64_t h, const void *data, size_t len)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < len; i++) {
        h ^= p[i];
        h *= 1099511628211ull; /* FNV-1a 64 prime */
    }
    return h;
}

static uint64_t mix_i64(uint64_t h, int64_t v)
{
    return irr_mix(h, &v, sizeof v);
}

/* Nearest multiple of tol, as an integer: a change of less than tol/2 about a multiple
 * keeps the key (rounding, so the quantisation cell is centred on the multiples). */
static int64_t quantise(double v, double tol)
{
    return (int64_t)llround(v / tol);
}

uint64_t irradiance_transport_hash(const struct irradiance_source *src)
{
    uint64_t h = scene_transport_hash(src->scene);
    return irr_mix(h, &src->uploads_hash, sizeof src->uploads_hash);
}

uint64_t irradiance_cache_key(const struct irradiance_cache *c, uint64_t transport,
                              const struct scene_light *l)
{
    double pt = c->desc.position_tolerance, dt = c->desc.direction_tolerance;
    uint64_t h = irr_mix(14695981039346656037ull, &transport, sizeof transport);
    h = mix_i64(h, l->kind);
    if (l->kind != SCENE_LIGHT_POINT) {
        /* A unit vector's components move by about the angle (radians) it turns. */
        h = mix_i64(h, quantise(l->direction.x, dt));
        h = mix_i64(h, quantise(l->direction.y, dt));
        h = mix_i64(h, quantise(l->direction.z, dt));
    }
    if (l->kind != SCENE_LIGHT_DIRECTIONAL) {
        h = mix_i64(h, quantise(l->position.x, pt));
        h = mix_i64(h, quantise(l->position.y, pt));
        h = mix_i64(h, quantise(l->position.z, pt));
    }
    if (l->kind == SCENE_LIGHT_SPOT)
        h = mix_i64(h, quantise(l->spot_angle_deg * M_PI / 180.0, dt));
    return h;
}

const char *irradiance_state_name(enum irradiance_state s)
{
    static const char *const names[] = {"queued", "computing", "ready",
                                        "stale",  "failed",    "not_needed"};
    return (unsigned)s < sizeof names / sizeof names[0] ? names[s] : "failed";
}

/* ---- table ----------------------------------------------------------------------------- */

struct irr_entry *irr_find_locked(struct irradiance_cache *c, uint64_t key)
{
    for (size_t i = 0; i < c->entry_count; i++) {
        if (c->entries[i]->key == key && !c->entries[i]->cancelled)
            return c->entries[i];
    }
    return NULL;
}

static struct irr_slot *find_slot(struct irradiance_cache *c, const char *scene, const char *light)
{
    for (size_t i = 0; i < c->slot_count; i++) {
        if (strcmp(c->slots[i].scene, scene) == 0 && strcmp(c->slots[i].light, light) == 0)
            return &c->slots[i];
    }
    return NULL;
}

static struct irr_slot *add_slot(struct irradiance_cache *c, const char *scene, const char *light)
{
    if (c->slot_count == c->slot_cap) {
        size_t cap = c->slot_cap ? c->slot_cap * 2 : 16;
        struct irr_slot *grown = realloc(c->slots, cap * sizeof *grown);
        if (grown == NULL)
            return NULL;
        c->slots = grown;
        c->slot_cap = cap;
    }
    struct irr_slot *s = &c->slots[c->slot_count++];
    memset(s, 0, sizeof *s);
    snprintf(s->scene, sizeof s->scene, "%s", scene);
    snprintf(s->light, sizeof s->light, "%s", light);
    return s;
}

void irr_push_task_locked(struct irradiance_cache *c, enum irr_task_kind kind, struct irr_entry *en)
{
    struct irr_task *t = calloc(1, sizeof *t);
    if (t == NULL) {
        if (kind == IRR_TASK_BUILD) {
            en->phase = IRR_FAILED;
            en->busy = false;
            snprintf(en->message, sizeof en->message, "out of memory queueing the recompute");
            irr_drop_source(en);
            irr_note_failed_locked(c, en);
        } else {
            en->persisting = false;
        }
        return;
    }
    t->kind = kind;
    t->entry = en;
    if (c->task_tail)
        c->task_tail->next = t;
    else
        c->task_head = t;
    c->task_tail = t;
    pthread_cond_signal(&c->wake);
}

void irr_drop_source(struct irr_entry *en)
{
    if (en->release && en->lookup_ctx)
        en->release(en->lookup_ctx);
    en->release = NULL;
    en->lookup_ctx = NULL;
    en->scene = NULL;
}

void irr_sweep_locked(struct irradiance_cache *c)
{
    size_t j = 0;
    for (size_t i = 0; i < c->entry_count; i++) {
        struct irr_entry *en = c->entries[i];
        if (en->cancelled && !en->busy && !en->persisting && !en->has_gpu && en->loading == 0 &&
            !en->uploading) {
            irr_host_free(&en->host);
            irr_drop_source(en);
            irr_photon_scene_free(en);
            free(en);
            continue;
        }
        c->entries[j++] = en;
    }
    c->entry_count = j;
}

static size_t host_bytes_locked(const struct irradiance_cache *c)
{
    size_t n = 0;
    for (size_t i = 0; i < c->entry_count; i++) {
        if (c->entries[i]->has_host)
            n += irr_host_bytes(&c->entries[i]->host);
    }
    return n;
}

static size_t gpu_bytes_locked(const struct irradiance_cache *c)
{
    size_t n = 0;
    for (size_t i = 0; i < c->entry_count; i++) {
        if (c->entries[i]->has_gpu)
            n += c->entries[i]->gpu.bytes;
    }
    return n;
}

void irr_evict_host_locked(struct irradiance_cache *c)
{
    while (host_bytes_locked(c) > c->desc.host_budget_bytes) {
        struct irr_entry *lru = NULL;
        for (size_t i = 0; i < c->entry_count; i++) {
            struct irr_entry *en = c->entries[i];
            /* Only what is safe on disk may leave memory, or a photon map that stopped
             * refining (its pose is no longer wanted: the entry goes with it). */
            bool partial = en->kind == IRR_KIND_PHOTONS && en->refining && !en->busy;
            if (en->has_host && (en->on_disk || partial) && !en->persisting && !en->uploading &&
                en->loading == 0 && (lru == NULL || en->last_use < lru->last_use))
                lru = en;
        }
        if (lru == NULL)
            return;
        irr_host_free(&lru->host);
        lru->has_host = false;
        if (!lru->on_disk)
            lru->cancelled = true; /* nothing left to use: swept */
        c->counters.evicted_host++;
    }
}

void irr_evict_gpu_locked(struct irradiance_cache *c, int64_t keep_tick)
{
    while (gpu_bytes_locked(c) > c->desc.gpu_budget_bytes) {
        struct irr_entry *lru = NULL;
        for (size_t i = 0; i < c->entry_count; i++) {
            struct irr_entry *en = c->entries[i];
            /* A GPU copy may go when a host or disk copy remains to upload again. */
            if (en->has_gpu && en->last_use < keep_tick && (en->has_host || en->on_disk) &&
                (lru == NULL || en->last_use < lru->last_use))
                lru = en;
        }
        if (lru == NULL)
            return;
        irradiance_gpu_free(&lru->gpu);
        lru->has_gpu = false;
        c->counters.evicted_gpu++;
    }
}

/* Installs a volume read back from disk (rc its outcome) as the entry's host copy, unless
 * another thread did first. Returns whether the entry now has one. */
static bool install_read_locked(struct irradiance_cache *c, struct irr_entry *en,
                                enum refract_code rc, struct irr_host *vol, enum irr_kind kind,
                                double ms, const struct err *e)
{
    if (en->has_host) {
        irr_host_free(vol);
        return true;
    }
    if (rc == REFRACT_E_OK && kind != en->kind) {
        irr_host_free(vol);
        rc = REFRACT_E_STORAGE;
        e = &(struct err){.code = rc, .msg = "its data file is of the other kind"};
    }
    if (rc != REFRACT_E_OK) {
        log_warn("irradiance", "volume %016" PRIx64 " could not be read back: %s", en->key, e->msg);
        en->on_disk = false; /* recompute it on the next request */
        if (!en->has_gpu)
            en->cancelled = true;
        return false;
    }
    en->host = *vol;
    en->has_host = true;
    en->has_stats = kind == IRR_KIND_VOLUME;
    en->stats = en->host.volume.stats;
    en->compute_ms = ms;
    en->loaded_from_disk = true;
    c->counters.loaded++;
    return true;
}

/* Reads a ready entry's volume back from disk into its host copy, holding the lock (the
 * GPU thread's fallback when a copy left memory between a request and its render). */
static bool load_locked(struct irradiance_cache *c, struct irr_entry *en)
{
    if (en->has_host)
        return true;
    if (!en->on_disk)
        return false;
    struct err e = {0};
    struct irr_host vol = {0};
    enum irr_kind kind = IRR_KIND_VOLUME;
    double ms = 0;
    enum refract_code rc = irr_disk_read(c, en->key, &vol, &kind, &ms, &e);
    return install_read_locked(c, en, rc, &vol, kind, ms, &e);
}

/* HTTP threads: reads the host copies of ready entries from disk with the lock released,
 * so renders on the GPU thread never wait on the disk. Called and returns with the lock
 * held; `loading` pins each entry against removal meanwhile. ok[i] tells whether list[i]
 * has a host copy afterwards. */
static void load_unlocked(struct irradiance_cache *c, struct irr_entry **list, int n, bool *ok)
{
    struct irr_host vol[SCENE_MAX_LIGHTS] = {0};
    enum irr_kind kind[SCENE_MAX_LIGHTS] = {IRR_KIND_VOLUME};
    enum refract_code rc[SCENE_MAX_LIGHTS];
    struct err e[SCENE_MAX_LIGHTS] = {0};
    double ms[SCENE_MAX_LIGHTS] = {0};
    for (int i = 0; i < n; i++)
        list[i]->loading++;
    pthread_mutex_unlock(&c->lock);
    for (int i = 0; i < n; i++)
        rc[i] = irr_disk_read(c, list[i]->key, &vol[i], &kind[i], &ms[i], &e[i]);
    pthread_mutex_lock(&c->lock);
    for (int i = 0; i < n; i++) {
        list[i]->loading--;
        ok[i] = install_read_locked(c, list[i], rc[i], &vol[i], kind[i], ms[i], &e[i]);
    }
}

/* A ready entry usable now (in memory, or read back from disk). */
static bool usable_locked(struct irradiance_cache *c, struct irr_entry *en)
{
    if (en == NULL || en->phase != IRR_READY || en->cancelled)
        return false;
    return en->has_gpu || en->has_host || load_locked(c, en);
}

/* ---- requests -------------------------------------------------------------------------- */

/* What the scene keeps in the cache per light: volumes, photon maps, or nothing. */
static bool needs_cache(const struct scene *s)
{
    return scene_needs_light_simulation(s) || scene_needs_photon_maps(s);
}

static uint64_t entry_key(const struct irradiance_cache *c, uint64_t transport,
                          const struct scene *s, const struct scene_light *l)
{
    return scene_needs_light_simulation(s) ? irradiance_cache_key(c, transport, l)
                                           : irr_photons_key(c, transport, s, l);
}

/* Gives en the source it is computed from (held until its fields or passes are done). */
static void take_source_locked(struct irr_entry *en, const struct irradiance_source *src)
{
    en->scene = src->scene;
    en->lookup = src->lookup;
    en->lookup_ctx = src->lookup_ctx;
    en->release = src->release;
    if (src->retain)
        src->retain(src->lookup_ctx);
}

/* A photon map that stopped refining when its pose was left (cache_photons.c) goes on when
 * the pose is wanted again. */
static void resume_locked(struct irradiance_cache *c, struct irr_entry *en,
                          const struct irradiance_source *src)
{
    if (en->kind != IRR_KIND_PHOTONS || en->phase != IRR_READY || !en->refining || en->busy ||
        en->cancelled)
        return;
    en->busy = true;
    take_source_locked(en, src);
    irr_push_task_locked(c, IRR_TASK_BUILD, en);
}

static void cancel_locked(struct irradiance_cache *c, struct irr_entry *en)
{
    if (en->phase != IRR_QUEUED && en->phase != IRR_COMPUTING)
        return;
    en->cancelled = true;
    c->counters.superseded++;
}

struct irr_entry *irr_entry_add_locked(struct irradiance_cache *c)
{
    if (c->entry_count == c->entry_cap) {
        size_t cap = c->entry_cap ? c->entry_cap * 2 : 64;
        struct irr_entry **grown = realloc(c->entries, cap * sizeof *grown);
        if (grown == NULL)
            return NULL;
        c->entries = grown;
        c->entry_cap = cap;
    }
    struct irr_entry *en = calloc(1, sizeof *en);
    if (en == NULL)
        return NULL;
    en->cache = c;
    c->entries[c->entry_count++] = en;
    return en;
}

/* Queues the computation of a new entry. */
static struct irr_entry *start_locked(struct irradiance_cache *c,
                                      const struct irradiance_source *src, uint64_t transport,
                                      uint64_t key, const struct scene_light *l)
{
    struct irr_entry *en = irr_entry_add_locked(c);
    if (en == NULL)
        return NULL;
    en->key = key;
    en->transport = transport;
    en->kind = scene_needs_light_simulation(src->scene) ? IRR_KIND_VOLUME : IRR_KIND_PHOTONS;
    en->receiver = src->scene->receiver;
    en->phase = IRR_QUEUED;
    en->busy = true;
    en->light = *l;
    en->set = src->scene->lightsim;
    en->last_use = c->tick;
    en->noted_phase = -1;
    take_source_locked(en, src);
    irr_note_progress_locked(c, en); /* queued */
    irr_push_task_locked(c, IRR_TASK_BUILD, en);
    return en;
}

bool irradiance_cache_request(struct irradiance_cache *c, const struct irradiance_source *src,
                              bool retry_failed)
{
    const struct scene *s = src->scene;
    if (!needs_cache(s))
        return true;
    uint64_t transport = irradiance_transport_hash(src);
    bool all_hit = true;
    struct irr_entry *to_load[SCENE_MAX_LIGHTS];
    struct irr_slot *load_slot[SCENE_MAX_LIGHTS];
    int loads = 0;
    pthread_mutex_lock(&c->lock);
    c->tick++;
    /* Slots of lights the scene no longer has. */
    size_t j = 0;
    for (size_t i = 0; i < c->slot_count; i++) {
        struct irr_slot *sl = &c->slots[i];
        bool keep = strcmp(sl->scene, src->scene_id) != 0;
        for (size_t k = 0; !keep && k < s->light_count; k++)
            keep = strcmp(sl->light, s->lights[k].name) == 0;
        if (!keep) {
            struct irr_entry *old = irr_find_locked(c, sl->current);
            if (old)
                cancel_locked(c, old);
            continue;
        }
        c->slots[j++] = *sl;
    }
    c->slot_count = j;
    for (size_t k = 0; k < s->light_count; k++) {
        const struct scene_light *l = &s->lights[k];
        uint64_t key = entry_key(c, transport, s, l);
        struct irr_slot *sl = find_slot(c, src->scene_id, l->name);
        if (sl == NULL) {
            sl = add_slot(c, src->scene_id, l->name);
            if (sl == NULL) {
                all_hit = false;
                continue;
            }
            sl->current = key ^ 1; /* differs from key: the branch below runs */
        }
        if (sl->current != key) {
            struct irr_entry *old = irr_find_locked(c, sl->current);
            if (old && old->phase == IRR_READY) {
                sl->previous = sl->current;
                sl->has_previous = true;
            } else if (old) {
                cancel_locked(c, old);
            }
            sl->current = key;
            sl->announced = false;
        }
        struct irr_entry *en = irr_find_locked(c, key);
        if (en && en->phase == IRR_FAILED && !en->busy && retry_failed) {
            /* A failure is retried when a client sets the lights again. */
            en->cancelled = true;
            en = NULL;
        }
        if (en == NULL)
            en = start_locked(c, src, transport, key, l);
        if (en == NULL) {
            all_hit = false;
            continue;
        }
        en->last_use = c->tick;
        irr_note_use_locked(c, en);
        resume_locked(c, en, src);
        bool ready = en->phase == IRR_READY && !en->cancelled;
        metrics_cache(METRICS_CACHE_IRRADIANCE, ready ? METRICS_HIT : METRICS_MISS);
        if (ready && en->refining)
            all_hit = false; /* usable, but a photon map's passes remain: jobs wait for them */
        if (ready && !en->has_gpu && !en->has_host && en->on_disk) {
            to_load[loads] = en; /* read back below, without the lock */
            load_slot[loads++] = sl;
        } else if (ready && (en->has_gpu || en->has_host)) {
            sl->previous = key;
            sl->has_previous = true;
            irr_note_ready_locked(c, en);
        } else {
            all_hit = false;
        }
    }
    /* Another request may add or drop slots while the lock is released (the array may
     * move): remember the names and keys, and look the slots up again afterwards. */
    uint64_t load_keys[SCENE_MAX_LIGHTS];
    char load_names[SCENE_MAX_LIGHTS][SCENE_NAME_MAX];
    for (int i = 0; i < loads; i++) {
        load_keys[i] = to_load[i]->key;
        snprintf(load_names[i], sizeof load_names[i], "%s", load_slot[i]->light);
    }
    bool ok[SCENE_MAX_LIGHTS];
    if (loads > 0)
        load_unlocked(c, to_load, loads, ok);
    for (int i = 0; i < loads; i++) {
        struct irr_slot *sl = find_slot(c, src->scene_id, load_names[i]);
        if (!ok[i])
            all_hit = false;
        else if (sl && sl->current == load_keys[i]) {
            sl->previous = load_keys[i];
            sl->has_previous = true;
            irr_note_ready_locked(c, to_load[i]);
        }
    }
    irr_evict_host_locked(c);
    irr_sweep_locked(c);
    pthread_mutex_unlock(&c->lock);
    irr_events_flush(c);
    return all_hit;
}

/* ---- status ---------------------------------------------------------------------------- */

int irradiance_cache_status(struct irradiance_cache *c, const struct irradiance_source *src,
                            struct irradiance_light_status *out)
{
    const struct scene *s = src->scene;
    bool needed = needs_cache(s);
    uint64_t transport = irradiance_transport_hash(src);
    pthread_mutex_lock(&c->lock);
    for (size_t k = 0; k < s->light_count; k++) {
        const struct scene_light *l = &s->lights[k];
        struct irradiance_light_status *st = &out[k];
        memset(st, 0, sizeof *st);
        snprintf(st->name, sizeof st->name, "%s", l->name);
        st->key = entry_key(c, transport, s, l);
        st->using_ = "none";
        st->photons = scene_needs_photon_maps(s) && !scene_needs_light_simulation(s);
        if (st->photons)
            st->passes_total = photon_pass_count(s->receiver.photons, s->receiver.photons_max);
        if (!needed) {
            st->state = IRRADIANCE_NOT_NEEDED;
            continue;
        }
        struct irr_entry *en = irr_find_locked(c, st->key);
        struct irr_slot *sl = find_slot(c, src->scene_id, l->name);
        struct irr_entry *prev = NULL;
        if (sl && sl->has_previous && sl->previous != st->key) {
            prev = irr_find_locked(c, sl->previous);
            if (prev && prev->phase != IRR_READY)
                prev = NULL;
        }
        if (en == NULL) {
            /* Not requested yet (e.g. before the first render); says what a render does. */
            st->state = prev ? IRRADIANCE_STALE : IRRADIANCE_QUEUED;
            st->using_ = prev ? "previous" : "none";
            continue;
        }
        st->progress = en->progress;
        st->patches_live = en->patches_live;
        st->compute_ms = en->compute_ms;
        st->loaded_from_disk = en->loaded_from_disk;
        st->gpu_bytes = en->has_gpu ? en->gpu.bytes : 0;
        st->host_bytes = en->has_host ? irr_host_bytes(&en->host) : 0;
        st->stats = en->stats;
        st->has_stats = en->has_stats;
        st->refining = en->refining;
        st->passes = en->passes;
        if (en->has_host && en->host.photons) {
            st->photons_emitted = en->host.photons->emitted;
            st->photons_landed = en->host.photons->landed;
            st->photon_radius = en->host.photons->grid.radius;
        }
        switch (en->phase) {
        case IRR_READY:
            st->state = IRRADIANCE_READY;
            st->progress = en->refining ? en->progress : 1.0;
            st->using_ = "current";
            break;
        case IRR_FAILED:
            st->state = IRRADIANCE_FAILED;
            snprintf(st->message, sizeof st->message, "%s", en->message);
            st->using_ = prev ? "previous" : "none";
            break;
        default:
            st->state = prev                      ? IRRADIANCE_STALE
                        : en->phase == IRR_QUEUED ? IRRADIANCE_QUEUED
                                                  : IRRADIANCE_COMPUTING;
            st->using_ = prev ? "previous" : "none";
            break;
        }
    }
    pthread_mutex_unlock(&c->lock);
    return (int)s->light_count;
}

const struct irradiance_cache_desc *irradiance_cache_settings(const struct irradiance_cache *c)
{
    return &c->desc;
}

void irradiance_cache_counters(struct irradiance_cache *c, struct irradiance_cache_counters *out)
{
    pthread_mutex_lock(&c->lock);
    *out = c->counters;
    out->entries = (int)c->entry_count;
    out->gpu_bytes = gpu_bytes_locked(c);
    out->host_bytes = host_bytes_locked(c);
    out->disk_bytes = irr_disk_bytes_locked(c);
    pthread_mutex_unlock(&c->lock);
}

/* ---- renders (GPU thread) -------------------------------------------------------------- */

/* The best ready entry for a light: the current pose's, else the slot's previous one. */
static struct irr_entry *best_locked(struct irradiance_cache *c, const char *scene_id,
                                     const char *light, uint64_t key, bool *previous)
{
    *previous = false;
    struct irr_entry *en = irr_find_locked(c, key);
    if (usable_locked(c, en))
        return en;
    struct irr_slot *sl = find_slot(c, scene_id, light);
    if (sl == NULL || !sl->has_previous || sl->previous == key)
        return NULL;
    en = irr_find_locked(c, sl->previous);
    if (!usable_locked(c, en))
        return NULL;
    *previous = true;
    return en;
}

const char *irradiance_cache_gather(struct irradiance_cache *c, const struct irradiance_source *src,
                                    struct render_light *out, int *count)
{
    const struct scene *s = src->scene;
    bool needed = needs_cache(s);
    uint64_t transport = needed ? irradiance_transport_hash(src) : 0;
    bool stale = false, missing = false;
    pthread_mutex_lock(&c->lock);
    int64_t tick = ++c->tick;
    /* The previous gather's photon maps are no longer read (this thread renders one gather
     * at a time). */
    for (int j = 0; j < SCENE_MAX_LIGHTS; j++) {
        irr_pmap_unref(c->gpu_borrowed[j]);
        c->gpu_borrowed[j] = NULL;
    }
    for (size_t k = 0; k < s->light_count; k++) {
        const struct scene_light *l = &s->lights[k];
        struct render_light *rl = &out[k];
        memset(rl, 0, sizeof *rl);
        rl->kind = l->kind;
        rl->position = l->position;
        rl->direction = l->direction;
        rl->cos_spot = cos(l->spot_angle_deg * M_PI / 180.0);
        for (int ch = 0; ch < 3; ch++)
            rl->scale[ch] = l->color[ch] * l->intensity;
        rl->radius = l->radius;
        rl->camera_hidden = !l->camera_visible;
        if (!needed)
            continue;
        bool previous = false;
        struct irr_entry *en =
            best_locked(c, src->scene_id, l->name, entry_key(c, transport, s, l), &previous);
        if (en && en->kind == IRR_KIND_PHOTONS) {
            struct irr_pmap *m = en->has_host ? en->host.photons : NULL;
            if (m && k < SCENE_MAX_LIGHTS) {
                m->refs++; /* borrowed until the next gather */
                c->gpu_borrowed[k] = m;
                rl->photons = &m->grid;
                rl->photon_key = en->key ^ ((uint64_t)m->emitted * 0x9e3779b97f4a7c15ull);
                en->last_use = tick;
                irr_note_use_locked(c, en);
                stale = stale || previous;
            } else {
                missing = true;
            }
            continue;
        }
        if (en && !en->has_gpu && en->has_host) {
            /* The upload (milliseconds for a large volume) runs with the lock released, so
             * HTTP threads asking for status or hits do not wait for it; the pin keeps the
             * entry and its host copy, and only this thread makes GPU copies. */
            struct err e = {0};
            struct irradiance_gpu tex = {0};
            en->uploading = true;
            pthread_mutex_unlock(&c->lock);
            enum refract_code rc = irradiance_gpu_upload(&en->host.volume, &tex, &e);
            pthread_mutex_lock(&c->lock);
            en->uploading = false;
            if (rc == REFRACT_E_OK) {
                en->gpu = tex;
                en->has_gpu = true;
            } else {
                log_warn("irradiance", "upload of volume %016" PRIx64 ": %s", en->key, e.msg);
            }
        }
        if (en && en->has_gpu) {
            en->last_use = tick;
            irr_note_use_locked(c, en);
            rl->volume = &en->gpu;
            stale = stale || previous;
        } else {
            missing = true;
        }
    }
    irr_evict_gpu_locked(c, tick);
    irr_evict_host_locked(c);
    pthread_mutex_unlock(&c->lock);
    *count = (int)s->light_count;
    if (!needed)
        return "not-needed";
    return missing ? "missing" : stale ? "stale" : "ready";
}

/* ---- downloads ------------------------------------------------------------------------- */

enum refract_code irradiance_cache_copy(struct irradiance_cache *c,
                                        const struct irradiance_source *src, const char *name,
                                        struct irradiance_volume *out, uint64_t *key,
                                        bool *using_previous, struct err *e)
{
    memset(out, 0, sizeof *out);
    const struct scene *s = src->scene;
    const struct scene_light *l = NULL;
    for (size_t k = 0; k < s->light_count && l == NULL; k++) {
        if (strcmp(s->lights[k].name, name) == 0)
            l = &s->lights[k];
    }
    if (l == NULL)
        return err_set(e, REFRACT_E_NOT_FOUND,
                       "scene \"%s\" has no light named \"%s\"; GET /v1/scenes/%s/lights "
                       "lists them",
                       src->scene_id, name, src->scene_id);
    if (!scene_needs_light_simulation(s))
        return err_set(e, REFRACT_E_CONFLICT,
                       "scene \"%s\" needs no light simulation (no scattering object, no "
                       "receiver with \"volume\" caustics), so light \"%s\" has no irradiance "
                       "volume",
                       src->scene_id, name);
    pthread_mutex_lock(&c->lock);
    struct irr_entry *en =
        best_locked(c, src->scene_id, name,
                    irradiance_cache_key(c, irradiance_transport_hash(src), l), using_previous);
    if (en && !en->has_host && en->on_disk) {
        bool ok = false;
        load_unlocked(c, &en, 1, &ok);
    }
    enum refract_code rc = REFRACT_E_OK;
    if (en == NULL || !en->has_host) {
        rc = err_set(e, REFRACT_E_CONFLICT,
                     "light \"%s\" of scene \"%s\" has no ready irradiance volume yet; GET "
                     "/v1/scenes/%s/irradiance shows the progress",
                     name, src->scene_id, src->scene_id);
    } else {
        const struct irradiance_volume *v = &en->host.volume;
        size_t n = (size_t)v->grid.dims[0] * v->grid.dims[1] * v->grid.dims[2] * 4;
        out->grid = v->grid;
        out->stats = v->stats;
        out->irradiance = malloc(n * sizeof(float));
        out->direction = malloc(n * sizeof(float));
        if (out->irradiance == NULL || out->direction == NULL) {
            irradiance_volume_free(out);
            rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory copying a volume");
        } else {
            memcpy(out->irradiance, v->irradiance, n * sizeof(float));
            memcpy(out->direction, v->direction, n * sizeof(float));
            *key = en->key;
            en->last_use = ++c->tick;
            irr_note_use_locked(c, en);
        }
    }
    irr_evict_host_locked(c);
    pthread_mutex_unlock(&c->lock);
    return rc;
}

void irradiance_cache_forget_scene(struct irradiance_cache *c, const char *scene_id)
{
    pthread_mutex_lock(&c->lock);
    size_t j = 0;
    for (size_t i = 0; i < c->slot_count; i++) {
        struct irr_slot *sl = &c->slots[i];
        if (strcmp(sl->scene, scene_id) == 0) {
            struct irr_entry *en = irr_find_locked(c, sl->current);
            if (en)
                cancel_locked(c, en);
            continue;
        }
        c->slots[j++] = *sl;
    }
    c->slot_count = j;
    irr_sweep_locked(c);
    pthread_mutex_unlock(&c->lock);
}

/* ---- life ------------------------------------------------------------------------------ */

struct irradiance_cache *irradiance_cache_create(const struct irradiance_cache_desc *desc,
                                                 struct gpu *gpu, struct err *e)
{
    struct irradiance_cache *c = calloc(1, sizeof *c);
    if (c == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory making the irradiance cache");
        return NULL;
    }
    c->desc = *desc;
    c->desc.data_dir = NULL;
    if (c->desc.gpu_budget_bytes == 0)
        c->desc.gpu_budget_bytes = (size_t)1 << 30;
    if (c->desc.host_budget_bytes == 0)
        c->desc.host_budget_bytes = (size_t)2 << 30;
    if (!(c->desc.position_tolerance > 0))
        c->desc.position_tolerance = 1e-3;
    if (!(c->desc.direction_tolerance > 0))
        c->desc.direction_tolerance = 1e-3;
    if (c->desc.chunk_steps <= 0)
        c->desc.chunk_steps = 16;
    if (c->desc.disk_budget_bytes == 0)
        c->desc.disk_budget_bytes = (size_t)8 << 30;
    if (desc->index) {
        c->index = *desc->index;
        c->has_index = true;
    }
    c->desc.index = NULL;
    c->gpu = gpu;
    snprintf(c->dir, sizeof c->dir, "%s/irradiance", desc->data_dir);
    pthread_mutex_init(&c->lock, NULL);
    pthread_mutex_init(&c->publish_lock, NULL);
    pthread_cond_init(&c->wake, NULL);
    if (io_mkdirs(c->dir, e) != REFRACT_E_OK) {
        irradiance_cache_destroy(c);
        return NULL;
    }
    irr_index_startup(c);
    if (pthread_create(&c->worker, NULL, irr_worker_main, c) != 0) {
        err_set(e, REFRACT_E_INTERNAL, "cannot start the irradiance cache's worker thread");
        irradiance_cache_destroy(c);
        return NULL;
    }
    c->worker_started = true;
    return c;
}

void irradiance_cache_release_gpu(struct irradiance_cache *c)
{
    if (c == NULL)
        return;
    pthread_mutex_lock(&c->lock);
    for (size_t i = 0; i < c->entry_count; i++)
        irr_release_gpu_entry(c->entries[i]);
    pthread_mutex_unlock(&c->lock);
}

void irradiance_cache_stop(struct irradiance_cache *c)
{
    if (c == NULL)
        return;
    pthread_mutex_lock(&c->lock);
    c->stop = true;
    pthread_cond_broadcast(&c->wake);
    pthread_mutex_unlock(&c->lock);
    if (c->worker_started)
        pthread_join(c->worker, NULL);
    c->worker_started = false;
}

void irradiance_cache_destroy(struct irradiance_cache *c)
{
    if (c == NULL)
        return;
    irradiance_cache_stop(c);
    while (c->task_head) {
        struct irr_task *t = c->task_head;
        c->task_head = t->next;
        free(t);
    }
    for (size_t i = 0; i < c->entry_count; i++) {
        struct irr_entry *en = c->entries[i];
        irr_host_free(&en->host);
        irr_photon_scene_free(en);
        irr_drop_source(en);
        if (en->fields)
            irr_fields_release(en->fields);
        free(en);
    }
    for (int i = 0; i < IRR_FIELDS_KEPT; i++) {
        if (c->fields[i])
            irr_fields_release(c->fields[i]);
    }
    for (int j = 0; j < SCENE_MAX_LIGHTS; j++)
        irr_pmap_unref(c->gpu_borrowed[j]);
    free(c->entries);
    free(c->slots);
    irr_notes_free(c);
    pthread_cond_destroy(&c->wake);
    pthread_mutex_destroy(&c->publish_lock);
    pthread_mutex_destroy(&c->lock);
    free(c);
}
