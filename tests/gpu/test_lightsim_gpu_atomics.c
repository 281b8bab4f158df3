/*
 * test_lightsim_gpu_atomics.c - the two ways the light simulator adds floats atomically
 * (deposits and flux sums): GL_NV_shader_atomic_float where the driver has it, and the
 * portable compare-and-swap loop (forced with REFRACT_LIGHTSIM_CAS_ATOMICS=1). The same
 * run, flux and max deposit, must give the same volumes and statistics up to the order of
 * float additions: irradiance relative L1 < 1e-5, flux terms within 1e-6 of flux_in,
 * identical patch counts. Where the extension is missing both runs take the CAS path
 * (and the test says so).
 */
#include "lightsim/gpu/lightsim_gpu_programs.h"
#include "test_lightsim_gpu_support.h"

/* A glass ball (n = 1.5, radius 0.6, smoothed over 0.1) absorbing (0.5, 1, 2) per unit. */
static void ball(vec3 x, const void *ctx, double *n, double ext[4])
{
    (void)ctx;
    double inside = 0.5 * erfc((vec3_length(x) - 0.6) / (sqrt(2.0) * 0.1));
    *n = 1.0 + 0.5 * inside;
    ext[0] = 0.5 * inside;
    ext[1] = 1.0 * inside;
    ext[2] = 2.0 * inside;
    ext[3] = 0;
}

struct rebuild_work {
    struct gpu_work work;
    bool cas;
};

static void rebuild(struct gpu_work *w, struct gpu *gpu)
{
    struct rebuild_work *r = w->user;
    lightsim_gpu_shutdown();
    setenv("REFRACT_LIGHTSIM_CAS_ATOMICS", r->cas ? "1" : "0", 1);
    if (lightsim_gpu_init(gpu, &w->err) == REFRACT_E_OK)
        r->cas = lightsim_gpu_programs_use_cas();
}

static bool rebuild_programs(struct gpu *gpu, bool cas)
{
    struct rebuild_work r = {.cas = cas};
    r.work = (struct gpu_work){.priority = GPU_PRIORITY_LIGHTSIM, .run = rebuild, .user = &r};
    CHECK_INT(gpu_run_sync(gpu, &r.work), REFRACT_E_OK);
    return r.cas;
}

static void same_results(struct gpu *gpu, enum scene_lightsim_deposit deposit)
{
    struct lightsim_fields f;
    int dims[3] = {20, 20, 20};
    test_fields_make(&f, dims, 0.1, 1.0, ball, NULL);
    struct test_gpu_run run[2];
    for (int k = 0; k < 2; k++) {
        CHECK(rebuild_programs(gpu, k == 1) == (k == 1));
        run[k] = (struct test_gpu_run){.fields = &f,
                                       .light = test_directional(0.1, -1, 0.2),
                                       .set = test_lightsim_settings(40)};
        run[k].set.energy_threshold = 1e-4;
        run[k].set.deposit = deposit;
        CHECK_INT(test_gpu_simulate(gpu, &run[k]), REFRACT_E_OK);
    }
    const struct irradiance_volume *a = &run[0].out, *b = &run[1].out;
    if (a->irradiance == NULL || b->irradiance == NULL)
        return;
    size_t n = (size_t)dims[0] * dims[1] * dims[2] * 4;
    double l1 = 0, norm = 0;
    for (size_t i = 0; i < n; i++) {
        l1 += fabs(a->irradiance[i] - b->irradiance[i]);
        norm += fabs(b->irradiance[i]);
    }
    double worst = 0;
    for (int ch = 0; ch < 3; ch++) {
        double in = b->stats.flux_in[ch];
        worst = fmax(worst, fabs(a->stats.flux_out[ch] - b->stats.flux_out[ch]) / in);
        worst = fmax(worst, fabs(a->stats.flux_absorbed[ch] - b->stats.flux_absorbed[ch]) / in);
        worst = fmax(worst, fabs(a->stats.flux_reflected[ch] - b->stats.flux_reflected[ch]) / in);
        worst = fmax(worst, fabs(a->stats.flux_culled[ch] - b->stats.flux_culled[ch]) / in);
    }
    printf("%s deposit: native %.0f ms, CAS %.0f ms; irradiance relative L1 %.2e; flux terms "
           "within %.2e of flux_in; patch steps %lld / %lld\n",
           deposit == SCENE_DEPOSIT_MAX ? "max" : "flux", run[0].ms, run[1].ms, l1 / norm, worst,
           a->stats.patch_steps, b->stats.patch_steps);
    CHECK(l1 / norm < 1e-5);
    CHECK(worst < 1e-6);
    CHECK(labs((long)(a->stats.patch_steps - b->stats.patch_steps)) <=
          a->stats.patch_steps / 10000);
    CHECK(test_bookkeeping_residual(&b->stats, 1) < 1e-5);
    irradiance_volume_free(&run[0].out);
    irradiance_volume_free(&run[1].out);
    test_fields_free(&f);
}

int main(void)
{
    struct gpu *gpu = test_start_gpu("test_lightsim_gpu_atomics");
    printf("GL_RENDERER: %s\n", gpu_info(gpu)->renderer);
    same_results(gpu, SCENE_DEPOSIT_FLUX);
    same_results(gpu, SCENE_DEPOSIT_MAX);
    gpu_destroy(gpu, NULL);
    return test_summary("test_lightsim_gpu_atomics");
}
