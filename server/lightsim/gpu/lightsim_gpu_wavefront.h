/*
 * lightsim_gpu_wavefront.h - the initial wavefront of a light (docs/lightsim.md "Initial
 * wavefront", tevs2007 sect. 6.2.1), built on the host in double precision and uploaded as
 * the GPU's first patch list, plus the run constants derived from the fields (max_steps,
 * t_sweep).
 *
 * Thread: any (no GL). Ownership: lightsim_wavefront_free releases the patch array.
 */
#ifndef REFRACT_LIGHTSIM_GPU_WAVEFRONT_H
#define REFRACT_LIGHTSIM_GPU_WAVEFRONT_H

#define REFRACT_HOST_C
#include "shared_types.h"
#undef REFRACT_HOST_C

#include "../lightsim.h"

struct lightsim_wavefront {
    ls_patch *patches;     /* the kept patches in list order, at most max_patches; owned */
    int count;
    int kept;              /* aimed at the domain (patches_initial), before capacity */
    double flux_in[3];     /* summed P of the kept patches */
    double flux_dropped[3]; /* kept but beyond max_patches (culled_capacity) */
    double mean_max_power; /* mean over the kept patches of max(P) */
};

/* Trilinear (grad n, n) of the fields at world point x, or (0, 0, 0, ambient n) outside
 * the grid box (docs/lightsim.md "Fields", sampling). */
void lightsim_fields_sample_ior(const struct lightsim_fields *f, vec3 x, double out[4]);

/* Builds the initial wavefront. OUT_OF_MEMORY. */
enum refract_code lightsim_wavefront_build(const struct lightsim_fields *f,
                                           const struct scene_light *l,
                                           const struct scene_lightsim *set,
                                           struct lightsim_wavefront *out, struct err *e);
void lightsim_wavefront_free(struct lightsim_wavefront *w);

/* Half the diagonal of the grid box (rho), its centre C, and the largest n of the fields
 * and the ambient index (n_max). */
double lightsim_grid_rho(const struct light_grid *g, vec3 *centre);
double lightsim_fields_n_max(const struct lightsim_fields *f);

#endif
