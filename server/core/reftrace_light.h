/*
 * reftrace_light.h - the light-dependent terms of the reference tracer (tevs2007 eqs.
 * 5.4-5.8; docs/tracing.md "Light"): a light's irradiance E and direction l at a world
 * point, the lights' reflected radiance at a Fresnel event, in-scattering, the receiver.
 * The double twins of shaders/lighting.glsl; used by reftrace.c and its tests.
 * Thread: any; borrows its inputs for the call.
 */
#ifndef REFRACT_REFTRACE_LIGHT_H
#define REFRACT_REFTRACE_LIGHT_H

#include <stdbool.h>

#include "reftrace.h"

/* E (times the light's scale) and the travel direction l at world x; false when the light
 * adds nothing there. Volumes: trilinear at v = (x - bmin) / voxel - 0.5 clamped to
 * [0, dims - 1], E = 0 outside [bmin, bmin + dims voxel]; l = normalised interpolated xyz. */
bool reftrace_light_at(const struct reftrace_light *l, vec3 x, vec3 *E, vec3 *dir);

/* The light's unshadowed direct E (times its scale) and travel direction l at world x,
 * whatever its mode: directional E = 1 along its direction, point and spot 1 / r^2 (the
 * spot inside its cone only); false when it adds nothing. light_direct in lighting.glsl. */
bool reftrace_light_direct(const struct reftrace_light *l, vec3 x, vec3 *E, vec3 *dir);

/* R sum_j f_r(v, -l_j, N) max(0, N . -l_j) E_j(x), v = -d, N turned to face v. */
vec3 reftrace_light_reflected(const struct reftrace_lighting *lt, const struct brdf_params *b,
                              vec3 x, vec3 d, vec3 nrm, double R);

/* sigma_s sum_j p_HG(g, l_j . -d) E_j(x): in-scattered radiance per unit length. */
vec3 reftrace_light_inscatter(const struct reftrace_lighting *lt, vec3 x, vec3 d, vec3 sigma_s,
                              double g);

/* The step of in-scattering along a surface medium's segment (medium_step.h): half the
 * smallest voxel of the lights' irradiance volumes; 0 where none has one (lt NULL too). */
double reftrace_light_inscatter_step(const struct reftrace_lighting *lt);

/* The receiver seen from x along d after the ray left the scene: true with its radiance
 * (albedo / pi) sum_j E_j(hit) max(0, -l_j.y) + albedo env_up, E read on the plane
 * (docs/lightsim.md "Domain": the light grid reaches two voxels below it) from light j's
 * volume at least LIGHT_RECEIVER_INSET voxels inside its grid's x and z faces, else from
 * reftrace_light_direct. */
bool reftrace_light_receiver(const struct reftrace_lighting *lt, vec3 env_up, vec3 x, vec3 d,
                             vec3 *L);

/* The nearest lamp a ray leaving the scene at x along unit d meets before t_max: true with
 * its radiance scale / (pi r^2), the radiance of the path tracer's spherical emitter of the
 * same far-field intensity (docs/pathtracer.md "Lights"). Point lights of radius r > 0
 * only; primary: the ray has met nothing yet, so lamps hidden from the camera are skipped
 * (docs/tracing.md "Lamps"; lighting.glsl's light_emitter is the twin). */
bool reftrace_light_emitter(const struct reftrace_lighting *lt, vec3 x, vec3 d, double t_max,
                            bool primary, vec3 *L);

#endif
