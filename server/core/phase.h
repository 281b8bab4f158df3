/*
 * phase.h - the Henyey-Greenstein phase function of in-scattering (tevs2007 eq. 5.5), the
 * double twin of phase_hg in shaders/lighting.glsl (docs/tracing.md "Light").
 * Thread: any; pure functions.
 */
#ifndef REFRACT_PHASE_H
#define REFRACT_PHASE_H

/* p_HG(g, cos_theta) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos_theta)^(3/2)), normalised over
 * the sphere (1 / (4 pi) at g = 0); its mean cosine is g. cos_theta is between the light's
 * travel direction and the scattered direction; g in (-1, 1). */
double phase_hg(double g, double cos_theta);

#endif
