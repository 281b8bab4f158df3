/*
 * store_mesh.c - a scene's uploaded meshes: parse and validate once, commit the file as
 * uploaded as a blob with an uploads row of kind "mesh" (blob first, row second, like
 * store_upload.c), share one parsed copy between versions, restore from the blob at
 * start-up. See store_mesh.h.
 *
 * INVARIANT: a version's meshes[0..mesh_count) have distinct names; the array has room
 * for STORE_MAX_MESHES_PER_SCENE references.
 */
#include "store_mesh.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>
#include <unistd.h>

#include "../io/io_files.h"
#include "../io/io_volume.h"
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

/* Parses `bytes` (the uploaded file) into a new store_mesh with its upload description
 * (the row's: type "mesh", format obj/ply, bounds as min/max, checksum, bytes). */
static enum refract_code mesh_new(const struct store *s, const char *name, const void *bytes,
                                  size_t len, enum mesh_format format, struct store_mesh **out,
                                  struct err *e)
{
    *out = NULL;
    if (format == MESH_FORMAT_UNKNOWN)
        format = mesh_sniff(bytes, len);
    int64_t max_t = s->desc.limits.max_mesh_triangles;
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
    m->checksum = io_fnv1a64_update(IO_FNV1A64_INIT, bytes, len);
    m->bytes = len;
    struct store_upload_info *in = &m->info;
    snprintf(in->type, sizeof in->type, "mesh");
    snprintf(in->format, sizeof in->format, "%s", mesh_format_name(format));
    const double lo[3] = {parsed->lo.x, parsed->lo.y, parsed->lo.z};
    const double hi[3] = {parsed->hi.x, parsed->hi.y, parsed->hi.z};
    for (int a = 0; a < 3; a++) {
        in->min[a] = lo[a];
        in->max[a] = hi[a];
    }
    in->min_all = lo[0] < lo[1] ? (lo[0] < lo[2] ? lo[0] : lo[2]) : (lo[1] < lo[2] ? lo[1] : lo[2]);
    in->max_all = hi[0] > hi[1] ? (hi[0] > hi[2] ? hi[0] : hi[2]) : (hi[1] > hi[2] ? hi[1] : hi[2]);
    in->checksum = m->checksum;
    in->bytes = len;
    in->created_unix = (int64_t)time(NULL);
    *out = m;
    return REFRACT_E_OK;
}

/* The checks that need the slot: the scene exists and has room for one more mesh. */
static enum refract_code mesh_room_locked(struct store *s, const char *id, const char *name,
                                          struct err *e)
{
    struct slot *slot = store_find_slot(s, id);
    if (slot == NULL)
        return err_set(e, REFRACT_E_SCENE_NOT_FOUND,
                       "no scene with id \"%s\"; GET /v1/scenes lists the scenes", id);
    const struct store_scene *cur = slot->current;
    if (store_mesh_lookup(cur, name) == NULL && cur->mesh_count >= STORE_MAX_MESHES_PER_SCENE)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "scene \"%s\" already holds %d meshes, the most a scene can; replace one "
                       "by uploading under its name",
                       id, STORE_MAX_MESHES_PER_SCENE);
    return REFRACT_E_OK;
}

/* Swaps in a copy of `id`'s current version with m added or replacing its namesake. */
static enum refract_code install_mesh_locked(struct store *s, const char *id, void *item,
                                             struct err *e)
{
    struct store_mesh *m = item;
    enum refract_code rc = mesh_room_locked(s, id, m->name, e);
    if (rc != REFRACT_E_OK)
        return rc;
    struct store_scene *v = store_version_new(s, id, store_find_slot(s, id)->current);
    if (v == NULL || !ensure_array(v)) {
        store_scene_release(v);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory adding mesh %s", m->name);
    }
    size_t i = 0;
    while (i < v->mesh_count && strcmp(v->meshes[i]->name, m->name) != 0)
        i++;
    atomic_fetch_add(&m->refs, 1);
    if (i < v->mesh_count)
        store_mesh_release(v->meshes[i]);
    else
        v->mesh_count++;
    v->meshes[i] = m;
    return store_install_locked(s, v, e);
}

enum refract_code store_mesh_put_file(struct store *s, const char *id, const char *name,
                                      const char *tmp_path, const char *sha256,
                                      enum mesh_format format, struct store_mesh **out,
                                      struct err *e)
{
    if (out)
        *out = NULL;
    const void *bytes = NULL;
    size_t len = 0;
    struct store_mesh *m = NULL;
    /* The parsers read the mapped file (they never read past len); the result is bounded
     * by --max-mesh-triangles. */
    enum refract_code rc = io_map_file(tmp_path, &bytes, &len, e);
    if (rc == REFRACT_E_OK)
        rc = mesh_new(s, name, bytes, len, format, &m, e);
    io_unmap_file(bytes, len);
    if (rc != REFRACT_E_OK) {
        unlink(tmp_path);
        return rc;
    }
    snprintf(m->info.sha256, sizeof m->info.sha256, "%s", sha256);
    pthread_mutex_lock(&s->lock);
    rc = store_upload_take_file_locked(s, id, "mesh", name, tmp_path, sha256, len, mesh_room_locked,
                                       e);
    if (rc == REFRACT_E_OK)
        rc =
            store_upload_finish_locked(s, id, "mesh", m->name, &m->info, install_mesh_locked, m, e);
    pthread_mutex_unlock(&s->lock);
    if (rc == REFRACT_E_OK && out)
        *out = m;
    else
        store_mesh_release(m);
    return rc;
}

enum refract_code store_mesh_restore(struct store *s, const struct store_upload_row *row,
                                     struct err *e)
{
    void *map = NULL;
    enum refract_code rc = store_blob_map(s, row->info.sha256, row->info.bytes, &map, e);
    if (rc != REFRACT_E_OK)
        return rc;
    enum mesh_format format = strcmp(row->info.format, "ply") == 0   ? MESH_FORMAT_PLY
                              : strcmp(row->info.format, "obj") == 0 ? MESH_FORMAT_OBJ
                                                                     : MESH_FORMAT_UNKNOWN;
    struct store_mesh *m = NULL;
    rc = mesh_new(s, row->name, map, row->info.bytes, format, &m, e);
    if (map)
        munmap(map, row->info.bytes);
    if (rc != REFRACT_E_OK)
        return rc;
    m->info = row->info;
    pthread_mutex_lock(&s->lock);
    rc = install_mesh_locked(s, row->scene, m, e);
    pthread_mutex_unlock(&s->lock);
    store_mesh_release(m);
    return rc;
}
