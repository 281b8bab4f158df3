/*
 * lightsim_init.h - the initial wavefront of a light (docs/lightsim.md "Initial
 * wavefront", tevs2007 sect. 6.2.1). Internal to the CPU reference.
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

#endif
