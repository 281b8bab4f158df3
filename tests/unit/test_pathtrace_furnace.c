/*
 * test_pathtrace_furnace.c - the path tracer conserves energy where nothing absorbs
 * (issue 14's closed forms): under a uniform environment of radiance L_env, a sphere of
 * index 1 filled with a medium of albedo 1 (the white furnace), a glass sphere of n 1.5
 * with no absorption, and both at once, all render L_env; a Lambertian plane of albedo
 * rho renders rho L_env. Tolerance: 1 % (the issue's), and for the estimators that are
 * not exact per sample also 4 standard errors of the mean.
 */
#include <math.h>

#include "pathtrace_test_util.h"
#include "test.h"

#define L_ENV 0.7

static void check_pixel(const struct pathtrace_scene *s, vec3 o, vec3 d, int n, double expect[3])
{
    struct pt_estimate e = pt_estimate_ray(s, o, d, n, 7);
    for (int c = 0; c < 3; c++) {
        CHECK_NEAR(e.mean[c], expect[c], 0.01 * expect[c]);
        CHECK_MSG(fabs(e.mean[c] - expect[c]) <= 4.0 * e.stderr_[c] + 1e-12,
                  "channel %d: %.6f vs %.6f, stderr %.2e", c, e.mean[c], expect[c], e.stderr_[c]);
    }
}

static void furnace(double ior, const double sigma_s[3], vec3 d, int n)
{
    struct pathtrace_scene s = pt_scene(L_ENV);
    struct pathtrace_surface ball = pt_sphere(vec3_make(0, 0, 0), 1.0, ior);
    for (int c = 0; c < 3; c++)
        ball.medium.sigma_s[c] = sigma_s[c];
    s.surfaces = &ball;
    s.surface_count = 1;
    double expect[3] = {L_ENV, L_ENV, L_ENV};
    check_pixel(&s, vec3_make(0, 0, 5), d, n, expect);
}

static void white_furnace_index_one_sphere_with_albedo_one_medium_renders_the_environment(void)
{
    const double grey[3] = {2.0, 2.0, 2.0};
    furnace(1.0, grey, vec3_make(0, 0, -1), 2000);
    furnace(1.0, grey, vec3_make(0.1, 0.05, -1), 2000); /* off centre */
}

/* sigma_s differs per channel: the one-sample MIS over channels (pathtrace_medium.c) is
 * then not exact per sample, but its mean still is. (Its variance grows fast with the
 * spread of sigma_t: (0.5, 2, 5) needs ~50x the samples; docs/pathtracer.md "Not yet".) */
static void white_furnace_holds_for_a_chromatic_medium(void)
{
    const double chroma[3] = {1.0, 1.5, 2.0};
    furnace(1.0, chroma, vec3_make(0.05, 0.0, -1), 80000);
}

static void glass_sphere_without_absorption_conserves_energy(void)
{
    const double none[3] = {0.0, 0.0, 0.0};
    furnace(1.5, none, vec3_make(0, 0, -1), 2000);
    furnace(1.5, none, vec3_make(0.18, 0.0, -1), 2000); /* near the rim: strong reflection */
}

static void glass_sphere_filled_with_albedo_one_medium_conserves_energy(void)
{
    const double grey[3] = {1.0, 1.0, 1.0};
    furnace(1.5, grey, vec3_make(0.1, 0.0, -1), 2000);
}

/* Henyey-Greenstein sampling is exact (its pdf is the phase function), so a forward- or
 * back-scattering medium of albedo 1 is as white as an isotropic one. */
static void white_furnace_holds_for_anisotropic_scattering(void)
{
    const double g[2] = {0.7, -0.5};
    for (int k = 0; k < 2; k++) {
        struct pathtrace_scene s = pt_scene(L_ENV);
        struct pathtrace_surface ball = pt_sphere(vec3_make(0, 0, 0), 1.0, 1.0);
        for (int c = 0; c < 3; c++)
            ball.medium.sigma_s[c] = 3.0;
        ball.medium.g = g[k];
        s.surfaces = &ball;
        s.surface_count = 1;
        double expect[3] = {L_ENV, L_ENV, L_ENV};
        check_pixel(&s, vec3_make(0, 0, 5), vec3_make(0.05, 0.02, -1), 2000, expect);
    }
}

static void lambertian_plane_under_uniform_sky_reflects_albedo_times_sky(void)
{
    struct pathtrace_scene s = pt_scene(L_ENV);
    s.receiver = (struct pathtrace_receiver){true, -1.0, INFINITY, {0.8, 0.5, 0.2}, {0, 0}};
    double expect[3] = {0.8 * L_ENV, 0.5 * L_ENV, 0.2 * L_ENV};
    check_pixel(&s, vec3_make(0, 2, 3), vec3_make(0.2, -1, -0.7), 2000, expect);
}

/* A glass ball on the plane: the plane's radiance is no longer closed-form, but a glass
 * sphere in the furnace loses nothing, so the ball seen from above still shows the sky
 * (paths that reach the plane are weighted by its albedo): with albedo 1 everything is
 * L_env. */
static void glass_ball_on_white_plane_in_furnace_renders_the_environment(void)
{
    struct pathtrace_scene s = pt_scene(L_ENV);
    s.receiver = (struct pathtrace_receiver){true, -1.0, INFINITY, {1.0, 1.0, 1.0}, {0, 0}};
    struct pathtrace_surface ball = pt_sphere(vec3_make(0, 0, 0), 1.0, 1.5);
    s.surfaces = &ball;
    s.surface_count = 1;
    double expect[3] = {L_ENV, L_ENV, L_ENV};
    check_pixel(&s, vec3_make(0, 3, 4), vec3_make(0.1, -3, -4), 4000, expect);
}

int main(void)
{
    white_furnace_index_one_sphere_with_albedo_one_medium_renders_the_environment();
    white_furnace_holds_for_a_chromatic_medium();
    glass_sphere_without_absorption_conserves_energy();
    glass_sphere_filled_with_albedo_one_medium_conserves_energy();
    white_furnace_holds_for_anisotropic_scattering();
    lambertian_plane_under_uniform_sky_reflects_albedo_times_sky();
    glass_ball_on_white_plane_in_furnace_renders_the_environment();
    return test_summary("test_pathtrace_furnace");
}
