/*
 * interface.h - the one interface event and the medium stack (docs/tracing.md
 * "Surfaces"). Every march calls these: the view renderer and the tracer on the GPU
 * (shaders/interface.glsl, the same names), the CPU reference (reftrace.c).
 *
 * Event (frisvad2010, "The Fresnel equations for reflection", "The law of refraction"):
 * a ray with unit direction d meets a surface with unit normal N (either orientation)
 * going from index n_i to n_t. R is the unpolarised Fresnel reflectance
 * (R_perp + R_par) / 2; under total internal reflection R = 1 and there is no
 * transmitted direction.
 *
 * Media by nesting priority: surfaces are numbered by priority, 0 the highest. A ray
 * carries the set of surfaces whose solids it is inside (bit k for surface k); the medium
 * it travels in is that of the highest-priority surface of the set, the scene's ambient
 * medium when the set is empty. Crossing surface k toggles bit k; when the medium does not
 * change (k lies inside a higher-priority solid) nothing happens there. This is the rule of
 * production renderers' nested dielectrics (Schmidt and Budge 2002): wine whose solid
 * overlaps the glass wall, the glass having the higher priority, meets the glass exactly at
 * the glass's inner surface.
 */
#ifndef REFRACT_INTERFACE_H
#define REFRACT_INTERFACE_H

#include <stdbool.h>
#include <stdint.h>

#include "vec3.h"

/* Surfaces a ray can be inside at once: the bits of the set. */
#define INTERFACE_MAX_SURFACES 32

struct interface_event {
    double R;       /* unpolarised Fresnel reflectance; 1 under total internal reflection */
    bool tir;       /* total internal reflection: no refracted ray */
    vec3 reflected; /* mirror direction of d about N */
    vec3 refracted; /* Snell's law (unit); = reflected under total internal reflection */
};

/* The event of d (unit) at a surface of normal N (unit, either orientation) from n_i to
 * n_t. */
struct interface_event interface_cross(vec3 d, vec3 N, double n_i, double n_t);

/* The medium of a set: the highest-priority surface in it (its lowest set bit), or -1 for
 * the ambient medium. */
int interface_medium(uint32_t inside);

#endif
