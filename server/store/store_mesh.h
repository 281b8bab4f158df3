/*
 * store_mesh.h - uploaded triangle meshes of a scene (POST /v1/scenes/{id}/meshes), kept
 * in the scene's versions next to its volumes. Persisted like the other uploads: the file
 * as uploaded (OBJ or PLY) is a content-addressed blob <data>/blobs/<aa>/<sha256>, named
 * by an uploads row of kind "mesh" (store.h, "Persistence"); so it counts towards
 * --max-storage-bytes and GET /v1/storage, and its blob goes when no row names it. A mesh
 * is parsed and validated once, at upload (and again from its blob when refractd starts),
 * into a struct mesh with its BVH; every version that has it shares one
 * reference-counted copy.
 *
 * Ownership: store_mesh_put_file's *out is a new reference; release it with
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
    struct store_upload_info info;
};

/* Parses the uploaded file tmp_path, whose SHA-256 is sha256 (format MESH_FORMAT_UNKNOWN:
 * sniffed), under the store's limits (scene_limits.max_mesh_triangles), commits it as a
 * blob and an uploads row, and makes a new version of scene `id` holding it as `name`
 * (replacing a mesh of that name). Consumes tmp_path: it is renamed into the blob store or
 * removed. SCENE_NOT_FOUND, the parse errors (INVALID_MESH, LIMIT_EXCEEDED),
 * LIMIT_EXCEEDED for more than STORE_MAX_MESHES_PER_SCENE meshes, STORAGE (disk, or over
 * --max-storage-bytes), OUT_OF_MEMORY. */
enum refract_code store_mesh_put_file(struct store *s, const char *id, const char *name,
                                      const char *tmp_path, const char *sha256,
                                      enum mesh_format format, struct store_mesh **out,
                                      struct err *e);
void store_mesh_release(struct store_mesh *m);

/* ---- for store.c ---- */

/* The lookup's answer for mesh `name` of version sc, or NULL. */
const struct scene_volume *store_mesh_lookup(const struct store_scene *sc, const char *name);
/* Gives v new references to base's meshes; false on out of memory (v keeps none). */
bool store_mesh_share(struct store_scene *v, const struct store_scene *base);
/* Releases the version's meshes and their array. */
void store_mesh_release_all(struct store_scene *sc);

#endif
