/*
 * store.c - the scene registry: slots of immutable scene versions, persisted to the data
 * directory (SQLite rows: store_db.c). See store.h for the design; the uploads are in
 * store_upload.c (meshes in store_mesh.c), start-up in store_open.c.
 *
 * INVARIANT: slots[0..slot_count) have distinct ids and a non-NULL `current`; each slot
 * holds one reference to its current version. `lock` guards the slot array and the
 * statuses, never the versions (they are immutable).
 */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include "../core/log.h"
#include "store_internal.h"
#include "store_mesh.h"

bool store_name_valid(const char *name, bool allow_upper)
{
    size_t n = strlen(name);
    if (n == 0 || n >= STORE_ID_MAX)
        return false;
    for (size_t i = 0; i < n; i++) {
        char c = name[i];
        bool ok = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
                  (allow_upper && c >= 'A' && c <= 'Z');
        if (!ok)
            return false;
    }
    return true;
}

/* ---- versions ---------------------------------------------------------------------- */

void store_volume_release(struct store_volume *v)
{
    if (v == NULL || atomic_fetch_sub(&v->refs, 1) != 1)
        return;
    if (v->mapped)
        munmap(v->data, v->count * sizeof(float));
    else
        free(v->data);
    free(v);
}

void store_env_release(struct store_env *env)
{
    if (env == NULL || atomic_fetch_sub(&env->refs, 1) != 1)
        return;
    free(env->rgba);
    free(env);
}

void store_scene_release(struct store_scene *sc)
{
    if (sc == NULL || atomic_fetch_sub(&sc->refs, 1) != 1)
        return;
    for (size_t i = 0; i < sc->volume_count; i++)
        store_volume_release(sc->volumes[i]);
    free(sc->volumes);
    store_mesh_release_all(sc);
    store_env_release(sc->env);
    scene_destroy(sc->scene);
    free(sc->json);
    free(sc);
}

/* A new version sharing `base`'s document, volumes and environment (new references);
 * base may be NULL. The caller fills or replaces what changes. */
struct store_scene *store_version_new(struct store *s, const char *id,
                                      const struct store_scene *base)
{
    struct store_scene *v = calloc(1, sizeof *v);
    if (v == NULL)
        return NULL;
    atomic_init(&v->refs, 1);
    snprintf(v->id, sizeof v->id, "%s", id);
    v->generation = atomic_fetch_add(&s->next_generation, 1);
    v->data_generation = v->generation;
    v->created_unix = (int64_t)time(NULL);
    if (base == NULL)
        return v;
    v->json = malloc(base->json_len + 1);
    v->volumes = calloc(STORE_MAX_VOLUMES_PER_SCENE, sizeof *v->volumes);
    if (v->json == NULL || v->volumes == NULL) {
        free(v->json);
        free(v->volumes);
        free(v);
        return NULL;
    }
    memcpy(v->json, base->json, base->json_len + 1);
    v->json_len = base->json_len;
    struct err e;
    if (scene_parse(v->json, v->json_len, &s->desc.limits, &v->scene, &e) != REFRACT_E_OK) {
        free(v->json);
        free(v->volumes);
        free(v);
        return NULL;
    }
    for (size_t i = 0; i < base->volume_count; i++) {
        atomic_fetch_add(&base->volumes[i]->refs, 1);
        v->volumes[v->volume_count++] = base->volumes[i];
    }
    if (base->env) {
        atomic_fetch_add(&base->env->refs, 1);
        v->env = base->env;
    }
    v->created_unix = base->created_unix;
    if (!store_mesh_share(v, base)) {
        store_scene_release(v);
        return NULL;
    }
    return v;
}

const struct scene_volume *store_volume_lookup(void *ctx, const char *name)
{
    const struct store_scene *sc = ctx;
    size_t prefix = strlen(SCENE_MESH_LOOKUP_PREFIX);
    if (strncmp(name, SCENE_MESH_LOOKUP_PREFIX, prefix) == 0)
        return store_mesh_lookup(sc, name + prefix);
    for (size_t i = 0; i < sc->volume_count; i++) {
        if (strcmp(sc->volumes[i]->name, name) == 0)
            return &sc->volumes[i]->view;
    }
    return NULL;
}

/* ---- slots ------------------------------------------------------------------------- */

struct slot *store_find_slot(struct store *s, const char *id)
{
    for (size_t i = 0; i < s->slot_count; i++) {
        if (strcmp(s->slots[i].id, id) == 0)
            return &s->slots[i];
    }
    return NULL;
}

static bool scene_limit_reached_locked(const struct store *s, struct err *e)
{
    int max = s->desc.max_scenes > 0 ? s->desc.max_scenes : 64;
    if (s->slot_count < (size_t)max)
        return false;
    err_set(e, REFRACT_E_LIMIT_EXCEEDED,
            "refractd holds %d scenes, its limit (--max-scenes); delete one with DELETE "
            "/v1/scenes/{id} or raise the limit",
            max);
    return true;
}

/* Installs v as the current version of its id (consumes the caller's reference). */
enum refract_code store_install_locked(struct store *s, struct store_scene *v, struct err *e)
{
    struct slot *slot = store_find_slot(s, v->id);
    if (slot) {
        struct store_scene *old = slot->current;
        slot->current = v;
        store_scene_release(old);
        return REFRACT_E_OK;
    }
    if (scene_limit_reached_locked(s, e)) {
        store_scene_release(v);
        return e->code;
    }
    if (s->slot_count == s->slot_cap) {
        size_t cap = s->slot_cap ? s->slot_cap * 2 : 16;
        struct slot *grown = realloc(s->slots, cap * sizeof *grown);
        if (grown == NULL) {
            store_scene_release(v);
            return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory adding a scene");
        }
        s->slots = grown;
        s->slot_cap = cap;
    }
    struct slot *n = &s->slots[s->slot_count++];
    memset(n, 0, sizeof *n);
    snprintf(n->id, sizeof n->id, "%s", v->id);
    n->current = v;
    return REFRACT_E_OK;
}

static void random_id(char out[STORE_ID_MAX])
{
    unsigned char bytes[6] = {0};
    int fd = open("/dev/urandom", O_RDONLY);
    if (fd < 0 || read(fd, bytes, sizeof bytes) != (ssize_t)sizeof bytes) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        uint64_t x = (uint64_t)ts.tv_nsec ^ ((uint64_t)ts.tv_sec << 20) ^ (uint64_t)getpid();
        memcpy(bytes, &x, sizeof bytes);
    }
    if (fd >= 0)
        close(fd);
    for (int i = 0; i < 6; i++)
        snprintf(out + 2 * i, 3, "%02x", bytes[i]);
}

/* ---- public API ---------------------------------------------------------------------- */

struct store_scene *store_scene_get(struct store *s, const char *id)
{
    pthread_mutex_lock(&s->lock);
    struct slot *slot = store_find_slot(s, id);
    struct store_scene *v = slot ? slot->current : NULL;
    if (v)
        atomic_fetch_add(&v->refs, 1);
    pthread_mutex_unlock(&s->lock);
    return v;
}

/* Commits the document of version v (a new scene, or a replacement whose uploads' rows
 * go in the same transaction; *old_blobs gets their blobs, for release after commit). */
static enum refract_code persist_document_locked(struct store *s, const struct store_scene *v,
                                                 bool replacing,
                                                 char (**old_blobs)[SHA256_HEX_SIZE],
                                                 size_t *old_count, struct err *e)
{
    enum refract_code rc = store_db_begin_locked(s, e);
    if (rc != REFRACT_E_OK)
        return rc;
    if (replacing)
        rc = store_db_scene_delete_locked(s, v->id, true, old_blobs, old_count, e);
    if (rc == REFRACT_E_OK)
        rc = store_db_scene_put_locked(s, v, e);
    if (rc == REFRACT_E_OK)
        rc = store_db_commit_locked(s, e);
    if (rc != REFRACT_E_OK) {
        store_db_rollback_locked(s);
        free(*old_blobs);
        *old_blobs = NULL;
        *old_count = 0;
    }
    return rc;
}

enum refract_code store_scene_create(struct store *s, const char *id, const char *json, size_t len,
                                     struct store_scene **out, struct err *e)
{
    if (out)
        *out = NULL;
    struct scene *parsed = NULL;
    enum refract_code rc = scene_parse(json, len, &s->desc.limits, &parsed, e);
    if (rc != REFRACT_E_OK)
        return rc;
    char new_id[STORE_ID_MAX];
    pthread_mutex_lock(&s->lock);
    if (id) {
        snprintf(new_id, sizeof new_id, "%s", id);
    } else {
        do {
            random_id(new_id);
        } while (store_find_slot(s, new_id) != NULL);
    }
    struct store_scene *v = store_version_new(s, new_id, NULL);
    if (v) {
        v->json = malloc(len + 1);
        v->volumes = calloc(STORE_MAX_VOLUMES_PER_SCENE, sizeof *v->volumes);
    }
    if (v == NULL || v->json == NULL || v->volumes == NULL) {
        pthread_mutex_unlock(&s->lock);
        scene_destroy(parsed);
        store_scene_release(v);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory storing a scene");
    }
    memcpy(v->json, json, len);
    v->json[len] = '\0';
    v->json_len = len;
    v->scene = parsed;
    bool replacing = store_find_slot(s, new_id) != NULL;
    char(*old_blobs)[SHA256_HEX_SIZE] = NULL;
    size_t old_count = 0;
    if (!replacing && scene_limit_reached_locked(s, e))
        rc = e->code;
    else
        rc = persist_document_locked(s, v, replacing, &old_blobs, &old_count, e);
    if (rc == REFRACT_E_OK) {
        if (out) {
            atomic_fetch_add(&v->refs, 1);
            *out = v;
        }
        rc = store_install_locked(s, v, e);
        if (rc != REFRACT_E_OK && out) {
            store_scene_release(*out);
            *out = NULL;
        }
    } else {
        store_scene_release(v);
    }
    if (rc == REFRACT_E_OK) {
        struct slot *slot = store_find_slot(s, new_id);
        slot->has_status = false;
    }
    /* A replaced document drops its uploads: their blobs go when nothing else uses them. */
    for (size_t i = 0; i < old_count; i++)
        store_blob_release_locked(s, old_blobs[i]);
    pthread_mutex_unlock(&s->lock);
    free(old_blobs);
    return rc;
}

enum refract_code store_scene_set_lights(struct store *s, const char *id, const char *json,
                                         size_t len, struct store_scene **out, struct err *e)
{
    if (out)
        *out = NULL;
    struct scene *parsed = NULL;
    enum refract_code rc = scene_parse(json, len, &s->desc.limits, &parsed, e);
    if (rc != REFRACT_E_OK)
        return rc;
    char *copy = malloc(len + 1);
    if (copy == NULL) {
        scene_destroy(parsed);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory storing the lights");
    }
    memcpy(copy, json, len);
    copy[len] = '\0';
    pthread_mutex_lock(&s->lock);
    struct slot *slot = store_find_slot(s, id);
    struct store_scene *v = slot ? store_version_new(s, id, slot->current) : NULL;
    if (slot == NULL)
        rc = err_set(e, REFRACT_E_SCENE_NOT_FOUND,
                     "no scene with id \"%s\"; GET /v1/scenes lists the scenes", id);
    else if (v == NULL)
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory storing the lights");
    if (rc == REFRACT_E_OK) {
        free(v->json);
        scene_destroy(v->scene);
        v->json = copy;
        v->json_len = len;
        v->scene = parsed;
        copy = NULL;
        parsed = NULL;
        v->data_generation = slot->current->data_generation;
        rc = store_db_scene_put_locked(s, v, e);
    }
    if (rc == REFRACT_E_OK) {
        if (out) {
            atomic_fetch_add(&v->refs, 1);
            *out = v;
        }
        rc = store_install_locked(s, v, e); /* never fails for an existing slot */
        v = NULL;
    }
    pthread_mutex_unlock(&s->lock);
    store_scene_release(v);
    scene_destroy(parsed);
    free(copy);
    return rc;
}

enum refract_code store_scene_derive(struct store *s, struct store_scene *base, const char *json,
                                     size_t len, struct store_scene **out, struct err *e)
{
    *out = NULL;
    struct scene *parsed = NULL;
    enum refract_code rc = scene_parse(json, len, &s->desc.limits, &parsed, e);
    if (rc != REFRACT_E_OK)
        return rc;
    char *copy = malloc(len + 1);
    pthread_mutex_lock(&s->lock);
    struct store_scene *v = copy ? store_version_new(s, base->id, base) : NULL;
    pthread_mutex_unlock(&s->lock);
    if (v == NULL) {
        free(copy);
        scene_destroy(parsed);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a derived scene version");
    }
    memcpy(copy, json, len);
    copy[len] = '\0';
    free(v->json);
    scene_destroy(v->scene);
    v->json = copy;
    v->json_len = len;
    v->scene = parsed;
    v->data_generation = base->data_generation;
    *out = v;
    return REFRACT_E_OK;
}

enum refract_code store_scene_delete(struct store *s, const char *id, struct err *e)
{
    pthread_mutex_lock(&s->lock);
    struct slot *slot = store_find_slot(s, id);
    if (slot == NULL) {
        pthread_mutex_unlock(&s->lock);
        return err_set(e, REFRACT_E_SCENE_NOT_FOUND,
                       "no scene with id \"%s\"; GET /v1/scenes lists the scenes", id);
    }
    char(*blobs)[SHA256_HEX_SIZE] = NULL;
    size_t count = 0;
    enum refract_code rc = store_db_begin_locked(s, e);
    if (rc == REFRACT_E_OK)
        rc = store_db_scene_delete_locked(s, id, false, &blobs, &count, e);
    if (rc == REFRACT_E_OK)
        rc = store_db_commit_locked(s, e);
    if (rc != REFRACT_E_OK) {
        store_db_rollback_locked(s);
        pthread_mutex_unlock(&s->lock);
        free(blobs);
        return rc;
    }
    struct store_scene *v = slot->current;
    *slot = s->slots[--s->slot_count];
    for (size_t i = 0; i < count; i++)
        store_blob_release_locked(s, blobs[i]);
    pthread_mutex_unlock(&s->lock);
    free(blobs);
    store_scene_release(v);
    return REFRACT_E_OK;
}

static int compare_versions(const void *a, const void *b)
{
    const struct store_scene *const *x = a, *const *y = b;
    return strcmp((*x)->id, (*y)->id);
}

size_t store_scene_list(struct store *s, struct store_scene ***out)
{
    pthread_mutex_lock(&s->lock);
    size_t n = s->slot_count;
    struct store_scene **list = calloc(n ? n : 1, sizeof *list);
    if (list == NULL) {
        pthread_mutex_unlock(&s->lock);
        *out = NULL;
        return 0;
    }
    for (size_t i = 0; i < n; i++) {
        list[i] = s->slots[i].current;
        atomic_fetch_add(&list[i]->refs, 1);
    }
    pthread_mutex_unlock(&s->lock);
    qsort(list, n, sizeof *list, compare_versions);
    *out = list;
    return n;
}

void store_list_free(struct store_scene **list, size_t count)
{
    for (size_t i = 0; i < count; i++)
        store_scene_release(list[i]);
    free(list);
}

void store_gpu_status_set(struct store *s, const char *id, const struct store_gpu_status *st)
{
    pthread_mutex_lock(&s->lock);
    struct slot *slot = store_find_slot(s, id);
    /* A report about an older version must not overwrite a newer one's. */
    if (slot && (!slot->has_status || st->generation >= slot->status.generation)) {
        slot->status = *st;
        slot->has_status = true;
    }
    pthread_mutex_unlock(&s->lock);
}

bool store_gpu_status_get(struct store *s, const char *id, struct store_gpu_status *out)
{
    pthread_mutex_lock(&s->lock);
    struct slot *slot = store_find_slot(s, id);
    bool found = slot && slot->has_status;
    if (found)
        *out = slot->status;
    pthread_mutex_unlock(&s->lock);
    return found;
}
