/*
 * cylinder.c - the exact closed cylinder (geom.h): side quadratic in the two coordinates
 * across the axis (in the same stable form as sphere.c), and the two caps. Twin:
 * shaders/geom/cylinder.glsl. prim: 0 side, 1 lower cap, 2 upper cap.
 */
#include <math.h>

#include "geom.h"

bool cylinder_intersect(vec3 c, double r, double height, int axis, vec3 o, vec3 d, double tmin,
                        double tmax, struct geom_hit *h)
{
    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    vec3 oc = vec3_sub(o, c);
    double half = 0.5 * height;
    double best = tmax;
    /* Side: (ox + t dx)^2 + (oy + t dy)^2 = r^2 over the two cross-axis coordinates. */
    double ox = vec3_get(oc, a1), oy = vec3_get(oc, a2);
    double dx = vec3_get(d, a1), dy = vec3_get(d, a2);
    double A = dx * dx + dy * dy;
    if (A > 0.0) {
        double b = (ox * dx + oy * dy) / A;
        double fx = ox - b * dx, fy = oy - b * dy;
        double disc = (r * r - (fx * fx + fy * fy)) / A;
        if (disc >= 0.0) {
            double cc = (ox * ox + oy * oy - r * r) / A;
            double q = -b - copysign(sqrt(disc), b);
            double roots[2] = {q, q != 0.0 ? cc / q : q};
            for (int i = 0; i < 2; i++) {
                double t = roots[i];
                double along = vec3_get(oc, axis) + t * vec3_get(d, axis);
                if (fabs(along) > half)
                    continue;
                vec3 nrm = vec3_make(0, 0, 0);
                vec3_set(&nrm, a1, (ox + t * dx) / r);
                vec3_set(&nrm, a2, (oy + t * dy) / r);
                geom_hit_consider(t, tmin, &best, vec3_normalize(nrm), 0, h);
            }
        }
    }
    /* Caps. */
    double da = vec3_get(d, axis);
    if (da != 0.0) {
        for (int s = 0; s < 2; s++) {
            double level = s ? half : -half;
            double t = (level - vec3_get(oc, axis)) / da;
            double x = ox + t * dx, y = oy + t * dy;
            if (x * x + y * y > r * r)
                continue;
            vec3 nrm = vec3_make(0, 0, 0);
            vec3_set(&nrm, axis, s ? 1.0 : -1.0);
            geom_hit_consider(t, tmin, &best, nrm, 1 + s, h);
        }
    }
    return best < tmax;
}

bool cylinder_inside(vec3 c, double r, double height, int axis, vec3 p)
{
    vec3 v = vec3_sub(p, c);
    double x = vec3_get(v, (axis + 1) % 3), y = vec3_get(v, (axis + 2) % 3);
    return fabs(vec3_get(v, axis)) < 0.5 * height && x * x + y * y < r * r;
}

void cylinder_bounds(vec3 c, double r, double height, int axis, vec3 *lo, vec3 *hi)
{
    vec3 e = vec3_make(r, r, r);
    vec3_set(&e, axis, 0.5 * height);
    *lo = vec3_sub(c, e);
    *hi = vec3_add(c, e);
}
