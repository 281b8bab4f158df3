/*
 * test_surfaces_ref.c - exact surfaces in the CPU reference march (docs/tracing.md
 * "Surfaces") against closed forms:
 *   - each kind's intersection: a lathe of a rectangle is a cylinder, a lathe of a
 *     triangle a cone; boxes, planes and spheres against their equations;
 *   - a glass (1.5) and a diamond (2.42) sphere against Snell at both surfaces
 *     (optics_sphere_transmit) on core, rim (to 0.999 R) and missing rays; total internal
 *     reflection of rays that start inside the diamond beyond the critical angle;
 *   - nested media by priority: a stack of slabs air | glass | water | glass | air
 *     against the closed-form multi-interface Snell, lateral shift and Fresnel
 *     transmittance; a water "wine" solid overlapping a glass wall meets the glass with
 *     the ratio of the two indices;
 *   - Beer-Lambert and the closed-form emission integral in a constant medium;
 *   - the transform: a scaled, rotated, translated sphere.
 * Tolerances are double rounding (1e-9) unless said otherwise: nothing is discretised.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/fresnel.h"
#include "core/optics_exact.h"
#include "core/reftrace.h"
#include "test.h"

#define DEG (180.0 / M_PI)

static struct reftrace_settings base_settings(void)
{
    return (struct reftrace_settings){
        .stepper = REFTRACE_RK4,
        .step_voxels = 0.5,
        .max_steps = 1000,
        .boundary_threshold = 0.02,
        .ambient_ior = 1.0,
        .env_intensity = 1.0,
        .min_throughput = -1.0,
    };
}

static struct reftrace_surface sphere_surface(vec3 c, double r, double n)
{
    struct reftrace_surface s = {.ior = n};
    s.geom.kind = GEOM_SPHERE;
    s.geom.xf = xform_identity();
    s.geom.center = c;
    s.geom.radius = r;
    return s;
}

static struct reftrace_surface box_surface(vec3 c, vec3 size, double n)
{
    struct reftrace_surface s = {.ior = n};
    s.geom.kind = GEOM_BOX;
    s.geom.xf = xform_identity();
    s.geom.center = c;
    s.geom.size = size;
    return s;
}

static double angle_deg(vec3 a, vec3 b)
{
    double c = vec3_dot(vec3_normalize(a), vec3_normalize(b));
    double s = vec3_length(vec3_cross(vec3_normalize(a), vec3_normalize(b)));
    return atan2(s, c) * DEG;
}

static void trace(const struct reftrace_surface *sf, int n, vec3 o, vec3 d,
                  struct reftrace_result *r)
{
    struct reftrace_settings st = base_settings();
    st.surfaces = sf;
    st.surface_count = n;
    reftrace_ray(NULL, 0, &st, o, vec3_normalize(d), r);
}

static double uniform(unsigned *seed)
{
    *seed = *seed * 1664525u + 1013904223u;
    return (*seed >> 8) * (1.0 / 16777216.0);
}

/* ---- kinds --------------------------------------------------------------------- */

static void test_lathe_rectangle_is_cylinder(void)
{
    const double rect[4][2] = {{0, -0.5}, {0.7, -0.5}, {0.7, 0.5}, {0, 0.5}};
    vec3 c = {0.1, 0.2, -0.3};
    unsigned seed = 7;
    int hits = 0;
    for (int i = 0; i < 2000; i++) {
        vec3 o = {uniform(&seed) * 4 - 2, uniform(&seed) * 4 - 2, uniform(&seed) * 4 - 2};
        vec3 aim = {c.x + 1.6 * (uniform(&seed) - 0.5), c.y + 1.6 * (uniform(&seed) - 0.5),
                    c.z + 1.6 * (uniform(&seed) - 0.5)};
        vec3 d = vec3_normalize(vec3_sub(aim, o));
        for (int axis = 0; axis < 3; axis++) {
            struct geom_hit hl, hc;
            bool bl = lathe_intersect(c, axis, rect, 4, o, d, 0.0, INFINITY, &hl);
            vec3 cc = c;
            bool bc = cylinder_intersect(cc, 0.7, 1.0, axis, o, d, 0.0, INFINITY, &hc);
            CHECK(bl == bc);
            if (bl && bc) {
                hits++;
                CHECK_NEAR(hl.t, hc.t, 1e-9);
                CHECK_NEAR(vec3_dot(hl.normal, hc.normal), 1.0, 1e-9);
            }
            vec3 p = vec3_madd(o, d, 0.37);
            CHECK(lathe_inside(c, axis, rect, 4, p) == cylinder_inside(cc, 0.7, 1.0, axis, p));
        }
    }
    CHECK(hits > 3000);
}

static void test_lathe_cone(void)
{
    /* Cone of base radius 1 at h = 0, apex at h = 2, about y: rho = 1 - h / 2. */
    const double tri[3][2] = {{0, 0}, {1, 0}, {0, 2}};
    vec3 base = {0, 0, 0};
    struct geom_hit h;
    /* Horizontal ray at height 1 from x = -3: meets the cone at rho = 0.5. */
    CHECK(
        lathe_intersect(base, 1, tri, 3, vec3_make(-3, 1, 0), vec3_make(1, 0, 0), 0, INFINITY, &h));
    CHECK_NEAR(h.t, 2.5, 1e-12);
    /* Outward normal of the side: (2, 1) / sqrt 5 in (rho, h), pointing to -x here. */
    CHECK_NEAR(h.normal.x, -2 / sqrt(5.0), 1e-12);
    CHECK_NEAR(h.normal.y, 1 / sqrt(5.0), 1e-12);
    /* From below along +y at x = 0.25: the base disc, normal -y. */
    CHECK(lathe_intersect(base, 1, tri, 3, vec3_make(0.25, -1, 0), vec3_make(0, 1, 0), 0, INFINITY,
                          &h));
    CHECK_NEAR(h.t, 1.0, 1e-12);
    CHECK_NEAR(h.normal.y, -1.0, 1e-12);
    /* A ray through the other nappe (above the apex) must not hit it. */
    CHECK(!lathe_intersect(base, 1, tri, 3, vec3_make(-3, 3, 0), vec3_make(1, 0, 0), 0, INFINITY,
                           &h));
    CHECK(lathe_inside(base, 1, tri, 3, vec3_make(0.2, 0.5, 0.1)));
    CHECK(!lathe_inside(base, 1, tri, 3, vec3_make(0.2, 1.8, 0.1)));
}

static void test_box_plane(void)
{
    struct geom_hit h;
    CHECK(box_intersect(vec3_make(0, 0, 0), vec3_make(2, 4, 6), vec3_make(-5, 0.5, 0.5),
                        vec3_make(1, 0, 0), 0, INFINITY, &h));
    CHECK_NEAR(h.t, 4.0, 1e-12);
    CHECK_NEAR(h.normal.x, -1.0, 0.0);
    /* From inside: the far face, normal along the ray. */
    CHECK(box_intersect(vec3_make(0, 0, 0), vec3_make(2, 4, 6), vec3_make(0, 0, 0),
                        vec3_make(0, 0, -1), 0, INFINITY, &h));
    CHECK_NEAR(h.t, 3.0, 1e-12);
    CHECK_NEAR(h.normal.z, -1.0, 0.0);
    vec3 n = vec3_normalize(vec3_make(0, 1, 1));
    CHECK(plane_intersect(vec3_make(0, 1, 0), n, vec3_make(0, 5, 0), vec3_make(0, -1, 0), 0,
                          INFINITY, &h));
    CHECK_NEAR(h.t, 4.0, 1e-12);
    CHECK(plane_inside(vec3_make(0, 1, 0), n, vec3_make(0, 0, 0)));
    CHECK(!plane_inside(vec3_make(0, 1, 0), n, vec3_make(0, 2, 0)));
    vec3 lo, hi;
    plane_bounds(vec3_make(0, -1, 0), vec3_make(0, 1, 0), &lo, &hi);
    CHECK(hi.y == -1.0 && isinf(lo.y) && isinf(hi.x));
}

/* ---- spheres against Snell ----------------------------------------------------- */

struct errs {
    double v[4096];
    int n;
};

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(struct errs *e)
{
    qsort(e->v, (size_t)e->n, sizeof e->v[0], cmp_double);
    return e->n ? e->v[e->n / 2] : 0.0;
}

static double worst(const struct errs *e)
{
    double w = 0.0;
    for (int i = 0; i < e->n; i++)
        w = fmax(w, e->v[i]);
    return w;
}

static void sphere_band(double n, double b_lo, double b_hi, bool miss, const char *what)
{
    vec3 c = {0.05, -0.02, 0.01};
    double R = 0.75;
    struct reftrace_surface sf = sphere_surface(c, R, n);
    struct errs e = {.n = 0};
    unsigned seed = 99;
    for (int i = 0; i < 400; i++) {
        double b = (b_lo + (b_hi - b_lo) * uniform(&seed)) * R;
        double phi = 2 * M_PI * uniform(&seed);
        vec3 o = {c.x + b * cos(phi), c.y + b * sin(phi), c.z - 2.0};
        vec3 d = {0, 0, 1};
        struct reftrace_result r;
        trace(&sf, 1, o, d, &r);
        vec3 xp, xd;
        if (miss) {
            CHECK(!optics_sphere_transmit(c, R, n, 1.0, o, d, &xp, &xd));
            CHECK_INT(r.status, RAY_MISSED);
            e.v[e.n++] = angle_deg(r.exit_direction, d);
            continue;
        }
        CHECK(optics_sphere_transmit(c, R, n, 1.0, o, d, &xp, &xd));
        CHECK_INT(r.status, RAY_EXITED);
        CHECK_INT(r.event_count, 2);
        e.v[e.n++] = angle_deg(r.exit_direction, xd);
        CHECK_NEAR(vec3_length(vec3_sub(r.exit_origin, xp)), 0.0, 1e-9);
        /* Transmittance: (1 - R) at both surfaces, equal angles (closed form). */
        double cos_i = fabs(vec3_dot(vec3_normalize(vec3_sub(vec3_madd(o, d, 0), c)), d));
        (void)cos_i;
        double ci = sqrt(fmax(0.0, 1.0 - (b / R) * (b / R)));
        double Rf = fresnel_unpolarized(ci, 1.0, n);
        CHECK_NEAR(r.transmittance.x, (1 - Rf) * (1 - Rf), 1e-9);
    }
    double med = median(&e), w = worst(&e);
    printf("sphere n=%.2f %s: median %.3g deg, worst %.3g deg over %d rays\n", n, what, med, w,
           e.n);
    if (miss) {
        CHECK(w <= 1e-5);
    } else {
        CHECK(med <= 1e-4);
        CHECK(w <= 1e-3);
    }
}

static void test_spheres(void)
{
    const double ns[2] = {1.5, 2.42};
    for (int i = 0; i < 2; i++) {
        sphere_band(ns[i], 0.0, 0.9, false, "core");
        sphere_band(ns[i], 0.9, 0.999, false, "rim");
        sphere_band(ns[i], 1.01, 1.05, true, "outside");
    }
}

/* A ray that starts inside the diamond with an angle of incidence beyond the critical
 * angle asin(1 / 2.42) = 24.4 deg reflects totally at every event, forever: every event
 * is a reflection at the same angle (the chord's symmetry), and the ray ends at max_steps
 * having lost nothing. */
static void test_diamond_tir(void)
{
    struct reftrace_surface sf = sphere_surface(vec3_make(0, 0, 0), 1.0, 2.42);
    double b = 0.6; /* impact parameter: sin(angle of incidence) = 0.6 > 1 / 2.42 */
    struct reftrace_result r;
    trace(&sf, 1, vec3_make(b, 0, 0), vec3_make(0, 0, 1), &r);
    CHECK_INT(r.status, RAY_MAX_STEPS);
    CHECK(r.event_count >= 50);
    int n = r.event_count < REFTRACE_MAX_EVENTS ? r.event_count : REFTRACE_MAX_EVENTS;
    for (int i = 0; i < n; i++) {
        CHECK_INT(r.events[i].kind, REFTRACE_EVENT_REFLECTED);
        CHECK_NEAR(r.events[i].fresnel_R, 1.0, 0.0);
        CHECK_NEAR(vec3_length(r.events[i].point), 1.0, 1e-9);
        CHECK_NEAR(r.events[i].point.y, 0.0, 1e-9); /* stays in the plane of the chord */
    }
    CHECK_NEAR(r.transmittance.x, 1.0, 1e-12);
    /* Below the critical angle the same ray leaves at once, refracted. */
    trace(&sf, 1, vec3_make(0.3, 0, 0), vec3_make(0, 0, 1), &r);
    CHECK_INT(r.status, RAY_EXITED);
    CHECK_INT(r.events[0].kind, REFTRACE_EVENT_REFRACTED);
    CHECK_NEAR(sin(angle_deg(r.exit_direction, r.events[0].normal) / DEG) * 1.0, 0.3 * 2.42, 1e-9);
}

/* ---- nested media -------------------------------------------------------------- */

/* air | glass 1.5 (z 0..1) | water 1.33 (z 1..2.5) | glass (z 2.5..3) | air: a glass
 * slab z in [0, 3] and a water slab z in [1, 2.5] of higher priority. */
static void test_slab_stack(void)
{
    struct reftrace_surface sf[2];
    sf[0] = box_surface(vec3_make(0, 0, 1.75), vec3_make(1e3, 1e3, 1.5), 1.33); /* water first */
    sf[1] = box_surface(vec3_make(0, 0, 1.5), vec3_make(1e3, 1e3, 3.0), 1.5);
    const double ns[5] = {1.0, 1.5, 1.33, 1.5, 1.0};
    const double thick[5] = {0, 1.0, 1.5, 0.5, 0};
    for (int k = 0; k < 6; k++) {
        double theta = k * 15.0 / DEG;
        vec3 d = {sin(theta), 0, cos(theta)};
        vec3 o = vec3_madd(vec3_make(0, 0, 0), d, -1.0);
        struct reftrace_result r;
        trace(sf, 2, o, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        CHECK_INT(r.event_count, 4);
        double s = sin(theta), T = 1.0, shift = 0.0;
        for (int i = 0; i < 4; i++) {
            double ci = sqrt(1 - (s / ns[i]) * (s / ns[i]));
            T *= 1.0 - fresnel_unpolarized(ci, ns[i], ns[i + 1]);
            double st = s / ns[i + 1];
            shift += thick[i + 1] * st / sqrt(1 - st * st);
            CHECK_NEAR(r.events[i].n_from, ns[i], 0.0);
            CHECK_NEAR(r.events[i].n_to, ns[i + 1], 0.0);
        }
        CHECK_NEAR(r.transmittance.x, T, 1e-12);
        CHECK_NEAR(angle_deg(r.exit_direction, d), 0.0, 1e-9);
        CHECK_NEAR(r.exit_origin.z, 3.0, 1e-9);
        CHECK_NEAR(r.exit_origin.x, shift, 1e-9);
    }
}

/* Wine (1.33) whose solid overlaps the glass wall (1.5, higher priority): from inside the
 * wine a ray meets the glass's inner surface with n 1.33 -> 1.5, then the air. */
static void test_wine_in_glass(void)
{
    struct reftrace_surface sf[2];
    sf[0] = sphere_surface(vec3_make(0, 0, 0), 1.0, 1.5);   /* glass ball shell: outer */
    sf[1] = sphere_surface(vec3_make(0, 0, 0), 0.95, 1.33); /* wine, to 0.95 */
    /* The glass solid is the whole ball; the wine's higher priority would make the core
     * wine: so the wine must come first to win... here glass has priority 0, so the whole
     * ball is glass and the wine surface is hidden. */
    struct reftrace_result r;
    trace(sf, 2, vec3_make(0, 0, -3), vec3_make(0, 0, 1), &r);
    CHECK_INT(r.event_count, 2); /* the wine's two crossings change nothing: no events */
    /* Wine first (priority 0), overlapping glass wall: glass shell 0.9..1.0 modelled as a
     * ball of radius 1 with a wine ball of radius 0.9 winning inside. */
    sf[0] = sphere_surface(vec3_make(0, 0, 0), 0.9, 1.33);
    sf[1] = sphere_surface(vec3_make(0, 0, 0), 1.0, 1.5);
    double b = 0.3;
    trace(sf, 2, vec3_make(b, 0, 0), vec3_make(0, 0, 1), &r); /* starts in the wine */
    CHECK_INT(r.status, RAY_EXITED);
    CHECK_INT(r.event_count, 2);
    CHECK_NEAR(r.events[0].n_from, 1.33, 0.0);
    CHECK_NEAR(r.events[0].n_to, 1.5, 0.0);
    double sin_i = b / 0.9;
    double sin_t = sin(angle_deg(r.events[1].point, vec3_make(0, 0, 0)) / DEG);
    (void)sin_t;
    /* Snell with the ratio of the two indices at the glass-wine interface. */
    vec3 N = vec3_normalize(r.events[0].point);
    vec3 d1 = vec3_normalize(vec3_sub(r.events[1].point, r.events[0].point));
    double s_out = vec3_length(vec3_cross(d1, N));
    CHECK_NEAR(1.5 * s_out, 1.33 * sin_i, 1e-9);
}

static void test_beer_lambert_emission(void)
{
    struct reftrace_surface sf = box_surface(vec3_make(0, 0, 0), vec3_make(2, 2, 2), 1.0);
    sf.attenuation[0] = 0.5;
    sf.attenuation[1] = 1.0;
    sf.attenuation[2] = 0.0;
    sf.emission[0] = sf.emission[1] = sf.emission[2] = 0.25;
    struct reftrace_settings st = base_settings();
    st.surfaces = &sf;
    st.surface_count = 1;
    st.env_intensity = 0.0;
    struct reftrace_result r;
    reftrace_ray(NULL, 0, &st, vec3_make(0, 0, -5), vec3_make(0, 0, 1), &r);
    CHECK_NEAR(r.transmittance.x, exp(-1.0), 1e-12);
    CHECK_NEAR(r.transmittance.y, exp(-2.0), 1e-12);
    CHECK_NEAR(r.transmittance.z, 1.0, 1e-12);
    CHECK_NEAR(r.radiance.x, 0.25 * (1 - exp(-1.0)) / 0.5, 1e-12);
    CHECK_NEAR(r.radiance.z, 0.25 * 2.0, 1e-12);
    CHECK_NEAR(r.optical_path_length, 6.0, 1e-12); /* to the exit face, z = 1 */
}

static void test_transformed_sphere(void)
{
    /* A unit sphere scaled by 0.5, rotated and moved equals a sphere of radius 0.5. */
    struct reftrace_surface a = sphere_surface(vec3_make(0, 0, 0), 1.0, 1.5);
    a.geom.xf = xform_make(vec3_make(0.3, -0.2, 0.1), vec3_make(1, 2, 3), 37.0, 0.5);
    struct reftrace_surface b = sphere_surface(vec3_make(0.3, -0.2, 0.1), 0.5, 1.5);
    unsigned seed = 3;
    for (int i = 0; i < 200; i++) {
        vec3 o = {uniform(&seed) - 0.5 + 0.3, uniform(&seed) - 0.5 - 0.2, -3};
        struct reftrace_result ra, rb;
        trace(&a, 1, o, vec3_make(0, 0, 1), &ra);
        trace(&b, 1, o, vec3_make(0, 0, 1), &rb);
        CHECK_INT(ra.status, rb.status);
        CHECK_NEAR(angle_deg(ra.exit_direction, rb.exit_direction), 0.0, 1e-9);
        CHECK_NEAR(ra.optical_path_length, rb.optical_path_length, 1e-9);
    }
}

int main(void)
{
    test_lathe_rectangle_is_cylinder();
    test_lathe_cone();
    test_box_plane();
    test_spheres();
    test_diamond_tir();
    test_slab_stack();
    test_wine_in_glass();
    test_beer_lambert_emission();
    test_transformed_sphere();
    return test_summary("test_surfaces_ref");
}
