/*
 * lightsim_gpu_wavefront.h - the GPU run's first patch list: the CPU reference's initial
 * wavefront (ls_initial_wavefront, docs/lightsim.md "Initial wavefront"), so both
 * implementations start from the same patches, converted to the std430 records of the
 * GPU lists with the initial capacity drop applied; and the run constants derived from
 * the fields (rho, n_max).
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
    ls_gpu_patch *patches; /* the kept patches in list order, at most max_patches; owned */
    int count;
    int kept;               /* aimed at the domain (patches_initial), before capacity */
    double flux_in[3];      /* summed P of the kept patches */
    double flux_dropped[3]; /* kept but at list index >= max_patches (culled_capacity) */
    double mean_max_power;  /* mean over the kept patches of max(P) */
};

/* Builds the first list. OUT_OF_MEMORY. */
enum refract_code lightsim_wavefront_build(const struct lightsim_fields *f,
                                           const struct scene_light *l,
                                           const struct scene_lightsim *set,
                                           struct lightsim_wavefront *out, struct err *e);
void lightsim_wavefront_free(struct lightsim_wavefront *w);

#endif
