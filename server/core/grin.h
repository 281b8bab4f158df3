/*
 * grin.h - analytic gradient-index (GRIN) refractive-index profiles, double precision.
 *
 * These are the exact continuous fields: the scene module samples them into voxels,
 * and the reference tracer integrates through them directly (no voxels) to measure
 * the error of the voxelised GPU path. Definitions (r = |x - center|, R = radius),
 * fixed by the project's foundation issue:
 *   luneburg         n = sqrt(2 - (r/R)^2) for r <= R, 1 outside
 *   maxwell_fisheye  n = n0 / (1 + (r/R)^2) for r <= R, n0/2 outside (n0 default 2)
 *   linear           n = n0 + gradient . (x - center)  (everywhere)
 *   gaussian         n = n_out + (n_peak - n_out) exp(-r^2 / (2 sigma^2))  (everywhere)
 * Positions are in the object space of the object that holds the profile.
 */
#ifndef REFRACT_GRIN_H
#define REFRACT_GRIN_H

#include "vec3.h"

enum grin_kind {
    GRIN_LUNEBURG = 0,
    GRIN_MAXWELL_FISHEYE = 1,
    GRIN_LINEAR = 2,
    GRIN_GAUSSIAN = 3,
};

struct grin_profile {
    enum grin_kind kind;
    vec3 center;
    double radius;   /* luneburg, maxwell_fisheye: R > 0 */
    double n0;       /* maxwell_fisheye (default 2), linear (default 1) */
    vec3 gradient;   /* linear: dn/dx per object-space unit */
    double n_peak;   /* gaussian */
    double n_out;    /* gaussian */
    double sigma;    /* gaussian: standard deviation in object-space units, > 0 */
};

/* Returns n at p and, when grad is not NULL, the exact gradient of n at p (the
 * one-sided limit from inside at r = R, where luneburg and maxwell_fisheye have a
 * kink). Pure; thread-safe. */
double grin_ior(const struct grin_profile *g, vec3 p, vec3 *grad);

/* "luneburg" ... "gaussian" <-> enum; grin_kind_parse returns -1 when unknown. */
const char *grin_kind_name(enum grin_kind k);
int grin_kind_parse(const char *name);

#endif
