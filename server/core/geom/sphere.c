/*
 * sphere.c - the exact sphere (geom.h). Twin: shaders/geom/sphere.glsl.
 *
 * The roots of |o + t d - c|^2 = r^2 are taken in the form that keeps precision for rays
 * that start on the surface or pass far from the centre (Haines et al., "Precision
 * Improvements for Ray/Sphere Intersection", Ray Tracing Gems ch. 7): the discriminant
 * from the closest-approach vector f = (o - c) - b d instead of b^2 - c, and the second
 * root from the product of the roots instead of a second subtraction.
 */
#include <math.h>

#include "geom.h"

bool sphere_intersect(vec3 c, double r, vec3 o, vec3 d, double tmin, double tmax,
                      struct geom_hit *h)
{
    vec3 oc = vec3_sub(o, c);
    double b = vec3_dot(oc, d); /* d is unit: the quadratic is t^2 + 2 b t + cc */
    vec3 f = vec3_madd(oc, d, -b);
    double disc = r * r - vec3_dot(f, f);
    if (disc < 0.0)
        return false;
    double cc = vec3_dot(oc, oc) - r * r;
    double q = -b - copysign(sqrt(disc), b);
    double t0 = q, t1 = q != 0.0 ? cc / q : q;
    if (t0 > t1) {
        double tmp = t0;
        t0 = t1;
        t1 = tmp;
    }
    bool near_root = t0 > tmin;
    double t = near_root ? t0 : t1;
    if (!(t > tmin && t < tmax))
        return false;
    h->t = t;
    /* The roots are -b -+ sqrt(disc), so the hit relative to the centre is
     * f -+ sqrt(disc) d: exact to the precision of f, where o + t d - c would lose
     * |o - c| / r of it. */
    h->normal = vec3_normalize(vec3_madd(f, d, near_root ? -sqrt(disc) : sqrt(disc)));
    h->shading = h->normal;
    h->prim = 0;
    return true;
}

bool sphere_inside(vec3 c, double r, vec3 p)
{
    vec3 v = vec3_sub(p, c);
    return vec3_dot(v, v) < r * r;
}

void sphere_bounds(vec3 c, double r, vec3 *lo, vec3 *hi)
{
    *lo = vec3_make(c.x - r, c.y - r, c.z - r);
    *hi = vec3_make(c.x + r, c.y + r, c.z + r);
}
