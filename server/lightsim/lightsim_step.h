/*
 * lightsim_step.h - one wavefront time step of one patch (docs/lightsim.md "A time step",
 * tevs2007 eqs. 4.12/4.13 and sect. 6.2): propagate, extinction, interface, opaque,
 * deposit, fate. Internal to the CPU reference.
 */
#ifndef REFRACT_LIGHTSIM_STEP_H
#define REFRACT_LIGHTSIM_STEP_H

#include "lightsim.h"
#include "lightsim_patch.h"

struct ls_step_ctx {
    const struct lightsim_fields *f;
    const struct scene_lightsim *set;
    double dt;           /* time step, world units (step_voxels * voxel) */
    double energy_floor; /* energy_threshold * mean initial max(P) */
    int deposit_every;   /* flux mode: steps per deposit, lightsim_deposit_every */
    vec3 lo, hi;         /* the domain box */
    double reach;        /* its diagonal: how far an event's crossings are predicted */
    double *acc_e;       /* 3 per voxel: flux deposit sum, or max mode's maximum */
    double *acc_d;       /* 3 per voxel: power-weighted direction sum */
    struct lightsim_stats *st;
};

enum ls_fate {
    LS_DIES = 0,   /* its power went to one of the stats' sinks */
    LS_LIVES = 1,  /* *p was updated in place */
    LS_SPLITS = 2, /* child[0..3] replace it */
};

/* One step of p. When a Fresnel event at an exact surface begins in this step
 * (docs/lightsim.md "Surfaces"), *twin is the reflected patch, already stepped, and
 * *twin_fate its fate (LS_DIES or LS_LIVES: a twin does not split in its first step);
 * else *twin_fate is LS_DIES and *twin untouched. Outputs go in the order p's (itself or
 * its children), then the twin. */
enum ls_fate ls_patch_step(const struct ls_step_ctx *c, struct ls_patch *p,
                           struct ls_patch child[4], struct ls_patch *twin,
                           enum ls_fate *twin_fate);

#endif
