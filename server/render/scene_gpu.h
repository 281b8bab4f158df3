/*
 * scene_gpu.h - one scene's data on the GPU: the channel atlases and the environment
 * map, built from a struct scene (internal to render/).
 *
 * Layout: all objects of a scene share one 3D texture per channel ("atlas"); object i
 * occupies the box [0, res_i) x [0, res_i) x [z_i, z_i + res_i.z) with z_i the sum of the
 * depths before it. Channels no object uses are not allocated (a 1x1x1 texture stands in).
 *
 * Ownership: scene_gpu owns its textures (this module creates and destroys them).
 * Thread: GPU thread.
 */
#ifndef REFRACT_SCENE_GPU_H
#define REFRACT_SCENE_GPU_H

#include <stdbool.h>

#include "../gpu/queue.h"
#include "../gpu/resources.h"
#include "bindings.h"
#include "render.h"

struct scene_gpu_object {
    int atlas_z;    /* first z slice of this object in the atlases */
    unsigned flags; /* OBJECT_HAS_* */
    int cells[3];   /* macro cells per axis of its empty-space map */
    int first_cell; /* its first cell in skip_cells */
};

struct photon_grid; /* core/photon.h */

struct scene_gpu {
    char id[64];
    uint64_t generation;
    struct gpu_volume ior_grad;         /* RGBA32F (RGBA16F: render.ior_texture float16): grad n
                                           (object units), n */
    struct gpu_volume attenuation;      /* RGBA16F or 1x1x1 stand-in */
    struct gpu_volume emission;         /* RGBA16F or stand-in */
    struct gpu_volume opaque;           /* RGBA16F or stand-in */
    struct gpu_volume scattering;       /* RGBA16F: sigma_s rgb per world unit, g; or stand-in (only
                                           built when some object scatters: OBJECT_HAS_SCATTERING) */
    struct gpu_volume environment;      /* RGBA32F 2D, or 1x1 stand-in */
    struct gpu_buffer skip_cells;       /* uint per macro cell, 1 = empty (docs/tracing.md "Empty
                                           space"); built on the CPU from the atlases' data */
    int skip_cell_voxels;               /* macro cell edge, voxels */
    int skip_border;                    /* texels of sampling footprint the map allowed for
                                           (MACROCELL_BORDER_*: the scene's index filter) */
    size_t empty_cells;                 /* over all objects: 0 means no skipping to do */
    struct gpu_buffer surfaces;         /* surface_params per exact surface, by priority */
    struct gpu_buffer surface_profiles; /* the lathes' (r, h) points */
    struct gpu_buffer mesh_nodes;       /* the mesh surfaces' hierarchies, concatenated */
    struct gpu_buffer mesh_tris;        /* ... their triangles (mesh_rt.h records) */
    struct gpu_buffer mesh_verts;       /* ... their vertices and shading normals */
    size_t surface_count;
    bool surfaces_scatter; /* some surface's constant medium has sigma_s > 0: the kernel's
                              MARCH_SCATTERING variant (docs/tracing.md "Scattering inside
                              surfaces") */
    int atlas_size[3];
    size_t object_count;
    struct scene_gpu_object objects[MAX_OBJECTS];
    size_t bytes;
    double build_ms;
    int64_t last_used_ms;
    /* The receiver's photon maps (receiver.caustics "photons", photons_gpu.c), one per light
     * at unit intensity, one after another in two buffers: the irradiance cache's maps
     * (render_view_request.photons_cached), or those traced here for requests without the
     * cache (photon_own, kept while their keys hold). photon_key mixes the keys of the
     * maps in the buffers. */
    struct gpu_buffer photons;     /* vec4 E per lattice hash slot (photon_grid.E); 0: none yet */
    struct gpu_buffer photon_keys; /* ivec2 per slot (photon_grid.keys) */
    uint64_t photon_key;
    int photon_maps;                             /* lights whose maps are in the buffers */
    float photon_grid[SCENE_MAX_LIGHTS][4];      /* march_lights.photon_grid[j] */
    int32_t photon_dims[SCENE_MAX_LIGHTS][4];    /* march_lights.photon_dims[j] */
    struct photon_grid *photon_own[SCENE_MAX_LIGHTS]; /* maps traced here (NULL: none) */
    uint64_t photon_own_key[SCENE_MAX_LIGHTS];
};

/* photons_gpu.c: makes sure sg's buffers hold the photon map of each of req's lights (a
 * no-op unless the scene's receiver.caustics is "photons"): the lights' own maps when
 * req->photons_cached, else maps traced now (on the GPU when trace_on_gpu and the scene has
 * no mesh surface, else on CPU threads); binds them and fills the lights block's photon
 * fields (count.z, photon_grid, photon_dims). CONFLICT from the photon tracer (docs/photons.md
 * "Not yet"), OUT_OF_MEMORY, or GPU errors. GPU thread. */
struct march_lights;
struct render_view_request;
enum refract_code photons_gpu_prepare(struct scene_gpu *sg, const struct render_scene_source *src,
                                      const struct render_view_request *req, bool trace_on_gpu,
                                      struct march_lights *ml, struct err *e);
/* Frees the maps photons_gpu_prepare traced itself (scene_gpu_destroy). */
void photons_gpu_free(struct scene_gpu *sg);

/* Builds a new scene_gpu from src. Returns it (destroy with scene_gpu_destroy) or NULL with
 * e filled (CONFLICT for a missing volume or environment, LIMIT_EXCEEDED for atlases
 * beyond GL_MAX_3D_TEXTURE_SIZE, GPU_OUT_OF_MEMORY from the driver, or before anything
 * is allocated when the textures would need more than max_bytes; 0 = no cap). */
struct scene_gpu *scene_gpu_build(struct gpu *gpu, const struct render_scene_source *src,
                                  size_t max_bytes, struct err *e);
/* The same with a macro cell edge of skip_cell_voxels (0: MACROCELL_DEFAULT_CELL). */
struct scene_gpu *scene_gpu_build_cells(struct gpu *gpu, const struct render_scene_source *src,
                                        size_t max_bytes, int skip_cell_voxels, struct err *e);
void scene_gpu_destroy(struct scene_gpu *sg);

/* surfaces_gpu.c: packs src's surfaces (shared_types.h surface_params), the lathes'
 * profile points and the mesh surfaces' arrays (mesh_rt.h) into sg's storage buffers (a
 * stand-in element where empty). CONFLICT for a mesh that was not uploaded,
 * INVALID_MESH for one that cannot bound a medium (open, non-manifold, ...). */
enum refract_code surfaces_gpu_build(const struct render_scene_source *src, struct scene_gpu *sg,
                                     struct err *e);

#endif
