/*
 * irradiance_cache.h - irradiance volumes cached by scene transport and light pose, with
 * asynchronous recompute on the GPU and persistence in the data directory
 * (docs/ARCHITECTURE.md, "The irradiance cache"; docs/lightsim.md).
 *
 * DESIGN. A volume depends on the scene's light transport (scene_transport_hash mixed
 * with the content checksums of the uploads it uses) and on the light's type and pose;
 * not on its colour or intensity, which scale it at render time. The key is the FNV-1a
 * mix of the transport hash, the type and the pose quantised to the configured
 * tolerances, so a pose change below the tolerance is a hit.
 *
 * Each (scene id, light name) has a *slot*: the key it wants now and the key of the last
 * volume that was ready for it. A miss creates an entry and queues it. The cache's worker
 * thread builds the simulator's input fields (lightsim_fields_build, CPU, once per
 * transport hash and kept for the next poses), then the GPU run proceeds in chunks of a
 * bounded number of wavefront steps, each a GPU_PRIORITY_LIGHTSIM work item that
 * resubmits itself, so interactive renders run between chunks. A newer pose of the same
 * light cancels a queued or computing entry: its run is destroyed at its next chunk.
 * Renders during a recompute use the slot's last ready volume ("previous": stale).
 *
 * Memory: ready entries hold GPU textures and/or a host copy, each under its own budget,
 * least recently used first out. Every finished volume is written (by the worker, temp
 * name then rename) to <data>/irradiance/<key>.exr with a <key>.json sidecar (grid,
 * statistics, compute time), so an entry evicted from both memories, or one made before
 * a restart (the directory is indexed at start-up), is read back instead of recomputed.
 *
 * Events (with desc.events): for every (scene, light) slot that wants a key, the cache
 * publishes irradiance.progress when its recompute is queued, when it starts computing and
 * then at most every 250 ms or 5 % of progress; irradiance.ready when the slot's wanted
 * volume becomes usable (computed, read back from disk, or already cached when the slot
 * turned to it), once per change of the slot's key; irradiance.failed when it fails.
 * They are collected under the lock and published after it is released, in order
 * (cache_events.c), so listeners never run under the cache's lock.
 *
 * Thread: the functions say which thread; the cache locks internally. Ownership: the
 * cache owns every entry, texture and host copy; callers get copies or borrow for a call.
 */
#ifndef REFRACT_IRRADIANCE_CACHE_H
#define REFRACT_IRRADIANCE_CACHE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"
#include "../gpu/queue.h"
#include "../lightsim/lightsim.h"
#include "../render/render.h"
#include "../scene/scene.h"

struct event_hub;

struct irradiance_index;

struct irradiance_cache_desc {
    const char *data_dir;       /* volumes persist under <data_dir>/irradiance */
    size_t gpu_budget_bytes;    /* GPU textures of ready volumes; 0 = 1 GiB */
    size_t host_budget_bytes;   /* host copies of ready volumes; 0 = 2 GiB */
    double position_tolerance;  /* world units; 0 = 1e-3 */
    double direction_tolerance; /* radians; 0 = 1e-3 */
    int chunk_steps;            /* wavefront steps per GPU work item; 0 = 16 */
    size_t disk_budget_bytes;   /* files under <data_dir>/irradiance before LRU removal;
                                   0 = 8 GiB */
    /* Where the volumes on disk are recorded (borrowed, outliving the cache; the store's
     * database in refractd); NULL = the directory alone. */
    const struct irradiance_index *index;
    /* Where irradiance.progress / .ready / .failed are published (events.h; borrowed,
     * outliving the cache); NULL = nowhere. */
    struct event_hub *events;
};

/* What the cache needs of a scene version; borrowed for the call, except that the cache
 * calls retain(ctx) to keep the scene and lookup_ctx alive until the fields are built,
 * then release(ctx). */
struct irradiance_source {
    const char *scene_id;
    const struct scene *scene;
    scene_volume_lookup_fn lookup;
    void *lookup_ctx;
    uint64_t uploads_hash; /* mix of the content checksums of the uploads the scene uses */
    void (*retain)(void *ctx);
    void (*release)(void *ctx);
};

enum irradiance_state {
    IRRADIANCE_QUEUED = 0,
    IRRADIANCE_COMPUTING = 1,
    IRRADIANCE_READY = 2,
    IRRADIANCE_STALE = 3, /* the current pose is being computed; the previous one is used */
    IRRADIANCE_FAILED = 4,
    IRRADIANCE_NOT_NEEDED = 5,
};
const char *irradiance_state_name(enum irradiance_state s);

/* One light's status (GET /v1/scenes/{id}/irradiance). */
struct irradiance_light_status {
    char name[SCENE_NAME_MAX];
    enum irradiance_state state;
    double progress;
    int patches_live;
    uint64_t key;
    size_t gpu_bytes, host_bytes;
    double compute_ms;
    bool loaded_from_disk; /* the ready volume was read back from the data directory */
    const char *using_;    /* "current", "previous", "none" */
    char message[ERR_MSG_MAX];
    struct lightsim_stats stats;
    bool has_stats;
    /* A photon map instead of a volume (receiver.caustics "photons", docs/photons.md "The
     * cache"): usable ("ready") after its first pass, `refining` while passes remain
     * (progress: the share of its photons traced); the map in use has photons_emitted
     * photons, photons_landed of them stored, and gathers with photon_radius. */
    bool photons;
    bool refining;
    int passes, passes_total;
    long photons_emitted;
    size_t photons_landed;
    double photon_radius;
};

/* Counters over the cache's lifetime (and what it holds now). */
struct irradiance_cache_counters {
    long long computed, superseded, loaded, failed, evicted_gpu, evicted_host, evicted_disk;
    int entries;
    size_t gpu_bytes, host_bytes;
    uint64_t disk_bytes; /* the volumes' files under <data>/irradiance */
};

struct irradiance_cache;

/* Any thread: opens (creating) <data_dir>/irradiance and indexes the volumes in it,
 * starts the worker thread. Returns a new cache or NULL with e filled. */
struct irradiance_cache *irradiance_cache_create(const struct irradiance_cache_desc *desc,
                                                 struct gpu *gpu, struct err *e);
/* GPU thread, in the GPU thread's final work item: destroys runs and textures. */
void irradiance_cache_release_gpu(struct irradiance_cache *c);
/* Any thread, after the GPU thread has stopped and before gpu_destroy frees the queue:
 * stops the worker and waits for it (a build in progress still calls gpu_submit, which
 * then refuses). Idempotent. */
void irradiance_cache_stop(struct irradiance_cache *c);
/* Any thread, after the GPU thread has stopped: stops the worker (irradiance_cache_stop),
 * frees the rest. */
void irradiance_cache_destroy(struct irradiance_cache *c);

/* The transport hash of a source: scene_transport_hash mixed with uploads_hash. */
uint64_t irradiance_transport_hash(const struct irradiance_source *src);
/* The key of one light of a scene with that transport hash (colour and intensity not in). */
uint64_t irradiance_cache_key(const struct irradiance_cache *c, uint64_t transport,
                              const struct scene_light *l);

/* HTTP thread: makes every light of the source wanted: a ready volume (in memory, or read
 * back from disk now) is a hit; otherwise a recompute is queued, and an older pose of the
 * same light that is still queued or computing is cancelled. Slots of lights the scene no
 * longer has are dropped. A failed pose is computed again only when retry_failed (a client
 * set the lights), not on every render. Returns true when every light hit (or none needs
 * simulation). */
bool irradiance_cache_request(struct irradiance_cache *c, const struct irradiance_source *src,
                              bool retry_failed);

/* Any thread: the settings in effect (defaults filled in). */
const struct irradiance_cache_desc *irradiance_cache_settings(const struct irradiance_cache *c);

/* Any thread: the status of each light of the source; out has SCENE_MAX_LIGHTS entries.
 * Returns the light count. */
int irradiance_cache_status(struct irradiance_cache *c, const struct irradiance_source *src,
                            struct irradiance_light_status *out);
void irradiance_cache_counters(struct irradiance_cache *c, struct irradiance_cache_counters *out);

/* GPU thread: the render_lights of the source's scene with the best volume for each
 * (current pose, else the previous one), uploaded to the GPU if needed. out has
 * SCENE_MAX_LIGHTS entries; the volumes are borrowed until the next cache call on the GPU
 * thread. Returns "ready", "stale", "missing" or "not-needed" (X-Refract-Irradiance). */
const char *irradiance_cache_gather(struct irradiance_cache *c, const struct irradiance_source *src,
                                    struct render_light *out, int *count);

/* HTTP thread: a copy of the ready volume used for light `name` (current, else previous:
 * *using_previous tells). NOT_FOUND-like codes: REFRACT_E_NOT_FOUND when the scene has no
 * such light, REFRACT_E_CONFLICT when it has no ready volume yet (state says why). */
enum refract_code irradiance_cache_copy(struct irradiance_cache *c,
                                        const struct irradiance_source *src, const char *name,
                                        struct irradiance_volume *out, uint64_t *key,
                                        bool *using_previous, struct err *e);

/* Any thread: a volume as OpenEXR bytes (docs/api.md, "Irradiance volumes as EXR"):
 * width = dims x, height = dims y * dims z, slice z in rows [z * dims y, (z + 1) * dims y)
 * (z = 0 at the top), row y of a slice = voxel row y; channels R, G, B (irradiance of a unit
 * light), dir.X, dir.Y, dir.Z, dir.W (mean light direction, W = 1 where light passed);
 * string attributes refract.grid ({"dims", "bmin", "voxel"}) and refract.key. */
enum refract_code irradiance_volume_encode_exr(const struct irradiance_volume *v, uint64_t key,
                                               void **bytes, size_t *len, struct err *e);
/* The reverse (grid from refract.grid; stats zero). */
enum refract_code irradiance_volume_decode_exr(const void *bytes, size_t len,
                                               struct irradiance_volume *out, struct err *e);

/* The statistics as a JSON object (flux_* triplets and counters), for the API. */
struct cJSON;
struct cJSON *irradiance_stats_json(const struct lightsim_stats *s);

/* Any thread: forgets the slots of a deleted scene (its volumes stay cached by key). */
void irradiance_cache_forget_scene(struct irradiance_cache *c, const char *scene_id);

#endif
