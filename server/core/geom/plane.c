/*
 * plane.c - the infinite plane (geom.h); its solid is the half-space behind the normal.
 * Twin: shaders/geom/plane.glsl.
 */
#include <math.h>

#include "geom.h"

bool plane_intersect(vec3 c, vec3 n, vec3 o, vec3 d, double tmin, double tmax, struct geom_hit *h)
{
    double dn = vec3_dot(d, n);
    if (dn == 0.0)
        return false; /* parallel: never crosses (a ray in the plane stays on its side) */
    double t = vec3_dot(vec3_sub(c, o), n) / dn;
    if (!(t > tmin && t < tmax))
        return false;
    h->t = t;
    h->normal = n;
    h->shading = n;
    h->prim = 0;
    return true;
}

bool plane_inside(vec3 c, vec3 n, vec3 p)
{
    return vec3_dot(vec3_sub(p, c), n) < 0.0;
}

void plane_bounds(vec3 c, vec3 n, vec3 *lo, vec3 *hi)
{
    *lo = vec3_make(-INFINITY, -INFINITY, -INFINITY);
    *hi = vec3_make(INFINITY, INFINITY, INFINITY);
    for (int a = 0; a < 3; a++) {
        int b = (a + 1) % 3, k = (a + 2) % 3;
        if (vec3_get(n, b) != 0.0 || vec3_get(n, k) != 0.0)
            continue;
        if (vec3_get(n, a) > 0.0)
            vec3_set(hi, a, vec3_get(c, a));
        else
            vec3_set(lo, a, vec3_get(c, a));
    }
}
