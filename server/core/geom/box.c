/*
 * box.c - the exact axis-aligned box (geom.h): the slab test. Twin: shaders/geom/box.glsl.
 * prim is the face: axis * 2 + (1 on the + side).
 */
#include <math.h>

#include "geom.h"

bool box_intersect(vec3 c, vec3 size, vec3 o, vec3 d, double tmin, double tmax, struct geom_hit *h)
{
    double t_near = -INFINITY, t_far = INFINITY;
    int ax_near = 0, ax_far = 0;
    for (int a = 0; a < 3; a++) {
        double lo = vec3_get(c, a) - 0.5 * vec3_get(size, a);
        double hi = vec3_get(c, a) + 0.5 * vec3_get(size, a);
        double oa = vec3_get(o, a), da = vec3_get(d, a);
        if (da == 0.0) {
            if (oa < lo || oa > hi)
                return false;
            continue;
        }
        double t0 = (lo - oa) / da, t1 = (hi - oa) / da;
        if (t0 > t1) {
            double tmp = t0;
            t0 = t1;
            t1 = tmp;
        }
        if (t0 > t_near) {
            t_near = t0;
            ax_near = a;
        }
        if (t1 < t_far) {
            t_far = t1;
            ax_far = a;
        }
    }
    if (t_near > t_far)
        return false;
    double t;
    int axis;
    double sign;
    if (t_near > tmin) {
        t = t_near;
        axis = ax_near;
        sign = vec3_get(d, axis) > 0.0 ? -1.0 : 1.0; /* entering through the face facing the ray */
    } else {
        t = t_far;
        axis = ax_far;
        sign = vec3_get(d, axis) > 0.0 ? 1.0 : -1.0;
    }
    if (!(t > tmin && t < tmax))
        return false;
    h->t = t;
    h->normal = vec3_make(0, 0, 0);
    vec3_set(&h->normal, axis, sign);
    h->shading = h->normal;
    h->prim = axis * 2 + (sign > 0.0);
    return true;
}

bool box_inside(vec3 c, vec3 size, vec3 p)
{
    for (int a = 0; a < 3; a++)
        if (!(fabs(vec3_get(p, a) - vec3_get(c, a)) < 0.5 * vec3_get(size, a)))
            return false;
    return true;
}

void box_bounds(vec3 c, vec3 size, vec3 *lo, vec3 *hi)
{
    *lo = vec3_madd(c, size, -0.5);
    *hi = vec3_madd(c, size, 0.5);
}
