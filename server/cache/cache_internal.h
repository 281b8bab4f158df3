/*
 * cache_internal.h - what the irradiance cache's files share (not used outside
 * server/cache/): entries, slots, the worker's task queue and the locking rules.
 *
 * LOCKING: `lock` guards the entry table, the slots, the task queue, the counters and
 * every entry field marked (L). Fields marked (G) belong to the GPU thread, (W) to the
 * worker. An entry's host copy is read outside the lock only by the worker while
 * `persisting` pins it; GPU textures are made and freed on the GPU thread only, under the
 * lock (so status readers see consistent byte counts).
 *
 * LIFETIME: an entry leaves the table only when it was cancelled (superseded) and no task
 * or GPU item refers to it (`busy` false). Ready entries are never removed, only evicted
 * from the GPU and host memories; an index entry (on disk only) costs a few hundred bytes.
 */
#ifndef REFRACT_CACHE_INTERNAL_H
#define REFRACT_CACHE_INTERNAL_H

#include <pthread.h>
#include <stdatomic.h>

#include "../core/photon.h"
#include "../lightsim/gpu/lightsim_gpu.h"
#include "../scene/scene_pathtrace.h"
#include "irradiance_cache.h"
#include "irradiance_index.h"

#define IRR_FIELDS_KEPT 4 /* input fields kept for the next poses, per transport hash */

/* Input fields of one transport hash, shared by the runs that start from them. */
struct irr_fields {
    atomic_int refs;
    uint64_t transport;
    struct lightsim_fields f;
};
void irr_fields_release(struct irr_fields *f);

enum irr_phase { IRR_QUEUED = 0, IRR_COMPUTING = 1, IRR_READY = 2, IRR_FAILED = 3 };

/* What an entry is: a light's irradiance volume (the light simulator's, on the GPU), or a
 * light's photon map at unit intensity (receiver.caustics "photons", traced on the worker's
 * CPU threads in passes: cache_photons.c, docs/photons.md "The cache"). */
enum irr_kind { IRR_KIND_VOLUME = 0, IRR_KIND_PHOTONS = 1 };

/* A photon map, shared by its entry and the GPU thread's last gather (which borrows it
 * until its next one: irradiance_cache_gather), so that a pass may replace an entry's map
 * or memory evict it while a render reads it. refs changes under the cache's lock. */
struct irr_pmap {
    int refs;
    struct photon_grid grid; /* unit light */
    long emitted;            /* the photons it was made of */
    size_t landed;
};
void irr_pmap_unref(struct irr_pmap *m);

/* An entry's host copy. */
struct irr_host {
    struct irradiance_volume volume; /* IRR_KIND_VOLUME */
    struct irr_pmap *photons;        /* IRR_KIND_PHOTONS */
};
size_t irr_host_bytes(const struct irr_host *h);
void irr_host_free(struct irr_host *h);

struct irr_entry {
    struct irradiance_cache *cache;
    uint64_t key, transport;
    enum irr_kind kind; /* set when made, never changed */
    enum irr_phase phase;     /* (L) */
    bool cancelled;           /* (L) superseded by a newer pose */
    bool busy;                /* (L) a worker task or a GPU item refers to it */
    bool persisting;          /* (L) the worker is writing the host copy */
    bool on_disk;             /* (L) <key>.exr and <key>.json exist */
    bool loaded_from_disk;    /* (L) */
    int loading;              /* (L) threads reading its volume back from disk */
    bool uploading;           /* (L) the GPU thread is making textures from the host copy,
                                 lock released: pins the entry and its host copy */
    struct scene_light light; /* the pose computed (unit colour; colour ignored) */
    struct scene_lightsim set;
    double progress;               /* (L) */
    int patches_live;              /* (L) */
    struct lightsim_stats stats;   /* (L) */
    bool has_stats;                /* (L) */
    char message[ERR_MSG_MAX];     /* (L) when failed */
    double compute_ms;             /* (L) begin to read-back, GPU thread time included */
    double started_ms;             /* (G) */
    int noted_phase;               /* (L) phase of the last progress event; -1 = none */
    double noted_progress;         /* (L) progress of the last progress event */
    double noted_ms;               /* (L) gpu_time_ms() of the last progress event */
    struct irr_host host;          /* (L) */
    bool has_host;                 /* (L) */
    /* IRR_KIND_PHOTONS: the map is usable (IRR_READY) after its first pass and refines
     * while `refining`; the last pass's map is the one persisted. */
    int passes;                    /* (L) passes done */
    bool refining;                 /* (L) passes remain */
    struct scene_receiver receiver; /* the photon settings (photons, photon_radius) */
    struct irr_photon_scene *pt;   /* (W) the geometry and the light, from the first pass on */
    struct irradiance_gpu gpu;     /* (L, made and freed on the GPU thread) */
    bool has_gpu;                  /* (L) */
    int64_t last_use;              /* (L) cache tick of the last request or render */
    int64_t used_ms;               /* (L) unix ms of the last use (disk LRU, the index) */
    int64_t touched_ms;            /* (L) used_ms last sent to the index */
    uint64_t disk_bytes;           /* (L) <key>.exr + <key>.json while on_disk */
    /* Until the fields are built (W): the scene version it was asked for. */
    const struct scene *scene;
    scene_volume_lookup_fn lookup;
    void *lookup_ctx;
    void (*release)(void *ctx);
    struct irr_fields *fields;    /* (G) held from the worker until the run begins */
    struct lightsim_gpu_run *run; /* (G) */
    bool finished;                /* (G) the run ended (ready, failed or cancelled) */
    struct gpu_work work;         /* the chunk item, resubmitted until finished */
};

struct irr_slot {
    char scene[64];
    char light[SCENE_NAME_MAX];
    uint64_t current;  /* key wanted now */
    uint64_t previous; /* key of the last volume that was ready for it */
    bool has_previous;
    bool announced; /* irradiance.ready was published for `current` */
};

enum irr_task_kind { IRR_TASK_BUILD = 0, IRR_TASK_PERSIST = 1 };
struct irr_task {
    enum irr_task_kind kind;
    struct irr_entry *entry;
    struct irr_task *next;
};

/* An event waiting to be published (cache_events.c): made under the lock, published after. */
struct irr_note {
    struct irr_note *next;
    const char *type; /* EVENT_IRRADIANCE_* */
    char scene[64];
    char light[SCENE_NAME_MAX];
    uint64_t key;
    const char *state; /* progress: "queued" or "computing" */
    double progress;
    double compute_ms;         /* ready */
    bool loaded_from_disk;     /* ready */
    bool photons;              /* ready: a photon map's pass */
    bool refining;             /* ready: passes remain */
    long photons_emitted;      /* ready: the map's photons */
    char message[ERR_MSG_MAX]; /* failed */
};

#define IRR_TOUCH_MAX 64

struct irradiance_cache {
    pthread_mutex_t lock;
    pthread_mutex_t publish_lock;             /* taken before lock: notes leave in the order made */
    struct irr_note *notes_head, *notes_tail; /* (L) */
    pthread_cond_t wake;
    pthread_t worker;
    bool worker_started, stop;
    struct irradiance_cache_desc desc;
    char dir[600]; /* <data>/irradiance */
    struct gpu *gpu;
    struct irr_entry **entries;
    size_t entry_count, entry_cap;
    struct irr_slot *slots;
    size_t slot_count, slot_cap;
    struct irr_task *task_head, *task_tail;
    struct irr_fields *fields[IRR_FIELDS_KEPT]; /* (W) most recent first */
    struct irr_pmap *gpu_borrowed[SCENE_MAX_LIGHTS]; /* (L) the last gather's photon maps */
    int64_t tick;
    struct irradiance_cache_counters counters;
    struct irradiance_index index; /* the database's rows (irradiance_index.h) */
    bool has_index;
    uint64_t touch_keys[IRR_TOUCH_MAX]; /* (L) uses waiting for the worker to record */
    int64_t touch_ms[IRR_TOUCH_MAX];    /* (L) */
    size_t touch_count;                 /* (L) */
};

/* cache.c */
/* FNV-1a 64 of data mixed into h (the keys). */
uint64_t irr_mix(uint64_t h, const void *data, size_t len);
struct irr_entry *irr_find_locked(struct irradiance_cache *c, uint64_t key);
/* A new zeroed entry of c (cache set), appended to the table; NULL when out of memory. */
struct irr_entry *irr_entry_add_locked(struct irradiance_cache *c);
/* Frees cancelled entries nothing refers to any more. */
void irr_sweep_locked(struct irradiance_cache *c);
void irr_push_task_locked(struct irradiance_cache *c, enum irr_task_kind kind,
                          struct irr_entry *en);
void irr_evict_host_locked(struct irradiance_cache *c);
/* GPU thread: frees textures of the least recently used entries, except those used at
 * tick `keep_tick` or later, until the GPU budget holds. */
void irr_evict_gpu_locked(struct irradiance_cache *c, int64_t keep_tick);
void irr_drop_source(struct irr_entry *en);

/* cache_compute.c */
/* Records en's failure (message, counter, event, log). */
void irr_fail_locked(struct irr_entry *en, const struct err *e);
void *irr_worker_main(void *arg);
void irr_release_gpu_entry(struct irr_entry *en); /* GPU thread */

/* cache_events.c. The *_locked ones queue a note for every slot that wants en->key now
 * (nothing without a hub); irr_events_flush publishes the queued notes: call it after
 * releasing the lock wherever notes may have been queued. */
void irr_note_progress_locked(struct irradiance_cache *c, struct irr_entry *en);
void irr_note_ready_locked(struct irradiance_cache *c, struct irr_entry *en);
void irr_note_failed_locked(struct irradiance_cache *c, const struct irr_entry *en);
void irr_events_flush(struct irradiance_cache *c);
void irr_notes_free(struct irradiance_cache *c);

/* cache_photons.c */
struct irr_photon_scene; /* the entry's pathtrace scene with its light alone, unit intensity */
/* The key of a light's photon map: the volume key's inputs, the lamp's radius and the photon
 * settings. */
uint64_t irr_photons_key(const struct irradiance_cache *c, uint64_t transport,
                         const struct scene *s, const struct scene_light *l);
/* Worker, lock not held: one pass of a photon entry (the task IRR_TASK_BUILD of such an
 * entry), queueing the next while passes remain and its key is still wanted. */
void irr_photons_pass(struct irradiance_cache *c, struct irr_entry *en);
void irr_photon_scene_free(struct irr_entry *en);
/* The map as <key>.pmap bytes (native byte order) and back. */
enum refract_code irr_photons_write(const char *path, const struct irr_host *h, struct err *e);
enum refract_code irr_photons_read(const char *path, struct irr_host *h, struct err *e);

/* cache_disk.c */
void irr_volume_path(const struct irradiance_cache *c, uint64_t key, const char *ext, char *out,
                     size_t size);
/* The data file's extension of a key on disk: "pmap" (a photon map) when <key>.pmap exists,
 * else "exr" (a volume). */
const char *irr_data_ext(const struct irradiance_cache *c, uint64_t key);
enum refract_code irr_disk_write(const struct irradiance_cache *c, const struct irr_entry *en,
                                 struct err *e);
/* Reads <key>.exr or <key>.pmap and its sidecar into a new host copy (stats and compute_ms
 * too); *kind says which it was. */
enum refract_code irr_disk_read(const struct irradiance_cache *c, uint64_t key,
                                struct irr_host *out, enum irr_kind *kind, double *compute_ms,
                                struct err *e);
/* The keys of every <key>.json with a <key>.exr or <key>.pmap in the directory; *keys
 * malloc'd. */
size_t irr_disk_list_pairs(const struct irradiance_cache *c, uint64_t **keys);

/* cache_index.c */
int64_t irr_unix_ms(void);
/* At creation: entries for the volumes on disk, rows and files reconciled (no lock). */
void irr_index_startup(struct irradiance_cache *c);
/* Worker, lock not held: en's files were just written; records its row, then keeps the
 * disk budget. */
void irr_index_recorded(struct irradiance_cache *c, struct irr_entry *en);
/* en was used now (a hit, a render, a copy): queues its last use for the index. */
void irr_note_use_locked(struct irradiance_cache *c, struct irr_entry *en);
/* Worker, lock not held: writes the queued uses in one transaction. */
void irr_index_flush_touches(struct irradiance_cache *c);
/* Lock not held: removes the least recently used volumes' files until the disk budget
 * holds. */
void irr_evict_disk(struct irradiance_cache *c);
uint64_t irr_disk_bytes_locked(const struct irradiance_cache *c);

#endif
