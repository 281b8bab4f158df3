/*
 * lightsim_corner.h - one patch corner's move over a time step among exact surfaces
 * (docs/lightsim.md "Surfaces"; issue 12 item 4): straight legs at speed 1/n in the
 * constant media the surfaces bound, the ray equation (tevs2007 eqs. 4.12/4.13) in the
 * voxel field outside them, and at each crossing the one Snell/Fresnel/TIR event of
 * core/interface.h (frisvad2010). Internal to the CPU reference; the GLSL twin is in
 * shaders/lightsim_corner.glsl.
 */
#ifndef REFRACT_LIGHTSIM_CORNER_H
#define REFRACT_LIGHTSIM_CORNER_H

#include "lightsim_step.h"

/* Legs of one corner in one step, at most (crossings beyond are left for the next step). */
#define LS_MAX_LEGS 8
/* |n_i - n_t| at or below this: index-matched, the corner passes unchanged (reftrace's
 * INDEX_EPS). */
#define LS_INDEX_EPS 1e-6

/* What the corner moves of one step report to the patch step. */
struct ls_spawn {
    bool spawned;  /* a Fresnel event began: the reflected twin is to be made */
    int surface;   /* its surface */
    int mask;      /* the corners that cross it (bit k: corner k) */
    double R_mean; /* the twin's share of the power: sum of the corners' R / 4 */
    double P[3];   /* the patch's power when the event began (before the split) */
};

/* The explicit midpoint step of the ray equation over time dt (docs/lightsim.md step 1). */
void ls_propagate(const struct lightsim_fields *f, double dt, vec3 *x, vec3 *w);

/* Moves corner k of p by the step's time c->dt. Without surfaces exactly ls_propagate.
 * With them: crossings toggle the corner's inside set and begin (may_spawn, no event
 * pending, none begun this step: *sp is filled and p's power scaled by 1 - R_mean),
 * continue (a pending corner: refracts, or reflects in a twin) or fall outside an event
 * (refracts independently, R / 4 of the power to flux_reflected). tau[3] gains the
 * corner's optical depth through the surfaces' media. */
void ls_corner_move(const struct ls_step_ctx *c, struct ls_patch *p, int k, bool may_spawn,
                    struct ls_spawn *sp, double tau[3]);

#endif
