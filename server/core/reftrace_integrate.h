/*
 * reftrace_integrate.h - internal to the reference tracer (reftrace.c): field sampling
 * and the steppers of the ray equation in object space. Not a public interface;
 * only reftrace*.c include it.
 *
 * The ray equation d/ds (n dx/ds) = grad n (tevs2007 eq. 4.7) is integrated as the
 * first-order system dx/ds = w / n, dw/ds = grad n (eqs. 4.8, 4.9), w = n * direction.
 * Positions, steps and gradients are in object units; sigma_a and L_e are per world
 * unit, so the accumulating integrands carry the object's scale.
 */
#ifndef REFRACT_REFTRACE_INTEGRATE_H
#define REFRACT_REFTRACE_INTEGRATE_H

#include <stdbool.h>

#include "reftrace.h"
#include "vec3.h"

/* Everything the march needs at one object-space point. */
struct reftrace_field {
    double n;      /* refractive index */
    vec3 grad;     /* grad n, per object unit */
    vec3 sigma_a;  /* absorption per world unit (0 for analytic fields) */
    vec3 emission; /* L_e per world unit (0 for analytic fields) */
    vec3 sigma_s;  /* scattering per world unit (0 without a scattering channel) */
    double g;      /* Henyey-Greenstein anisotropy (0 without an anisotropy channel) */
};

/* State of the adaptive stepper: the ray plus the integrals it carries along one
 * step (all zero at the start of a step except p and w). */
struct reftrace_ode {
    vec3 p, w;  /* object space */
    double opl; /* integral of n ds, world units */
    vec3 alpha; /* integral of sigma_t ds, sigma_t = sigma_a + sigma_s (tevs2007 eq. 5.9) */
    vec3 emit;  /* integral of exp(-alpha) L_e / n^2 ds (eq. 5.10's emission term, in basic
                   radiance: the march multiplies by n_amb^2, frisvad2010) */
};

/* Voxel size per axis, (bmax - bmin) / res, object units. */
vec3 reftrace_voxel_size(const struct reftrace_object *o);

/* n and grad n at object-space p, for grids at v = (p - bmin) / vs - 0.5: trilinear of the
 * stored (grad n, n), or (o->ior_filter tricubic) Catmull-Rom of n with the exact gradient
 * of that interpolant; the callback for analytic fields. The other channels are always
 * trilinear. */
double reftrace_sample_ior(const struct reftrace_object *o, vec3 p, vec3 *grad);
void reftrace_sample_field(const struct reftrace_object *o, vec3 p, struct reftrace_field *f);
/* Opaque embedding at p: returns false when the object has no opaque channel. */
bool reftrace_sample_opaque(const struct reftrace_object *o, vec3 p, vec3 *colour,
                            double *coverage);

/* One fixed step of size h (object units) from (p, w), in place. */
void reftrace_step_euler(const struct reftrace_object *o, double h, vec3 *p, vec3 *w);
void reftrace_step_rk4(const struct reftrace_object *o, double h, vec3 *p, vec3 *w);
void reftrace_step_rk2(const struct reftrace_object *o, double h, vec3 *p, vec3 *w);
/* One Bogacki-Shampine 3(2) step (the GLSL twin is ray_equation_step_bs23): the third-order
 * solution in place; returns |e_p| + extent |e_w| / |w| (object units), the embedded error
 * estimate of the position plus the displacement the direction error causes over the
 * object's largest extent. */
double reftrace_step_bs23(const struct reftrace_object *o, double h, double extent, vec3 *p,
                          vec3 *w);

/* One Dormand-Prince 5(4) step of size h from y0 (scale = world units per object unit).
 * Writes the fifth-order solution to y1, and to err the differences between the fifth-
 * and fourth-order solutions: err[0] = |dp| (object units), err[1] = |dw|,
 * err[2] = |d opl| (world units). */
void reftrace_step_dopri(const struct reftrace_object *o, double scale, double h,
                         const struct reftrace_ode *y0, struct reftrace_ode *y1, double err[3]);

#endif
