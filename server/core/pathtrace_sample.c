/*
 * pathtrace_sample.c - direction sampling of the path tracer (pathtrace.h): cosine
 * hemisphere (Malley's method), Henyey-Greenstein (pbrt-v3 HenyeyGreenstein::Sample_p,
 * the inverted CDF of cos theta) and a uniform cone (pbrt-v3 UniformSampleCone).
 */
#include <math.h>

#include "pathtrace.h"

/* An orthonormal basis (t, b) about unit n (Duff et al. 2017, "Building an orthonormal
 * basis, revisited"). */
static void basis(vec3 n, vec3 *t, vec3 *b)
{
    double sign = copysign(1.0, n.z);
    double a = -1.0 / (sign + n.z);
    double c = n.x * n.y * a;
    *t = vec3_make(1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x);
    *b = vec3_make(c, sign + n.y * n.y * a, -n.y);
}

static vec3 around(vec3 axis, double cos_t, double phi)
{
    vec3 t, b;
    basis(axis, &t, &b);
    double sin_t = sqrt(fmax(0.0, 1.0 - cos_t * cos_t));
    vec3 v = vec3_scale(axis, cos_t);
    v = vec3_madd(v, t, sin_t * cos(phi));
    v = vec3_madd(v, b, sin_t * sin(phi));
    return vec3_normalize(v);
}

vec3 pathtrace_sample_cosine(vec3 n, struct pathtrace_rng *rng)
{
    double u1 = pathtrace_rng_uniform(rng), u2 = pathtrace_rng_uniform(rng);
    return around(n, sqrt(1.0 - u1), 2.0 * M_PI * u2);
}

vec3 pathtrace_sample_hg(vec3 d, double g, struct pathtrace_rng *rng)
{
    double u1 = pathtrace_rng_uniform(rng), u2 = pathtrace_rng_uniform(rng);
    double cos_t;
    if (fabs(g) < 1e-3) {
        cos_t = 1.0 - 2.0 * u1;
    } else {
        double sq = (1.0 - g * g) / (1.0 + g - 2.0 * g * u1);
        cos_t = (1.0 + g * g - sq * sq) / (2.0 * g);
    }
    cos_t = fmin(1.0, fmax(-1.0, cos_t));
    return around(d, cos_t, 2.0 * M_PI * u2);
}

vec3 pathtrace_sample_cone(vec3 axis, double cos_max, struct pathtrace_rng *rng)
{
    double u1 = pathtrace_rng_uniform(rng), u2 = pathtrace_rng_uniform(rng);
    double cos_t = 1.0 - u1 * (1.0 - cos_max);
    return around(axis, cos_t, 2.0 * M_PI * u2);
}
