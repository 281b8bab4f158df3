/*
 * lightsim_gpu_surfaces.h - the light fields' exact surfaces packed for the light
 * simulator's kernels (shared_types.h surface_params, shaders/geom/surface.glsl), the
 * layout server/render/surfaces_gpu.c gives the view renderer from a scene. (The fields
 * hold core/geom surfaces, not the scene's, and this module cannot link the renderer's.)
 * Thread: any (no GL). Include core/geom/geom.h before this header where both are needed
 * (shaders/bindings.h names the kinds as macros).
 */
#ifndef REFRACT_LIGHTSIM_GPU_SURFACES_H
#define REFRACT_LIGHTSIM_GPU_SURFACES_H

#include "../lightsim.h"
#define REFRACT_HOST_C
#include "shared_types.h"
#undef REFRACT_HOST_C

/* New arrays: *records (max(1, surface_count) records), *points (2 floats per lathe
 * profile point, at least 2; *point_count float pairs) and *meshes (*mesh_records >= 1
 * 16-byte records: the fields' meshes' BVH nodes, then triangles, then vertices, as
 * shaders/geom/mesh.glsl reads them with MESH_RT_PACKED; each mesh record's surface_params
 * .mesh says where its own begin). Free all three. false: out of memory. */
bool lightsim_gpu_pack_surfaces(const struct lightsim_fields *f, surface_params **records,
                                float **points, size_t *point_count, void **meshes,
                                size_t *mesh_records);

#endif
