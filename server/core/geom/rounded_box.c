/*
 * rounded_box.c - the exact rounded box (geom.h): an axis-aligned box of full sizes size
 * whose edges and corners are rounded with radius r, i.e. the points within r of the inner
 * box of half sizes b = size / 2 - r (the Minkowski sum of that box and a ball).
 * Twin: shaders/geom/rounded_box.glsl.
 *
 * Why a union: the solid is the union of three slabs (the inner box grown by r along one
 * axis), twelve edge cylinders and eight corner balls, and it is convex, so a ray meets it
 * in one interval whose ends are the smallest entry and the largest exit over the parts.
 * Every root is a closed form (slab planes, cylinder and sphere quadratics), so the hit is
 * exact to rounding, with no iteration. The outward normal at a boundary point p is
 * (p - q) / r, q the nearest point of the inner box: the same for every part, and
 * continuous across the seams between faces, edges and corners.
 */
#include <math.h>

#include "geom.h"

/* The interval of the ray o + t d inside a box centred at the origin with half sizes h. */
static bool slab_interval(vec3 h, vec3 o, vec3 d, double *t0, double *t1)
{
    double lo = -INFINITY, hi = INFINITY;
    for (int a = 0; a < 3; a++) {
        double oa = vec3_get(o, a), da = vec3_get(d, a), ha = vec3_get(h, a);
        if (da == 0.0) {
            if (fabs(oa) > ha)
                return false;
            continue;
        }
        double ta = (-ha - oa) / da, tb = (ha - oa) / da;
        lo = fmax(lo, fmin(ta, tb));
        hi = fmin(hi, fmax(ta, tb));
    }
    *t0 = lo;
    *t1 = hi;
    return lo <= hi;
}

/* The interval inside |x - c| < r for the ray's coordinates x restricted to k dimensions of
 * the quadratic: oc and dd are o - c and d projected on them (a sphere: all three; a
 * cylinder: the two across its axis). Roots in Ray Tracing Gems ch. 7's stable form. */
static bool ball_interval(vec3 oc, vec3 dd, double r, double *t0, double *t1)
{
    double a = vec3_dot(dd, dd);
    double c = vec3_dot(oc, oc) - r * r;
    if (a < 1e-300) { /* parallel to a cylinder's axis: inside for ever or never */
        if (c > 0.0)
            return false;
        *t0 = -INFINITY;
        *t1 = INFINITY;
        return true;
    }
    double b = vec3_dot(oc, dd) / a;
    vec3 f = vec3_madd(oc, dd, -b); /* closest approach */
    double disc = (r * r - vec3_dot(f, f)) / a;
    if (disc < 0.0)
        return false;
    double q = -b - (b >= 0.0 ? sqrt(disc) : -sqrt(disc));
    double other = q != 0.0 ? (c / a) / q : q;
    *t0 = fmin(q, other);
    *t1 = fmax(q, other);
    return true;
}

static void widen(double t0, double t1, double *tin, double *tout)
{
    *tin = fmin(*tin, t0);
    *tout = fmax(*tout, t1);
}

bool rounded_box_intersect(vec3 c, vec3 size, double r, vec3 o, vec3 d, double tmin, double tmax,
                           struct geom_hit *h)
{
    if (!(r > 0.0))
        return box_intersect(c, size, o, d, tmin, tmax, h);
    vec3 b = vec3_sub(vec3_scale(size, 0.5), vec3_make(r, r, r));
    vec3 oc = vec3_sub(o, c);
    double t0, t1;
    /* The outer box holds every part: most rays that miss stop here. */
    if (!slab_interval(vec3_scale(size, 0.5), oc, d, &t0, &t1) || t1 <= tmin || t0 >= tmax)
        return false;
    double tin = INFINITY, tout = -INFINITY;
    for (int a = 0; a < 3; a++) {
        vec3 hs = b;
        vec3_set(&hs, a, vec3_get(b, a) + r);
        if (slab_interval(hs, oc, d, &t0, &t1))
            widen(t0, t1, &tin, &tout);
        /* The four edge cylinders along axis a: across it, at (+-b_u, +-b_v). */
        int u = (a + 1) % 3, v = (a + 2) % 3;
        vec3 dd = d;
        vec3_set(&dd, a, 0.0);
        for (int s = 0; s < 4; s++) {
            vec3 e = vec3_make(0, 0, 0);
            vec3_set(&e, u, (s & 1) ? vec3_get(b, u) : -vec3_get(b, u));
            vec3_set(&e, v, (s & 2) ? vec3_get(b, v) : -vec3_get(b, v));
            vec3 oe = vec3_sub(oc, e);
            vec3_set(&oe, a, 0.0);
            if (!ball_interval(oe, dd, r, &t0, &t1))
                continue;
            /* Cut to the edge's length |x_a| <= b_a. */
            double oa = vec3_get(oc, a), da = vec3_get(d, a), ba = vec3_get(b, a);
            if (da != 0.0) {
                double ta = (-ba - oa) / da, tb = (ba - oa) / da;
                t0 = fmax(t0, fmin(ta, tb));
                t1 = fmin(t1, fmax(ta, tb));
            } else if (fabs(oa) > ba) {
                continue;
            }
            if (t0 <= t1)
                widen(t0, t1, &tin, &tout);
        }
    }
    for (int k = 0; k < 8; k++) {
        vec3 corner = vec3_make((k & 1) ? b.x : -b.x, (k & 2) ? b.y : -b.y, (k & 4) ? b.z : -b.z);
        if (ball_interval(vec3_sub(oc, corner), d, r, &t0, &t1))
            widen(t0, t1, &tin, &tout);
    }
    if (!(tin <= tout))
        return false;
    double t = tin > tmin ? tin : tout;
    if (!(t > tmin && t < tmax))
        return false;
    vec3 p = vec3_madd(oc, d, t);
    vec3 q = vec3_make(fmax(-b.x, fmin(b.x, p.x)), fmax(-b.y, fmin(b.y, p.y)),
                       fmax(-b.z, fmin(b.z, p.z)));
    h->t = t;
    h->normal = vec3_normalize(vec3_sub(p, q));
    h->shading = h->normal;
    h->prim = 0;
    return true;
}

bool rounded_box_inside(vec3 c, vec3 size, double r, vec3 p)
{
    if (!(r > 0.0))
        return box_inside(c, size, p);
    vec3 q = vec3_sub(p, c);
    double s = 0.0;
    for (int a = 0; a < 3; a++) {
        double e = fabs(vec3_get(q, a)) - (0.5 * vec3_get(size, a) - r);
        if (e > 0.0)
            s += e * e;
    }
    return s < r * r;
}
