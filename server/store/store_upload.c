/*
 * store_upload.c - uploads: volumes (mapped from their blobs) and environment images
 * (decoded from theirs; meshes: store_mesh.c), each committed as blob first, row second
 * (store_blob.c says why that order is crash safe), then installed as a new version of the scene.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include "../core/log.h"
#include "../io/io_files.h"
#include "../io/io_image.h"
#include "../io/io_volume.h"
#include "store_internal.h"

/* A volume over `data` (malloc'd, or mapped when mapped is true), consumed. */
static struct store_volume *volume_new(const char *name, const struct store_upload_info *info,
                                       float *data, bool mapped)
{
    struct store_volume *v = calloc(1, sizeof *v);
    if (v == NULL)
        return NULL;
    atomic_init(&v->refs, 1);
    snprintf(v->name, sizeof v->name, "%s", name);
    v->data = data;
    v->mapped = mapped;
    v->count = info->bytes / sizeof(float);
    memcpy(v->view.dims, info->dims, sizeof v->view.dims);
    v->view.components = info->components;
    v->view.data = data;
    v->min = info->min_all;
    v->max = info->max_all;
    v->checksum = info->checksum;
    v->info = *info;
    return v;
}

void store_describe_floats(const float *data, size_t count, int components,
                           struct store_upload_info *info)
{
    for (int c = 0; c < 3; c++) {
        info->min[c] = c < components && count ? data[c] : 0.0;
        info->max[c] = info->min[c];
    }
    for (size_t i = 0; i < count; i++) {
        int c = (int)(i % (size_t)components);
        if (data[i] < info->min[c])
            info->min[c] = data[i];
        if (data[i] > info->max[c])
            info->max[c] = data[i];
    }
    info->min_all = info->min[0];
    info->max_all = info->max[0];
    for (int c = 1; c < components; c++) {
        info->min_all = info->min[c] < info->min_all ? info->min[c] : info->min_all;
        info->max_all = info->max[c] > info->max_all ? info->max[c] : info->max_all;
    }
    info->checksum = io_fnv1a64_update(IO_FNV1A64_INIT, data, count * sizeof(float));
    info->bytes = count * sizeof(float);
}

/* Swaps in a copy of `id`'s current version with `vol` added or replacing its namesake. */
static enum refract_code install_volume_locked(struct store *s, const char *id, void *item,
                                               struct err *e)
{
    struct store_volume *vol = item;
    struct slot *slot = store_find_slot(s, id);
    if (slot == NULL)
        return err_set(e, REFRACT_E_SCENE_NOT_FOUND, "no scene with id \"%s\"", id);
    struct store_scene *v = store_version_new(s, id, slot->current);
    if (v == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory adding a volume");
    size_t i = 0;
    while (i < v->volume_count && strcmp(v->volumes[i]->name, vol->name) != 0)
        i++;
    atomic_fetch_add(&vol->refs, 1);
    if (i < v->volume_count)
        store_volume_release(v->volumes[i]);
    else
        v->volume_count++;
    v->volumes[i] = vol;
    return store_install_locked(s, v, e);
}

/* The checks that need the slot: the scene exists and has room for one more volume. */
static enum refract_code volume_room_locked(struct store *s, const char *id, const char *name,
                                            struct err *e)
{
    struct slot *slot = store_find_slot(s, id);
    if (slot == NULL)
        return err_set(e, REFRACT_E_SCENE_NOT_FOUND,
                       "no scene with id \"%s\"; GET /v1/scenes lists the scenes", id);
    const struct store_scene *cur = slot->current;
    bool replaces = false;
    for (size_t i = 0; i < cur->volume_count; i++)
        replaces = replaces || strcmp(cur->volumes[i]->name, name) == 0;
    if (!replaces && cur->volume_count >= STORE_MAX_VOLUMES_PER_SCENE)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "a scene holds at most %d volumes; delete the scene or replace a volume",
                       STORE_MAX_VOLUMES_PER_SCENE);
    return REFRACT_E_OK;
}

/* Commits the row of an upload whose blob is durable, in its own transaction; *old_blob
 * gets the blob the row replaced ("" if none). */
static enum refract_code commit_row_locked(struct store *s, const struct store_upload_row *row,
                                           char old_blob[SHA256_HEX_SIZE], struct err *e)
{
    enum refract_code rc = store_db_begin_locked(s, e);
    if (rc == REFRACT_E_OK)
        rc = store_db_upload_put_locked(s, row, old_blob, e);
    if (rc == REFRACT_E_OK)
        rc = store_db_commit_locked(s, e);
    if (rc != REFRACT_E_OK)
        store_db_rollback_locked(s);
    return rc;
}

enum refract_code store_upload_take_file_locked(struct store *s, const char *id, const char *kind,
                                                const char *name, const char *tmp_path,
                                                const char *sha256, size_t len,
                                                store_upload_room_fn room, struct err *e)
{
    enum refract_code rc = room(s, id, name, e);
    if (rc != REFRACT_E_OK) {
        unlink(tmp_path);
        return rc;
    }
    return store_blob_commit_locked(s, tmp_path, sha256, len,
                                    store_db_replace_credit_locked(s, id, kind, name), e);
}

enum refract_code store_upload_finish_locked(struct store *s, const char *id, const char *kind,
                                             const char *name, const struct store_upload_info *info,
                                             store_upload_install_fn install, void *item,
                                             struct err *e)
{
    struct store_upload_row row = {.info = *info};
    snprintf(row.scene, sizeof row.scene, "%s", id);
    snprintf(row.name, sizeof row.name, "%s", name);
    snprintf(row.kind, sizeof row.kind, "%s", kind);
    char old_blob[SHA256_HEX_SIZE];
    enum refract_code rc = commit_row_locked(s, &row, old_blob, e);
    if (rc != REFRACT_E_OK) {
        store_blob_release_locked(s, info->sha256);
        return rc;
    }
    rc = install(s, id, item, e);
    store_blob_release_locked(s, old_blob);
    return rc;
}

enum refract_code store_volume_put(struct store *s, const char *id, const char *name,
                                   const int dims[3], int components, float *data, size_t count,
                                   struct store_volume **out, struct err *e)
{
    if (out)
        *out = NULL;
    struct store_upload_info info = {.dims = {dims[0], dims[1], dims[2]},
                                     .components = components,
                                     .created_unix = (int64_t)time(NULL)};
    snprintf(info.type, sizeof info.type, "float32");
    snprintf(info.format, sizeof info.format, "raw");
    store_describe_floats(data, count, components, &info);
    pthread_mutex_lock(&s->lock);
    enum refract_code rc = volume_room_locked(s, id, name, e);
    if (rc == REFRACT_E_OK)
        rc = store_blob_write_locked(s, data, count * sizeof(float), info.sha256, e);
    struct store_volume *vol = NULL;
    if (rc == REFRACT_E_OK) {
        vol = volume_new(name, &info, data, false);
        data = NULL;
        if (vol == NULL) {
            store_blob_release_locked(s, info.sha256);
            rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory storing volume %s", name);
        }
    }
    if (rc == REFRACT_E_OK)
        rc = store_upload_finish_locked(s, id, "volume", vol->name, &vol->info,
                                        install_volume_locked, vol, e);
    pthread_mutex_unlock(&s->lock);
    free(data);
    if (rc == REFRACT_E_OK && out)
        *out = vol;
    else
        store_volume_release(vol);
    return rc;
}

enum refract_code store_volume_put_file(struct store *s, const char *id, const char *name,
                                        const struct store_upload_info *info, const char *tmp_path,
                                        struct store_volume **out, struct err *e)
{
    if (out)
        *out = NULL;
    pthread_mutex_lock(&s->lock);
    enum refract_code rc = store_upload_take_file_locked(
        s, id, "volume", name, tmp_path, info->sha256, info->bytes, volume_room_locked, e);
    void *map = NULL;
    if (rc == REFRACT_E_OK) {
        rc = store_blob_map(s, info->sha256, info->bytes, &map, e);
        if (rc != REFRACT_E_OK)
            store_blob_release_locked(s, info->sha256);
    }
    struct store_volume *vol = NULL;
    if (rc == REFRACT_E_OK) {
        vol = volume_new(name, info, map, true);
        if (vol == NULL) {
            munmap(map, info->bytes);
            store_blob_release_locked(s, info->sha256);
            rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory storing volume %s", name);
        }
    }
    if (rc == REFRACT_E_OK)
        rc = store_upload_finish_locked(s, id, "volume", vol->name, &vol->info,
                                        install_volume_locked, vol, e);
    pthread_mutex_unlock(&s->lock);
    if (rc == REFRACT_E_OK && out)
        *out = vol;
    else
        store_volume_release(vol);
    return rc;
}

/* ---- environments ---------------------------------------------------------------------- */

static enum refract_code decode_env(struct store *s, const void *bytes, size_t len,
                                    struct store_env **out, struct err *e)
{
    struct io_image img;
    long long max_px = s->desc.max_env_pixels > 0 ? s->desc.max_env_pixels : (8ll << 20);
    enum refract_code rc = io_image_decode(bytes, len, max_px, &img, e);
    if (rc != REFRACT_E_OK)
        return rc;
    struct store_env *env = calloc(1, sizeof *env);
    if (env == NULL) {
        io_image_free(&img);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory storing the environment");
    }
    atomic_init(&env->refs, 1);
    env->width = img.width;
    env->height = img.height;
    env->rgba = img.rgba; /* take ownership */
    env->source_bytes = len;
    struct store_upload_info *in = &env->info;
    in->dims[0] = img.width;
    in->dims[1] = img.height;
    in->dims[2] = 1;
    in->components = 4;
    snprintf(in->type, sizeof in->type, "image");
    snprintf(in->format, sizeof in->format, "image");
    in->checksum = io_fnv1a64_update(IO_FNV1A64_INIT, bytes, len);
    in->bytes = len;
    in->created_unix = (int64_t)time(NULL);
    *out = env;
    return REFRACT_E_OK;
}

/* Swaps in a copy of `id`'s current version with environment `item`. */
/* An environment replaces the scene's one: only the scene must exist. */
static enum refract_code env_room_locked(struct store *s, const char *id, const char *name,
                                         struct err *e)
{
    (void)name;
    if (store_find_slot(s, id) == NULL)
        return err_set(e, REFRACT_E_SCENE_NOT_FOUND, "no scene with id \"%s\"", id);
    return REFRACT_E_OK;
}

static enum refract_code install_env_locked(struct store *s, const char *id, void *item,
                                            struct err *e)
{
    struct store_env *env = item;
    struct store_scene *v = store_version_new(s, id, store_find_slot(s, id)->current);
    if (v == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory");
    store_env_release(v->env);
    atomic_fetch_add(&env->refs, 1);
    v->env = env;
    return store_install_locked(s, v, e);
}

/* Commits the environment row (blob durable) and installs it. */
static enum refract_code finish_env_locked(struct store *s, const char *id, struct store_env *env,
                                           struct err *e)
{
    if (store_find_slot(s, id) == NULL) {
        store_blob_release_locked(s, env->info.sha256);
        return err_set(e, REFRACT_E_SCENE_NOT_FOUND, "no scene with id \"%s\"", id);
    }
    return store_upload_finish_locked(s, id, "environment", "environment", &env->info,
                                      install_env_locked, env, e);
}

enum refract_code store_env_put(struct store *s, const char *id, const void *bytes, size_t len,
                                int *width, int *height, struct err *e)
{
    struct store_env *env = NULL;
    enum refract_code rc = decode_env(s, bytes, len, &env, e);
    if (rc != REFRACT_E_OK)
        return rc;
    pthread_mutex_lock(&s->lock);
    if (store_find_slot(s, id) == NULL)
        rc = err_set(e, REFRACT_E_SCENE_NOT_FOUND, "no scene with id \"%s\"", id);
    if (rc == REFRACT_E_OK)
        rc = store_blob_write_locked(s, bytes, len, env->info.sha256, e);
    if (rc == REFRACT_E_OK)
        rc = finish_env_locked(s, id, env, e);
    pthread_mutex_unlock(&s->lock);
    if (rc == REFRACT_E_OK && width && height) {
        *width = env->width;
        *height = env->height;
    }
    store_env_release(env);
    return rc;
}

enum refract_code store_env_put_file(struct store *s, const char *id, const char *tmp_path,
                                     const char *sha256, int *width, int *height, struct err *e)
{
    const void *bytes = NULL;
    size_t len = 0;
    struct store_env *env = NULL;
    /* The decoder reads the mapped file; its pixels are bounded by --max-env-pixels. */
    enum refract_code rc = io_map_file(tmp_path, &bytes, &len, e);
    if (rc == REFRACT_E_OK)
        rc = decode_env(s, bytes, len, &env, e);
    io_unmap_file(bytes, len);
    if (rc != REFRACT_E_OK) {
        unlink(tmp_path);
        return rc;
    }
    snprintf(env->info.sha256, sizeof env->info.sha256, "%s", sha256);
    pthread_mutex_lock(&s->lock);
    rc = store_upload_take_file_locked(s, id, "environment", "environment", tmp_path, sha256, len,
                                       env_room_locked, e);
    if (rc == REFRACT_E_OK)
        rc = finish_env_locked(s, id, env, e);
    pthread_mutex_unlock(&s->lock);
    if (rc == REFRACT_E_OK && width && height) {
        *width = env->width;
        *height = env->height;
    }
    store_env_release(env);
    return rc;
}

/* ---- start-up -------------------------------------------------------------------------- */

enum refract_code store_upload_restore(struct store *s, const struct store_upload_row *row,
                                       struct err *e)
{
    void *map = NULL;
    enum refract_code rc = store_blob_map(s, row->info.sha256, row->info.bytes, &map, e);
    if (rc != REFRACT_E_OK)
        return rc;
    if (strcmp(row->kind, "environment") == 0) {
        struct store_env *env = NULL;
        rc = decode_env(s, map, row->info.bytes, &env, e);
        if (map)
            munmap(map, row->info.bytes);
        if (rc != REFRACT_E_OK)
            return rc;
        env->info = row->info;
        pthread_mutex_lock(&s->lock);
        struct slot *slot = store_find_slot(s, row->scene);
        struct store_scene *v = slot ? store_version_new(s, row->scene, slot->current) : NULL;
        if (v) {
            store_env_release(v->env);
            v->env = env;
            env = NULL;
            rc = store_install_locked(s, v, e);
        }
        pthread_mutex_unlock(&s->lock);
        store_env_release(env);
        return rc;
    }
    if (strcmp(row->kind, "mesh") == 0) {
        if (map)
            munmap(map, row->info.bytes);
        return store_mesh_restore(s, row, e);
    }
    if (strcmp(row->kind, "volume") != 0) {
        if (map)
            munmap(map, row->info.bytes);
        return err_set(e, REFRACT_E_STORAGE, "unknown upload kind \"%s\"", row->kind);
    }
    size_t expect = (size_t)row->info.dims[0] * row->info.dims[1] * row->info.dims[2] *
                    (size_t)row->info.components * sizeof(float);
    if (expect != row->info.bytes || map == NULL) {
        if (map)
            munmap(map, row->info.bytes);
        return err_set(e, REFRACT_E_STORAGE, "volume %s: %zu bytes do not match its dims",
                       row->name, row->info.bytes);
    }
    struct store_volume *vol = volume_new(row->name, &row->info, map, true);
    if (vol == NULL) {
        munmap(map, row->info.bytes);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory restoring a volume");
    }
    pthread_mutex_lock(&s->lock);
    rc = install_volume_locked(s, row->scene, vol, e);
    pthread_mutex_unlock(&s->lock);
    store_volume_release(vol);
    return rc;
}
