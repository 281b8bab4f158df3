/*
 * lightsim_patch.h - the wavefront patch of docs/lightsim.md "Patches" and the geometry
 * shared by the initial wavefront, the time step and the split (tevs2007 sect. 4.2.3,
 * fig. 4.3): derived quantities, the four children, and the half-line/box test.
 *
 * Internal to the CPU reference (server/lightsim); the GLSL twin is
 * shaders/lightsim_patches.glsl. Thread: any; pure functions.
 */
#ifndef REFRACT_LIGHTSIM_PATCH_H
#define REFRACT_LIGHTSIM_PATCH_H

#include <stdbool.h>
#include <stdint.h>

#include "../core/vec3.h"

/* Corners p00, p10, p11, p01 in that order round the quad. */
struct ls_patch {
    vec3 x[4];    /* positions, world units */
    vec3 w[4];    /* ray vectors w = n d (tevs2007 eq. 4.8) */
    double P[3];  /* power, RGB */
    int level;    /* how often it was split */
    bool in_zone; /* interface-zone state (docs/lightsim.md step 3) */
    bool crossed;
    double n_lo, n_hi;
    /* Pending flux deposit (docs/lightsim.md step 5): sum of P ds over the last
     * pend_steps steps, which started at pend_from. */
    double pend[3];
    vec3 pend_from;
    int pend_steps;
    /* Exact surfaces (docs/lightsim.md "Surfaces"): each corner's inside set
     * (core/interface.h) and the surface it crossed last (-1: none), and the patch's
     * pending Fresnel event: the surface ev_surface (-1: none), the corners that have not
     * crossed it yet (ev_mask, bit k for corner k), and whether this patch is the event's
     * reflected twin (its pending corners reflect there) or the transmitted one. */
    uint32_t inside[4];
    int last[4];
    int ev_surface;
    int ev_mask;
    bool ev_reflect;
};

/* What each step derives from the corners (docs/lightsim.md "Patches"). */
struct ls_derived {
    vec3 c;       /* centre: mean of the corners */
    vec3 d;       /* unit direction: normalize(sum of w) */
    vec3 D;       /* (x11 - x00) x (x01 - x10) */
    double area;  /* |D| / 2 */
    double e_max; /* longest edge */
};

void ls_patch_derive(const struct ls_patch *p, struct ls_derived *out);

/* Orientation sign(dot(D, d)) > 0 (positive at the start). */
bool ls_patch_oriented(const struct ls_derived *g);

/* The four children of a split (docs/lightsim.md "Children of a split"), in order, each
 * level + 1 with the parent's zone state and power shared by area. A new corner's inside
 * set is the parent's when its four corners agree, else inside(x) at the new corner, by
 * the caller's function (NULL: the set of the parent corner it was made next to). */
typedef uint32_t (*ls_inside_fn)(const void *ctx, vec3 p);
void ls_patch_split(const struct ls_patch *p, ls_inside_fn inside, const void *ctx,
                    struct ls_patch child[4]);

/* Whether the closed box [lo, hi] contains p. */
bool ls_box_contains(vec3 lo, vec3 hi, vec3 p);

/* Whether the half-line o + t d, t >= 0, meets the closed box [lo, hi] (slab test; an
 * axis with d = 0 meets only when o lies within that slab). */
bool ls_halfline_meets_box(vec3 o, vec3 d, vec3 lo, vec3 hi);

#endif
