/*
 * store_open.c - opening the data directory and closing it: directories, database,
 * migration of the old layout, loading every scene and upload, the start-up sweep of
 * temporaries and orphan blobs; and the usage report.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../core/log.h"
#include "../io/io_files.h"
#include "store_internal.h"

struct load_ctx {
    uint64_t max_generation;
    int skipped;
};

static void load_upload(struct store *s, const struct store_upload_row *row, void *ctx)
{
    struct load_ctx *lc = ctx;
    struct err e;
    if (store_upload_restore(s, row, &e) != REFRACT_E_OK) {
        log_warn("store", "scene %s: %s %s not restored: %s", row->scene, row->kind, row->name,
                 e.msg);
        lc->skipped++;
    }
}

static void load_scene(struct store *s, const char *id, const char *json, size_t len,
                       int64_t created, uint64_t generation, void *ctx)
{
    struct load_ctx *lc = ctx;
    if (generation > lc->max_generation)
        lc->max_generation = generation;
    struct err e;
    struct scene *parsed = NULL;
    if (scene_parse(json, len, &s->desc.limits, &parsed, &e) != REFRACT_E_OK) {
        log_warn("store", "skipping scene %s: it no longer validates: %s", id, e.msg);
        lc->skipped++;
        return;
    }
    struct store_scene *v = store_version_new(s, id, NULL);
    if (v) {
        v->volumes = calloc(STORE_MAX_VOLUMES_PER_SCENE, sizeof *v->volumes);
        v->json = malloc(len + 1);
    }
    if (v == NULL || v->volumes == NULL || v->json == NULL) {
        scene_destroy(parsed);
        store_scene_release(v);
        lc->skipped++;
        return;
    }
    memcpy(v->json, json, len);
    v->json[len] = '\0';
    v->json_len = len;
    v->scene = parsed;
    v->created_unix = created;
    pthread_mutex_lock(&s->lock);
    enum refract_code rc = store_install_locked(s, v, &e);
    pthread_mutex_unlock(&s->lock);
    if (rc != REFRACT_E_OK) {
        log_warn("store", "skipping scene %s: %s", id, e.msg);
        lc->skipped++;
        return;
    }
    store_db_each_upload(s, id, load_upload, lc, &e);
}

static enum refract_code make_dirs(const struct store *s, struct err *e)
{
    const char *subdirs[] = {"", "/tmp", "/blobs"};
    for (size_t i = 0; i < sizeof subdirs / sizeof subdirs[0]; i++) {
        char dir[STORE_PATH_MAX];
        snprintf(dir, sizeof dir, "%s%s", s->data_dir, subdirs[i]);
        if (io_mkdirs(dir, e) != REFRACT_E_OK) {
            err_prefix(e, "data directory (--data-dir): ");
            return e->code;
        }
    }
    return REFRACT_E_OK;
}

struct store *store_open(const struct store_desc *desc, struct err *e)
{
    struct store *s = calloc(1, sizeof *s);
    if (s == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory opening the store");
        return NULL;
    }
    s->desc = *desc;
    snprintf(s->data_dir, sizeof s->data_dir, "%s", desc->data_dir);
    s->desc.data_dir = s->data_dir;
    atomic_init(&s->next_generation, 1);
    pthread_mutex_init(&s->lock, NULL);
    if (make_dirs(s, e) != REFRACT_E_OK || store_db_open(s, e) != REFRACT_E_OK ||
        store_migrate_files(s, e) != REFRACT_E_OK) {
        store_close(s);
        return NULL;
    }
    struct load_ctx lc = {0};
    if (store_db_each_scene(s, load_scene, &lc, e) != REFRACT_E_OK) {
        store_close(s);
        return NULL;
    }
    /* Generations stay unique across restarts (rows record them). */
    if (lc.max_generation + 1 > atomic_load(&s->next_generation))
        atomic_store(&s->next_generation, lc.max_generation + 1);
    pthread_mutex_lock(&s->lock);
    store_blob_sweep_locked(s);
    long long uploads = store_db_upload_count_locked(s);
    pthread_mutex_unlock(&s->lock);
    log_info("store",
             "data directory %s: %zu scenes, %lld uploads, %llu blobs (%llu bytes) loaded%s",
             s->data_dir, s->slot_count, uploads, s->blob_count, s->blob_bytes,
             lc.skipped ? "; some were skipped (see the warnings above)" : "");
    return s;
}

void store_close(struct store *s)
{
    if (s == NULL)
        return;
    for (size_t i = 0; i < s->slot_count; i++)
        store_scene_release(s->slots[i].current);
    free(s->slots);
    store_db_close(s);
    pthread_mutex_destroy(&s->lock);
    free(s);
}

void store_usage_get(struct store *s, struct store_usage *out)
{
    pthread_mutex_lock(&s->lock);
    out->blob_bytes = s->blob_bytes;
    out->blob_count = s->blob_count;
    out->max_storage_bytes = s->desc.max_storage_bytes;
    out->scenes = (long long)s->slot_count;
    out->uploads = store_db_upload_count_locked(s);
    pthread_mutex_unlock(&s->lock);
}
