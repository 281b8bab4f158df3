/*
 * test_lightsim_gpu_surfaces.c - the GPU light simulator among exact surfaces
 * (docs/lightsim.md "Surfaces"; issue 12 item 4's acceptance), on llvmpipe in CI:
 *   - against its CPU double twin (lightsim_ref_run) on coarse grids: an absorbing and
 *     scattering glass sphere surface (extinction sigma_a + sigma_s) under a directional
 *     light, a rotated glass box (refraction, reflected twins, total internal reflection at
 *     its side faces) under a point light; the same
 *     quantities as test_lightsim_gpu_vs_ref.c bounds for voxel scenes, about 10x looser:
 *     a corner that ends a step within float rounding of a surface crosses it one step
 *     earlier or later on the GPU, which moves when a patch's event completes, so when it
 *     may split, and whether a rim patch's next crossing falls inside or outside an event.
 *     Measured on llvmpipe (sphere / box): flux terms 5.0e-5 / 2.6e-4 of flux_in,
 *     patch-steps 9.7e-4 / 1.1e-3, irradiance relative L1 3.1e-4 / 7.9e-4, direction
 *     mean 1 - cos 1.3e-4 / 7.4e-4; bounds 1e-3, 1e-2, 3e-3, 3e-3. A GPU that followed no
 *     twin, or refracted wrongly, misses them by 10-100x (the twins carry 4-8 % of the
 *     power into other voxels);
 *   - the ball lens of test_lightsim_surfaces.c (n = 1.5, 1.8, R = 0.5, stopped down):
 *     the axis maximum at n R / (2 (n - 1)) within 1 % of R, and the bookkeeping identity
 *     to float rounding.
 */
#include "scene/scene.h"
#include "test_lightsim_gpu_support.h"
#include "unit/test_lightsim_axis.h"

static struct scene *parse(const char *json)
{
    struct scene *s = NULL;
    struct err e = {0};
    if (scene_parse(json, strlen(json), NULL, &s, &e) != REFRACT_E_OK) {
        fprintf(stderr, "scene: %s\n", e.msg);
        test_setup_failed("test_lightsim_gpu_surfaces", "a scene did not parse");
    }
    return s;
}

static void print_stats(const char *what, const struct lightsim_stats *a)
{
    printf("%s: in %.6g out %.6g refl %.6g abs %.6g culled %.6g live %.6g | steps %lld "
           "patch_steps %lld splits %lld peak %d\n",
           what, a->flux_in[0], a->flux_out[0], a->flux_reflected[0], a->flux_absorbed[0],
           a->flux_culled[0], a->flux_live[0], a->steps, a->patch_steps, a->splits,
           a->patches_peak);
}

struct compare_case {
    const char *name;
    const char *json;
    struct scene_light light;
    int resolution, initial_patches;
};

static void compare(struct gpu *gpu, const struct compare_case *c)
{
    struct scene *s = parse(c->json);
    struct err e = {0};
    s->lightsim = test_lightsim_settings(c->initial_patches);
    s->lightsim.resolution = c->resolution;
    s->lightsim.energy_threshold = 1e-4;
    struct lightsim_fields f;
    CHECK_INT(lightsim_fields_build(s, NULL, NULL, &f, &e), REFRACT_E_OK);
    double t0 = gpu_time_ms();
    struct irradiance_volume ref;
    CHECK_INT(lightsim_ref_run(&f, &c->light, &s->lightsim, &ref, &e), REFRACT_E_OK);
    double cpu_ms = gpu_time_ms() - t0;
    struct test_gpu_run t = {.fields = &f, .light = c->light, .set = s->lightsim, .chunk = 32};
    CHECK_INT(test_gpu_simulate(gpu, &t), REFRACT_E_OK);
    if (t.out.irradiance == NULL || ref.irradiance == NULL)
        return;
    const struct lightsim_stats *a = &t.out.stats, *b = &ref.stats;
    printf("%s (%dx%dx%d, N0 %d): CPU %.0f ms, GPU %.0f ms\n", c->name, f.grid.dims[0],
           f.grid.dims[1], f.grid.dims[2], c->initial_patches, cpu_ms, t.ms);
    print_stats("  GPU", a);
    print_stats("  CPU", b);
    CHECK_INT(a->patches_initial, b->patches_initial);
    CHECK(a->done && b->done);
    double dps = fabs((double)a->patch_steps - (double)b->patch_steps) / (double)b->patch_steps;
    printf("  patch_steps differ by %.2e\n", dps);
    CHECK(dps <= 1e-2);
    for (int ch = 0; ch < 3; ch++) {
        double in = b->flux_in[ch];
        double d[4] = {fabs(a->flux_out[ch] - b->flux_out[ch]) / in,
                       fabs(a->flux_reflected[ch] - b->flux_reflected[ch]) / in,
                       fabs(a->flux_absorbed[ch] - b->flux_absorbed[ch]) / in,
                       fabs(a->flux_culled[ch] - b->flux_culled[ch]) / in};
        double worst = fmax(fmax(d[0], d[1]), fmax(d[2], d[3]));
        printf("  ch %d: out %.6f/%.6f refl %.6f/%.6f abs %.6f/%.6f culled %.6f/%.6f -> max "
               "diff %.2e of flux_in; residual GPU %.1e CPU %.1e\n",
               ch, a->flux_out[ch], b->flux_out[ch], a->flux_reflected[ch], b->flux_reflected[ch],
               a->flux_absorbed[ch], b->flux_absorbed[ch], a->flux_culled[ch], b->flux_culled[ch],
               worst, test_bookkeeping_residual(a, ch), test_bookkeeping_residual(b, ch));
        CHECK(fabs(a->flux_in[ch] - in) / in < 1e-6);
        CHECK(worst < 1e-3);
        CHECK(test_bookkeeping_residual(a, ch) < 1e-5);
        CHECK(test_bookkeeping_residual(b, ch) < 1e-12);
    }
    size_t n = (size_t)f.grid.dims[0] * f.grid.dims[1] * f.grid.dims[2];
    double l1 = 0, norm = 0, max_diff = 0, max_e = 0, dir_sum = 0;
    int lit_both = 0, lit_either = 0;
    for (size_t v = 0; v < n; v++) {
        for (int ch = 0; ch < 3; ch++) {
            double g = t.out.irradiance[4 * v + ch], r = ref.irradiance[4 * v + ch];
            l1 += fabs(g - r);
            norm += fabs(r);
            max_diff = fmax(max_diff, fabs(g - r));
            max_e = fmax(max_e, fabs(r));
        }
        bool lg = t.out.direction[4 * v + 3] == 1.0f, lr = ref.direction[4 * v + 3] == 1.0f;
        lit_either += lg || lr;
        if (lg && lr) {
            lit_both++;
            double dot = 0, lg2 = 0, lr2 = 0;
            for (int k = 0; k < 3; k++) {
                double dg = t.out.direction[4 * v + k], dr = ref.direction[4 * v + k];
                dot += dg * dr;
                lg2 += dg * dg;
                lr2 += dr * dr;
            }
            dir_sum += 1 - dot / sqrt(lg2 * lr2);
        }
    }
    printf("  irradiance: relative L1 %.2e, max voxel diff %.3g (%.2e of max E %.3g); lit %d "
           "both / %d either, direction 1 - cos mean %.2e\n",
           l1 / norm, max_diff, max_diff / max_e, max_e, lit_both, lit_either,
           lit_both ? dir_sum / lit_both : 0);
    CHECK(l1 / norm < 3e-3);
    CHECK(lit_both >= 0.99 * lit_either);
    CHECK(lit_both == 0 || dir_sum / lit_both < 3e-3);
    irradiance_volume_free(&t.out);
    irradiance_volume_free(&ref);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

static void ball_lens(struct gpu *gpu, double n, int resolution, int patches)
{
    const double R = 0.5, a = 0.06;
    double f_eff = n * R / (2.0 * (n - 1.0)), floor_y = -f_eff - 0.12;
    char json[2048];
    ball_lens_json(json, sizeof json, R, n, a);
    struct scene *s = parse(json);
    struct err e = {0};
    s->lightsim = test_lightsim_settings(patches);
    s->lightsim.resolution = resolution;
    s->lightsim.energy_threshold = 1e-4;
    struct lightsim_fields f;
    CHECK_INT(lightsim_fields_build(s, NULL, NULL, &f, &e), REFRACT_E_OK);
    struct test_gpu_run t = {
        .fields = &f, .light = test_directional(0, -1, 0), .set = s->lightsim, .chunk = 64};
    CHECK_INT(test_gpu_simulate(gpu, &t), REFRACT_E_OK);
    if (t.out.irradiance != NULL) {
        char what[64];
        snprintf(what, sizeof what, "GPU ball n %.2f", n);
        print_stats(what, &t.out.stats);
        double E_max, y = axis_focus(&t.out, -R - 0.02, floor_y + 0.02, 0.06, &E_max);
        printf("%s: resolution %d (voxel %.4f), N0 %d: axis maximum E %.2f at %.4f below the "
               "centre, f = %.4f: error %.2f %% of R (%.2f voxels); %.1f s\n",
               what, resolution, t.out.grid.voxel, patches, E_max, -y, f_eff,
               100.0 * (-y - f_eff) / R, (-y - f_eff) / t.out.grid.voxel, 1e-3 * t.ms);
        CHECK_NEAR(-y, f_eff, 0.01 * R);
        CHECK(E_max > 3.0);
        for (int ch = 0; ch < 3; ch++) {
            printf("  ch %d bookkeeping residual %.2e\n", ch,
                   test_bookkeeping_residual(&t.out.stats, ch));
            CHECK(test_bookkeeping_residual(&t.out.stats, ch) < 1e-5);
        }
        CHECK(t.out.stats.done && t.out.stats.patches_live == 0);
        irradiance_volume_free(&t.out);
    }
    lightsim_fields_free(&f);
    scene_destroy(s);
}

static const char *const sphere_json =
    "{\"surfaces\": [{\"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 0.6,"
    " \"medium\": {\"ior\": 1.5, \"attenuation\": [0.2, 0.5, 1.0],"
    " \"scattering\": [0.6, 0.2, 0]}}],"
    " \"receiver\": {\"height\": -0.8, \"half_size\": 0.8}}";

static const char *const box_json =
    "{\"surfaces\": [{\"shape\": \"box\", \"center\": [0, 0, 0], \"size\": [1.2, 0.4, 1.2],"
    " \"transform\": {\"rotate\": {\"axis\": [0, 0, 1], \"angle_deg\": 25}},"
    " \"medium\": {\"ior\": 1.5}}]}";

int main(void)
{
    struct gpu *gpu = test_start_gpu("test_lightsim_gpu_surfaces");
    printf("GL_RENDERER: %s\n", gpu_info(gpu)->renderer);
    const struct compare_case cases[] = {
        {"glass sphere surface, directional", sphere_json, test_directional(0.1, -1, 0.05), 24,
         32},
        {"rotated glass box surface, point light", box_json, test_point(0.3, 0.9, 0.2), 24, 8},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        compare(gpu, &cases[i]);
    ball_lens(gpu, 1.5, 128, 192);
    /* n = 1.8 runs the same code as n = 1.5; the sanitizer build leaves it out. */
    if (!test_sanitized())
        ball_lens(gpu, 1.8, 128, 208);
    gpu_destroy(gpu, NULL);
    return test_summary("test_lightsim_gpu_surfaces");
}
