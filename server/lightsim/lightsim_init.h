/*
 * lightsim_init.h - the initial wavefront of a light (docs/lightsim.md "Initial
 * wavefront", tevs2007 sect. 6.2.1) and the run's step budget. Internal to the light
 * simulator (the CPU reference and server/lightsim/gpu).
 */
#ifndef REFRACT_LIGHTSIM_INIT_H
#define REFRACT_LIGHTSIM_INIT_H

#include <stddef.h>

#include "lightsim.h"
#include "lightsim_patch.h"

/* The initial patches aimed at the domain, in the specified order (directional: patch
 * (i, j) at index j N0 + i; point and spot: faces +x, -x, +y, -y, +z, -z, each in that
 * order). *out is a new array (free()); *count may be 0. OUT_OF_MEMORY. */
enum refract_code ls_initial_wavefront(const struct lightsim_fields *f, const struct scene_light *l,
                                       const struct scene_lightsim *set, struct ls_patch **out,
                                       size_t *count, struct err *e);

/* How long a run with time step dt may go (docs/lightsim.md "Termination and progress"):
 * max_steps = ceil(4 n_max rho 2 / dt) + 16 and t_sweep = 2 (rho + voxel) n_max, rho half
 * the grid box's diagonal, n_max the largest index in the fields or ambient_ior. Shared
 * by the CPU reference and the GPU run. */
void ls_step_budget(const struct lightsim_fields *f, double dt, long long *max_steps,
                    double *t_sweep);

#endif
