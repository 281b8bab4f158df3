/*
 * test_rounded_box.c - the exact rounded box (server/core/geom/rounded_box.c) against an
 * independent description of the same solid: the signed distance to the inner box minus r.
 *   - every ray's first crossing equals the root of that distance along the ray, found by
 *     fine sampling and bisection (1e-9), from outside (entry) and from inside (exit), on
 *     rays aimed at faces, edges and corners, and on grazing rays;
 *   - the normal equals the distance's gradient (unit, outward);
 *   - the inside test agrees with the distance's sign;
 *   - radius 0 is the plain box, and radius = half the smallest size a capsule/sphere;
 *   - a placed (scaled, rotated) rounded box through geom_surface_intersect.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/geom/geom.h"
#include "test.h"

static unsigned seed = 777;
static double uniform(void)
{
    seed = seed * 1664525u + 1013904223u;
    return (seed >> 8) / 16777216.0;
}

/* Signed distance to the rounded box (negative inside). */
static double sdf(vec3 c, vec3 size, double r, vec3 p)
{
    vec3 q = vec3_sub(p, c);
    double out2 = 0.0, in_max = -INFINITY;
    for (int a = 0; a < 3; a++) {
        double e = fabs(vec3_get(q, a)) - (0.5 * vec3_get(size, a) - r);
        if (e > 0.0)
            out2 += e * e;
        in_max = fmax(in_max, e);
    }
    return (out2 > 0.0 ? sqrt(out2) : fmin(in_max, 0.0)) - r;
}

static vec3 sdf_gradient(vec3 c, vec3 size, double r, vec3 p)
{
    const double h = 1e-7;
    vec3 g = {0, 0, 0};
    for (int a = 0; a < 3; a++) {
        vec3 lo = p, hi = p;
        vec3_set(&lo, a, vec3_get(p, a) - h);
        vec3_set(&hi, a, vec3_get(p, a) + h);
        vec3_set(&g, a, (sdf(c, size, r, hi) - sdf(c, size, r, lo)) / (2 * h));
    }
    return vec3_normalize(g);
}

/* The first sign change of the distance along o + t d past tmin: sampled every 1e-3, then
 * bisected. -1 when there is none before t = 20. */
static double brute_root(vec3 c, vec3 size, double r, vec3 o, vec3 d, double tmin)
{
    const double dt = 1e-3;
    double t0 = tmin, f0 = sdf(c, size, r, vec3_madd(o, d, t0));
    for (double t1 = tmin + dt; t1 < 20.0; t1 += dt) {
        double f1 = sdf(c, size, r, vec3_madd(o, d, t1));
        if ((f0 < 0) != (f1 < 0)) {
            for (int i = 0; i < 200 && t1 - t0 > 1e-13; i++) {
                double tm = 0.5 * (t0 + t1), fm = sdf(c, size, r, vec3_madd(o, d, tm));
                if ((fm < 0) == (f0 < 0))
                    t0 = tm;
                else
                    t1 = tm;
            }
            return 0.5 * (t0 + t1);
        }
        t0 = t1;
        f0 = f1;
    }
    return -1.0;
}

static vec3 random_dir(void)
{
    for (;;) {
        vec3 v = {2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1};
        double l = vec3_length(v);
        if (l > 0.1 && l < 1.0)
            return vec3_scale(v, 1.0 / l);
    }
}

static void check_rays(vec3 c, vec3 size, double r, const char *what)
{
    int checked = 0, hits = 0, bad_t = 0, bad_n = 0, bad_inside = 0;
    double worst_t = 0, worst_n = 0;
    for (int i = 0; i < 3000; i++) {
        /* Aim at a point near the surface: a face, an edge or a corner region. */
        vec3 aim = vec3_add(c, vec3_make(size.x * (uniform() - 0.5) * 1.1,
                                         size.y * (uniform() - 0.5) * 1.1,
                                         size.z * (uniform() - 0.5) * 1.1));
        vec3 o, d;
        if (i % 3 == 2) { /* from inside: the exit */
            o = vec3_add(c, vec3_make(size.x * (uniform() - 0.5) * 0.5,
                                      size.y * (uniform() - 0.5) * 0.5,
                                      size.z * (uniform() - 0.5) * 0.5));
            d = random_dir();
        } else {
            o = vec3_madd(aim, random_dir(), 3.0);
            d = vec3_normalize(vec3_sub(aim, o));
        }
        struct geom_hit h;
        bool hit = rounded_box_intersect(c, size, r, o, d, 0.0, INFINITY, &h);
        double want = brute_root(c, size, r, o, d, 0.0);
        checked++;
        if (hit != (want >= 0)) {
            /* A ray that only grazes an edge within the sampling step may be missed by the
             * brute force: accept when the distance's minimum along it is ~0. */
            if (hit && fabs(sdf(c, size, r, vec3_madd(o, d, h.t))) < 1e-9)
                continue;
            bad_t++;
            continue;
        }
        if (!hit)
            continue;
        hits++;
        double et = fabs(h.t - want);
        worst_t = fmax(worst_t, et);
        if (et > 1e-9)
            bad_t++;
        vec3 p = vec3_madd(o, d, h.t);
        vec3 g = sdf_gradient(c, size, r, p);
        double en = vec3_length(vec3_sub(g, h.normal));
        worst_n = fmax(worst_n, en);
        if (en > 1e-5 || fabs(vec3_length(h.normal) - 1.0) > 1e-12)
            bad_n++;
        /* Just before and after the hit, the inside test flips. */
        bool before = rounded_box_inside(c, size, r, vec3_madd(o, d, h.t - 1e-7));
        bool after = rounded_box_inside(c, size, r, vec3_madd(o, d, h.t + 1e-7));
        bool entering = vec3_dot(d, h.normal) < 0;
        if (before == after || after != entering)
            bad_inside++;
    }
    printf("%s: %d rays, %d hits, worst |t - brute| %.3g, worst |N - grad| %.3g; bad t %d, "
           "normal %d, inside %d\n",
           what, checked, hits, worst_t, worst_n, bad_t, bad_n, bad_inside);
    CHECK(hits > checked / 2);
    CHECK_INT(bad_t, 0);
    CHECK_INT(bad_n, 0);
    CHECK_INT(bad_inside, 0);
}

int main(void)
{
    vec3 c = {0.1, -0.2, 0.3};
    check_rays(c, vec3_make(1.6, 1.0, 0.7), 0.2, "rounded box r = 0.2");
    check_rays(c, vec3_make(1.6, 1.0, 0.7), 0.35, "rounded box r = half the smallest size");
    check_rays(c, vec3_make(1.0, 1.0, 1.0), 0.5, "rounded box that is a sphere");
    check_rays(c, vec3_make(1.0, 1.0, 1.0), 0.01, "rounded box r = 0.01");

    /* Radius 0 is the box, hit for hit. */
    int differ = 0;
    for (int i = 0; i < 2000; i++) {
        vec3 o = vec3_madd(c, random_dir(), 2.5);
        vec3 d = vec3_normalize(vec3_sub(vec3_add(c, vec3_scale(random_dir(), 0.5)), o));
        struct geom_hit a, b;
        bool ha = rounded_box_intersect(c, vec3_make(1, 0.8, 0.6), 0.0, o, d, 0, INFINITY, &a);
        bool hb = box_intersect(c, vec3_make(1, 0.8, 0.6), o, d, 0, INFINITY, &b);
        differ += ha != hb || (ha && (a.t != b.t || vec3_length(vec3_sub(a.normal, b.normal)) > 0));
    }
    CHECK_INT(differ, 0);

    /* Grazing: a ray along a face at a distance just under and just over the half size. */
    struct geom_hit h;
    vec3 size = {1, 1, 1};
    CHECK(rounded_box_intersect(vec3_make(0, 0, 0), size, 0.2, vec3_make(-3, 0.4999, 0),
                                vec3_make(1, 0, 0), 0, INFINITY, &h));
    CHECK(!rounded_box_intersect(vec3_make(0, 0, 0), size, 0.2, vec3_make(-3, 0.5001, 0),
                                 vec3_make(1, 0, 0), 0, INFINITY, &h));
    /* Past an edge's rounding: y = z = 0.45 is outside the rounded edge (the corner of the
     * square is cut by the circle of radius 0.2 about (0.3, 0.3)): a miss. */
    CHECK(!rounded_box_intersect(vec3_make(0, 0, 0), size, 0.2, vec3_make(-3, 0.45, 0.45),
                                 vec3_make(1, 0, 0), 0, INFINITY, &h));
    CHECK(rounded_box_intersect(vec3_make(0, 0, 0), size, 0.2, vec3_make(-3, 0.4, 0.4),
                                vec3_make(1, 0, 0), 0, INFINITY, &h));

    /* Placed: scaled by 2, rotated 30 degrees about y, moved; the world hit lies on the
     * world solid's surface (the inside test flips there). */
    struct geom_surface g = {.kind = GEOM_ROUNDED_BOX,
                             .xf = xform_make(vec3_make(1, 2, 3), vec3_make(0, 1, 0),
                                              30.0, 2.0),
                             .center = vec3_make(0, 0, 0),
                             .size = vec3_make(1, 0.6, 0.8),
                             .radius = 0.15};
    int placed_bad = 0;
    for (int i = 0; i < 500; i++) {
        vec3 o = vec3_madd(vec3_make(1, 2, 3), random_dir(), 6.0);
        vec3 d = vec3_normalize(vec3_sub(vec3_add(vec3_make(1, 2, 3), random_dir()), o));
        if (!geom_surface_intersect(&g, o, d, 0, INFINITY, -1, &h))
            continue;
        bool before = geom_surface_inside(&g, vec3_madd(o, d, h.t - 1e-7));
        bool after = geom_surface_inside(&g, vec3_madd(o, d, h.t + 1e-7));
        placed_bad += before || !after || vec3_dot(h.normal, d) >= 0;
    }
    CHECK_INT(placed_bad, 0);
    vec3 lo, hi;
    CHECK(geom_surface_bounds(&g, &lo, &hi));
    CHECK(lo.x < 0.2 && hi.x > 1.8 && lo.y < 1.5 && hi.y > 2.5);
    return test_summary("test_rounded_box");
}
