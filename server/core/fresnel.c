/*
 * fresnel.c - unpolarised Fresnel reflectance and the vector form of Snell's law, in
 * double precision, exactly as docs/tracing.md "Fresnel and Snell" writes them.
 *
 * This is the reference twin of shaders/fresnel.glsl: same names, same argument order,
 * same branch on total internal reflection. It deliberately handles only real indices
 * (no absorbing metals; frisvad2010 notes the equations also hold for complex n).
 */
#include "fresnel.h"

#include <math.h>

double fresnel_unpolarized(double cos_i, double n_i, double n_t)
{
    /* cos_i is documented to lie in [0, 1]; clamping keeps a direction that is off by
     * rounding (|cos| a few ulp above 1) from producing a negative sin^2. */
    cos_i = fmin(fabs(cos_i), 1.0);
    double eta = n_i / n_t;
    /* Law of refraction, n_i sin_i = n_t sin_t (frisvad2010, "The laws of reflection
     * and refraction"). */
    double sin_t2 = eta * eta * (1.0 - cos_i * cos_i);
    if (sin_t2 >= 1.0)
        return 1.0; /* total internal reflection */
    double cos_t = sqrt(1.0 - sin_t2);
    /* frisvad2010, "The Fresnel equations for reflection": amplitude ratios r_perp and
     * r_par, reflectances R = |r|^2, unpolarised R = (R_perp + R_par) / 2. */
    double r_perp = (n_i * cos_i - n_t * cos_t) / (n_i * cos_i + n_t * cos_t);
    double r_par = (n_t * cos_i - n_i * cos_t) / (n_t * cos_i + n_i * cos_t);
    return 0.5 * (r_perp * r_perp + r_par * r_par);
}

bool snell_refract(vec3 d, vec3 nrm, double n_i, double n_t, vec3 *t)
{
    /* Orient the normal towards the incident side, so c = cos_i >= 0. */
    double c = -vec3_dot(d, nrm);
    if (c < 0.0) {
        nrm = vec3_scale(nrm, -1.0);
        c = -c;
    }
    double eta = n_i / n_t;
    double k = 1.0 - eta * eta * (1.0 - c * c); /* cos_t^2 */
    /* Same test as fresnel_unpolarized (sin_t^2 >= 1), so the two never disagree on
     * whether a ray is totally reflected. */
    if (k <= 0.0)
        return false;
    /* frisvad2010's w_t = eta((w'.n) n - w') - n sqrt(1 - eta^2 (1 - (w'.n)^2)) with
     * w' = -d: t = eta d + (eta c - sqrt(k)) N. It is unit length analytically; the
     * normalisation only removes rounding. */
    *t = vec3_normalize(vec3_add(vec3_scale(d, eta), vec3_scale(nrm, eta * c - sqrt(k))));
    return true;
}

double fresnel_brewster_angle(double n_i, double n_t)
{
    return atan(n_t / n_i);
}

double fresnel_critical_angle(double n_i, double n_t)
{
    if (n_t >= n_i)
        return NAN;
    return asin(n_t / n_i);
}
