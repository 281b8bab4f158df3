/*
 * test_lightsim_energy.c - where the light simulator's power goes (docs/lightsim.md
 * "Energy bookkeeping"), against closed forms: Fresnel reflection at a tilted glass plate
 * (frisvad2010's unpolarised reflectance at both faces; the reflected wavefront is not
 * propagated) and Beer-Lambert extinction in an index-matched absorbing slab, per channel.
 */
#include "core/fresnel.h"
#include "test_lightsim_fixture.h"

/* R1 + (1 - R1) R2 of a plate of index n in air, for a ray at cos_i to its normal. */
static double plate_reflectance(double cos_i, double n)
{
    double sin_i = sqrt(fmax(0.0, 1.0 - cos_i * cos_i));
    double cos_t = sqrt(1.0 - sin_i * sin_i / (n * n));
    double R1 = fresnel_unpolarized(cos_i, 1.0, n);
    double R2 = fresnel_unpolarized(cos_t, n, 1.0);
    return R1 + (1.0 - R1) * R2;
}

/* The mean of plate_reflectance over a cone of half angle `cone` about axis `a`, by solid
 * angle (a spot's intensity is uniform per steradian): midpoint rule, 400 x 400. */
static double cone_mean_reflectance(vec3 a, double cone, vec3 nrm, double n)
{
    vec3 u = vec3_normalize(vec3_cross(a, fabs(a.x) < 0.9 ? (vec3){1, 0, 0} : (vec3){0, 1, 0}));
    vec3 v = vec3_cross(a, u);
    double sum = 0.0, wsum = 0.0;
    const int N = 400;
    for (int i = 0; i < N; i++) {
        double th = cone * (i + 0.5) / N;
        for (int j = 0; j < N; j++) {
            double ph = 2.0 * M_PI * (j + 0.5) / N;
            vec3 d = vec3_add(vec3_scale(a, cos(th)), vec3_add(vec3_scale(u, sin(th) * cos(ph)),
                                                               vec3_scale(v, sin(th) * sin(ph))));
            double w = sin(th);
            sum += w * plate_reflectance(fabs(vec3_dot(d, nrm)), n);
            wsum += w;
        }
    }
    return sum / wsum;
}

/* A glass plate (n = 1.5, 0.4 thick, filling its bounds sideways) tilted 30 degrees about
 * z, lit by a narrow spot straight down, so every ray enters through the top face at
 * 30 +- 12 degrees and leaves through the bottom face. */
static void test_fresnel_plate(void)
{
    struct scene *s = fx_scene(
        "{\"objects\": [{\"bounds\": {\"min\": [-0.8, -0.3, -0.8], \"max\": [0.8, 0.3, 0.8]},"
        " \"resolution\": [48, 18, 48], \"transform\": {\"rotate\": {\"axis\": [0, 0, 1], "
        "\"angle_deg\": 30}}, \"ior\": {\"shape\": \"box\", \"size\": [4, 0.4, 4], \"inside\": "
        "1.5}}]}");
    struct scene_lightsim set = fx_settings(40, 128);
    struct scene_light l = {.kind = SCENE_LIGHT_SPOT,
                            .position = {0, 1.0, 0},
                            .direction = {0, -1, 0},
                            .spot_angle_deg = 12,
                            .color = {1, 1, 1},
                            .intensity = 1};
    struct lightsim_fields f;
    struct irradiance_volume v;
    double t0 = fx_seconds();
    fx_run(s, &l, &set, &f, &v);
    double secs = fx_seconds() - t0;
    const struct lightsim_stats *st = &v.stats;
    fx_print_stats("plate", st);
    vec3 nrm = {-sin(M_PI / 6), cos(M_PI / 6), 0}; /* the plate's normal, object y rotated */
    double expected = cone_mean_reflectance(l.direction, 12.0 * M_PI / 180.0, nrm, 1.5);
    double measured = st->flux_reflected[0] / st->flux_in[0];
    printf("plate: reflected fraction %.5f, closed form %.5f (R at 30 deg alone %.5f), "
           "%.2f s\n",
           measured, expected, plate_reflectance(cos(M_PI / 6), 1.5), secs);
    /* 3 %: measured +1.7 %. The incidence angle comes from Snell's invariant (exact for
     * a plane interface), so what remains is the interface as the light grid sees it:
     * its normal from central differences of a rotated, resampled, smoothed step, and
     * the probed n_lo, n_hi; and the spot's jagged rim (patch centres in the cone) */
    CHECK_NEAR(measured, expected, 0.03 * expected);
    /* a non-absorbing plate: what is not reflected leaves the domain */
    CHECK(st->flux_absorbed[0] == 0.0);
    CHECK(st->flux_culled[0] <= 1e-9 * st->flux_in[0]);
    CHECK_NEAR(st->flux_out[0], st->flux_in[0] - st->flux_reflected[0], 1e-9 * st->flux_in[0]);
    CHECK(lightsim_stats_imbalance(st) <= 1e-9);
    CHECK(st->done && st->patches_live == 0);
    irradiance_volume_free(&v);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

/* Mean E over the voxels of layer j with |x|, |z| <= half (world). */
static void layer_mean(const struct irradiance_volume *v, int j, double half, double out[3])
{
    const struct light_grid *g = &v->grid;
    long n = 0;
    out[0] = out[1] = out[2] = 0.0;
    for (int k = 0; k < g->dims[2]; k++)
        for (int i = 0; i < g->dims[0]; i++) {
            vec3 x = fx_centre(g, i, j, k);
            if (fabs(x.x) > half || fabs(x.z) > half)
                continue;
            for (int c = 0; c < 3; c++)
                out[c] += fx_E(v, i, j, k)[c];
            n++;
        }
    for (int c = 0; c < 3; c++)
        out[c] /= (double)n;
}

/* An index-matched slab 0.5 thick with sigma_t = (2, 1, 0.5) per unit, lit from above:
 * all absorption, or half of it scattering (sigma_t = sigma_a + sigma_s, docs/lightsim.md
 * "Fields"; scattered light leaves the beam). */
static void test_beer_lambert(const char *channels)
{
    char json[1024];
    snprintf(json, sizeof json,
             "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
             "\"resolution\": 32, %s}]}",
             channels);
    struct scene *s = fx_scene(json);
    struct scene_lightsim set = fx_settings(32, 24);
    struct scene_light l = fx_directional((vec3){0, -1, 0});
    struct lightsim_fields f;
    struct irradiance_volume v;
    fx_run(s, &l, &set, &f, &v);
    fx_print_stats("beer-lambert", &v.stats);
    const struct light_grid *g = &v.grid;
    /* layers 0.25 above and below the slab's faces (3.5 voxels: clear of the B-spline) */
    int j_front = (int)floor((0.5 - g->bmin.y) / g->voxel);
    int j_back = (int)floor((-0.5 - g->bmin.y) / g->voxel);
    double front[3], back[3];
    layer_mean(&v, j_front, 0.7, front);
    layer_mean(&v, j_back, 0.7, back);
    const double sigma[3] = {2, 1, 0.5}, d = 0.5;
    for (int c = 0; c < 3; c++) {
        double ratio = back[c] / front[c], expected = exp(-sigma[c] * d);
        printf("beer-lambert channel %d: front %.5f back %.5f ratio %.5f, exp(-sigma d) %.5f\n", c,
               front[c], back[c], ratio, expected);
        /* 1.5 %: the trapezoid rule on a sampled profile (the anti-aliased faces are
         * resampled onto the light grid), and the deposit's ripple (<= 0.5 %) */
        CHECK_NEAR(ratio, expected, 0.015 * expected);
        CHECK_NEAR(front[c], 1.0, 0.01);
    }
    /* every ray crosses the slab (it fills the bounds sideways); only the two-voxel pad
     * around the bounds is clear, so the absorbed power is that of the bounds' top face */
    for (int c = 0; c < 3; c++) {
        double expected = 4.0 * (1.0 - exp(-sigma[c] * d));
        CHECK_NEAR(v.stats.flux_absorbed[c], expected, 0.02 * expected);
    }
    CHECK(lightsim_stats_imbalance(&v.stats) <= 1e-9);
    irradiance_volume_free(&v);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

int main(void)
{
    test_fresnel_plate();
    test_beer_lambert("\"attenuation\": {\"shape\": \"box\", \"size\": [4, 0.5, 4], "
                      "\"inside\": [2, 1, 0.5]}");
    test_beer_lambert("\"attenuation\": {\"shape\": \"box\", \"size\": [4, 0.5, 4], "
                      "\"inside\": [1, 0.5, 0.25]}, \"scattering\": {\"shape\": \"box\", "
                      "\"size\": [4, 0.5, 4], \"inside\": [1, 0.5, 0.25]}");
    return test_summary("test_lightsim_energy");
}
