/*
 * test_phase_brdf.c - the phase function and the BRDFs of the light-dependent terms
 * (core/phase.c, core/brdf.c; docs/tracing.md "Light") against their defining integrals:
 * Henyey-Greenstein is normalised over the sphere and its mean cosine is g (tevs2007 eq.
 * 5.5); Lambert reflects exactly its albedo, normalised Phong exactly 1 at normal view and
 * less elsewhere; the GGX distribution is normalised (integral of D cos_h = 1) and GGX with
 * Smith G never reflects more than it receives (white furnace, F = 1); every BRDF is
 * reciprocal.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bindings.h"
#include "core/brdf.h"
#include "core/phase.h"
#include "test.h"

/* Simpson's rule of p_HG(g, mu) * mu^k over mu in [-1, 1], times 2 pi (azimuth). */
static double hg_moment(double g, int k)
{
    const int n = 200000; /* even */
    double h = 2.0 / n, sum = 0.0;
    for (int i = 0; i <= n; i++) {
        double mu = -1.0 + i * h;
        double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        sum += w * phase_hg(g, mu) * pow(mu, k);
    }
    return 2.0 * M_PI * sum * h / 3.0;
}

static void henyey_greenstein_is_normalised_and_its_mean_cosine_is_g(void)
{
    const double gs[] = {-0.8, 0.0, 0.5, 0.9};
    for (size_t i = 0; i < sizeof gs / sizeof gs[0]; i++) {
        double norm = hg_moment(gs[i], 0), mean = hg_moment(gs[i], 1);
        printf("HG g = %+.1f: integral %.9f, mean cosine %.9f\n", gs[i], norm, mean);
        CHECK_NEAR(norm, 1.0, 1e-7);
        CHECK_NEAR(mean, gs[i], 1e-7);
    }
    CHECK_NEAR(phase_hg(0.0, 0.3), 1.0 / (4.0 * M_PI), 1e-15);
    CHECK(phase_hg(0.5, 1.0) > phase_hg(0.5, -1.0)); /* g > 0 scatters forward */
}

/* Directional albedo: the integral over the hemisphere of f_r(v, l) cos_i dl, by the
 * midpoint rule in (theta, phi) with the given number of cells. */
static double albedo(const struct brdf_params *b, double theta_v, int cells)
{
    vec3 n = {0, 0, 1};
    vec3 v = {sin(theta_v), 0, cos(theta_v)};
    double dt = 0.5 * M_PI / cells, dp = 2.0 * M_PI / cells, sum = 0.0;
    for (int i = 0; i < cells; i++) {
        double t = (i + 0.5) * dt, st = sin(t), ct = cos(t);
        for (int j = 0; j < cells; j++) {
            double p = (j + 0.5) * dp;
            vec3 l = {st * cos(p), st * sin(p), ct};
            double f[3];
            brdf_eval(b, v, l, n, f);
            sum += f[0] * ct * st;
        }
    }
    return sum * dt * dp;
}

static void lambert_reflects_its_albedo(void)
{
    struct brdf_params b = {.kind = BRDF_LAMBERT, .color = {1, 1, 1}};
    double a0 = albedo(&b, 0.0, 400), a60 = albedo(&b, M_PI / 3.0, 400);
    printf("Lambert albedo: %.6f (normal view), %.6f (60 deg)\n", a0, a60);
    CHECK_NEAR(a0, 1.0, 1e-4);
    CHECK_NEAR(a60, 1.0, 1e-4);
    b.color[0] = 0.25;
    double f[3];
    brdf_eval(&b, (vec3){0, 0, 1}, (vec3){0, 0.6, 0.8}, (vec3){0, 0, 1}, f);
    CHECK_NEAR(f[0], 0.25 / M_PI, 1e-15);
    CHECK_NEAR(f[1], 1.0 / M_PI, 1e-15);
}

/* Normalised Phong: at normal view the lobe lies inside the hemisphere and its albedo is
 * (e + 2) / (2 pi) * 2 pi / (e + 2) = 1; oblique views lose the part below the horizon. */
static void normalised_phong_never_exceeds_one(void)
{
    const double es[] = {1.0, 20.0, 200.0};
    for (size_t i = 0; i < 3; i++) {
        struct brdf_params b = {.kind = BRDF_PHONG, .color = {1, 1, 1}, .exponent = es[i]};
        int cells = es[i] > 100 ? 1600 : 600;
        double a0 = albedo(&b, 0.0, cells), a70 = albedo(&b, 70.0 * M_PI / 180.0, cells);
        printf("Phong e = %.0f: albedo %.6f (normal view), %.6f (70 deg)\n", es[i], a0, a70);
        CHECK_NEAR(a0, 1.0, 2e-3);
        CHECK(a70 < 1.0 + 1e-3);
        CHECK(a70 > 0.3);
    }
}

static void ggx_distribution_is_normalised_and_ggx_conserves_energy(void)
{
    const double alphas[] = {0.1, 0.3, 0.7, 1.0};
    for (size_t i = 0; i < 4; i++) {
        double a = alphas[i];
        /* integral of D(h) cos_h over the hemisphere of h = 1. */
        const int n = 200000;
        double dt = 0.5 * M_PI / n, sum = 0.0;
        for (int k = 0; k < n; k++) {
            double t = (k + 0.5) * dt;
            sum += brdf_ggx_d(a, cos(t)) * cos(t) * sin(t);
        }
        double norm = 2.0 * M_PI * sum * dt;
        struct brdf_params b = {.kind = BRDF_GGX, .color = {1, 1, 1}, .alpha = a};
        int cells = a < 0.2 ? 1600 : 600;
        double a0 = albedo(&b, 0.0, cells), a60 = albedo(&b, M_PI / 3.0, cells);
        double a85 = albedo(&b, 85.0 * M_PI / 180.0, cells);
        printf("GGX alpha = %.1f: integral of D cos_h %.7f; white furnace albedo %.5f (0 deg), "
               "%.5f (60 deg), %.5f (85 deg)\n",
               a, norm, a0, a60, a85);
        CHECK_NEAR(norm, 1.0, 1e-5);
        /* Smith G only removes energy; a single-scattering microfacet model loses more as
         * roughness grows. At alpha = 1, D = 1 / pi and G1(c) = 2 c / (c + 1), so the
         * albedo at normal view is the closed form integral_0^1 mu / (1 + mu) d mu * 2 =
         * 1 - ln 2; at alpha = 0.1 almost nothing is lost. */
        CHECK(a0 <= 1.0 + 2e-3 && a60 <= 1.0 + 2e-3 && a85 <= 1.0 + 2e-3);
        if (a == 1.0)
            CHECK_NEAR(a0, 1.0 - log(2.0), 1e-4);
        if (a == 0.1)
            CHECK(a0 > 0.98 && a60 > 0.95);
        CHECK(a85 > 0.3);
    }
}

static vec3 random_dir(unsigned *seed)
{
    for (;;) {
        vec3 v;
        *seed = *seed * 1103515245u + 12345u;
        v.x = (*seed >> 8) / 8388608.0 - 1.0;
        *seed = *seed * 1103515245u + 12345u;
        v.y = (*seed >> 8) / 8388608.0 - 1.0;
        *seed = *seed * 1103515245u + 12345u;
        v.z = (*seed >> 8) / 8388608.0;
        double l = vec3_length(v);
        if (l > 0.1 && l <= 1.0)
            return vec3_scale(v, 1.0 / l);
    }
}

static void every_brdf_is_reciprocal(void)
{
    unsigned seed = 7;
    vec3 n = {0, 0, 1};
    const struct brdf_params bs[] = {
        {.kind = BRDF_LAMBERT, .color = {1, 1, 1}},
        {.kind = BRDF_PHONG, .color = {1, 1, 1}, .exponent = 30},
        {.kind = BRDF_GGX, .color = {1, 1, 1}, .alpha = 0.2},
        {.kind = BRDF_GGX, .color = {1, 1, 1}, .alpha = 0.9},
    };
    double worst = 0.0;
    int nonzero = 0;
    for (size_t k = 0; k < 4; k++) {
        for (int i = 0; i < 1000; i++) {
            vec3 v = random_dir(&seed), l = random_dir(&seed);
            double a[3], b[3];
            brdf_eval(&bs[k], v, l, n, a);
            brdf_eval(&bs[k], l, v, n, b);
            worst = fmax(worst, fabs(a[0] - b[0]) / fmax(fabs(a[0]), 1e-300));
            nonzero += a[0] > 0.0;
        }
    }
    printf("reciprocity: worst relative |f(v,l) - f(l,v)| = %.2e over 4000 pairs\n", worst);
    CHECK(worst < 1e-12);
    CHECK(nonzero > 3000);
    /* Below the surface: nothing. */
    double f[3];
    brdf_eval(&bs[2], (vec3){0, 0, 1}, (vec3){0, 0.6, -0.8}, n, f);
    CHECK(f[0] == 0.0);
    struct brdf_params none = {.kind = BRDF_NONE, .color = {1, 1, 1}};
    brdf_eval(&none, (vec3){0, 0, 1}, (vec3){0, 0, 1}, n, f);
    CHECK(f[0] == 0.0);
}

int main(void)
{
    henyey_greenstein_is_normalised_and_its_mean_cosine_is_g();
    lambert_reflects_its_albedo();
    normalised_phong_never_exceeds_one();
    ggx_distribution_is_normalised_and_ggx_conserves_energy();
    every_brdf_is_reciprocal();
    return test_summary("test_phase_brdf");
}
