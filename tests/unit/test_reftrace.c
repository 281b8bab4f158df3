/*
 * test_reftrace.c - the reference march of docs/tracing.md against closed forms:
 * straight rays and OPL in uniform media, Snell and Fresnel at the bounds faces, total
 * internal reflection, Luneburg focusing, Maxwell fish-eye imaging, reversibility,
 * convergence orders, the mirage (linear GRIN, closed-form trajectory), Beer-Lambert,
 * emission, statuses, several objects and transforms, sharp-boundary Fresnel events.
 *
 * Tolerances, and why:
 *   1e-9 (relative where said): straight paths, where every stepper is exact and
 *        only rounding over a few hundred steps remains.
 *   1e-6 R: adaptive Dormand-Prince with tolerance 1e-10 per step over a few hundred
 *        steps, and the kink of the Luneburg / fish-eye profiles at r = R.
 *   Convergence ratios: 8x..32x for RK4 (4th order: 16x) and 1.5x..3x for Euler.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/env.h"
#include "core/fresnel.h"
#include "core/grin.h"
#include "core/reftrace.h"
#include "core/smooth.h"
#include "test.h"

/* ---- fixtures ------------------------------------------------------------------- */

static struct reftrace_settings settings_for(enum reftrace_stepper stepper, double step_voxels)
{
    return (struct reftrace_settings){
        .stepper = stepper,
        .step_voxels = step_voxels,
        .max_steps = 1000000,
        .boundary_threshold = 0.02,
        .ambient_ior = 1.0,
        .tolerance = 1e-10,
        .env_intensity = 1.0,
    };
}

static double grin_field(void *ctx, vec3 p, vec3 *grad)
{
    return grin_ior(ctx, p, grad);
}

static struct reftrace_object analytic_object(vec3 bmin, vec3 bmax, int res, struct grin_profile *g)
{
    return (struct reftrace_object){
        .bmin = bmin,
        .bmax = bmax,
        .res = {res, res, res},
        .xf = xform_identity(),
        .opaque_ior = 1.5,
        .ior = grin_field,
        .ior_ctx = g,
    };
}

/* A voxel grid with uniform channels; owns its arrays. */
struct uniform_grid {
    int res;
    double *ior_grad, *attenuation, *emission;
    struct reftrace_grid grid;
};

static void fill4(double *a, size_t count, double x, double y, double z, double w)
{
    for (size_t i = 0; i < count; i++) {
        a[4 * i + 0] = x;
        a[4 * i + 1] = y;
        a[4 * i + 2] = z;
        a[4 * i + 3] = w;
    }
}

static void uniform_grid_init(struct uniform_grid *u, int res, double n, vec3 sigma_a,
                              vec3 emission)
{
    size_t count = (size_t)res * res * res;
    u->res = res;
    u->ior_grad = malloc(sizeof(double) * 4 * count);
    u->attenuation = malloc(sizeof(double) * 4 * count);
    u->emission = malloc(sizeof(double) * 4 * count);
    fill4(u->ior_grad, count, 0.0, 0.0, 0.0, n);
    fill4(u->attenuation, count, sigma_a.x, sigma_a.y, sigma_a.z, 0.0);
    fill4(u->emission, count, emission.x, emission.y, emission.z, 0.0);
    u->grid = (struct reftrace_grid){
        .ior_grad = u->ior_grad, .attenuation = u->attenuation, .emission = u->emission};
}

static void uniform_grid_fini(struct uniform_grid *u)
{
    free(u->ior_grad);
    free(u->attenuation);
    free(u->emission);
}

static struct reftrace_object grid_object(vec3 bmin, vec3 bmax, const struct uniform_grid *u)
{
    return (struct reftrace_object){
        .bmin = bmin,
        .bmax = bmax,
        .res = {u->res, u->res, u->res},
        .xf = xform_identity(),
        .opaque_ior = 1.5,
        .grid = &u->grid,
    };
}

static double dist(vec3 a, vec3 b)
{
    return vec3_length(vec3_sub(a, b));
}

/* Distance from point c to the line through a with unit direction d. */
static double line_distance(vec3 a, vec3 d, vec3 c)
{
    vec3 ac = vec3_sub(c, a);
    return vec3_length(vec3_sub(ac, vec3_scale(d, vec3_dot(ac, d))));
}

static void check_vec(vec3 a, vec3 b, double tol)
{
    CHECK_NEAR(a.x, b.x, tol);
    CHECK_NEAR(a.y, b.y, tol);
    CHECK_NEAR(a.z, b.z, tol);
}

static const enum reftrace_stepper all_steppers[3] = {REFTRACE_EULER, REFTRACE_RK4,
                                                      REFTRACE_ADAPTIVE};

/* ---- uniform media and faces ------------------------------------------------------ */

/* A glass cube n = 1.5 (voxel grid) at normal incidence: straight through, OPL = 2
 * (ambient) + 1.5 * 1, T = (1 - 0.04)^2. Every stepper is exact when grad n = 0. */
static void uniform_field_ray_goes_straight_and_opl_is_n_times_length(void)
{
    struct uniform_grid u;
    uniform_grid_init(&u, 8, 1.5, (vec3){0, 0, 0}, (vec3){0, 0, 0});
    struct reftrace_object obj = grid_object((vec3){0, 0, 0}, (vec3){1, 1, 1}, &u);
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = settings_for(all_steppers[i], 0.5);
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &s, (vec3){0.3, 0.4, -2.0}, (vec3){0, 0, 1}, &r);
        CHECK_INT(r.status, RAY_EXITED);
        check_vec(r.exit_origin, (vec3){0.3, 0.4, 1.0}, 1e-12);
        check_vec(r.exit_direction, (vec3){0, 0, 1}, 1e-12);
        CHECK_NEAR(r.optical_path_length, 3.5, 3.5e-9);
        CHECK_NEAR(r.transmittance.x, 0.96 * 0.96, 1e-12);
        CHECK(r.steps > 0);
        /* Radiance: 4 % of the sky behind the eye at the entry face, 4 % of the 96 %
         * reflected back at the exit face (it looks up the environment directly,
         * tevs2007 sect. 6.3), and the transmitted background. */
        vec3 back = env_procedural((vec3){0, 0, -1}), ahead = env_procedural((vec3){0, 0, 1});
        vec3 expect = vec3_add(vec3_scale(back, 0.04 + 0.96 * 0.04), vec3_scale(ahead, 0.9216));
        check_vec(r.radiance, expect, 1e-12);
    }

    /* Oblique: refracts at z = 0 per Snell, runs straight, leaves parallel to d. */
    vec3 d = vec3_normalize((vec3){0.3, 0.0, 1.0});
    double sin_i = d.x, cos_i = d.z;
    double sin_t = sin_i / 1.5, cos_t = sqrt(1.0 - sin_t * sin_t);
    vec3 entry = {-0.5 + 2.0 * sin_i / cos_i, 0.4, 0.0};
    vec3 exit = {entry.x + sin_t / cos_t, 0.4, 1.0};
    double opl = 2.0 / cos_i + 1.5 / cos_t;
    double T =
        (1.0 - fresnel_unpolarized(cos_i, 1.0, 1.5)) * (1.0 - fresnel_unpolarized(cos_t, 1.5, 1.0));
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = settings_for(all_steppers[i], 0.5);
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &s, (vec3){-0.5, 0.4, -2.0}, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        check_vec(r.exit_origin, exit, 1e-9);
        check_vec(r.exit_direction, d, 1e-12);
        CHECK_NEAR(r.optical_path_length, opl, opl * 1e-9);
        CHECK_NEAR(r.transmittance.y, T, 1e-12);
    }
    uniform_grid_fini(&u);
}

/* A "linear" GRIN profile with zero gradient and n0 = 1.5 is a parallel glass slab
 * (analytic path): Snell at the entry face, back to the original direction at the exit
 * face, T = (1 - R1)(1 - R2), OPL = ambient part + 1.5 * inside length. */
static void parallel_grin_slab_refracts_per_snell_and_exits_parallel(void)
{
    struct grin_profile g = {.kind = GRIN_LINEAR, .n0 = 1.5};
    struct reftrace_object obj = analytic_object((vec3){-2, -2, 0}, (vec3){2, 2, 0.5}, 32, &g);
    double th = 40.0 * M_PI / 180.0;
    vec3 d = {sin(th) * cos(0.3), sin(th) * sin(0.3), cos(th)};
    vec3 origin = {-0.5, -0.2, -1.0};
    double sin_t = sin(th) / 1.5, cos_t = sqrt(1.0 - sin_t * sin_t);
    vec3 entry = vec3_madd(origin, d, 1.0 / cos(th));
    double lateral = 0.5 * sin_t / cos_t; /* inside, along the plane of incidence */
    vec3 exit = {entry.x + lateral * cos(0.3), entry.y + lateral * sin(0.3), 0.5};
    double T = (1.0 - fresnel_unpolarized(cos(th), 1.0, 1.5)) *
               (1.0 - fresnel_unpolarized(cos_t, 1.5, 1.0));
    double opl = 1.0 / cos(th) + 1.5 * 0.5 / cos_t;
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = settings_for(all_steppers[i], 0.5);
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &s, origin, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        check_vec(r.exit_origin, exit, 1e-9);
        check_vec(r.exit_direction, d, 1e-12);
        CHECK_NEAR(r.transmittance.z, T, 1e-12);
        CHECK_NEAR(r.optical_path_length, opl, opl * 1e-9);
    }
    /* Both faces reflect the same share (reciprocity of the Fresnel equations). */
    CHECK_NEAR(fresnel_unpolarized(cos(th), 1.0, 1.5), fresnel_unpolarized(cos_t, 1.5, 1.0), 1e-12);
}

/* Inside a glass cube a ray meets the x = 1 face at 60 deg from its normal (> 41.8 deg
 * critical): it reflects without loss, then leaves through z = 1 at 30 deg, refracted
 * to sin_t = 1.5 sin 30 = 0.75. */
static void ray_inside_glass_totally_reflects_at_a_steep_face(void)
{
    struct uniform_grid u;
    uniform_grid_init(&u, 8, 1.5, (vec3){0, 0, 0}, (vec3){0, 0, 0});
    struct reftrace_object obj = grid_object((vec3){0, 0, 0}, (vec3){1, 1, 1}, &u);
    vec3 origin = {0.6, 0.5, 0.1};
    vec3 d = {sin(M_PI / 6.0), 0.0, cos(M_PI / 6.0)};
    double l1 = 0.4 / d.x; /* to x = 1 */
    double z1 = origin.z + l1 * d.z;
    double l2 = (1.0 - z1) / d.z; /* mirrored, to z = 1 */
    vec3 exit = {1.0 - l2 * d.x, 0.5, 1.0};
    vec3 exit_dir = {-0.75, 0.0, sqrt(1.0 - 0.75 * 0.75)};
    double T = 1.0 - fresnel_unpolarized(cos(M_PI / 6.0), 1.5, 1.0);
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = settings_for(all_steppers[i], 0.5);
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &s, origin, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        check_vec(r.exit_origin, exit, 1e-9);
        check_vec(r.exit_direction, exit_dir, 1e-12);
        CHECK_NEAR(r.transmittance.x, T, 1e-12);
        CHECK_NEAR(r.optical_path_length, 1.5 * (l1 + l2), 1e-9);
    }
    uniform_grid_fini(&u);
}

/* ---- analytic GRIN lenses (adaptive reference) ------------------------------------ */

static struct grin_profile luneburg = {.kind = GRIN_LUNEBURG, .radius = 1.0};

/* n = sqrt(2 - r^2) focuses a parallel bundle on the far surface: rays along +z at any
 * height leave the sphere at (0, 0, R), which is also where the sphere touches the
 * bounds face z = R, so the exit points coincide there. Along the way
 * |grad n| h_min <= h_min / R = 2 / 128 = 0.0156 < 0.02: no boundary event fires, so
 * T stays exactly 1. */
static void luneburg_focuses_parallel_rays_on_the_far_side(void)
{
    struct reftrace_object obj =
        analytic_object((vec3){-1, -1, -1}, (vec3){1, 1, 1}, 128, &luneburg);
    struct reftrace_settings s = settings_for(REFTRACE_ADAPTIVE, 0.5);
    double worst = 0.0, worst_dir = 0.0, worst_opl = 0.0;
    int steps = 0;
    for (int k = 1; k <= 9; k++) {
        double h = 0.1 * k;
        vec3 starts[2] = {{0.0, h, -3.0}, {h * 0.6, -h * 0.8, -3.0}};
        for (int j = 0; j < 2; j++) {
            struct reftrace_result r;
            reftrace_ray(&obj, 1, &s, starts[j], (vec3){0, 0, 1}, &r);
            CHECK_INT(r.status, RAY_EXITED);
            CHECK_NEAR(r.transmittance.x, 1.0, 0.0);
            worst = fmax(worst, dist(r.exit_origin, (vec3){0, 0, 1}));
            /* n r sin(psi) is conserved (the ray equation's angular momentum): at the
             * focus (r = R, n = 1) sin(psi) = h, so d = (-x0, -y0, sqrt(1 - h^2)). */
            vec3 exit_dir = {-starts[j].x, -starts[j].y, sqrt(1.0 - h * h)};
            worst_dir = fmax(worst_dir, dist(r.exit_direction, exit_dir));
            /* A perfect focus has equal optical paths from the plane wave (Malus-Dupin):
             * on the axis, 2 in air plus the integral of sqrt(2 - z^2) over [-1, 1],
             * which is 1 + pi / 2. */
            worst_opl = fmax(worst_opl, fabs(r.optical_path_length - (3.0 + M_PI / 2.0)));
            steps += r.steps;
        }
    }
    CHECK_NEAR(worst, 0.0, 1e-6);
    CHECK_NEAR(worst_dir, 0.0, 1e-6);
    /* OPL: measured 1e-8 at tolerance 1e-10, levelling off at 3e-10 for tighter
     * tolerances (the kink of n at r = R is where the embedded error estimate is
     * least reliable). */
    CHECK_NEAR(worst_opl, 0.0, 5e-8);
    printf("luneburg adaptive (tol 1e-10): worst focus miss %.3g R, direction %.3g, "
           "OPL %.3g, %d steps for 18 rays\n",
           worst, worst_dir, worst_opl, steps);

    /* The fixed-step steppers accumulate OPL with the trapezoid rule (second order):
     * at half a voxel of 128 the error is well under 1e-4 of the path. */
    for (int i = 0; i < 2; i++) {
        struct reftrace_settings fs = settings_for(all_steppers[i], 0.5);
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &fs, (vec3){0, 0, -3}, (vec3){0, 0, 1}, &r);
        CHECK_NEAR(r.optical_path_length, 3.0 + M_PI / 2.0, 1e-4);
    }
}

/* A bundle along any direction u focuses on R u, inside the bounds here: after the
 * focus the ray runs straight (n = 1), so its exit line passes through R u. */
static void luneburg_focuses_an_oblique_bundle_on_the_antipode_of_its_direction(void)
{
    struct reftrace_object obj =
        analytic_object((vec3){-1, -1, -1}, (vec3){1, 1, 1}, 128, &luneburg);
    struct reftrace_settings s = settings_for(REFTRACE_ADAPTIVE, 0.5);
    vec3 u = vec3_normalize((vec3){0.6, 0.3, 1.0});
    vec3 a = vec3_normalize(vec3_cross(u, (vec3){0, 1, 0}));
    vec3 b = vec3_cross(u, a);
    double worst = 0.0;
    for (int k = 1; k <= 8; k++) {
        double h = 0.1 * k, phi = 0.7 * k;
        vec3 start = vec3_madd(vec3_madd(vec3_scale(u, -3.0), a, h * cos(phi)), b, h * sin(phi));
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &s, start, u, &r);
        CHECK_INT(r.status, RAY_EXITED);
        worst = fmax(worst, line_distance(r.exit_origin, r.exit_direction, u));
    }
    CHECK_NEAR(worst, 0.0, 1e-6);
}

/* Maxwell's fish-eye n = n0 / (1 + (r/R)^2) images every point of the surface r = R on
 * its antipode. From the south pole (0, 0, -R), on the bounds face, every ray arrives at
 * the north pole (0, 0, R), where the sphere touches the opposite face. From a general
 * surface point P the ray passes through -P and continues straight (n = n0/2 = 1
 * outside), so its exit line passes through -P. */
static void maxwell_fisheye_images_a_surface_point_on_its_antipode(void)
{
    struct grin_profile g = {.kind = GRIN_MAXWELL_FISHEYE, .radius = 1.0, .n0 = 2.0};
    struct reftrace_object obj = analytic_object((vec3){-1, -1, -1}, (vec3){1, 1, 1}, 128, &g);
    struct reftrace_settings s = settings_for(REFTRACE_ADAPTIVE, 0.5);
    double worst_pole = 0.0, worst_general = 0.0;
    for (int k = 1; k <= 7; k++) {
        double b = (10.0 * k) * M_PI / 180.0, phi = 0.9 * k;
        vec3 d = {sin(b) * cos(phi), sin(b) * sin(phi), cos(b)};
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &s, (vec3){0, 0, -1}, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        worst_pole = fmax(worst_pole, dist(r.exit_origin, (vec3){0, 0, 1}));
    }
    for (int k = 1; k <= 6; k++) {
        double a = 0.5 * k, e = 0.3 * (k - 3);
        vec3 P = {cos(e) * sin(a), sin(e), -cos(e) * cos(a)};
        /* Any direction into the sphere: tilt the inward normal by 35 deg. */
        vec3 in = vec3_scale(P, -1.0);
        vec3 t = vec3_normalize(vec3_cross(in, (vec3){0.3, 1, 0.2}));
        vec3 d = vec3_normalize(vec3_add(in, vec3_scale(t, tan(35.0 * M_PI / 180.0))));
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &s, P, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        worst_general = fmax(worst_general,
                             line_distance(r.exit_origin, r.exit_direction, vec3_scale(P, -1.0)));
    }
    CHECK_NEAR(worst_pole, 0.0, 1e-5);
    CHECK_NEAR(worst_general, 0.0, 1e-5);
    printf("fisheye adaptive: worst antipode miss %.3g R (poles), %.3g R (general)\n", worst_pole,
           worst_general);
}

/* A smooth Gaussian bump whose index at the bounds differs from 1 by < 1e-7 (so the
 * faces neither refract nor reflect measurably) and whose curvature there is as small:
 * exit errors then come from the integration alone. */
static struct grin_profile bump = {
    .kind = GRIN_GAUSSIAN, .n_peak = 1.5, .n_out = 1.0, .sigma = 0.18};

/* Where a world ray first meets the bounds [-1, 1]^3 (the ambient part is straight). */
static vec3 box_entry(vec3 o, vec3 d)
{
    double t0 = -INFINITY;
    for (int a = 0; a < 3; a++) {
        double oa = vec3_get(o, a), da = vec3_get(d, a);
        if (da == 0.0)
            continue;
        double ta = (-1.0 - oa) / da, tb = (1.0 - oa) / da;
        t0 = fmax(t0, fmin(ta, tb));
    }
    return vec3_madd(o, d, t0);
}

static void reversed_exit_ray_retraces_its_path(void)
{
    struct reftrace_object obj = analytic_object((vec3){-1, -1, -1}, (vec3){1, 1, 1}, 64, &bump);
    struct reftrace_settings s = settings_for(REFTRACE_ADAPTIVE, 0.5);
    vec3 origin = {-3.0, 0.2, 0.1};
    vec3 d = vec3_normalize((vec3){1.0, 0.05, 0.02});
    struct reftrace_result fwd, back;
    reftrace_ray(&obj, 1, &s, origin, d, &fwd);
    CHECK_INT(fwd.status, RAY_EXITED);
    CHECK(dist(fwd.exit_direction, d) > 0.05); /* it really was bent */
    reftrace_ray(&obj, 1, &s, fwd.exit_origin, vec3_scale(fwd.exit_direction, -1.0), &back);
    CHECK_INT(back.status, RAY_EXITED);
    check_vec(back.exit_origin, box_entry(origin, d), 1e-6);
    check_vec(back.exit_direction, vec3_scale(d, -1.0), 1e-6);

    /* The Luneburg lens, traced back from its focus. */
    struct reftrace_object lun =
        analytic_object((vec3){-1, -1, -1}, (vec3){1, 1, 1}, 128, &luneburg);
    reftrace_ray(&lun, 1, &s, (vec3){0, 0.5, -3.0}, (vec3){0, 0, 1}, &fwd);
    reftrace_ray(&lun, 1, &s, fwd.exit_origin, vec3_scale(fwd.exit_direction, -1.0), &back);
    CHECK_INT(back.status, RAY_EXITED);
    check_vec(back.exit_origin, (vec3){0, 0.5, -1.0}, 1e-6);
    check_vec(back.exit_direction, (vec3){0, 0, -1}, 1e-6);
}

/* Exit-point error against the adaptive reference, for the bump at 64 voxels. */
static double bump_exit_error(enum reftrace_stepper stepper, double step, vec3 ref)
{
    struct reftrace_object obj = analytic_object((vec3){-1, -1, -1}, (vec3){1, 1, 1}, 64, &bump);
    struct reftrace_settings s = settings_for(stepper, step);
    struct reftrace_result r;
    reftrace_ray(&obj, 1, &s, (vec3){-3.0, 0.1, 0.05}, (vec3){1, 0, 0}, &r);
    CHECK_INT(r.status, RAY_EXITED);
    return dist(r.exit_origin, ref);
}

static void halving_the_step_cuts_rk4_error_sixteenfold_and_euler_twofold(void)
{
    struct reftrace_object obj = analytic_object((vec3){-1, -1, -1}, (vec3){1, 1, 1}, 64, &bump);
    struct reftrace_settings s = settings_for(REFTRACE_ADAPTIVE, 0.5);
    s.tolerance = 1e-12;
    struct reftrace_result ref;
    reftrace_ray(&obj, 1, &s, (vec3){-3.0, 0.1, 0.05}, (vec3){1, 0, 0}, &ref);
    CHECK_INT(ref.status, RAY_EXITED);
    CHECK(fabs(ref.exit_origin.x - 1.0) < 1e-12 || fabs(fabs(ref.exit_origin.y) - 1.0) < 1e-12);

    double rk_a = bump_exit_error(REFTRACE_RK4, 1.0, ref.exit_origin);
    double rk_b = bump_exit_error(REFTRACE_RK4, 0.5, ref.exit_origin);
    double eu_a = bump_exit_error(REFTRACE_EULER, 0.5, ref.exit_origin);
    double eu_b = bump_exit_error(REFTRACE_EULER, 0.25, ref.exit_origin);
    printf("bump, 64 voxels: rk4 error %.3g (1 voxel) %.3g (1/2), ratio %.1f; "
           "euler %.3g (1/2) %.3g (1/4), ratio %.2f\n",
           rk_a, rk_b, rk_a / rk_b, eu_a, eu_b, eu_a / eu_b);
    CHECK_MSG(rk_a / rk_b > 8.0 && rk_a / rk_b < 32.0, "rk4 ratio %g", rk_a / rk_b);
    CHECK_MSG(eu_a / eu_b > 1.5 && eu_a / eu_b < 3.0, "euler ratio %g", eu_a / eu_b);
    /* A fourth-order method is far ahead of the first-order one at equal step. */
    CHECK(rk_b < 1e-3 * eu_a);
}

/* Linear GRIN n = n0 + g y: with dtau = ds / n the ray equation becomes
 * x'' = 0, y'' = g n = g^2 (y - y*), y* = -n0 / g (tevs2007 eq. 4.7 with w = n dx/ds,
 * n grad n = grad(n^2 / 2)). So w_x = a is constant and
 * y(tau) = y* + (y0 - y*) cosh(g tau) + (w_y0 / g) sinh(g tau). A ray launched slightly
 * downwards (towards lower n) turns around and leaves upwards: the mirage. */
static void linear_gradient_bends_a_grazing_ray_back_up_like_a_mirage(void)
{
    const double n0 = 1.5, gy = 0.2;
    struct grin_profile g = {.kind = GRIN_LINEAR, .n0 = n0, .gradient = {0, gy, 0}};
    struct reftrace_object obj = analytic_object((vec3){-1, -1, -1}, (vec3){1, 1, 1}, 64, &g);
    double th = 5.0 * M_PI / 180.0;
    vec3 origin = {-0.9, 0.0, 0.0};
    vec3 d = {cos(th), -sin(th), 0.0};
    double a = n0 * d.x, wy0 = n0 * d.y, ystar = -n0 / gy;
    double tau = (1.0 - origin.x) / a;
    double ye = ystar + (origin.y - ystar) * cosh(gy * tau) + wy0 / gy * sinh(gy * tau);
    double wye = gy * (origin.y - ystar) * sinh(gy * tau) + wy0 * cosh(gy * tau);
    /* Exit face x = 1 into ambient 1: the tangential part of n d (= w) is conserved. */
    vec3 exit_dir = {sqrt(1.0 - wye * wye), wye, 0.0};
    CHECK(wye > 0.0);
    /* OPL = int n ds = int n^2 dtau = g^2 int (A cosh + B sinh)^2 dtau over [0, tau],
     * A = y0 - y*, B = w_y0 / g. */
    double A = origin.y - ystar, B = wy0 / gy, gt = gy * tau;
    double opl = gy * gy *
                 (A * A * (tau / 2.0 + sinh(2.0 * gt) / (4.0 * gy)) +
                  B * B * (sinh(2.0 * gt) / (4.0 * gy) - tau / 2.0) +
                  A * B * (cosh(2.0 * gt) - 1.0) / (2.0 * gy));

    struct reftrace_settings s = settings_for(REFTRACE_ADAPTIVE, 0.5);
    struct reftrace_result r;
    reftrace_ray(&obj, 1, &s, origin, d, &r);
    CHECK_INT(r.status, RAY_EXITED);
    check_vec(r.exit_origin, (vec3){1.0, ye, 0.0}, 1e-8);
    check_vec(r.exit_direction, exit_dir, 1e-8);
    CHECK(r.exit_direction.y > 0.0);
    CHECK_NEAR(r.optical_path_length, opl, 1e-8);

    /* The fixed-step steppers turn it around too. At half a voxel RK4 is limited by
     * the straight cut of the last step (bounded by h^2 kappa / 8 ~ 4e-6; measured
     * 4e-7), Euler by its first order (measured 2e-3). */
    for (int i = 0; i < 2; i++) {
        s = settings_for(all_steppers[i], 0.5);
        reftrace_ray(&obj, 1, &s, origin, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        CHECK(r.exit_direction.y > 0.0);
        CHECK_NEAR(r.exit_origin.y, ye, i == 0 ? 1e-2 : 1e-5);
        printf("mirage, half-voxel %s: exit y error %.3g, OPL error %.3g\n",
               i == 0 ? "euler" : "rk4", r.exit_origin.y - ye, r.optical_path_length - opl);
        /* The trapezoid rule is second order; a one-sided rule would be off by about
         * h (n_exit - n_entry) / 2 = 1e-4 here. */
        if (i == 1)
            CHECK_NEAR(r.optical_path_length, opl, 5e-6);
    }
}

/* ---- absorption, emission, statuses ------------------------------------------------ */

static void constant_absorption_follows_beer_lambert(void)
{
    struct uniform_grid u;
    uniform_grid_init(&u, 8, 1.0, (vec3){1, 2, 3}, (vec3){0, 0, 0});
    struct reftrace_object obj = grid_object((vec3){0, 0, 0}, (vec3){1, 1, 1}, &u);
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = settings_for(all_steppers[i], 0.5);
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &s, (vec3){0.5, 0.5, -1}, (vec3){0, 0, 1}, &r);
        CHECK_INT(r.status, RAY_EXITED);
        CHECK_NEAR(r.transmittance.x, exp(-1.0), 1e-9);
        CHECK_NEAR(r.transmittance.y, exp(-2.0), 1e-9);
        CHECK_NEAR(r.transmittance.z, exp(-3.0), 1e-9);
    }
    uniform_grid_fini(&u);

    /* With glass faces the two Fresnel factors multiply in. */
    uniform_grid_init(&u, 8, 1.5, (vec3){0.5, 0.5, 0.5}, (vec3){0, 0, 0});
    obj = grid_object((vec3){0, 0, 0}, (vec3){1, 1, 1}, &u);
    struct reftrace_settings s = settings_for(REFTRACE_RK4, 0.5);
    struct reftrace_result r;
    reftrace_ray(&obj, 1, &s, (vec3){0.5, 0.5, -1}, (vec3){0, 0, 1}, &r);
    CHECK_NEAR(r.transmittance.x, 0.96 * 0.96 * exp(-0.5), 1e-9);
    uniform_grid_fini(&u);
}

static void enormous_absorption_stops_the_ray_as_absorbed(void)
{
    struct uniform_grid u;
    uniform_grid_init(&u, 8, 1.0, (vec3){1e6, 1e6, 1e6}, (vec3){0, 0, 0});
    struct reftrace_object obj = grid_object((vec3){0, 0, 0}, (vec3){1, 1, 1}, &u);
    struct reftrace_settings s = settings_for(REFTRACE_RK4, 0.5);
    struct reftrace_result r;
    reftrace_ray(&obj, 1, &s, (vec3){0.5, 0.5, -1}, (vec3){0, 0, 1}, &r);
    CHECK_INT(r.status, RAY_ABSORBED);
    CHECK_INT(r.steps, 1);
    CHECK_NEAR(r.exit_origin.z, 0.5 / 8.0, 1e-12); /* stopped after one half-voxel step */
    CHECK(r.transmittance.x < 1e-6);
    uniform_grid_fini(&u);
}

static void tiny_step_budget_ends_with_max_steps(void)
{
    struct uniform_grid u;
    uniform_grid_init(&u, 8, 1.0, (vec3){0, 0, 0}, (vec3){0, 0, 0});
    struct reftrace_object obj = grid_object((vec3){0, 0, 0}, (vec3){1, 1, 1}, &u);
    struct reftrace_settings s = settings_for(REFTRACE_EULER, 0.5);
    s.max_steps = 3;
    struct reftrace_result r;
    reftrace_ray(&obj, 1, &s, (vec3){0.5, 0.5, -1}, (vec3){0, 0, 1}, &r);
    CHECK_INT(r.status, RAY_MAX_STEPS);
    CHECK_INT(r.steps, 3);
    CHECK_NEAR(r.exit_origin.z, 3.0 * 0.5 / 8.0, 1e-12);
    CHECK_NEAR(r.optical_path_length, 1.0 + 3.0 * 0.5 / 8.0, 1e-12);
    uniform_grid_fini(&u);
}

static void ray_that_misses_every_object_is_missed(void)
{
    struct uniform_grid u;
    uniform_grid_init(&u, 8, 1.5, (vec3){0, 0, 0}, (vec3){0, 0, 0});
    struct reftrace_object obj = grid_object((vec3){0, 0, 0}, (vec3){1, 1, 1}, &u);
    struct reftrace_settings s = settings_for(REFTRACE_RK4, 0.5);
    s.env_intensity = 2.0;
    vec3 o = {0.5, 0.5, -1}, d = vec3_normalize((vec3){0, 1, -1});
    struct reftrace_result r;
    reftrace_ray(&obj, 1, &s, o, d, &r);
    CHECK_INT(r.status, RAY_MISSED);
    check_vec(r.exit_origin, o, 0.0);
    check_vec(r.exit_direction, d, 1e-15);
    CHECK_NEAR(r.optical_path_length, 0.0, 0.0);
    CHECK_INT(r.steps, 0);
    CHECK_NEAR(r.transmittance.x, 1.0, 0.0);
    check_vec(r.radiance, vec3_scale(env_procedural(d), 2.0), 1e-15);
    /* A box behind the origin is not hit either. */
    reftrace_ray(&obj, 1, &s, (vec3){0.5, 0.5, 2}, (vec3){0, 0, 1}, &r);
    CHECK_INT(r.status, RAY_MISSED);
    uniform_grid_fini(&u);
}

/* A (emitting, z in [0, 1]) is listed after B (absorbing, z in [2, 3]); the ray meets A
 * first, so A's emission is not attenuated by B while the background is:
 * L = L_e * 1 + env * exp(-1). Taken in the wrong order the emission would carry
 * exp(-1) too. */
static void two_boxes_on_a_line_are_crossed_in_order(void)
{
    struct uniform_grid ua, ub;
    uniform_grid_init(&ua, 8, 1.0, (vec3){0, 0, 0}, (vec3){0.5, 0.25, 0.125});
    uniform_grid_init(&ub, 8, 1.0, (vec3){1, 1, 1}, (vec3){0, 0, 0});
    struct reftrace_object objs[2] = {
        grid_object((vec3){0, 0, 2}, (vec3){1, 1, 3}, &ub),
        grid_object((vec3){0, 0, 0}, (vec3){1, 1, 1}, &ua),
    };
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = settings_for(all_steppers[i], 0.5);
        struct reftrace_result r;
        vec3 d = {0, 0, 1};
        reftrace_ray(objs, 2, &s, (vec3){0.5, 0.5, -1}, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        check_vec(r.exit_origin, (vec3){0.5, 0.5, 3}, 1e-12);
        CHECK_NEAR(r.optical_path_length, 4.0, 4e-9);
        vec3 expect = vec3_add((vec3){0.5, 0.25, 0.125}, vec3_scale(env_procedural(d), exp(-1.0)));
        check_vec(r.radiance, expect, 1e-9);
    }
    uniform_grid_fini(&ua);
    uniform_grid_fini(&ub);
}

/* n = 1, no absorption, L_e uniform over a length of 2: L = env * intensity + L_e * 2. */
static void uniform_emission_adds_radiance_times_length(void)
{
    struct uniform_grid u;
    vec3 le = {0.2, 0.3, 0.4};
    uniform_grid_init(&u, 8, 1.0, (vec3){0, 0, 0}, le);
    struct reftrace_object obj = grid_object((vec3){0, 0, 0}, (vec3){1, 1, 2}, &u);
    vec3 d = vec3_normalize((vec3){0, 0.1, 1});
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = settings_for(all_steppers[i], 0.5);
        s.env_intensity = 1.5;
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &s, (vec3){0.5, 0.4, -1}, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        double len = 2.0 / d.z;
        check_vec(r.radiance, vec3_add(vec3_scale(env_procedural(d), 1.5), vec3_scale(le, len)),
                  1e-9);
    }
    uniform_grid_fini(&u);
}

/* Object [-0.5, 0.5]^3 rotated 90 deg about y, scaled by 2, moved to (3, 0, 0) is the
 * world box [2, 4] x [-1, 1]^2; its field n0 + g . p_object is the world field
 * n0 + (R g / 2) . (x - t). Same world step (h_min scales with the bounds), so the two
 * traces agree to rounding (the OPL sums ~300 adaptive steps: 1e-9 leaves room for it). */
static void transformed_object_matches_the_equivalent_untransformed_one(void)
{
    struct xform xf = xform_make((vec3){3, 0, 0}, (vec3){0, 1, 0}, 90.0, 2.0);
    struct grin_profile g_obj = {.kind = GRIN_LINEAR, .n0 = 1.3, .gradient = {0.1, 0.2, 0.05}};
    struct grin_profile g_world = {.kind = GRIN_LINEAR,
                                   .n0 = 1.3,
                                   .center = {3, 0, 0},
                                   .gradient = xform_gradient_to_world(&xf, g_obj.gradient)};
    struct reftrace_object a =
        analytic_object((vec3){-0.5, -0.5, -0.5}, (vec3){0.5, 0.5, 0.5}, 16, &g_obj);
    a.xf = xf;
    struct reftrace_object b = analytic_object((vec3){2, -1, -1}, (vec3){4, 1, 1}, 16, &g_world);
    vec3 o = {0, 0.3, 0.2}, d = vec3_normalize((vec3){1, 0.1, -0.05});
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = settings_for(all_steppers[i], 0.5);
        struct reftrace_result ra, rb;
        reftrace_ray(&a, 1, &s, o, d, &ra);
        reftrace_ray(&b, 1, &s, o, d, &rb);
        CHECK_INT(ra.status, RAY_EXITED);
        CHECK_INT(ra.status, rb.status);
        check_vec(ra.exit_origin, rb.exit_origin, 1e-10);
        check_vec(ra.exit_direction, rb.exit_direction, 1e-10);
        CHECK_NEAR(ra.optical_path_length, rb.optical_path_length, 1e-9);
        CHECK_NEAR(ra.transmittance.x, rb.transmittance.x, 1e-12);
        if (all_steppers[i] != REFTRACE_ADAPTIVE)
            CHECK_INT(ra.steps, rb.steps);
    }

    /* Absorption is per world unit: a unit object cube scaled by 2 absorbs over 2. */
    struct uniform_grid u;
    uniform_grid_init(&u, 8, 1.2, (vec3){0.25, 0.5, 1.0}, (vec3){0, 0, 0});
    struct reftrace_object c = grid_object((vec3){-0.5, -0.5, -0.5}, (vec3){0.5, 0.5, 0.5}, &u);
    c.xf = xf;
    double R = (0.2 / 2.2) * (0.2 / 2.2);
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = settings_for(all_steppers[i], 0.5);
        struct reftrace_result r;
        reftrace_ray(&c, 1, &s, (vec3){0, 0.1, 0.2}, (vec3){1, 0, 0}, &r);
        CHECK_INT(r.status, RAY_EXITED);
        check_vec(r.exit_origin, (vec3){4, 0.1, 0.2}, 1e-12);
        CHECK_NEAR(r.optical_path_length, 2.0 + 1.2 * 2.0, 1e-9);
        CHECK_NEAR(r.transmittance.x, (1 - R) * (1 - R) * exp(-0.5), 1e-9);
        CHECK_NEAR(r.transmittance.z, (1 - R) * (1 - R) * exp(-2.0), 1e-9);
    }
    uniform_grid_fini(&u);
}

/* Opaque coverage 1 for z > 0.5 (voxel centres), 0 below: trilinear coverage reaches
 * 0.5 at z = 0.5, so the ray stops on the first step end at or beyond it, sees
 * R env(reflect) + (1 - R) colour with R = 0.04 (n = 1 against opaque_ior 1.5 at
 * normal incidence, normal from the coverage gradient) and ends absorbed. */
static void opaque_embedding_stops_the_ray_and_shows_its_colour(void)
{
    struct uniform_grid u;
    uniform_grid_init(&u, 8, 1.0, (vec3){0, 0, 0}, (vec3){0, 0, 0});
    double *opq = malloc(sizeof(double) * 4 * 512);
    for (int i = 0; i < 512; i++) {
        int z = i / 64;
        opq[4 * i + 0] = 0.2;
        opq[4 * i + 1] = 0.4;
        opq[4 * i + 2] = 0.6;
        opq[4 * i + 3] = z >= 4 ? 1.0 : 0.0;
    }
    u.grid.opaque = opq;
    struct reftrace_object obj = grid_object((vec3){0, 0, 0}, (vec3){1, 1, 1}, &u);
    struct reftrace_settings s = settings_for(REFTRACE_RK4, 0.5);
    struct reftrace_result r;
    reftrace_ray(&obj, 1, &s, (vec3){0.5, 0.5, -1}, (vec3){0, 0, 1}, &r);
    CHECK_INT(r.status, RAY_ABSORBED);
    CHECK(r.exit_origin.z >= 0.5 && r.exit_origin.z < 0.5 + 0.5 / 8.0 + 1e-12);
    vec3 expect = vec3_add(vec3_scale(env_procedural((vec3){0, 0, -1}), 0.04),
                           vec3_scale((vec3){0.2, 0.4, 0.6}, 0.96));
    check_vec(r.radiance, expect, 1e-12);
    free(opq);
    uniform_grid_fini(&u);
}

/* ---- voxelised fields ---------------------------------------------------------------- */

/* A voxel grid from n(x) at the voxel centres, smoothed and differentiated exactly as
 * the scene loader does (docs/tracing.md "Precomputation"). Returns ior_grad; the
 * caller frees it. */
static double *voxelise(const struct grin_profile *g, int res, double sigma, double n_in_ball,
                        double ball_radius)
{
    size_t count = (size_t)res * res * res;
    float *n = malloc(sizeof(float) * count);
    double *sm = malloc(sizeof(double) * count);
    double *out = malloc(sizeof(double) * 4 * count);
    double vs = 2.0 / res;
    for (int z = 0; z < res; z++)
        for (int y = 0; y < res; y++)
            for (int x = 0; x < res; x++) {
                vec3 p = {-1 + (x + 0.5) * vs, -1 + (y + 0.5) * vs, -1 + (z + 0.5) * vs};
                double v = g != NULL ? grin_ior(g, p, NULL)
                                     : (vec3_length(p) < ball_radius ? n_in_ball : 1.0);
                n[(size_t)x + (size_t)res * ((size_t)y + (size_t)res * z)] = (float)v;
            }
    const int r3[3] = {res, res, res};
    smooth_gaussian_ref(n, r3, sigma, sm);
    gradient_central_ref(sm, r3, (vec3){vs, vs, vs}, out);
    free(n);
    free(sm);
    return out;
}

/* A sharp glass ball (n = 1.5, radius 0.5) in a 64^3 grid, smoothed with sigma = 1
 * voxel: a ray through the centre meets each interface at normal incidence, so the
 * boundary events reflect 4 % each, once per crossing thanks to the hysteresis:
 * T = 0.96^2 to the accuracy of the probed indices. Rays through any part of the ball
 * keep T in [0, 1]. */
static void sharp_ball_reflects_fresnel_share_once_per_crossing(void)
{
    double *ig = voxelise(NULL, 64, 1.0, 1.5, 0.5);
    struct reftrace_grid grid = {.ior_grad = ig};
    struct reftrace_object obj = {.bmin = {-1, -1, -1},
                                  .bmax = {1, 1, 1},
                                  .res = {64, 64, 64},
                                  .xf = xform_identity(),
                                  .smoothing_sigma_voxels = 1.0,
                                  .grid = &grid};
    struct reftrace_settings s = settings_for(REFTRACE_RK4, 0.5);
    struct reftrace_result r;
    reftrace_ray(&obj, 1, &s, (vec3){0.001, 0.002, -3}, (vec3){0, 0, 1}, &r);
    CHECK_INT(r.status, RAY_EXITED);
    CHECK_NEAR(r.transmittance.x, 0.96 * 0.96, 2e-3);
    printf("sharp ball, 64 voxels, sigma 1: T through the centre %.6f (0.96^2 = 0.9216)\n",
           r.transmittance.x);
    int bad = 0;
    for (int k = 0; k < 200; k++) {
        double y = -0.6 + 1.2 * k / 199.0;
        reftrace_ray(&obj, 1, &s, (vec3){0.05, y, -3}, vec3_normalize((vec3){0.02, 0, 1}), &r);
        vec3 t = r.transmittance;
        if (!(t.x >= 0.0 && t.x <= 1.0 && vec3_is_finite(r.radiance)) || r.status != RAY_EXITED)
            bad++;
    }
    CHECK_INT(bad, 0);
    free(ig);
}

/* A steep linear ramp (n = 1.3 + 0.2 y at 16^3: 0.025 per voxel, above the 0.02 boundary
 * threshold) is a smooth field, not an interface: crossing its zone must add no Fresnel
 * event, even at grazing incidence to grad n (where a spurious one would reflect 80%).
 * So T equals the trace with zones disabled, i.e. only the two bounds faces reflect.
 * The same test keeps true interfaces: an unsmoothed ball still loses 4% per crossing. */
static void steep_ramp_has_no_interface_but_a_sharp_ball_does(void)
{
    double *ig =
        voxelise(&(struct grin_profile){.kind = GRIN_LINEAR, .n0 = 1.3, .gradient = {0, 0.2, 0}},
                 16, 0.0, 0, 0);
    struct reftrace_grid grid = {.ior_grad = ig};
    struct reftrace_object ramp = {.bmin = {-1, -1, -1},
                                   .bmax = {1, 1, 1},
                                   .res = {16, 16, 16},
                                   .xf = xform_identity(),
                                   .grid = &grid};
    for (int i = 0; i < 2; i++) {
        struct reftrace_settings s = settings_for(all_steppers[i], 0.5), off = s;
        off.boundary_threshold = 10.0;
        struct reftrace_result with_zones, without;
        for (int k = 0; k < 5; k++) {
            vec3 o = {0.1 * k, -0.5 + 0.2 * k, -3};
            reftrace_ray(&ramp, 1, &s, o, (vec3){0, 0, 1}, &with_zones);
            reftrace_ray(&ramp, 1, &off, o, (vec3){0, 0, 1}, &without);
            CHECK_INT(with_zones.status, RAY_EXITED);
            CHECK_NEAR(with_zones.transmittance.x, without.transmittance.x, 1e-12);
            CHECK_MSG(with_zones.transmittance.x > 0.9, "ray %d T %g", k,
                      with_zones.transmittance.x);
        }
    }
    free(ig);

    double *ball = voxelise(NULL, 64, 0.0, 1.5, 0.5);
    struct reftrace_grid bg = {.ior_grad = ball};
    struct reftrace_object obj = {.bmin = {-1, -1, -1},
                                  .bmax = {1, 1, 1},
                                  .res = {64, 64, 64},
                                  .xf = xform_identity(),
                                  .grid = &bg};
    struct reftrace_settings s = settings_for(REFTRACE_RK4, 0.5);
    struct reftrace_result r;
    reftrace_ray(&obj, 1, &s, (vec3){0.001, 0.002, -3}, (vec3){0, 0, 1}, &r);
    CHECK_INT(r.status, RAY_EXITED);
    CHECK_NEAR(r.transmittance.x, 0.96 * 0.96, 2e-3);
    free(ball);
}

/* Measurement, not a closed form: Euler and RK4 at half a voxel on a 128^3 Luneburg
 * grid (no smoothing, central-difference gradient) against the analytic focus. The
 * bounds only guard against regressions; the printed numbers are what to compare. */
static void luneburg_grid_at_128_voxels_focuses_near_the_analytic_point(void)
{
    struct grin_profile g = luneburg;
    double *ig = voxelise(&g, 128, 0.0, 0.0, 0.0);
    struct reftrace_grid grid = {.ior_grad = ig};
    struct reftrace_object obj = {.bmin = {-1, -1, -1},
                                  .bmax = {1, 1, 1},
                                  .res = {128, 128, 128},
                                  .xf = xform_identity(),
                                  .grid = &grid};
    double worst[2] = {0, 0}, mean[2] = {0, 0};
    for (int i = 0; i < 2; i++) {
        struct reftrace_settings s = settings_for(all_steppers[i], 0.5);
        for (int k = 1; k <= 9; k++) {
            struct reftrace_result r;
            reftrace_ray(&obj, 1, &s, (vec3){0, 0.1 * k, -3}, (vec3){0, 0, 1}, &r);
            CHECK_INT(r.status, RAY_EXITED);
            double e = dist(r.exit_origin, (vec3){0, 0, 1});
            worst[i] = fmax(worst[i], e);
            mean[i] += e / 9.0;
        }
    }
    printf("luneburg 128^3 grid, step 0.5 voxel: euler focus miss worst %.3g mean %.3g R; "
           "rk4 worst %.3g mean %.3g R\n",
           worst[0], mean[0], worst[1], mean[1]);
    CHECK(worst[0] < 0.1);
    CHECK(worst[1] < 0.05);
    free(ig);
}

int main(void)
{
    uniform_field_ray_goes_straight_and_opl_is_n_times_length();
    parallel_grin_slab_refracts_per_snell_and_exits_parallel();
    ray_inside_glass_totally_reflects_at_a_steep_face();
    luneburg_focuses_parallel_rays_on_the_far_side();
    luneburg_focuses_an_oblique_bundle_on_the_antipode_of_its_direction();
    maxwell_fisheye_images_a_surface_point_on_its_antipode();
    reversed_exit_ray_retraces_its_path();
    halving_the_step_cuts_rk4_error_sixteenfold_and_euler_twofold();
    linear_gradient_bends_a_grazing_ray_back_up_like_a_mirage();
    constant_absorption_follows_beer_lambert();
    enormous_absorption_stops_the_ray_as_absorbed();
    tiny_step_budget_ends_with_max_steps();
    ray_that_misses_every_object_is_missed();
    two_boxes_on_a_line_are_crossed_in_order();
    opaque_embedding_stops_the_ray_and_shows_its_colour();
    uniform_emission_adds_radiance_times_length();
    transformed_object_matches_the_equivalent_untransformed_one();
    sharp_ball_reflects_fresnel_share_once_per_crossing();
    steep_ramp_has_no_interface_but_a_sharp_ball_does();
    luneburg_grid_at_128_voxels_focuses_near_the_analytic_point();
    return test_summary("test_reftrace");
}
