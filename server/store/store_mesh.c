/*
 * store_mesh.c - a scene's uploaded meshes: parse and validate once, persist the file as
 * uploaded, share one parsed copy between versions, restore at start-up. See
 * store_mesh.h. Kept apart from store.c, which it reaches only through store_internal.h
 * (store_edit_version), so the persistence underneath can change without touching it.
 *
 * INVARIANT: a version's meshes[0..mesh_count) have distinct names; the array has room
 * for STORE_MAX_MESHES_PER_SCENE references.
 */
#include "store_mesh.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../core/log.h"
#include "../io/io_files.h"
#include "store_internal.h"

void store_mesh_release(struct store_mesh *m)
{
    if (m == NULL || atomic_fetch_sub(&m->refs, 1) != 1)
        return;
    mesh_destroy(m->mesh);
    free(m);
}

void store_mesh_release_all(struct store_scene *sc)
{
    for (size_t i = 0; i < sc->mesh_count; i++)
        store_mesh_release(sc->meshes[i]);
    free(sc->meshes);
    sc->meshes = NULL;
    sc->mesh_count = 0;
}

static bool ensure_array(struct store_scene *v)
{
    if (v->meshes == NULL)
        v->meshes = calloc(STORE_MAX_MESHES_PER_SCENE, sizeof *v->meshes);
    return v->meshes != NULL;
}

bool store_mesh_share(struct store_scene *v, const struct store_scene *base)
{
    if (base->mesh_count == 0)
        return true;
    if (!ensure_array(v))
        return false;
    for (size_t i = 0; i < base->mesh_count; i++) {
        atomic_fetch_add(&base->meshes[i]->refs, 1);
        v->meshes[v->mesh_count++] = base->meshes[i];
    }
    return true;
}

const struct scene_volume *store_mesh_lookup(const struct store_scene *sc, const char *name)
{
    for (size_t i = 0; i < sc->mesh_count; i++) {
        if (strcmp(sc->meshes[i]->name, name) == 0)
            return &sc->meshes[i]->view;
    }
    return NULL;
}

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

/* What store_edit_version's callbacks need. */
struct put_ctx {
    struct store_mesh *mesh;
    const void *bytes;
    size_t len;
};

static enum refract_code persist(const char *scene_dir, void *ctx, struct err *e)
{
    const struct put_ctx *p = ctx;
    char dir[4200], path[4400], other[4400];
    snprintf(dir, sizeof dir, "%s/meshes", scene_dir);
    enum refract_code rc = io_mkdirs(dir, e);
    const char *ext = mesh_format_name(p->mesh->format);
    const char *other_ext = p->mesh->format == MESH_FORMAT_OBJ ? "ply" : "obj";
    snprintf(path, sizeof path, "%s/%s.%s", dir, p->mesh->name, ext);
    snprintf(other, sizeof other, "%s/%s.%s", dir, p->mesh->name, other_ext);
    if (rc == REFRACT_E_OK)
        rc = io_write_atomic(path, p->bytes, p->len, e);
    /* A replacement in the other format must not leave the old file to be restored. */
    if (rc == REFRACT_E_OK)
        unlink(other);
    return rc;
}

static enum refract_code add_to_version(struct store_scene *v, void *ctx, struct err *e)
{
    struct store_mesh *m = ((struct put_ctx *)ctx)->mesh;
    if (!ensure_array(v))
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory adding mesh %s", m->name);
    size_t i = 0;
    while (i < v->mesh_count && strcmp(v->meshes[i]->name, m->name) != 0)
        i++;
    if (i == v->mesh_count && v->mesh_count >= STORE_MAX_MESHES_PER_SCENE)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "scene \"%s\" already holds %d meshes, the most a scene can; replace one "
                       "by uploading under its name",
                       v->id, STORE_MAX_MESHES_PER_SCENE);
    atomic_fetch_add(&m->refs, 1);
    if (i < v->mesh_count)
        store_mesh_release(v->meshes[i]);
    else
        v->mesh_count++;
    v->meshes[i] = m;
    return REFRACT_E_OK;
}

static enum refract_code mesh_put(struct store *s, const char *id, const char *name,
                                  const void *bytes, size_t len, enum mesh_format format,
                                  bool write, struct store_mesh **out, struct err *e)
{
    if (out)
        *out = NULL;
    if (format == MESH_FORMAT_UNKNOWN)
        format = mesh_sniff(bytes, len);
    int64_t max_t = store_limits(s)->max_mesh_triangles;
    struct mesh_limits lim = {.max_triangles = max_t > 0 ? (size_t)max_t : 0};
    struct mesh *parsed = NULL;
    enum refract_code rc = mesh_parse(bytes, len, format, &lim, &parsed, e);
    if (rc != REFRACT_E_OK)
        return rc;
    struct store_mesh *m = calloc(1, sizeof *m);
    if (m == NULL) {
        mesh_destroy(parsed);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory storing mesh %s", name);
    }
    atomic_init(&m->refs, 1);
    snprintf(m->name, sizeof m->name, "%s", name);
    m->format = format;
    m->mesh = parsed;
    m->view.mesh = parsed;
    m->checksum = fnv1a64(bytes, len);
    m->bytes = len;
    struct put_ctx ctx = {.mesh = m, .bytes = bytes, .len = len};
    rc = store_edit_version(s, id, write ? persist : NULL, add_to_version, &ctx, e);
    if (rc == REFRACT_E_OK && out)
        *out = m;
    else
        store_mesh_release(m);
    return rc;
}

enum refract_code store_mesh_put(struct store *s, const char *id, const char *name,
                                 const void *bytes, size_t len, enum mesh_format format,
                                 struct store_mesh **out, struct err *e)
{
    return mesh_put(s, id, name, bytes, len, format, true, out, e);
}

void store_mesh_load_all(struct store *s, const char *id, const char *dir)
{
    char mdir[4200];
    snprintf(mdir, sizeof mdir, "%s/meshes", dir);
    DIR *d = opendir(mdir);
    if (d == NULL)
        return;
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        size_t n = strlen(ent->d_name);
        bool obj = n > 4 && strcmp(ent->d_name + n - 4, ".obj") == 0;
        bool ply = n > 4 && strcmp(ent->d_name + n - 4, ".ply") == 0;
        if ((!obj && !ply) || n - 4 >= SCENE_VOLUME_NAME_MAX)
            continue;
        char name[SCENE_VOLUME_NAME_MAX] = {0}, path[4400];
        memcpy(name, ent->d_name, n - 4);
        snprintf(path, sizeof path, "%s/%s", mdir, ent->d_name);
        char *bytes = NULL;
        size_t len = 0;
        struct err e = {0};
        enum refract_code rc = io_read_file(path, (size_t)1 << 40, &bytes, &len, &e);
        if (rc == REFRACT_E_OK)
            rc = mesh_put(s, id, name, bytes, len, obj ? MESH_FORMAT_OBJ : MESH_FORMAT_PLY, false,
                          NULL, &e);
        if (rc != REFRACT_E_OK)
            log_warn("store", "scene %s: mesh %s not restored: %s", id, name, e.msg);
        free(bytes);
    }
    closedir(d);
}
