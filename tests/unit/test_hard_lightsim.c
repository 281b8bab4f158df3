/*
 * test_hard_lightsim.c - the CPU light simulator (lightsim_ref_run) on the hard cases of
 * docs/tracing.md "Hard cases": a light inside the volume (a point light at the centre
 * of a glass ball, inside an absorbing medium, and off-centre in a diamond ball where most
 * of its light is trapped by total internal reflection), and a wavefront that meets an
 * enormous attenuation. For each: every irradiance and direction value finite, E >= 0,
 * the energy bookkeeping identity (docs/lightsim.md) to 1e-9 of flux_in, nothing created
 * (flux_out <= flux_in), the run done within its step budget, and closed forms:
 *   - point light in a glass ball, n = 1.5: every ray meets the surface at normal
 *     incidence, so flux_reflected = R(0) flux_in = 0.04 flux_in (10 %: the smoothed,
 *     voxelised interface), E r^2 = 1 inside and 1 - R = 0.96 outside (4 %: the splat's
 *     blur, as in test_lightsim_ref's point light, plus the interface);
 *   - point light in an index-matched absorber: E r^2 = exp(-sigma r) (4 %).
 * The bumpy sphere's caustic cusps on the CPU are in test_lightsim_focus.c; on the GPU
 * against this reference in tests/gpu/test_hard_lightsim.c.
 */
#include "core/fresnel.h"
#include "lightsim/lightsim_init.h"
#include "test_lightsim_fixture.h"

/* The invariants of a finished run of fields f with settings set: finite, E >= 0, unit
 * directions where lit, the bookkeeping identity, nothing created, and done; a run that
 * still has live patches when it is done has spent its step budget (docs/lightsim.md
 * "Termination and progress": max_steps = ceil(4 n_max rho 2 / dt) + 16), and their power
 * is reported as flux_live. */
static void check_run(const char *what, const struct lightsim_fields *f,
                      const struct scene_lightsim *set, const struct irradiance_volume *v)
{
    const struct lightsim_stats *st = &v->stats;
    const struct light_grid *g = &v->grid;
    size_t n = (size_t)g->dims[0] * g->dims[1] * g->dims[2];
    size_t bad = 0, negative = 0, unit_bad = 0;
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 4; c++) {
            bad += !isfinite(v->irradiance[4 * i + c]) || !isfinite(v->direction[4 * i + c]);
        }
        for (int c = 0; c < 3; c++)
            negative += v->irradiance[4 * i + c] < 0.0f;
        if (v->direction[4 * i + 3] == 1.0f) {
            double l = sqrt((double)v->direction[4 * i] * v->direction[4 * i] +
                            (double)v->direction[4 * i + 1] * v->direction[4 * i + 1] +
                            (double)v->direction[4 * i + 2] * v->direction[4 * i + 2]);
            unit_bad += fabs(l - 1.0) > 1e-3;
        }
    }
    CHECK_MSG(bad == 0, "%s: %zu non-finite values", what, bad);
    CHECK_MSG(negative == 0, "%s: %zu negative irradiance values", what, negative);
    CHECK_MSG(unit_bad == 0, "%s: %zu lit voxels without a unit direction", what, unit_bad);
    long long budget;
    double t_sweep;
    ls_step_budget(f, set->step_voxels * f->grid.voxel, &budget, &t_sweep);
    CHECK_MSG(st->done && st->steps <= budget, "%s: done %d after %lld of %lld steps", what,
              st->done, st->steps, budget);
    if (st->patches_live > 0)
        CHECK_MSG(st->steps == budget && st->flux_live[0] > 0.0,
                  "%s: %d patches live after %lld of %lld steps", what, st->patches_live, st->steps,
                  budget);
    else
        CHECK(st->flux_live[0] == 0.0);
    CHECK_MSG(lightsim_stats_imbalance(st) <= 1e-9, "%s: bookkeeping off by %g", what,
              lightsim_stats_imbalance(st));
    for (int c = 0; c < 3; c++) {
        CHECK(isfinite(st->flux_in[c]) && st->flux_in[c] > 0.0);
        CHECK(st->flux_out[c] >= 0.0 && st->flux_out[c] <= st->flux_in[c] * (1.0 + 1e-12));
        CHECK(st->flux_reflected[c] >= 0.0 && st->flux_absorbed[c] >= 0.0);
        CHECK(st->flux_culled[c] >= 0.0);
    }
    CHECK(st->steps > 0);
}

/* Largest |E r^2 / expected(r) - 1| over interior voxels at r in [r_lo, r_hi] from q. */
static double worst_inverse_square(const struct irradiance_volume *v, vec3 q, double r_lo,
                                   double r_hi, double (*expected)(double r, const void *ctx),
                                   const void *ctx, long *count)
{
    const struct light_grid *g = &v->grid;
    double worst = 0.0;
    *count = 0;
    for (int k = 3; k < g->dims[2] - 3; k++)
        for (int j = 3; j < g->dims[1] - 3; j++)
            for (int i = 3; i < g->dims[0] - 3; i++) {
                double r = vec3_length(vec3_sub(fx_centre(g, i, j, k), q));
                if (r < r_lo || r > r_hi)
                    continue;
                double E = fx_E(v, i, j, k)[0];
                worst = fmax(worst, fabs(E * r * r / expected(r, ctx) - 1.0));
                (*count)++;
            }
    return worst;
}

static double constant_fn(double r, const void *ctx)
{
    (void)r;
    return *(const double *)ctx;
}

static double beer_fn(double r, const void *ctx)
{
    return exp(-*(const double *)ctx * r);
}

/* A point light at the centre of a glass ball (R = 0.6, n = 1.5, 32^3 light voxels). */
static void point_light_inside_a_glass_ball(void)
{
    struct scene *s = fx_scene(
        "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": "
        "32, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.6, \"inside\": 1.5}}]}");
    struct scene_lightsim set = fx_settings(32, 16);
    vec3 q = {0.0, 0.0, 0.0};
    struct scene_light l = fx_point(q);
    struct lightsim_fields f;
    struct irradiance_volume v;
    double t0 = fx_seconds();
    fx_run(s, &l, &set, &f, &v);
    fx_print_stats("point in glass", &v.stats);
    check_run("point in glass", &f, &set, &v);
    double R = fresnel_unpolarized(1.0, 1.5, 1.0);
    double refl = v.stats.flux_reflected[0] / v.stats.flux_in[0];
    double voxel = v.grid.voxel, one = 1.0, outside = 1.0 - R;
    long n_in, n_out;
    double w_in = worst_inverse_square(&v, q, 4 * voxel, 0.6 - 4 * voxel, constant_fn, &one, &n_in);
    double w_out = worst_inverse_square(&v, q, 0.6 + 4 * voxel, 1.0, constant_fn, &outside, &n_out);
    printf("point in glass: reflected %.4f of flux_in (R = %.4f); E r^2 inside within %.3f of 1 "
           "(%ld voxels), outside within %.3f of 1 - R (%ld voxels); %.2f s\n",
           refl, R, w_in, n_in, w_out, n_out, fx_seconds() - t0);
    CHECK_NEAR(refl, R, 0.1 * R);
    CHECK(n_in > 50 && n_out > 1000);
    CHECK(w_in <= 0.04);
    CHECK(w_out <= 0.04);
    irradiance_volume_free(&v);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

/* A point light inside an index-matched absorber sigma = 1.5 per unit filling the bounds. */
static void point_light_inside_an_absorber(void)
{
    struct scene *s = fx_scene(
        "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": "
        "32, \"attenuation\": 1.5}]}");
    struct scene_lightsim set = fx_settings(32, 16);
    vec3 q = {0.1, -0.05, 0.0};
    struct scene_light l = fx_point(q);
    struct lightsim_fields f;
    struct irradiance_volume v;
    fx_run(s, &l, &set, &f, &v);
    fx_print_stats("point in absorber", &v.stats);
    check_run("point in absorber", &f, &set, &v);
    double sigma = 1.5;
    long n;
    double w = worst_inverse_square(&v, q, 4 * v.grid.voxel, 0.8, beer_fn, &sigma, &n);
    printf("point in absorber: E r^2 within %.3f of exp(-sigma r) (%ld voxels)\n", w, n);
    CHECK(n > 1000);
    CHECK(w <= 0.04);
    CHECK(v.stats.flux_absorbed[0] > 0.5 * v.stats.flux_in[0]);
    irradiance_volume_free(&v);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

/* A point light off-centre in a diamond ball (n = 2.42, critical angle 24 degrees): most
 * of its rays meet the surface beyond the critical angle and are turned back inside by
 * the ray equation, again and again, until the patches' splitting and the energy threshold
 * end them. The run must still finish with every joule accounted for. */
static void point_light_trapped_in_a_diamond(void)
{
    struct scene *s = fx_scene(
        "{\"objects\": [{\"bounds\": {\"min\": [-0.8, -0.8, -0.8], \"max\": [0.8, 0.8, 0.8]}, "
        "\"resolution\": 16, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.6, \"inside\": "
        "2.42}}]}");
    /* coarse and shallow: the trapped light splits patches at every bounce, and each level
     * multiplies the work by four */
    struct scene_lightsim set = fx_settings(16, 4);
    set.max_level = 3;
    set.energy_threshold = 1e-3;
    struct scene_light l = fx_point((vec3){0.35, 0.1, -0.05});
    struct lightsim_fields f;
    struct irradiance_volume v;
    double t0 = fx_seconds();
    fx_run(s, &l, &set, &f, &v);
    fx_print_stats("point in diamond", &v.stats);
    printf("point in diamond: out %.3f, reflected %.3f, culled %.3f of flux_in; %.2f s\n",
           v.stats.flux_out[0] / v.stats.flux_in[0], v.stats.flux_reflected[0] / v.stats.flux_in[0],
           v.stats.flux_culled[0] / v.stats.flux_in[0], fx_seconds() - t0);
    check_run("point in diamond", &f, &set, &v);
    irradiance_volume_free(&v);
    /* Near the rim (r = 0.5 of 0.6), and without splitting or an energy threshold: a ray
     * whose impact parameter gives sin(incidence) > 1 / 2.42 keeps that incidence at every
     * bounce in a sphere (a whispering-gallery path), so those patches bounce until the
     * step budget ends the run: done, with their power reported as flux_live. */
    set.split_voxels = 1e9; /* patches never grow past it: no splits, no level culls */
    set.energy_threshold = 0.0;
    l = fx_point((vec3){0.5, 0.0, 0.02});
    CHECK_INT(lightsim_ref_run(&f, &l, &set, &v, &(struct err){0}), REFRACT_E_OK);
    fx_print_stats("point in diamond, no splits", &v.stats);
    check_run("point in diamond, no splits", &f, &set, &v);
    CHECK(v.stats.patches_live > 0 && v.stats.flux_live[0] > 0.005 * v.stats.flux_in[0]);
    irradiance_volume_free(&v);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

/* A directional light onto an index-matched slab with the largest attenuation a scene
 * allows (1e5 per unit): everything that enters the slab is absorbed within a voxel. Below
 * the slab E = 0 exactly; above it the beam is undisturbed (E = 1 within 1 %). */
static void enormous_attenuation_absorbs_the_wavefront(void)
{
    struct scene *s = fx_scene(
        "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": "
        "32, \"attenuation\": {\"shape\": \"box\", \"size\": [4, 0.5, 4], \"inside\": 1e5}}]}");
    struct scene_lightsim set = fx_settings(32, 16);
    struct scene_light l = fx_directional((vec3){0, -1, 0});
    struct lightsim_fields f;
    struct irradiance_volume v;
    fx_run(s, &l, &set, &f, &v);
    fx_print_stats("attenuation 1e5", &v.stats);
    check_run("attenuation 1e5", &f, &set, &v);
    const struct light_grid *g = &v.grid;
    int j_above = (int)floor((0.6 - g->bmin.y) / g->voxel);
    int j_below = (int)floor((-0.6 - g->bmin.y) / g->voxel);
    double above = 0.0, below = 0.0;
    long n = 0;
    for (int k = 6; k < g->dims[2] - 6; k++)
        for (int i = 6; i < g->dims[0] - 6; i++) {
            above += fx_E(&v, i, j_above, k)[0];
            below = fmax(below, fx_E(&v, i, j_below, k)[0]);
            n++;
        }
    above /= (double)n;
    printf("attenuation 1e5: E above %.4f, largest E below %.3g\n", above, below);
    CHECK_NEAR(above, 1.0, 0.01);
    CHECK(below == 0.0);
    irradiance_volume_free(&v);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

int main(void)
{
    point_light_inside_a_glass_ball();
    point_light_inside_an_absorber();
    point_light_trapped_in_a_diamond();
    enormous_attenuation_absorbs_the_wavefront();
    return test_summary("test_hard_lightsim");
}
