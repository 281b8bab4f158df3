/*
 * store.h - the daemon's scenes and their uploads, in memory and in the data directory.
 *
 * DESIGN: a scene id maps to a slot holding the current *version* of the scene: an
 * immutable, reference-counted struct store_scene (the document, its parsed model, the
 * uploaded volumes and environment image). Changing a scene (an upload) makes a new
 * version with a new generation number and swaps it into the slot; work in flight keeps
 * the version it started with until it releases it. So a render never sees a half-made
 * change, and readers need no lock beyond the slot lookup.
 *
 * Persistence (docs/ARCHITECTURE.md, "Data directory"): metadata in SQLite (WAL,
 * synchronous=FULL), content in immutable content-addressed blob files:
 *     <data>/refract.db (+ -wal, -shm)   scenes, uploads, jobs, job_frames, meta
 *     <data>/blobs/<aa>/<sha256>          volumes as little-endian float32 (x fastest,
 *                                         components interleaved), environment images
 *                                         and meshes (OBJ or PLY) as uploaded; <aa> = the
 *                                         hash's first 2 digits
 *     <data>/tmp/                         uploads being received and blobs being written;
 *                                         emptied at start-up
 *     <data>/irradiance/                  the irradiance cache's files (cache_disk.c),
 *                                         indexed by the irradiance table
 *                                         (store_irradiance.c)
 * A blob is written to <data>/tmp, fsynced, renamed into blobs/ and its directory
 * fsynced before the row naming it is committed; so every committed row names a
 * complete blob, and a crash leaves at most an orphan blob (collected at start-up) or a
 * temporary file (removed at start-up). Every accepted change is committed before the
 * call returns. A data directory in the file layout of before (scenes/<id>/scene.json,
 * volumes/<name>.f32 + .json, environment.img, meshes/<name>.obj|.ply) is converted on
 * first open and kept as scenes.migrated/ (store_migrate.c).
 *
 * Volumes are mapped from their blob files (read-only): a volume costs page cache, not
 * heap, and the HTTP upload path never holds a whole volume in memory.
 *
 * Ownership: functions returning a struct store_scene * return a new reference that the
 * caller releases with store_scene_release(). Thread: any; the store locks internally.
 */
#ifndef REFRACT_STORE_H
#define REFRACT_STORE_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"
#include "../core/sha256.h"
#include "../scene/scene.h"

#define STORE_ID_MAX 64

/* What an upload's row records; the 201 answer of an upload reports it. */
struct store_upload_info {
    int dims[3];           /* volumes; environments: width, height, 1 */
    int components;        /* 1 or 3 (volumes), 4 (environments: RGBA after decoding) */
    char type[16];         /* source sample type ("float32", "uint8", ...; "image") */
    char format[8];        /* "raw", "nrrd", "exr"; "image" for environments */
    double min[3], max[3]; /* per component, as stored */
    double min_all, max_all;
    uint64_t checksum;            /* FNV-1a 64 of the blob's bytes */
    char sha256[SHA256_HEX_SIZE]; /* the blob's content address */
    size_t bytes;                 /* the blob's size */
    int64_t created_unix;
};

struct store_volume {
    atomic_int refs;
    char name[SCENE_VOLUME_NAME_MAX];
    struct scene_volume view; /* dims, components, data (points into `data`) */
    float *data;              /* owned: mapped from the blob (mapped) or malloc'd */
    bool mapped;
    size_t count; /* floats */
    double min, max;
    uint64_t checksum; /* FNV-1a 64 of the little-endian bytes */
    struct store_upload_info info;
};

struct store_env {
    atomic_int refs;
    int width, height;
    float *rgba; /* linear, row 0 at the top; owned */
    size_t source_bytes;
    struct store_upload_info info;
};

struct store_scene {
    atomic_int refs;
    char id[STORE_ID_MAX];
    uint64_t generation; /* unique per version across the store's lifetime */
    /* The generation of the last change to what the GPU scene data is built from (the
     * document's objects or an upload). A lights-only change (store_scene_set_lights)
     * makes a new version with the same data_generation, so the renderer's scene cache,
     * keyed on it, is not rebuilt. */
    uint64_t data_generation;
    char *json; /* the document as received; owned */
    size_t json_len;
    struct scene *scene;           /* owned */
    struct store_volume **volumes; /* owned references */
    size_t volume_count;
    struct store_env *env; /* owned reference or NULL */
    int64_t created_unix;
    struct store_mesh **meshes; /* owned references (store_mesh.h); NULL when none */
    size_t mesh_count;
};

/* What the GPU thread last reported about a scene's build. */
struct store_gpu_status {
    char state[16]; /* "pending", "ready", "failed" */
    uint64_t generation;
    size_t gpu_bytes;
    double build_ms;
    char message[ERR_MSG_MAX];
};

struct store_desc {
    const char *data_dir;                 /* created if missing */
    struct scene_limits limits;           /* for parsing documents */
    int max_scenes;                       /* 0 = 64 */
    long long max_env_pixels;             /* 0 = 8M */
    unsigned long long max_storage_bytes; /* total blob bytes; 0 = unlimited */
};

/* What GET /v1/storage reports. */
struct store_usage {
    unsigned long long blob_bytes, blob_count, max_storage_bytes; /* 0 = unlimited */
    long long scenes, uploads;
};

struct store;

/* Opens (creating) the data directory: removes temporary files, migrates the old
 * layout, loads every scene and upload, collects orphan blobs. Scenes that no longer
 * parse are skipped with a warning (and left in the database). Returns a new store (close with
 * store_close) or NULL with e filled. */
struct store *store_open(const struct store_desc *desc, struct err *e);
void store_close(struct store *s);

/* Validates and stores a new scene. id may be NULL (a random id is made) or a name of
 * [a-z0-9_-], 1..63 chars (then an existing scene with that id is replaced). */
enum refract_code store_scene_create(struct store *s, const char *id, const char *json, size_t len,
                                     struct store_scene **out, struct err *e);
/* Replaces the document of an existing scene by `json` (a copy of its document with a
 * different "lights" array: the caller promises nothing else changed), validating it
 * completely. Makes a new version that keeps the uploads and the data_generation, and
 * persists the document. SCENE_NOT_FOUND, the parse errors, STORAGE. */
enum refract_code store_scene_set_lights(struct store *s, const char *id, const char *json,
                                         size_t len, struct store_scene **out, struct err *e);
/* A private version of base (not installed, not persisted) with document `json`: a copy of
 * base's with other light poses (the caller promises nothing else changed). It keeps
 * base's uploads and data_generation, so the renderer reuses base's GPU data. For batch
 * jobs that move a light. *out is a new reference. Parse errors, OUT_OF_MEMORY. */
enum refract_code store_scene_derive(struct store *s, struct store_scene *base, const char *json,
                                     size_t len, struct store_scene **out, struct err *e);
/* New reference to the current version, or NULL when unknown. */
struct store_scene *store_scene_get(struct store *s, const char *id);
void store_scene_release(struct store_scene *sc);
enum refract_code store_scene_delete(struct store *s, const char *id, struct err *e);

/* Current versions of all scenes, sorted by id: *out is a new array of new references;
 * release each and free the array with store_list_free. Returns the count. */
size_t store_scene_list(struct store *s, struct store_scene ***out);
void store_list_free(struct store_scene **list, size_t count);

/* Adds or replaces volume `name` of scene `id`. Consumes `data` (count floats, freed on
 * failure too). Makes a new version; *out (may be NULL) gets a reference to the stored
 * volume. */
enum refract_code store_volume_put(struct store *s, const char *id, const char *name,
                                   const int dims[3], int components, float *data, size_t count,
                                   struct store_volume **out, struct err *e);
void store_volume_release(struct store_volume *v);

/* Adds or replaces volume `name` of scene `id` from the canonical blob in file tmp_path
 * (little-endian float32 as io_volume_decode writes it, described by info, whose sha256
 * is the file's hash). Consumes tmp_path: it is renamed into the blob store or removed.
 * Errors: SCENE_NOT_FOUND, LIMIT_EXCEEDED (volumes per scene), STORAGE (disk, or over
 * --max-storage-bytes). */
enum refract_code store_volume_put_file(struct store *s, const char *id, const char *name,
                                        const struct store_upload_info *info, const char *tmp_path,
                                        struct store_volume **out, struct err *e);

/* Decodes and stores the environment image of scene `id` (bytes as uploaded). */
enum refract_code store_env_put(struct store *s, const char *id, const void *bytes, size_t len,
                                int *width, int *height, struct err *e);
/* The same from the uploaded file tmp_path whose SHA-256 is sha256 (consumed like
 * store_volume_put_file's). */
enum refract_code store_env_put_file(struct store *s, const char *id, const char *tmp_path,
                                     const char *sha256, int *width, int *height, struct err *e);

/* Creates a new temporary file under <data>/tmp (removed at the next start-up if left
 * behind): returns an fd open for writing and its path, or -1 with e filled (STORAGE).
 * For request bodies streamed to disk (server/http/server.c). */
int store_upload_tmp_create(struct store *s, char *path_out, size_t size, struct err *e);

/* The data directory's use and limit. */
void store_usage_get(struct store *s, struct store_usage *out);

/* The irradiance cache's index in the database (store_irradiance.c, irradiance_index.h):
 * fills out with functions bound to s (valid while s is open). */
struct irradiance_index;
void store_irradiance_index(struct store *s, struct irradiance_index *out);
/* The rows of that index: how many volumes the cache keeps on disk and their bytes. */
void store_irradiance_usage(struct store *s, long long *volumes, unsigned long long *bytes);

/* The scene_volume_lookup_fn of a version: ctx is a struct store_scene *. Names with
 * SCENE_MESH_LOOKUP_PREFIX find its meshes (store_mesh.h). */
const struct scene_volume *store_volume_lookup(void *ctx, const char *name);

void store_gpu_status_set(struct store *s, const char *id, const struct store_gpu_status *st);
/* Copies the status; returns false when the id has none. */
bool store_gpu_status_get(struct store *s, const char *id, struct store_gpu_status *out);

/* True when name is 1..63 chars of [A-Za-z0-9_-] (volume names, ids). */
bool store_name_valid(const char *name, bool allow_upper);

/* ---- batch jobs (store_jobs.c; server/jobs/ runs them) ---- */

/* One row of the jobs table. spec is the job's normalised specification (JSON). */
struct store_job_row {
    char id[STORE_ID_MAX];
    char scene[STORE_ID_MAX]; /* "" (NULL in the table): an inline scene */
    char state[16];           /* queued, running, done, failed, cancelled */
    int frames_total, frames_done;
    int64_t created_unix, updated_unix;
    int64_t started_unix, finished_unix; /* 0 = not yet */
    char message[ERR_MSG_MAX];
    const char *spec; /* borrowed (insert) or valid during the callback (each) */
};

/* Inserts a new job row (committed before it returns). */
enum refract_code store_job_insert(struct store *s, const struct store_job_row *row, struct err *e);
/* Stores frame `frame` of job `id` as a durable blob, then, in one transaction, inserts its
 * job_frames row and advances frames_done from `frame` to frame + 1 (state running). So a
 * frame is either committed together with the count that says it is done, or not at all;
 * committing the same frame twice is refused (CONFLICT): no frame is ever stored twice. */
enum refract_code store_job_frame_commit(struct store *s, const char *id, int frame,
                                         const void *bytes, size_t len, struct err *e);
/* Sets state and message (NULL = none) and the updated time; the first "running" sets
 * started, "done", "failed" and "cancelled" set finished. */
enum refract_code store_job_state_set(struct store *s, const char *id, const char *state,
                                      const char *message, struct err *e);
/* Calls fn for every job row, by creation time. */
typedef void (*store_job_fn)(const struct store_job_row *row, void *ctx);
enum refract_code store_job_each(struct store *s, store_job_fn fn, void *ctx, struct err *e);
/* A copy of the bytes of a committed frame (*bytes is new; caller frees). NOT_FOUND when
 * the frame is not committed. */
enum refract_code store_job_frame_read(struct store *s, const char *id, int frame, void **bytes,
                                       size_t *len, struct err *e);
/* Deletes the job's rows and frees the frames' blobs no other row names. */
enum refract_code store_job_delete(struct store *s, const char *id, struct err *e);
/* Where a committed frame's bytes are: its blob's address and size. */
struct store_job_frame_ref {
    char sha256[SHA256_HEX_SIZE];
    size_t bytes;
};
/* The refs of frames 0 .. count - 1 of job id, in order: *out is a new array (caller
 * frees). NOT_FOUND when one of them is not committed, STORAGE. For the job archive, which
 * streams each frame from its blob (store_job_frame_open) instead of holding them. */
enum refract_code store_job_frame_refs(struct store *s, const char *id, int count,
                                       struct store_job_frame_ref **out, struct err *e);
/* Opens a frame's blob read-only: returns an fd the caller closes, or -1 with e filled
 * (STORAGE: the blob is gone, e.g. its job was deleted since the refs were read, or has
 * another size). An open fd stays readable even if the blob is removed meanwhile. */
int store_job_frame_open(struct store *s, const struct store_job_frame_ref *ref, struct err *e);
/* A private version for a job's inline scene: document json (len bytes) parsed and
 * validated with the same limits as store_scene_create's, under id (e.g. "job:<job id>",
 * which is not a scene id, so the render and irradiance caches keep it apart from every
 * scene), with no uploads. Never installed or persisted: the job's specification, stored
 * as sent, is what survives a restart. *out is a new reference. The parse errors,
 * OUT_OF_MEMORY. */
enum refract_code store_scene_private(struct store *s, const char *id, const char *json, size_t len,
                                      struct store_scene **out, struct err *e);

#endif
