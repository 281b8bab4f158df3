/*
 * scene_pathtrace.h - a parsed scene as the reference path tracer sees it
 * (core/pathtrace.h, docs/pathtracer.md "From a scene"): its exact surfaces with their
 * constant media, the receiver (a half_size as large as the scene allows is the infinite
 * floor for every practical view), the lights, and the procedural environment times its
 * intensity.
 *
 * What it refuses, with a message that says so: volume objects (voxel fields: GRIN and
 * heterogeneous media are not in the path tracer yet), an image environment, mesh
 * surfaces whose mesh is missing.
 *
 * Ownership: scene_pathtrace_init fills a struct scene_pathtrace that borrows `s` (and the
 * meshes lookup finds) for as long as it is used; it owns nothing itself.
 */
#ifndef REFRACT_SCENE_PATHTRACE_H
#define REFRACT_SCENE_PATHTRACE_H

#include "../core/pathtrace.h"
#include "scene.h"

struct scene_pathtrace {
    struct pathtrace_surface surfaces[SCENE_MAX_SURFACES];
    struct pathtrace_scene scene; /* scene.surfaces points into surfaces[] */
};

/* Fills *out from s. Returns REFRACT_E_OK, or REFRACT_E_CONFLICT with a message naming
 * what the reference mode cannot render yet. *out must not be copied: scene.surfaces
 * points into it. */
enum refract_code scene_pathtrace_init(const struct scene *s, scene_volume_lookup_fn lookup,
                                       void *ctx, struct scene_pathtrace *out, struct err *e);
/* One light as the path tracer sees it: intensity (colour * intensity) I per channel; a
 * point light with radius > 0 becomes the Lambertian sphere of the same far-field intensity
 * (L_e = I / (pi r^2), docs/pathtracer.md "Lights"); cos_spot for spots. scene lights and
 * the render requests' lights (render/photons_gpu.c) both go through it. */
void scene_pathtrace_light(enum scene_light_kind kind, vec3 position, vec3 direction,
                           double cos_spot, const double intensity[3], double radius, bool visible,
                           struct pathtrace_light *p);
/* Scene light l at unit intensity (colour and intensity 1): a light's own photon map,
 * which its colour times intensity scales at render time (docs/photons.md "Emission"). */
void scene_pathtrace_light_unit(const struct scene_light *l, struct pathtrace_light *p);

/* The same without the environment's check (its light is not used: the photon map,
 * docs/photons.md, needs the surfaces, the receiver and the lights only). */
enum refract_code scene_pathtrace_geometry(const struct scene *s, scene_volume_lookup_fn lookup,
                                           void *ctx, struct scene_pathtrace *out, struct err *e);

#endif
