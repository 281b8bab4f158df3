/*
 * store.c - the scene registry: slots of immutable scene versions, persisted to the data
 * directory. See store.h for the design.
 *
 * INVARIANT: slots[0..slot_count) have distinct ids and a non-NULL `current`; each slot
 * holds one reference to its current version. `lock` guards the slot array and the
 * statuses, never the versions (they are immutable).
 */
#include "store.h"
#include "store_internal.h"
#include "store_mesh.h"

#include <dirent.h>
#include <fcntl.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../core/log.h"
#include "../io/io_image.h"
#include "../io/io_files.h"

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
};

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
    free(v->data);
    free(v);
}

static void env_release(struct store_env *env)
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
    env_release(sc->env);
    scene_destroy(sc->scene);
    free(sc->json);
    free(sc);
}

/* A new version sharing `base`'s document, volumes and environment (new references);
 * base may be NULL. The caller fills or replaces what changes. */
static struct store_scene *version_new(struct store *s, const char *id,
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

static struct slot *find_slot(struct store *s, const char *id)
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
static enum refract_code install_locked(struct store *s, struct store_scene *v, struct err *e)
{
    struct slot *slot = find_slot(s, v->id);
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

static void scene_dir(const struct store *s, const char *id, char *out, size_t size)
{
    snprintf(out, size, "%s/scenes/%s", s->data_dir, id);
}

/* ---- public API ---------------------------------------------------------------------- */

struct store_scene *store_scene_get(struct store *s, const char *id)
{
    pthread_mutex_lock(&s->lock);
    struct slot *slot = find_slot(s, id);
    struct store_scene *v = slot ? slot->current : NULL;
    if (v)
        atomic_fetch_add(&v->refs, 1);
    pthread_mutex_unlock(&s->lock);
    return v;
}

static enum refract_code persist_document(struct store *s, const char *id, const char *json,
                                          size_t len, struct err *e)
{
    char dir[4096], path[4200];
    scene_dir(s, id, dir, sizeof dir);
    enum refract_code rc = io_remove_tree(dir, e);
    if (rc == REFRACT_E_OK)
        rc = io_mkdirs(dir, e);
    snprintf(path, sizeof path, "%s/scene.json", dir);
    if (rc == REFRACT_E_OK)
        rc = io_write_atomic(path, json, len, e);
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
        } while (find_slot(s, new_id) != NULL);
    }
    struct store_scene *v = version_new(s, new_id, NULL);
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
    if (find_slot(s, new_id) == NULL && scene_limit_reached_locked(s, e))
        rc = e->code;
    else
        rc = persist_document(s, new_id, json, len, e);
    if (rc == REFRACT_E_OK) {
        if (out) {
            atomic_fetch_add(&v->refs, 1);
            *out = v;
        }
        rc = install_locked(s, v, e);
        if (rc != REFRACT_E_OK && out) {
            store_scene_release(*out);
            *out = NULL;
        }
    } else {
        store_scene_release(v);
    }
    if (rc == REFRACT_E_OK) {
        struct slot *slot = find_slot(s, new_id);
        slot->has_status = false;
    }
    pthread_mutex_unlock(&s->lock);
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
    struct slot *slot = find_slot(s, id);
    struct store_scene *v = slot ? version_new(s, id, slot->current) : NULL;
    if (slot == NULL)
        rc = err_set(e, REFRACT_E_SCENE_NOT_FOUND,
                     "no scene with id \"%s\"; GET /v1/scenes lists the scenes", id);
    else if (v == NULL)
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory storing the lights");
    if (rc == REFRACT_E_OK) {
        char dir[4096], path[4200];
        scene_dir(s, id, dir, sizeof dir);
        snprintf(path, sizeof path, "%s/scene.json", dir);
        rc = io_write_atomic(path, json, len, e);
    }
    if (rc == REFRACT_E_OK) {
        free(v->json);
        scene_destroy(v->scene);
        v->json = copy;
        v->json_len = len;
        v->scene = parsed;
        copy = NULL;
        parsed = NULL;
        v->data_generation = slot->current->data_generation;
        if (out) {
            atomic_fetch_add(&v->refs, 1);
            *out = v;
        }
        rc = install_locked(s, v, e); /* never fails for an existing slot */
        v = NULL;
    }
    pthread_mutex_unlock(&s->lock);
    store_scene_release(v);
    scene_destroy(parsed);
    free(copy);
    return rc;
}

enum refract_code store_scene_delete(struct store *s, const char *id, struct err *e)
{
    pthread_mutex_lock(&s->lock);
    struct slot *slot = find_slot(s, id);
    if (slot == NULL) {
        pthread_mutex_unlock(&s->lock);
        return err_set(e, REFRACT_E_SCENE_NOT_FOUND,
                       "no scene with id \"%s\"; GET /v1/scenes lists the scenes", id);
    }
    struct store_scene *v = slot->current;
    *slot = s->slots[--s->slot_count];
    char dir[4096];
    scene_dir(s, id, dir, sizeof dir);
    enum refract_code rc = io_remove_tree(dir, e);
    pthread_mutex_unlock(&s->lock);
    store_scene_release(v);
    return rc;
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
    struct slot *slot = find_slot(s, id);
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
    struct slot *slot = find_slot(s, id);
    bool found = slot && slot->has_status;
    if (found)
        *out = slot->status;
    pthread_mutex_unlock(&s->lock);
    return found;
}

/* ---- uploads ------------------------------------------------------------------------- */

static uint64_t fnv1a64(const void *data, size_t len)
{
    const unsigned char *p = data;
    uint64_t h = 14695981039346656037ull; /* FNV-1a 64 offset basis */
    for (size_t i = 0; i < len; i++) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

static struct store_volume *volume_new(const char *name, const int dims[3], int components,
                                       float *data, size_t count)
{
    struct store_volume *v = calloc(1, sizeof *v);
    if (v == NULL)
        return NULL;
    atomic_init(&v->refs, 1);
    snprintf(v->name, sizeof v->name, "%s", name);
    v->data = data;
    v->count = count;
    for (int a = 0; a < 3; a++)
        v->view.dims[a] = dims[a];
    v->view.components = components;
    v->view.data = data;
    v->min = count ? data[0] : 0.0;
    v->max = v->min;
    for (size_t i = 0; i < count; i++) {
        if (data[i] < v->min)
            v->min = data[i];
        if (data[i] > v->max)
            v->max = data[i];
    }
    v->checksum = fnv1a64(data, count * sizeof(float));
    return v;
}

static enum refract_code persist_volume(struct store *s, const char *id,
                                        const struct store_volume *v, struct err *e)
{
    char dir[4096], path[4200], meta[256];
    scene_dir(s, id, dir, sizeof dir);
    strncat(dir, "/volumes", sizeof dir - strlen(dir) - 1);
    enum refract_code rc = io_mkdirs(dir, e);
    snprintf(path, sizeof path, "%s/%s.f32", dir, v->name);
    if (rc == REFRACT_E_OK)
        rc = io_write_atomic(path, v->data, v->count * sizeof(float), e);
    int n = snprintf(meta, sizeof meta, "{\"dims\": [%d, %d, %d], \"components\": %d}\n",
                     v->view.dims[0], v->view.dims[1], v->view.dims[2], v->view.components);
    snprintf(path, sizeof path, "%s/%s.json", dir, v->name);
    if (rc == REFRACT_E_OK)
        rc = io_write_atomic(path, meta, (size_t)n, e);
    return rc;
}

/* Swaps in a copy of `id`'s current version with `vol` added or replacing its namesake. */
static enum refract_code install_volume_locked(struct store *s, const char *id,
                                               struct store_volume *vol, struct err *e)
{
    struct slot *slot = find_slot(s, id);
    if (slot == NULL)
        return err_set(e, REFRACT_E_SCENE_NOT_FOUND, "no scene with id \"%s\"", id);
    struct store_scene *v = version_new(s, id, slot->current);
    if (v == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory adding a volume");
    size_t i = 0;
    while (i < v->volume_count && strcmp(v->volumes[i]->name, vol->name) != 0)
        i++;
    if (i == v->volume_count && v->volume_count >= STORE_MAX_VOLUMES_PER_SCENE) {
        store_scene_release(v);
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED, "a scene holds at most %d volumes",
                       STORE_MAX_VOLUMES_PER_SCENE);
    }
    atomic_fetch_add(&vol->refs, 1);
    if (i < v->volume_count)
        store_volume_release(v->volumes[i]);
    else
        v->volume_count++;
    v->volumes[i] = vol;
    return install_locked(s, v, e);
}

static enum refract_code volume_put(struct store *s, const char *id, const char *name,
                                    const int dims[3], int components, float *data, size_t count,
                                    bool persist, struct store_volume **out, struct err *e)
{
    if (out)
        *out = NULL;
    struct store_volume *vol = volume_new(name, dims, components, data, count);
    if (vol == NULL) {
        free(data);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory storing volume %s", name);
    }
    pthread_mutex_lock(&s->lock);
    enum refract_code rc = REFRACT_E_OK;
    if (find_slot(s, id) == NULL)
        rc = err_set(e, REFRACT_E_SCENE_NOT_FOUND, "no scene with id \"%s\"", id);
    else if (persist)
        rc = persist_volume(s, id, vol, e);
    if (rc == REFRACT_E_OK)
        rc = install_volume_locked(s, id, vol, e);
    pthread_mutex_unlock(&s->lock);
    if (rc == REFRACT_E_OK && out)
        *out = vol;
    else
        store_volume_release(vol);
    return rc;
}

enum refract_code store_volume_put(struct store *s, const char *id, const char *name,
                                   const int dims[3], int components, float *data, size_t count,
                                   struct store_volume **out, struct err *e)
{
    return volume_put(s, id, name, dims, components, data, count, true, out, e);
}

static enum refract_code decode_env(struct store *s, const void *bytes, size_t len,
                                    struct store_env **out, struct err *e)
{
    struct io_image img;
    long long max_px = s->desc.max_env_pixels > 0 ? s->desc.max_env_pixels : (64ll << 20);
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
    *out = env;
    return REFRACT_E_OK;
}

static enum refract_code env_put(struct store *s, const char *id, const void *bytes, size_t len,
                                 bool persist, int *width, int *height, struct err *e)
{
    struct store_env *env = NULL;
    enum refract_code rc = decode_env(s, bytes, len, &env, e);
    if (rc != REFRACT_E_OK)
        return rc;
    pthread_mutex_lock(&s->lock);
    struct slot *slot = find_slot(s, id);
    if (slot == NULL) {
        rc = err_set(e, REFRACT_E_SCENE_NOT_FOUND, "no scene with id \"%s\"", id);
    } else if (persist) {
        char dir[4096], path[4200];
        scene_dir(s, id, dir, sizeof dir);
        snprintf(path, sizeof path, "%s/environment.img", dir);
        rc = io_write_atomic(path, bytes, len, e);
    }
    if (rc == REFRACT_E_OK) {
        struct store_scene *v = version_new(s, id, slot->current);
        if (v == NULL) {
            rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory");
        } else {
            env_release(v->env);
            atomic_fetch_add(&env->refs, 1);
            v->env = env;
            rc = install_locked(s, v, e);
        }
    }
    pthread_mutex_unlock(&s->lock);
    if (rc == REFRACT_E_OK && width && height) {
        *width = env->width;
        *height = env->height;
    }
    env_release(env);
    return rc;
}

enum refract_code store_env_put(struct store *s, const char *id, const void *bytes, size_t len,
                                int *width, int *height, struct err *e)
{
    return env_put(s, id, bytes, len, true, width, height, e);
}

/* ---- for the store's other files (store_internal.h) ---------------------------------- */

enum refract_code
store_edit_version(struct store *s, const char *id,
                   enum refract_code (*persist)(const char *scene_dir, void *ctx, struct err *e),
                   enum refract_code (*edit)(struct store_scene *v, void *ctx, struct err *e),
                   void *ctx, struct err *e)
{
    char dir[4096];
    scene_dir(s, id, dir, sizeof dir);
    pthread_mutex_lock(&s->lock);
    struct slot *slot = find_slot(s, id);
    enum refract_code rc = REFRACT_E_OK;
    struct store_scene *v = NULL;
    if (slot == NULL)
        rc = err_set(e, REFRACT_E_SCENE_NOT_FOUND, "no scene with id \"%s\"", id);
    if (rc == REFRACT_E_OK && persist != NULL)
        rc = persist(dir, ctx, e);
    if (rc == REFRACT_E_OK) {
        v = version_new(s, id, slot->current);
        if (v == NULL)
            rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory making a new version");
    }
    if (rc == REFRACT_E_OK)
        rc = edit(v, ctx, e);
    if (rc == REFRACT_E_OK)
        rc = install_locked(s, v, e);
    else
        store_scene_release(v);
    pthread_mutex_unlock(&s->lock);
    return rc;
}

const struct scene_limits *store_limits(const struct store *s)
{
    return &s->desc.limits;
}

/* ---- start-up -------------------------------------------------------------------------- */

static void load_volumes(struct store *s, const char *id, const char *dir)
{
    char vdir[4200];
    snprintf(vdir, sizeof vdir, "%s/volumes", dir);
    DIR *d = opendir(vdir);
    if (d == NULL)
        return;
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        size_t n = strlen(ent->d_name);
        if (n < 6 || strcmp(ent->d_name + n - 5, ".json") != 0)
            continue;
        char name[SCENE_VOLUME_NAME_MAX] = {0};
        if (n - 5 >= sizeof name)
            continue;
        memcpy(name, ent->d_name, n - 5);
        char path[4400];
        char *meta = NULL, *raw = NULL;
        size_t meta_len = 0, raw_len = 0;
        struct err e;
        int dims[3] = {0}, comps = 0;
        snprintf(path, sizeof path, "%s/%s.json", vdir, name);
        if (io_read_file(path, 4096, &meta, &meta_len, &e) != REFRACT_E_OK ||
            sscanf(meta, "{\"dims\": [%d, %d, %d], \"components\": %d}", &dims[0], &dims[1],
                   &dims[2], &comps) != 4) {
            log_warn("store", "skipping volume %s of scene %s: unreadable metadata", name, id);
            free(meta);
            continue;
        }
        free(meta);
        snprintf(path, sizeof path, "%s/%s.f32", vdir, name);
        size_t expect = (size_t)dims[0] * dims[1] * dims[2] * comps * sizeof(float);
        if (io_read_file(path, expect, &raw, &raw_len, &e) != REFRACT_E_OK || raw_len != expect) {
            log_warn("store", "skipping volume %s of scene %s: %s", name, id,
                     raw ? "size does not match its metadata" : e.msg);
            free(raw);
            continue;
        }
        float *data = malloc(raw_len ? raw_len : 1);
        if (data)
            memcpy(data, raw, raw_len);
        free(raw);
        if (data == NULL || volume_put(s, id, name, dims, comps, data, raw_len / sizeof(float),
                                       false, NULL, &e) != REFRACT_E_OK)
            log_warn("store", "could not restore volume %s of scene %s", name, id);
    }
    closedir(d);
}

static void load_scene(struct store *s, const char *id)
{
    char dir[4096], path[4200];
    scene_dir(s, id, dir, sizeof dir);
    snprintf(path, sizeof path, "%s/scene.json", dir);
    char *json = NULL;
    size_t len = 0;
    struct err e;
    if (io_read_file(path, STORE_MAX_JSON_BYTES, &json, &len, &e) != REFRACT_E_OK) {
        log_warn("store", "skipping %s: %s", dir, e.msg);
        return;
    }
    struct scene *parsed = NULL;
    if (scene_parse(json, len, &s->desc.limits, &parsed, &e) != REFRACT_E_OK) {
        log_warn("store", "skipping scene %s: it no longer validates: %s", id, e.msg);
        free(json);
        return;
    }
    struct store_scene *v = version_new(s, id, NULL);
    if (v)
        v->volumes = calloc(STORE_MAX_VOLUMES_PER_SCENE, sizeof *v->volumes);
    if (v == NULL || v->volumes == NULL) {
        free(json);
        scene_destroy(parsed);
        store_scene_release(v);
        return;
    }
    v->json = json;
    v->json_len = len;
    v->scene = parsed;
    pthread_mutex_lock(&s->lock);
    enum refract_code rc = install_locked(s, v, &e);
    pthread_mutex_unlock(&s->lock);
    if (rc != REFRACT_E_OK) {
        log_warn("store", "skipping scene %s: %s", id, e.msg);
        return;
    }
    load_volumes(s, id, dir);
    store_mesh_load_all(s, id, dir);
    snprintf(path, sizeof path, "%s/environment.img", dir);
    char *img = NULL;
    size_t img_len = 0;
    if (access(path, R_OK) == 0) {
        if (io_read_file(path, (size_t)1 << 31, &img, &img_len, &e) != REFRACT_E_OK ||
            env_put(s, id, img, img_len, false, NULL, NULL, &e) != REFRACT_E_OK)
            log_warn("store", "scene %s: environment image not restored: %s", id, e.msg);
        free(img);
    }
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
    char scenes[1024];
    snprintf(scenes, sizeof scenes, "%s/scenes", s->data_dir);
    if (io_mkdirs(scenes, e) != REFRACT_E_OK) {
        err_prefix(e, "data directory (--data-dir): ");
        store_close(s);
        return NULL;
    }
    DIR *d = opendir(scenes);
    if (d == NULL) {
        err_set(e, REFRACT_E_STORAGE, "cannot list %s", scenes);
        store_close(s);
        return NULL;
    }
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        if (store_name_valid(ent->d_name, false))
            load_scene(s, ent->d_name);
    }
    closedir(d);
    log_info("store", "data directory %s: %zu scenes loaded", s->data_dir, s->slot_count);
    return s;
}

void store_close(struct store *s)
{
    if (s == NULL)
        return;
    for (size_t i = 0; i < s->slot_count; i++)
        store_scene_release(s->slots[i].current);
    free(s->slots);
    pthread_mutex_destroy(&s->lock);
    free(s);
}
