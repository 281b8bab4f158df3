/*
 * test_fresnel.c - Fresnel reflectance and Snell refraction against closed forms
 * (frisvad2010, "The Fresnel equations for reflection", "The law of refraction").
 *
 * Tolerances: 1e-12 where the closed form is evaluated in the same double arithmetic
 * (a few ulp of rounding on values of order 1); 1e-9 for quantities that pass through
 * sqrt/asin near their sensitive ends.
 */
#include <math.h>
#include <stdlib.h>

#include "core/fresnel.h"
#include "test.h"

static double deg(double d)
{
    return d * M_PI / 180.0;
}

/* ((n_i - n_t) / (n_i + n_t))^2 = (0.5 / 2.5)^2 = 0.04 */
static void normal_incidence_glass_reflects_four_percent(void)
{
    CHECK_NEAR(fresnel_unpolarized(1.0, 1.0, 1.5), 0.04, 1e-12);
}

static void normal_incidence_is_symmetric_in_the_two_indices(void)
{
    CHECK_NEAR(fresnel_unpolarized(1.0, 1.5, 1.0), 0.04, 1e-12);
    CHECK_NEAR(fresnel_unpolarized(1.0, 1.33, 1.0), fresnel_unpolarized(1.0, 1.0, 1.33), 1e-12);
}

/* At Brewster's angle r_par = 0, so R = R_perp / 2 with the closed form
 * R_perp = ((n_i cos_i - n_t cos_t) / (n_i cos_i + n_t cos_t))^2 and, since
 * theta_i + theta_t = 90 deg there, cos_t = sin_i. */
static void brewster_angle_reflects_only_perpendicular_polarisation(void)
{
    const double pairs[3][2] = {{1.0, 1.5}, {1.5, 1.0}, {1.0, 2.4}};
    for (int i = 0; i < 3; i++) {
        double n_i = pairs[i][0], n_t = pairs[i][1];
        double tb = fresnel_brewster_angle(n_i, n_t);
        CHECK_NEAR(tb, atan(n_t / n_i), 1e-15);
        double ci = cos(tb), ct = sin(tb);
        double r_perp = (n_i * ci - n_t * ct) / (n_i * ci + n_t * ct);
        CHECK_NEAR(fresnel_unpolarized(ci, n_i, n_t), 0.5 * r_perp * r_perp, 1e-12);
    }
}

static void beyond_the_critical_angle_reflection_is_total(void)
{
    double tc = fresnel_critical_angle(1.5, 1.0);
    CHECK_NEAR(tc, asin(1.0 / 1.5), 1e-15);
    CHECK(tc < deg(42.0) && tc > deg(41.0)); /* 41.81 deg */
    CHECK(fresnel_unpolarized(cos(deg(42.0)), 1.5, 1.0) == 1.0);
    CHECK(fresnel_unpolarized(cos(deg(60.0)), 1.5, 1.0) == 1.0);
    /* Just below the critical angle light still gets through. */
    CHECK(fresnel_unpolarized(cos(deg(41.5)), 1.5, 1.0) < 1.0);
    CHECK(isnan(fresnel_critical_angle(1.0, 1.5)));
    CHECK(isnan(fresnel_critical_angle(1.5, 1.5)));
}

static void grazing_incidence_reflects_everything(void)
{
    CHECK_NEAR(fresnel_unpolarized(0.0, 1.0, 1.5), 1.0, 1e-12);
    /* Approaches 1 monotonically over the last degrees. */
    double prev = 0.0;
    for (double a = 80.0; a <= 89.999; a += 0.5) {
        double R = fresnel_unpolarized(cos(deg(a)), 1.0, 1.5);
        CHECK_MSG(R > prev, "R(%g deg) = %g not above %g", a, R, prev);
        prev = R;
    }
    CHECK(fresnel_unpolarized(cos(deg(89.9)), 1.0, 1.5) > 0.98);
}

static void reflectance_stays_in_unit_interval_over_a_sweep(void)
{
    const double ns[5] = {1.0, 1.2, 1.333, 1.5, 2.4};
    int bad = 0;
    for (int a = 0; a < 5; a++) {
        for (int b = 0; b < 5; b++) {
            for (int k = 0; k <= 1000; k++) {
                double R = fresnel_unpolarized(k / 1000.0, ns[a], ns[b]);
                if (!(R >= 0.0 && R <= 1.0))
                    bad++;
            }
        }
    }
    CHECK_INT(bad, 0);
    /* Equal indices: no interface, nothing reflected. */
    CHECK_NEAR(fresnel_unpolarized(0.3, 1.5, 1.5), 0.0, 1e-15);
}

/* n_i sin_i = n_t sin_t, |t| = 1, t in the plane of d and N, and t on the far side. */
static void snell_vector_form_obeys_the_law_of_refraction(void)
{
    vec3 nrm = vec3_normalize((vec3){0.2, 1.0, -0.3});
    vec3 tangent = vec3_normalize(vec3_cross(nrm, (vec3){1, 0, 0}));
    const double n_pairs[3][2] = {{1.0, 1.5}, {1.5, 1.0}, {1.0, 1.333}};
    for (int p = 0; p < 3; p++) {
        double n_i = n_pairs[p][0], n_t = n_pairs[p][1];
        for (int a = 0; a < 40; a++) {
            double th = deg(a);
            vec3 d = vec3_add(vec3_scale(nrm, -cos(th)), vec3_scale(tangent, sin(th)));
            vec3 t;
            if (!snell_refract(d, nrm, n_i, n_t, &t)) {
                CHECK_MSG(false, "no transmission at %d deg, %g -> %g", a, n_i, n_t);
                continue;
            }
            double sin_i = vec3_length(vec3_cross(d, nrm));
            double sin_t = vec3_length(vec3_cross(t, nrm));
            CHECK_NEAR(n_i * sin_i, n_t * sin_t, 1e-12);
            CHECK_NEAR(vec3_length(t), 1.0, 1e-14);
            /* Coplanar: t . (d x N) = 0. */
            CHECK_NEAR(vec3_dot(t, vec3_cross(d, nrm)), 0.0, 1e-14);
            CHECK(vec3_dot(t, nrm) < 0.0); /* continues through the surface */
            /* Same tangential side as the incident ray. */
            CHECK(a == 0 || vec3_dot(t, tangent) > 0.0);
        }
    }
}

static void snell_refuses_beyond_the_critical_angle(void)
{
    vec3 nrm = {0, 0, 1};
    vec3 t = {7, 7, 7};
    vec3 d60 = {sin(deg(60.0)), 0, -cos(deg(60.0))};
    CHECK(!snell_refract(d60, nrm, 1.5, 1.0, &t));
    CHECK(t.x == 7 && t.y == 7 && t.z == 7); /* left untouched */
    vec3 d40 = {sin(deg(40.0)), 0, -cos(deg(40.0))};
    CHECK(snell_refract(d40, nrm, 1.5, 1.0, &t));
}

static void snell_does_not_depend_on_normal_orientation(void)
{
    vec3 nrm = vec3_normalize((vec3){0.1, 0.3, 1.0});
    vec3 d = vec3_normalize((vec3){0.5, -0.2, -0.8});
    vec3 t1, t2;
    CHECK(snell_refract(d, nrm, 1.0, 1.5, &t1));
    CHECK(snell_refract(d, vec3_scale(nrm, -1.0), 1.0, 1.5, &t2));
    CHECK_NEAR(t1.x, t2.x, 1e-15);
    CHECK_NEAR(t1.y, t2.y, 1e-15);
    CHECK_NEAR(t1.z, t2.z, 1e-15);
    /* Normal incidence goes straight through. */
    vec3 t3;
    CHECK(snell_refract(vec3_scale(nrm, -1.0), nrm, 1.0, 1.5, &t3));
    CHECK_NEAR(vec3_dot(t3, nrm), -1.0, 1e-15);
}

int main(void)
{
    normal_incidence_glass_reflects_four_percent();
    normal_incidence_is_symmetric_in_the_two_indices();
    brewster_angle_reflects_only_perpendicular_polarisation();
    beyond_the_critical_angle_reflection_is_total();
    grazing_incidence_reflects_everything();
    reflectance_stays_in_unit_interval_over_a_sweep();
    snell_vector_form_obeys_the_law_of_refraction();
    snell_refuses_beyond_the_critical_angle();
    snell_does_not_depend_on_normal_orientation();
    return test_summary("test_fresnel");
}
