/*
 * optics_exact.h - closed-form ray paths that serve as references where no stepper is
 * needed: the transmitted ray through a homogeneous sphere (Snell's law at both
 * surfaces), the exact reference for the "smoothed sharp sphere" cases of docs/accuracy.md.
 *
 * Pure functions, double precision, any thread.
 */
#ifndef REFRACT_OPTICS_EXACT_H
#define REFRACT_OPTICS_EXACT_H

#include <stdbool.h>

#include "vec3.h"

/* The ray o + t d (unit d) in a medium of index n_out meets a homogeneous sphere
 * (centre, radius, index n_sphere): refracts in, crosses the chord, refracts out
 * (Fresnel reflections are not followed). Writes the exit point on the sphere and the
 * unit exit direction; returns false when the ray misses the sphere (or only touches
 * it), leaving the outputs alone. Total internal reflection cannot happen on the way
 * out of a sphere: the exit angle equals the refracted entry angle. */
bool optics_sphere_transmit(vec3 center, double radius, double n_sphere, double n_out, vec3 o,
                            vec3 d, vec3 *exit_point, vec3 *exit_dir);

#endif
