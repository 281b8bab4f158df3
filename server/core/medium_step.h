/*
 * medium_step.h - single scattering along a straight segment through a constant medium
 * (docs/tracing.md "Scattering inside surfaces"): how the segment is cut into steps, and
 * the exact integral of the transmittance over one step. The GLSL twin is
 * shaders/medium_step.glsl (same names); the view renderer's surface legs
 * (shaders/ray_march.glsl march_surface_leg) and the CPU reference (reftrace.c
 * surface_leg) both use it.
 *
 * Along a segment of constant extinction sigma_t = sigma_a + sigma_s (tevs2007 eq. 5.9),
 * tevs2007 eq. 5.4's source term over a step [s_i, s_i + h] is
 *   int_0^h exp(-sigma_t (tau_i + u)) S(s_i + u) du
 *     ~= exp(-sigma_t tau_i) S(s_i + h / 2) medium_step_weight(sigma_t, h),
 * the transmittance integrated exactly and the source S (emission, which is constant, and
 * in-scattering, eq. 5.5, whose irradiance varies) taken at the step's midpoint: exact
 * for the emission, second order in h for the in-scattering.
 */
#ifndef REFRACT_MEDIUM_STEP_H
#define REFRACT_MEDIUM_STEP_H

/* Most steps one segment is cut into (a longer segment takes longer steps). */
#define MEDIUM_MAX_STEPS 1024
/* Steps of a segment where no light has an irradiance volume (step <= 0): direct lights. */
#define MEDIUM_DIRECT_STEPS 64

/* int_0^h exp(-sigma_t u) du = (1 - exp(-sigma_t h)) / sigma_t; h where sigma_t = 0. */
double medium_step_weight(double sigma_t, double h);

/* The number of equal steps a segment of world length t is cut into for the step length
 * `step` (world units; <= 0: MEDIUM_DIRECT_STEPS): ceil(t / step), 1..MEDIUM_MAX_STEPS. */
int medium_step_count(double t, double step);

#endif
