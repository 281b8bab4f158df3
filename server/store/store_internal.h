/*
 * store_internal.h - what the store's files share: the store itself, the metadata
 * database (store_db.c), the blob files (store_blob.c), the migration of the old
 * file layout (store_migrate.c) and the meshes (store_mesh.c). Not used outside
 * server/store/.
 *
 * LOCKING: `lock` guards the slots, the statuses, the database connection and the
 * blob directory's contents (blob_bytes included). Every function here named *_locked
 * expects it held; the others take no lock.
 */
#ifndef REFRACT_STORE_INTERNAL_H
#define REFRACT_STORE_INTERNAL_H

#include <pthread.h>
#include <sqlite3.h>

#include "store.h"

#define STORE_PATH_MAX 4096
#define STORE_MAX_JSON_BYTES (64u << 20)
#define STORE_MAX_VOLUMES_PER_SCENE 64

struct slot {
    char id[STORE_ID_MAX];
    struct store_scene *current;
    struct store_gpu_status status;
    bool has_status;
};

struct store {
    pthread_mutex_t lock;
    struct store_desc desc;
    char data_dir[512];
    struct slot *slots;
    size_t slot_count, slot_cap;
    atomic_uint_fast64_t next_generation;
    sqlite3 *db;
    unsigned long long blob_bytes; /* sum of the sizes of the files under <data>/blobs */
    unsigned long long blob_count;
    /* Bytes of uploads being received under <data>/tmp (store_tmp.c): they count against
     * --max-storage-bytes while they arrive, so a client cannot fill the disk with
     * uploads it never finishes. */
    unsigned long long tmp_bytes;
};

/* One row of the uploads table. */
struct store_upload_row {
    char scene[STORE_ID_MAX];
    char name[SCENE_VOLUME_NAME_MAX];
    char kind[16]; /* "volume", "environment", "mesh" */
    struct store_upload_info info;
};

/* ---- store_db.c ---- */
enum refract_code store_db_open(struct store *s, struct err *e);
void store_db_close(struct store *s);
enum refract_code store_db_begin_locked(struct store *s, struct err *e);
enum refract_code store_db_commit_locked(struct store *s, struct err *e);
void store_db_rollback_locked(struct store *s);
enum refract_code store_db_scene_put_locked(struct store *s, const struct store_scene *v,
                                            struct err *e);
/* Deletes the scene's row and its uploads' rows; *blobs (may be NULL) gets a new array of
 * the blob hashes those rows named (caller frees), *count their number. */
enum refract_code store_db_scene_delete_locked(struct store *s, const char *id, bool keep_scene_row,
                                               char (**blobs)[SHA256_HEX_SIZE], size_t *count,
                                               struct err *e);
/* Inserts or replaces an upload row; *old_blob gets the blob it replaced ("" if none). */
enum refract_code store_db_upload_put_locked(struct store *s, const struct store_upload_row *row,
                                             char old_blob[SHA256_HEX_SIZE], struct err *e);
bool store_db_blob_referenced_locked(struct store *s, const char *hash);
/* The bytes that replacing upload (scene, kind, name) would free: its blob's size when no
 * other row names that blob, else 0. */
size_t store_db_replace_credit_locked(struct store *s, const char *scene, const char *kind,
                                      const char *name);
typedef void (*store_db_scene_fn)(struct store *s, const char *id, const char *json, size_t len,
                                  int64_t created, uint64_t generation, void *ctx);
typedef void (*store_db_upload_fn)(struct store *s, const struct store_upload_row *row, void *ctx);
enum refract_code store_db_each_scene(struct store *s, store_db_scene_fn fn, void *ctx,
                                      struct err *e);
enum refract_code store_db_each_upload(struct store *s, const char *scene, store_db_upload_fn fn,
                                       void *ctx, struct err *e);
/* meta table: key/value strings. get returns false when absent. */
bool store_db_meta_get_locked(struct store *s, const char *key, char *out, size_t size);
enum refract_code store_db_meta_set_locked(struct store *s, const char *key, const char *value,
                                           struct err *e);
/* Upload rows count, for GET /v1/storage. */
long long store_db_upload_count_locked(struct store *s);

/* ---- store_blob.c ---- */
void store_blob_path(const struct store *s, const char *hash, char *out, size_t size);
/* Opens the blob read-only and checks its size against the row's `bytes`: the fd, or -1
 * with e filled ("<what> <path>: <errno text><hint>", or the size mismatch). */
int store_blob_open(const struct store *s, const char *hash, size_t bytes, const char *what,
                    const char *hint, struct err *e);
/* Creates <data>/tmp/<stem>-XXXXXX for writing; returns its fd (path in path_out) or -1
 * with e filled. */
int store_tmp_create(struct store *s, const char *stem, char *path_out, size_t size, struct err *e);
/* Moves the finished file tmp_path (fsynced here) to blobs/<aa>/<hash>, fsyncing the
 * directories, unless that blob exists (then tmp_path is removed). Consumes tmp_path
 * either way. Fails with STORAGE when over --max-storage-bytes (message names the flag
 * and the use; `credit` bytes that the commit will free, a replaced upload's blob, count as
 * free). */
enum refract_code store_blob_commit_locked(struct store *s, const char *tmp_path, const char *hash,
                                           size_t bytes, size_t credit, struct err *e);
/* Writes bytes as a new blob (hashing them); hash_out gets its address. */
enum refract_code store_blob_write_locked(struct store *s, const void *data, size_t len,
                                          char hash_out[SHA256_HEX_SIZE], struct err *e);
/* Removes the blob when no row references it. */
void store_blob_release_locked(struct store *s, const char *hash);
/* Start-up: removes every file under <data>/tmp and stray temporaries of atomic writes
 * under <data>/irradiance, then every blob no row references, and counts what is left. */
void store_blob_sweep_locked(struct store *s);
/* Maps a blob read-only; checks its size. *map is NULL for 0 bytes. */
enum refract_code store_blob_map(const struct store *s, const char *hash, size_t bytes, void **map,
                                 struct err *e);
/* The storage limit check alone (for an upload that may add `bytes`). */
enum refract_code store_storage_check_locked(struct store *s, size_t bytes, size_t credit,
                                             struct err *e);

/* ---- store_migrate.c ---- */
/* Converts the file layout of before issue 5 (<data>/scenes/<id>/...) into rows and
 * blobs, then renames <data>/scenes to <data>/scenes.migrated. */
enum refract_code store_migrate_files(struct store *s, struct err *e);

/* ---- store.c ---- */
/* A new version sharing base's document, volumes and environment (new references); base
 * may be NULL. Returns NULL when out of memory. */
struct store_scene *store_version_new(struct store *s, const char *id,
                                      const struct store_scene *base);
struct slot *store_find_slot(struct store *s, const char *id);
/* Installs v as the current version of its id (consumes the caller's reference). */
enum refract_code store_install_locked(struct store *s, struct store_scene *v, struct err *e);
void store_env_release(struct store_env *env);

/* Makes `item` (a volume, mesh or environment) part of a new version of scene id. */
typedef enum refract_code (*store_upload_install_fn)(struct store *s, const char *id, void *item,
                                                     struct err *e);

/* Fills info's per-component and overall range, FNV-1a checksum and size from count
 * floats (components interleaved). */
void store_describe_floats(const float *data, size_t count, int components,
                           struct store_upload_info *info);

/* The checks that need the scene's slot before an upload may commit (the scene exists,
 * there is room for one more of the kind unless name replaces one). */
typedef enum refract_code (*store_upload_room_fn)(struct store *s, const char *id, const char *name,
                                                  struct err *e);

/* The first half of committing an uploaded file: room(...) then the temporary file becomes
 * the blob (store_blob_commit_locked, crediting the blob the row of (id, kind, name) would
 * replace). The temporary file is gone afterwards either way. */
enum refract_code store_upload_take_file_locked(struct store *s, const char *id, const char *kind,
                                                const char *name, const char *tmp_path,
                                                const char *sha256, size_t len,
                                                store_upload_room_fn room, struct err *e);

/* The commit path of an upload whose blob (info->sha256) is durable: commits its uploads row
 * (scene id, kind, name, info) in its own transaction (on failure the new blob is
 * released), then installs item and releases the blob the row replaced. */
enum refract_code store_upload_finish_locked(struct store *s, const char *id, const char *kind,
                                             const char *name, const struct store_upload_info *info,
                                             store_upload_install_fn install, void *item,
                                             struct err *e);

/* ---- store_upload.c (for start-up) ---- */
/* Restores one upload row into the scene's current version (mapping or decoding its
 * blob). */
enum refract_code store_upload_restore(struct store *s, const struct store_upload_row *row,
                                       struct err *e);

/* ---- store_mesh.c (for start-up) ---- */
/* Restores a mesh row (kind "mesh"): parses its blob again into the scene's current
 * version. */
enum refract_code store_mesh_restore(struct store *s, const struct store_upload_row *row,
                                     struct err *e);

#endif
