/*
 * hard_checks.h - what the hard-case tests share (tests/unit/test_hard_*.c on the CPU
 * reference, tests/gpu/test_hard_*.c on the GPU against it): the scenes parsed from JSON,
 * their voxel reference (scene_reference.h), and the invariants every traced ray must keep
 * whatever the input: finite numbers, transmittance in [0, 1], radiance no brighter than
 * what lights it, termination within the step budget with a documented status
 * (docs/tracing.md "Hard cases"). Header-only (static inline); not a test itself (the test
 * glob is test_*.c).
 */
#ifndef REFRACT_TEST_HARD_CHECKS_H
#define REFRACT_TEST_HARD_CHECKS_H

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "core/reftrace.h"
#include "scene/scene.h"
#include "scene/scene_reference.h"
#include "test.h"

/* Rounding slack of the energy bounds: double sums of a few hundred Fresnel factors. */
#define HARD_ENERGY_EPS 1e-9
/* The procedural environment's brightest channel (docs/tracing.md "Environment": the
 * horizon's blue, 1.0; the ground's light squares are 0.80): radiance gathered from it
 * with weights that sum to at most 1 cannot exceed this times environment.intensity. */
#define HARD_ENV_MAX 1.0

/* One ray's outcome in the form both sides share (reftrace_result, render_trace_hit). */
struct hard_hit {
    int status;
    double origin[3], direction[3], transmittance[3];
    double optical_path_length;
    int steps;
};

static inline struct hard_hit hard_from_ref(const struct reftrace_result *r)
{
    return (struct hard_hit){
        .status = (int)r->status,
        .origin = {r->exit_origin.x, r->exit_origin.y, r->exit_origin.z},
        .direction = {r->exit_direction.x, r->exit_direction.y, r->exit_direction.z},
        .transmittance = {r->transmittance.x, r->transmittance.y, r->transmittance.z},
        .optical_path_length = r->optical_path_length,
        .steps = r->steps};
}

static inline bool hard_finite3(const double v[3])
{
    return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

static inline bool hard_status_known(int status)
{
    return status == RAY_EXITED || status == RAY_ABSORBED || status == RAY_MAX_STEPS ||
           status == RAY_MISSED;
}

/* The invariants of one ray: finite, unit exit direction, 0 <= T <= 1 (+ tol), OPL >= 0,
 * steps within the budget, a known status, and max_steps only when the budget is spent
 * (or the object-entry cap, with fewer steps: allow_pass_cap). `tol` covers float
 * arithmetic on the GPU (1e-9 for the reference). */
static inline void hard_check_hit(const char *what, int ray, const struct hard_hit *h,
                                  int max_steps, double tol, bool allow_pass_cap)
{
    CHECK_MSG(hard_status_known(h->status), "%s ray %d: status %d", what, ray, h->status);
    CHECK_MSG(hard_finite3(h->origin) && hard_finite3(h->direction) &&
                  hard_finite3(h->transmittance) && isfinite(h->optical_path_length),
              "%s ray %d: non-finite output (origin %g %g %g, dir %g %g %g, T %g %g %g, opl %g)",
              what, ray, h->origin[0], h->origin[1], h->origin[2], h->direction[0], h->direction[1],
              h->direction[2], h->transmittance[0], h->transmittance[1], h->transmittance[2],
              h->optical_path_length);
    double len = sqrt(h->direction[0] * h->direction[0] + h->direction[1] * h->direction[1] +
                      h->direction[2] * h->direction[2]);
    CHECK_MSG(fabs(len - 1.0) <= fmax(tol, 1e-9) * 10.0, "%s ray %d: |exit_direction| = %.9g", what,
              ray, len);
    for (int c = 0; c < 3; c++)
        CHECK_MSG(h->transmittance[c] >= 0.0 && h->transmittance[c] <= 1.0 + tol,
                  "%s ray %d: transmittance[%d] = %.9g", what, ray, c, h->transmittance[c]);
    CHECK_MSG(h->optical_path_length >= 0.0, "%s ray %d: opl %g", what, ray,
              h->optical_path_length);
    CHECK_MSG(h->steps >= 0 && h->steps <= max_steps, "%s ray %d: %d steps, budget %d", what, ray,
              h->steps, max_steps);
    if (h->status == RAY_MAX_STEPS && !allow_pass_cap)
        CHECK_MSG(h->steps == max_steps, "%s ray %d: max_steps after %d of %d steps", what, ray,
                  h->steps, max_steps);
    if (h->steps == max_steps && max_steps > 0 && h->status != RAY_MAX_STEPS)
        /* A ray that ends exactly on its last step may still exit or be absorbed. */
        CHECK_MSG(h->status == RAY_EXITED || h->status == RAY_ABSORBED,
                  "%s ray %d: spent its budget with status %d", what, ray, h->status);
}

/* Radiance of a scene without lights or emission: finite, >= 0 and at most the brightest
 * environment radiance (the gathered weights R and T_f exp(-alpha) sum to <= 1; an
 * opaque embedding's colour is <= 1 too). */
static inline void hard_check_radiance(const char *what, int pixel, const double L[3],
                                       double env_intensity, double tol)
{
    double bound = HARD_ENV_MAX * env_intensity * (1.0 + tol) + tol;
    CHECK_MSG(hard_finite3(L), "%s pixel %d: radiance %g %g %g", what, pixel, L[0], L[1], L[2]);
    for (int c = 0; c < 3; c++)
        CHECK_MSG(L[c] >= -tol && L[c] <= bound, "%s pixel %d: radiance[%d] = %.9g (bound %g)",
                  what, pixel, c, L[c], bound);
}

/* Parses a scene that must be valid (default limits); NULL (and a failed check) if not. */
static inline struct scene *hard_scene(const char *json)
{
    struct scene *s = NULL;
    struct err e = {0};
    struct scene_limits lim = scene_limits_default();
    enum refract_code rc = scene_parse(json, strlen(json), &lim, &s, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "%s\n  -> %s", json, e.msg);
    return rc == REFRACT_E_OK ? s : NULL;
}

/* The voxel reference of s (the GPU's own fields in double precision). */
static inline bool hard_reference(const struct scene *s, struct scene_reference *ref)
{
    struct err e = {0};
    enum refract_code rc = scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, ref, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "scene_reference_build: %s", e.msg);
    return rc == REFRACT_E_OK;
}

/* ---- the hard scenes, shared by the CPU and the GPU tests --------------------------- */

/* A glass block n = 1.5 that fills its bounds (exact faces, no field interfaces). */
#define HARD_BLOCK                                                                                 \
    "{\"render\": {\"max_steps\": 400}, \"objects\": [{\"bounds\": {\"min\": [-0.5, -0.5, "        \
    "-0.5], \"max\": [0.5, 0.5, 0.5]}, \"resolution\": 8, \"ior\": 1.5}]}"
/* A glass rod 4 long and 0.2 across: a light pipe (total internal reflection at its sides). */
#define HARD_ROD                                                                                   \
    "{\"objects\": [{\"bounds\": {\"min\": [-2, -0.1, -0.1], \"max\": [2, 0.1, 0.1]}, "            \
    "\"resolution\": [40, 4, 4], \"ior\": 1.5}]}"
/* A glass sphere in a field (smoothed interface) for rays that graze its rim. */
#define HARD_SPHERE(n)                                                                             \
    "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": "    \
    "24, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": " n "}}]}"
/* A slab 1 -> 3 -> 1 inside the field, 1 thick (16 voxels), filling the bounds sideways. */
#define HARD_JUMP3                                                                                 \
    "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": "    \
    "32, \"ior\": {\"shape\": \"box\", \"size\": [4, 4, 1], \"inside\": 3}}]}"
/* A spherical glass shell between radii `inner` and `outer` (object units; the voxel is
 * 2/24 = 0.0833). */
#define HARD_SHELL(outer, inner)                                                                   \
    "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": "    \
    "24, \"ior\": [{\"shape\": \"sphere\", \"radius\": " outer ", \"inside\": 1.5}, "              \
    "{\"shape\": \"sphere\", \"radius\": " inner ", \"inside\": 1}]}]}"
/* A linear GRIN n = 1 + 1.9 (y + 1): from 1 to 4.8 over two units, 0.24 per voxel at 16^3
 * (twelve times the boundary threshold). */
#define HARD_STEEP                                                                                 \
    "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": "    \
    "16, \"smoothing_sigma\": 0, \"ior\": {\"profile\": \"linear\", \"center\": [0, -1, 0], "      \
    "\"n0\": 1, \"gradient\": "                                                                    \
    "[0, 1.9, 0]}}]}"
/* An unsmoothed sphere: the index jumps 1 -> 2 between neighbouring voxels. */
#define HARD_STEP_SPHERE                                                                           \
    "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": "    \
    "16, \"smoothing_sigma\": 0, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.7, \"inside\": "   \
    "2}}]}"
/* A glass block n = 1.5 filling its bounds with a constant attenuation `sigma` per world
 * unit (0, 2 and the scene's largest, 1e5, in the tests). */
#define HARD_ABSORBER(sigma)                                                                       \
    "{\"objects\": [{\"bounds\": {\"min\": [-0.5, -0.5, -0.5], \"max\": [0.5, 0.5, 0.5]}, "        \
    "\"resolution\": 8, \"ior\": 1.5, \"attenuation\": " sigma "}]}"
/* Two index-1 slabs in an ambient index 2 facing each other across a gap 0.01 wide: a ray
 * in the gap reflects totally off one face, then the other, ~200 times without a step. */
#define HARD_MIRRORS                                                                               \
    "{\"ambient_ior\": 2, \"objects\": [{\"bounds\": {\"min\": [-1, 0.005, -1], \"max\": [1, "     \
    "0.5, 1]}, \"resolution\": 4, \"ior\": 1}, {\"bounds\": {\"min\": [-1, -0.5, -1], \"max\": "   \
    "[1, -0.005, 1]}, \"resolution\": 4, \"ior\": 1}]}"

#endif
