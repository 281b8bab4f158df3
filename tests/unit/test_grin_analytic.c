/*
 * test_grin_analytic.c - the references of the accuracy report (docs/accuracy.md)
 * against closed forms, on exact continuous fields (no voxels):
 *   - optics_sphere_transmit (the Snell reference of the sharp-sphere cases): its
 *     deviation 2 (theta_i - theta_t), exit point on the sphere, paraxial focus
 *     f = n R / (2 (n - 1)) from the centre, for n = 1.5 and 2.42;
 *   - the adaptive Dormand-Prince reference through a steep but smooth sphere (a tanh
 *     step of width eps) converges to that Snell ray as eps shrinks: the ray equation
 *     reproduces Snell's law in the limit the report's smoothed spheres approach;
 *   - the same reference through a strong Gaussian lens (n_peak = 2) against the
 *     deflection integral of a spherically symmetric medium (Bouguer's invariant
 *     n r sin(psi) = b), evaluated by quadrature, independent of any ODE solver.
 * The Luneburg focus, the fish-eye antipode and the mirage's closed-form trajectory are
 * checked in test_reftrace.c with the same reference settings.
 *
 * Tolerances: 1e-12 for the closed form's own identities (rounding); Dormand-Prince at
 * 1e-11 per step against the quadrature: 1e-7 rad (the quadrature is good to 1e-10);
 * the tanh sphere's error is O(eps) (the interface has a thickness), so the bound is
 * 3 eps / R rad, and it must fall by > 2.5x when eps falls 4x.
 */
#include <math.h>
#include <stdio.h>

#include "core/grin.h"
#include "core/optics_exact.h"
#include "core/reftrace.h"
#include "test.h"

static double angle_between(vec3 a, vec3 b)
{
    double c = vec3_dot(vec3_normalize(a), vec3_normalize(b));
    return acos(fmax(-1.0, fmin(1.0, c)));
}

static struct reftrace_settings dopri(double tolerance)
{
    return (struct reftrace_settings){
        .stepper = REFTRACE_ADAPTIVE,
        .step_voxels = 1.0,
        .max_steps = 10000000,
        .boundary_threshold = 1e9, /* no Fresnel events: only the path matters here */
        .ambient_ior = 1.0,
        .tolerance = tolerance,
        .env_intensity = 1.0,
    };
}

/* ---- the closed form itself ------------------------------------------------------ */

static void sphere_closed_form_deviates_by_twice_the_refraction_angle(void)
{
    const double R = 0.8, ns[2] = {1.5, 2.42};
    for (int k = 0; k < 2; k++) {
        double n = ns[k];
        for (double b = 0.05; b < 0.95 * R; b += 0.1) {
            vec3 o = {b, 0, -3}, d = {0, 0, 1}, x, t;
            CHECK(optics_sphere_transmit((vec3){0, 0, 0}, R, n, 1.0, o, d, &x, &t));
            double ti = asin(b / R), tt = asin(b / (n * R));
            CHECK_NEAR(angle_between(t, d), 2.0 * (ti - tt), 1e-12);
            CHECK(t.x < 0.0); /* towards the axis: a converging ball */
            CHECK_NEAR(vec3_length(x), R, 1e-12);
            /* The exit point: the chord turns the polar angle by pi - 2 theta_t. */
            /* The entry point sits at polar angle pi - theta_i (from +z towards +x); the
             * chord turns it by pi - 2 theta_t. */
            CHECK_NEAR(atan2(x.x, x.z), 2.0 * tt - ti, 1e-12);
        }
        /* Paraxial focus of a ball lens, measured from its centre. */
        double b = 1e-4 * R;
        vec3 x, t;
        CHECK(optics_sphere_transmit((vec3){0, 0, 0}, R, n, 1.0, (vec3){b, 0, -3}, (vec3){0, 0, 1},
                                     &x, &t));
        double z_axis = x.z - x.x * t.z / t.x;
        CHECK_NEAR(z_axis, n * R / (2.0 * (n - 1.0)), 1e-6 * R);
    }
    vec3 x = {7, 7, 7}, t = x;
    CHECK(!optics_sphere_transmit((vec3){0, 0, 0}, 0.8, 1.5, 1.0, (vec3){0.9, 0, -3},
                                  (vec3){0, 0, 1}, &x, &t));
    CHECK(x.x == 7.0 && t.x == 7.0);
}

/* ---- a steep smooth sphere approaches Snell ------------------------------------- */

struct tanh_ball {
    double radius, n_in, eps; /* n = 1 + (n_in - 1) (1 - tanh((r - R) / eps)) / 2 */
};

static double tanh_ball_ior(void *ctx, vec3 p, vec3 *grad)
{
    const struct tanh_ball *b = ctx;
    double r = vec3_length(p);
    double th = tanh((r - b->radius) / b->eps);
    double dn_dr = -(b->n_in - 1.0) * 0.5 * (1.0 - th * th) / b->eps;
    *grad = r > 0.0 ? vec3_scale(p, dn_dr / r) : (vec3){0, 0, 0};
    return 1.0 + (b->n_in - 1.0) * 0.5 * (1.0 - th);
}

static struct reftrace_object field_object(double half, reftrace_ior_fn fn, void *ctx)
{
    return (struct reftrace_object){
        .bmin = {-half, -half, -half},
        .bmax = {half, half, half},
        .res = {256, 256, 256},
        .xf = xform_identity(),
        .opaque_ior = 1.5,
        .ior = fn,
        .ior_ctx = ctx,
    };
}

/* Worst exit-direction error over a bundle, against the Snell closed form. */
static double tanh_ball_worst_error(double n, double eps)
{
    struct tanh_ball ball = {.radius = 0.8, .n_in = n, .eps = eps};
    struct reftrace_object o = field_object(1.0, tanh_ball_ior, &ball);
    struct reftrace_settings st = dopri(1e-10);
    double worst = 0.0;
    for (double b = 0.04; b < 0.6; b += 0.08) {
        vec3 org = {b, 0.3 * b, -3}, d = {0, 0, 1}, x, t;
        CHECK(optics_sphere_transmit((vec3){0, 0, 0}, 0.8, n, 1.0, org, d, &x, &t));
        struct reftrace_result r;
        reftrace_ray(&o, 1, &st, org, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        worst = fmax(worst, angle_between(r.exit_direction, t));
    }
    return worst;
}

static void dopri_through_a_steep_smooth_sphere_converges_to_snell(void)
{
    const double ns[2] = {1.5, 2.42};
    for (int k = 0; k < 2; k++) {
        double coarse = tanh_ball_worst_error(ns[k], 0.008);
        double fine = tanh_ball_worst_error(ns[k], 0.002);
        printf("tanh sphere n = %.2f: worst direction error %.3g rad (eps 0.008), %.3g (eps "
               "0.002)\n",
               ns[k], coarse, fine);
        CHECK_MSG(fine <= 3.0 * 0.002 / 0.8, "fine %g", fine);
        CHECK_MSG(coarse > 2.5 * fine, "coarse %g fine %g", coarse, fine);
    }
}

/* ---- a strong Gaussian lens against the deflection integral -------------------- */

static const struct grin_profile strong_gaussian = {
    .kind = GRIN_GAUSSIAN, .n_peak = 2.0, .n_out = 1.0, .sigma = 0.2};

static double n_of_r(double r)
{
    vec3 g;
    return grin_ior(&strong_gaussian, (vec3){r, 0, 0}, &g);
}

/* d(n^2 r^2)/dr, from the profile's exact gradient. */
static double dn2r2_dr(double r)
{
    vec3 g;
    double n = grin_ior(&strong_gaussian, (vec3){r, 0, 0}, &g);
    return 2.0 * n * r * (n + r * g.x);
}

/* The turning radius: n(r) r = b (n r rises monotonically: n + r n' > 0 for n_peak -
 * n_out < e). */
static double turning_radius(double b, double r_far)
{
    double lo = 0.0, hi = r_far;
    for (int i = 0; i < 200; i++) {
        double mid = 0.5 * (lo + hi);
        if (n_of_r(mid) * mid < b)
            lo = mid;
        else
            hi = mid;
    }
    return 0.5 * (lo + hi);
}

/* The polar angle a ray of impact parameter b sweeps, 2 int_{r_min}^inf b dr / (r
 * sqrt(n^2 r^2 - b^2)), split at r_far beyond which n = 1 (closed form asin(b / r_far)).
 * Below r_far, r = r_min + u^2 removes the inverse square root; composite Simpson. The
 * deflection of the direction is pi minus the sweep (negative: towards the axis). */
static double gaussian_deflection(double b, double r_far)
{
    double r_min = turning_radius(b, r_far);
    double u_max = sqrt(r_far - r_min);
    enum { N = 4000 };
    double sum = 0.0;
    for (int i = 0; i <= N; i++) {
        double u = u_max * i / N, r = r_min + u * u, f;
        if (i == 0)
            f = 2.0 * b / (r_min * sqrt(dn2r2_dr(r_min)));
        else
            f = 2.0 * u * b / (r * sqrt(fmax(n_of_r(r) * n_of_r(r) * r * r - b * b, 1e-300)));
        double wgt = (i == 0 || i == N) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        sum += wgt * f;
    }
    double inner = sum * (u_max / N) / 3.0;
    double sweep = 2.0 * (inner + asin(b / r_far));
    return M_PI - sweep;
}

static double grin_fn(void *ctx, vec3 p, vec3 *grad)
{
    return grin_ior(ctx, p, grad);
}

static void dopri_through_a_strong_gaussian_lens_matches_the_deflection_integral(void)
{
    /* Bounds at 6 sigma: n - 1 = 1.5e-8 there, so the faces refract by nothing. */
    struct reftrace_object o = field_object(1.2, grin_fn, (void *)&strong_gaussian);
    struct reftrace_settings st = dopri(1e-11);
    double worst = 0.0, worst_l = 0.0;
    for (double b = 0.04; b < 0.6; b += 0.04) {
        vec3 org = {b, 0, -3}, d = {0, 0, 1};
        struct reftrace_result r;
        reftrace_ray(&o, 1, &st, org, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        double expect = gaussian_deflection(b, 1.2);
        double got = atan2(r.exit_direction.x, r.exit_direction.z);
        worst = fmax(worst, fabs(got - expect));
        /* The exit ray keeps the impact parameter: |x cross d| = b (n = 1 at both ends). */
        worst_l = fmax(worst_l, fabs(vec3_length(vec3_cross(r.exit_origin, r.exit_direction)) - b));
    }
    printf("strong gaussian (n_peak 2, sigma 0.2): worst deflection error %.3g rad, impact "
           "parameter %.3g\n",
           worst, worst_l);
    CHECK_MSG(worst < 1e-7, "deflection error %g", worst);
    CHECK_MSG(worst_l < 1e-7, "impact parameter error %g", worst_l);
    /* The lens is strong: the ray at b = 0.2 = sigma turns by more than 0.5 rad. */
    CHECK(gaussian_deflection(0.2, 1.2) < -0.5);
}

int main(void)
{
    sphere_closed_form_deviates_by_twice_the_refraction_angle();
    dopri_through_a_steep_smooth_sphere_converges_to_snell();
    dopri_through_a_strong_gaussian_lens_matches_the_deflection_integral();
    return test_summary("test_grin_analytic");
}
