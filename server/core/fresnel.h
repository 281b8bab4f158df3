/*
 * fresnel.h - Fresnel reflectance and Snell refraction, double precision.
 *
 * The GLSL twins live in shaders/fresnel.glsl with the same names and argument order.
 * Directions are unit vectors along propagation. Source: frisvad2010, "The Fresnel
 * equations for reflection" and "The law of refraction"; docs/tracing.md.
 */
#ifndef REFRACT_FRESNEL_H
#define REFRACT_FRESNEL_H

#include <stdbool.h>

#include "vec3.h"

/* Unpolarised reflectance R = (R_perp + R_par) / 2 for light going from index n_i to
 * n_t with cos_i = cos(angle of incidence) in [0, 1]. Returns 1 under total internal
 * reflection. */
double fresnel_unpolarized(double cos_i, double n_i, double n_t);

/* Refracts unit direction d at a surface with unit normal nrm (either orientation; it
 * is flipped to face the incident side). Returns false under total internal reflection
 * (and leaves *t untouched), else writes the unit transmitted direction. */
bool snell_refract(vec3 d, vec3 nrm, double n_i, double n_t, vec3 *t);

/* Brewster's angle atan(n_t / n_i) in radians, where R_par = 0. */
double fresnel_brewster_angle(double n_i, double n_t);
/* Critical angle asin(n_t / n_i) in radians; returns NAN when n_t >= n_i. */
double fresnel_critical_angle(double n_i, double n_t);

#endif
