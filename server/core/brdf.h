/*
 * brdf.h - the BRDFs f_r of light reflected at boundaries (tevs2007 eq. 5.6/5.8, the
 * delta(x) R L_r term of eq. 5.4), the double twins of brdf_eval in shaders/lighting.glsl
 * (docs/tracing.md "Light"). The kinds are BRDF_* of shaders/bindings.h (equal to
 * enum scene_brdf_kind).
 * Thread: any; pure functions.
 */
#ifndef REFRACT_BRDF_H
#define REFRACT_BRDF_H

#include "vec3.h"

struct brdf_params {
    int kind;        /* BRDF_NONE, BRDF_LAMBERT, BRDF_PHONG, BRDF_GGX */
    double color[3]; /* multiplies every kind */
    double alpha;    /* GGX: alpha = roughness^2 */
    double exponent; /* Phong exponent e */
};

/* f_r for unit v (towards the viewer), l_in (towards the light) and unit normal n on their
 * side; 0 when either is below the surface. Lambert: color / pi. Normalised Phong: color
 * (e + 2) / (2 pi) max(0, reflect(-l_in, n) . v)^e. GGX: color D G / (4 cos_i cos_o) with
 * the Trowbridge-Reitz D = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2) and the separable
 * Smith G = G1(cos_i) G1(cos_o), G1(c) = 2 c / (c + sqrt(alpha^2 + (1 - alpha^2) c^2));
 * no Fresnel factor (the caller's event has its R). Writes rgb to out. */
void brdf_eval(const struct brdf_params *b, vec3 v, vec3 l_in, vec3 n, double out[3]);

/* The GGX normal distribution D(cos_h) alone (for its normalisation test). */
double brdf_ggx_d(double alpha, double cos_h);

#endif
