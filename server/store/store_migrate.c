/*
 * store_migrate.c - converts a data directory in the file layout of before issue 5
 *     <data>/scenes/<id>/scene.json
 *     <data>/scenes/<id>/volumes/<name>.f32   raw little-endian float32
 *     <data>/scenes/<id>/volumes/<name>.json  {"dims": [x, y, z], "components": c}
 *     <data>/scenes/<id>/environment.img      the uploaded image file
 *     <data>/scenes/<id>/meshes/<name>.obj|.ply  uploaded meshes (branch mesh's layout)
 * into rows and blobs, once: every blob is written (durably) first, then all rows and
 * meta.migrated_files = 1 commit in one transaction, then scenes/ is renamed to
 * scenes.migrated/ (kept, for the operator to remove). A crash before the commit leaves
 * the old layout in charge (the next start converts it again; the blobs written so far
 * are orphans the sweep collects); a crash after it only repeats the rename.
 * Documents that no longer validate are converted all the same (and skipped at load,
 * with a warning), so nothing is lost.
 */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "../core/log.h"
#include "../io/io_files.h"
#include "../io/io_image.h"
#include "../io/io_volume.h"
#include "store_internal.h"

/* The end of every conversion: data (len bytes) becomes the blob of row, whose info the
 * caller filled except the size, time and address, and the row (scene id, kind, name) is
 * inserted. */
static enum refract_code put_migrated(struct store *s, const char *id, const char *kind,
                                      const char *name, const void *data, size_t len,
                                      struct store_upload_row *row, struct err *e)
{
    row->info.bytes = len;
    row->info.created_unix = (int64_t)time(NULL);
    enum refract_code rc = store_blob_write_locked(s, data, len, row->info.sha256, e);
    if (rc != REFRACT_E_OK)
        return rc;
    snprintf(row->scene, sizeof row->scene, "%.63s", id);
    snprintf(row->name, sizeof row->name, "%.63s", name);
    snprintf(row->kind, sizeof row->kind, "%s", kind);
    char old[SHA256_HEX_SIZE];
    return store_db_upload_put_locked(s, row, old, e);
}

static enum refract_code migrate_volume(struct store *s, const char *id, const char *vdir,
                                        const char *name, struct err *e)
{
    char path[1400];
    char *meta = NULL, *raw = NULL;
    size_t meta_len = 0, raw_len = 0;
    struct store_upload_row row = {0};
    struct store_upload_info *in = &row.info;
    snprintf(path, sizeof path, "%s/%s.json", vdir, name);
    enum refract_code rc = io_read_file(path, 4096, &meta, &meta_len, e);
    if (rc == REFRACT_E_OK &&
        sscanf(meta, "{\"dims\": [%d, %d, %d], \"components\": %d}", &in->dims[0], &in->dims[1],
               &in->dims[2], &in->components) != 4)
        rc = err_set(e, REFRACT_E_STORAGE, "%s: unreadable metadata", path);
    free(meta);
    size_t expect = rc == REFRACT_E_OK ? (size_t)in->dims[0] * in->dims[1] * in->dims[2] *
                                             (size_t)in->components * sizeof(float)
                                       : 0;
    snprintf(path, sizeof path, "%s/%s.f32", vdir, name);
    if (rc == REFRACT_E_OK)
        rc = io_read_file(path, expect, &raw, &raw_len, e);
    if (rc == REFRACT_E_OK && raw_len != expect)
        rc = err_set(e, REFRACT_E_STORAGE, "%s: %zu bytes, its metadata says %zu", path, raw_len,
                     expect);
    if (rc == REFRACT_E_OK) {
        store_describe_floats((const float *)raw, raw_len / sizeof(float), in->components, in);
        snprintf(in->type, sizeof in->type, "float32");
        snprintf(in->format, sizeof in->format, "raw");
        rc = put_migrated(s, id, "volume", name, raw, raw_len, &row, e);
    }
    free(raw);
    return rc;
}

static enum refract_code migrate_env(struct store *s, const char *id, const char *path,
                                     struct err *e)
{
    char *img = NULL;
    size_t len = 0;
    struct store_upload_row row = {0};
    struct store_upload_info *in = &row.info;
    enum refract_code rc = io_read_file(path, (size_t)1 << 31, &img, &len, e);
    struct io_image decoded;
    if (rc == REFRACT_E_OK && io_image_decode(img, len, 1ll << 30, &decoded, e) == REFRACT_E_OK) {
        in->dims[0] = decoded.width;
        in->dims[1] = decoded.height;
        io_image_free(&decoded);
    }
    if (rc == REFRACT_E_OK) {
        in->dims[2] = 1;
        in->components = 4;
        snprintf(in->type, sizeof in->type, "image");
        snprintf(in->format, sizeof in->format, "image");
        in->checksum = io_fnv1a64_update(IO_FNV1A64_INIT, img, len);
        rc = put_migrated(s, id, "environment", "environment", img, len, &row, e);
    }
    free(img);
    return rc;
}

/* A mesh file as uploaded becomes its blob and a "mesh" row; it is parsed (and its bounds
 * found) when the row is loaded (store_mesh_restore). */
static enum refract_code migrate_mesh(struct store *s, const char *id, const char *path,
                                      const char *name, const char *format, struct err *e)
{
    char *bytes = NULL;
    size_t len = 0;
    struct store_upload_row row = {0};
    struct store_upload_info *in = &row.info;
    enum refract_code rc = io_read_file(path, (size_t)1 << 32, &bytes, &len, e);
    if (rc == REFRACT_E_OK) {
        snprintf(in->type, sizeof in->type, "mesh");
        snprintf(in->format, sizeof in->format, "%s", format);
        in->checksum = io_fnv1a64_update(IO_FNV1A64_INIT, bytes, len);
        rc = put_migrated(s, id, "mesh", name, bytes, len, &row, e);
    }
    free(bytes);
    return rc;
}

static void migrate_meshes(struct store *s, const char *id, const char *dir)
{
    char mdir[1000];
    snprintf(mdir, sizeof mdir, "%s/meshes", dir);
    DIR *d = opendir(mdir);
    struct dirent *ent;
    while (d && (ent = readdir(d)) != NULL) {
        size_t n = strlen(ent->d_name);
        bool obj = n > 4 && strcmp(ent->d_name + n - 4, ".obj") == 0;
        bool ply = n > 4 && strcmp(ent->d_name + n - 4, ".ply") == 0;
        char name[SCENE_VOLUME_NAME_MAX] = {0}, path[1400];
        if ((!obj && !ply) || n - 4 >= sizeof name)
            continue;
        memcpy(name, ent->d_name, n - 4);
        snprintf(path, sizeof path, "%s/%s", mdir, ent->d_name);
        struct err me;
        if (migrate_mesh(s, id, path, name, obj ? "obj" : "ply", &me) != REFRACT_E_OK)
            log_warn("store", "migration: mesh %s of scene %s not converted: %s", name, id, me.msg);
    }
    if (d)
        closedir(d);
}

static enum refract_code migrate_scene(struct store *s, const char *scenes, const char *id,
                                       int *volumes, struct err *e)
{
    char dir[900], path[1000];
    snprintf(dir, sizeof dir, "%s/%s", scenes, id);
    snprintf(path, sizeof path, "%s/scene.json", dir);
    char *json = NULL;
    size_t len = 0;
    if (io_read_file(path, STORE_MAX_JSON_BYTES, &json, &len, e) != REFRACT_E_OK)
        return REFRACT_E_OK; /* no document: nothing to convert */
    struct store_scene v = {.json = json,
                            .json_len = len,
                            .generation = atomic_fetch_add(&s->next_generation, 1),
                            .created_unix = (int64_t)time(NULL)};
    snprintf(v.id, sizeof v.id, "%.63s", id);
    enum refract_code rc = store_db_scene_put_locked(s, &v, e);
    free(json);
    char vdir[1000];
    snprintf(vdir, sizeof vdir, "%s/volumes", dir);
    DIR *d = rc == REFRACT_E_OK ? opendir(vdir) : NULL;
    struct dirent *ent;
    while (d && rc == REFRACT_E_OK && (ent = readdir(d)) != NULL) {
        size_t n = strlen(ent->d_name);
        char name[SCENE_VOLUME_NAME_MAX] = {0};
        if (n < 6 || n - 5 >= sizeof name || strcmp(ent->d_name + n - 5, ".json") != 0)
            continue;
        memcpy(name, ent->d_name, n - 5);
        struct err ve;
        if (migrate_volume(s, id, vdir, name, &ve) == REFRACT_E_OK)
            (*volumes)++;
        else
            log_warn("store", "migration: volume %s of scene %s not converted: %s", name, id,
                     ve.msg);
    }
    if (d)
        closedir(d);
    snprintf(path, sizeof path, "%s/environment.img", dir);
    struct err ee;
    if (rc == REFRACT_E_OK && access(path, R_OK) == 0 &&
        migrate_env(s, id, path, &ee) != REFRACT_E_OK)
        log_warn("store", "migration: environment of scene %s not converted: %s", id, ee.msg);
    if (rc == REFRACT_E_OK)
        migrate_meshes(s, id, dir);
    return rc;
}

static void retire_old_layout(struct store *s, const char *scenes)
{
    char target[STORE_PATH_MAX];
    snprintf(target, sizeof target, "%s/scenes.migrated", s->data_dir);
    struct stat st;
    if (stat(target, &st) == 0)
        snprintf(target, sizeof target, "%s/scenes.migrated.%lld", s->data_dir,
                 (long long)time(NULL));
    if (rename(scenes, target) != 0)
        log_warn("store", "migration: could not rename %s to %s; it is ignored now", scenes,
                 target);
    else
        log_info("store", "migration: the old layout is kept in %s (safe to remove)", target);
}

enum refract_code store_migrate_files(struct store *s, struct err *e)
{
    char scenes[600];
    snprintf(scenes, sizeof scenes, "%s/scenes", s->data_dir);
    DIR *d = opendir(scenes);
    if (d == NULL)
        return REFRACT_E_OK;
    pthread_mutex_lock(&s->lock);
    char done[8] = "";
    if (store_db_meta_get_locked(s, "migrated_files", done, sizeof done) &&
        strcmp(done, "1") == 0) {
        closedir(d);
        retire_old_layout(s, scenes);
        pthread_mutex_unlock(&s->lock);
        return REFRACT_E_OK;
    }
    enum refract_code rc = store_db_begin_locked(s, e);
    int count = 0, volumes = 0;
    struct dirent *ent;
    while (rc == REFRACT_E_OK && (ent = readdir(d)) != NULL) {
        if (!store_name_valid(ent->d_name, false))
            continue;
        rc = migrate_scene(s, scenes, ent->d_name, &volumes, e);
        count += rc == REFRACT_E_OK;
    }
    closedir(d);
    if (rc == REFRACT_E_OK)
        rc = store_db_meta_set_locked(s, "migrated_files", "1", e);
    if (rc == REFRACT_E_OK)
        rc = store_db_commit_locked(s, e);
    if (rc != REFRACT_E_OK) {
        store_db_rollback_locked(s);
        pthread_mutex_unlock(&s->lock);
        err_prefix(e, "converting the old data directory layout: ");
        return rc;
    }
    log_info("store", "migration: converted %d scene(s) and %d volume(s) of the old layout", count,
             volumes);
    retire_old_layout(s, scenes);
    pthread_mutex_unlock(&s->lock);
    return REFRACT_E_OK;
}
