/*
 * lightsim_sample.h - sampling the simulator's fields at a world point (docs/lightsim.md
 * "Fields", last paragraph): trilinear in light-grid voxel coordinates, clamp to edge,
 * ambient outside the grid box. Internal to the CPU reference.
 */
#ifndef REFRACT_LIGHTSIM_SAMPLE_H
#define REFRACT_LIGHTSIM_SAMPLE_H

#include "lightsim.h"

struct ls_sample {
    double n;
    vec3 grad;       /* grad n, world units */
    double sigma[3]; /* sigma_t per world unit */
    double coverage; /* opaque */
};

/* n and grad n only (the ray equation's right-hand side). */
void ls_sample_ior(const struct lightsim_fields *f, vec3 x, double *n, vec3 *grad);
/* Everything. */
void ls_sample_all(const struct lightsim_fields *f, vec3 x, struct ls_sample *out);

/* The light grid's box [bmin, bmin + dims * voxel]. */
void ls_grid_box(const struct light_grid *g, vec3 *lo, vec3 *hi);

#endif
