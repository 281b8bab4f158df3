/*
 * lightsim_surfaces.h - the light simulator's view of the scene's exact surfaces
 * (docs/lightsim.md "Surfaces", issue 12 item 4): the copy the fields own, the inside set
 * of a point, the medium's index and the nearest crossing of a straight leg. The event at
 * a crossing is core/interface.h's interface_cross, as in every march.
 *
 * Internal to the CPU reference; the GLSL twins are in shaders/lightsim_surfaces.glsl.
 * Thread: any; pure functions of the fields.
 */
#ifndef REFRACT_LIGHTSIM_SURFACES_H
#define REFRACT_LIGHTSIM_SURFACES_H

#include <stdint.h>

#include "../core/geom/geom.h"
#include "../core/reftrace.h"
#include "lightsim.h"

/* Self-intersection offset of the surface a corner crossed last, relative to the surface's
 * size (the CPU reference march's SURFACE_EPS_SAME); other surfaces from EPS_OTHER on. */
#define LS_SURFACE_EPS_SAME 1e-9
#define LS_SURFACE_EPS_OTHER 1e-13

/* Copies s's surfaces into f (f->surfaces, f->profile_points, and f->meshes: a copy of
 * each mesh surface's mesh, found through lookup). CONFLICT for a mesh not uploaded,
 * INVALID_MESH for one that cannot bound a medium (mesh_rt.h), INVALID_FIELD for a
 * receiver above a mesh's bottom, OUT_OF_MEMORY; f then holds nothing. */
enum refract_code ls_surfaces_build(const struct scene *s, scene_volume_lookup_fn lookup,
                                    void *ctx, struct lightsim_fields *f, struct err *e);
void ls_surfaces_free(struct lightsim_fields *f);

/* The set of surfaces whose solids contain p (bit k: f->surfaces[k]). */
uint32_t ls_surfaces_inside(const struct lightsim_fields *f, vec3 p);

/* n of a medium: the surface's constant index, or for -1 (outside every surface) the
 * field's index at x (the ambient n away from voxel objects). */
double ls_medium_ior(const struct lightsim_fields *f, int medium, vec3 x);

/* The nearest crossing of o + t d (unit d), t in (eps, tmax), over every surface; last is
 * the surface the ray left last (-1: none). Returns the surface index or -1. */
int ls_next_surface(const struct lightsim_fields *f, vec3 o, vec3 d, int last, double tmax,
                    struct geom_hit *hit);

/* The crossing of surface k alone (the prediction of docs/lightsim.md "Surfaces"). */
bool ls_surface_hit(const struct lightsim_fields *f, int k, vec3 o, vec3 d, int last, double tmax,
                    struct geom_hit *hit);

#endif
