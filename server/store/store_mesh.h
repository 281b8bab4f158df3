/*
 * store_mesh.h - uploaded triangle meshes of a scene (POST /v1/scenes/{id}/meshes), kept
 * in the scene's versions next to its volumes, and persisted in the data directory as the
 * file that was uploaded:
 *     <data>/scenes/<id>/meshes/<name>.obj | <name>.ply
 * A mesh is parsed and validated once, at upload (and again when refractd starts), into a
 * struct mesh with its BVH; every version that has it shares one reference-counted copy.
 *
 * Ownership: store_mesh_put's *out is a new reference; release it with
 * store_mesh_release(). Thread: any; the store locks internally.
 */
#ifndef REFRACT_STORE_MESH_H
#define REFRACT_STORE_MESH_H

#include "../mesh/mesh.h"
#include "store.h"

#define STORE_MAX_MESHES_PER_SCENE 64

struct store_mesh {
    atomic_int refs;
    char name[SCENE_VOLUME_NAME_MAX];
    enum mesh_format format;
    struct mesh *mesh;        /* owned */
    struct scene_volume view; /* what the scene lookup answers: view.mesh = mesh */
    uint64_t checksum;        /* FNV-1a 64 of the uploaded bytes */
    size_t bytes;             /* size of the uploaded file */
};

/* Parses `bytes` (the uploaded file; format MESH_FORMAT_UNKNOWN: sniffed) under the
 * store's limits (scene_limits.max_mesh_triangles), persists the file, and makes a new
 * version of scene `id` holding it as `name` (replacing a mesh of that name). Borrows
 * bytes. SCENE_NOT_FOUND, the parse errors (INVALID_MESH, LIMIT_EXCEEDED), LIMIT_EXCEEDED
 * for more than STORE_MAX_MESHES_PER_SCENE meshes, STORAGE, OUT_OF_MEMORY. */
enum refract_code store_mesh_put(struct store *s, const char *id, const char *name,
                                 const void *bytes, size_t len, enum mesh_format format,
                                 struct store_mesh **out, struct err *e);
void store_mesh_release(struct store_mesh *m);

/* ---- for store.c ---- */

/* The lookup's answer for mesh `name` of version sc, or NULL. */
const struct scene_volume *store_mesh_lookup(const struct store_scene *sc, const char *name);
/* Gives v new references to base's meshes; false on out of memory (v keeps none). */
bool store_mesh_share(struct store_scene *v, const struct store_scene *base);
/* Releases the version's meshes and their array. */
void store_mesh_release_all(struct store_scene *sc);
/* Restores the meshes of scene `id` from <dir>/meshes at start-up (warns and skips files
 * that no longer parse). */
void store_mesh_load_all(struct store *s, const char *id, const char *dir);

#endif
