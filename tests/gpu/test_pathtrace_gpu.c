/*
 * test_pathtrace_gpu.c - the GPU path tracer (shaders/pathtrace_render.comp) against its
 * CPU double-precision twin (core/pathtrace.c): the two draw different random numbers, so
 * they agree in distribution, not per sample. Per pixel, z = (m_gpu - m_cpu) /
 * sqrt(v_gpu + v_cpu) with each image's variance of the mean; with equal estimators
 * E[z^2] = 1 and the image-wide z of the summed differences is standard normal. The
 * scenes: a glass ball filled with a scattering medium on a grey floor under a uniform
 * sky and a spherical light (every estimator: Fresnel choice, TIR, free flights,
 * Henyey-Greenstein, NEE and MIS, roulette), and a white furnace (energy conservation in
 * float). Small images, a few seconds on llvmpipe.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gpu_test_util.h"
#include "render/pathtrace_gpu.h"

#define W 20
#define H 15

static struct pathtrace_surface ball;

static struct pathtrace_scene glass_ball_scene(void)
{
    struct pathtrace_scene s;
    memset(&s, 0, sizeof s);
    s.ambient.ior = 1.0;
    s.env_kind = PATHTRACE_ENV_UNIFORM;
    for (int c = 0; c < 3; c++)
        s.env_radiance[c] = 0.2;
    s.receiver = (struct pathtrace_receiver){true, -1.0, INFINITY, {0.5, 0.6, 0.7}, {0, 0}};
    memset(&ball, 0, sizeof ball);
    ball.geom.kind = GEOM_SPHERE;
    ball.geom.xf = xform_identity();
    ball.geom.radius = 1.0;
    ball.medium = (struct pathtrace_medium){1.5, {0.05, 0.05, 0.1}, {0.5, 0.5, 0.5}, 0.3};
    s.surfaces = &ball;
    s.surface_count = 1;
    s.lights[0] = (struct pathtrace_light){.kind = PATHTRACE_LIGHT_SPHERE,
                                           .position = {2, 4, 1},
                                           .radius = 0.5,
                                           .value = {5, 5, 5},
                                           .visible = true};
    s.lights[1] = (struct pathtrace_light){
        .kind = PATHTRACE_LIGHT_POINT, .position = {-2, 3, 2}, .value = {3, 2, 1}};
    s.light_count = 2;
    return s;
}

static const struct pathtrace_camera cam = {{0, 2.5, 7}, {0, -0.5, 0}, {0, 1, 0}, 35.0, W, H};

struct pt_work {
    struct gpu_work work;
    const struct pathtrace_scene *scene;
    struct pathtrace_image *img;
    int samples;
};

static void pt_run(struct gpu_work *w, struct gpu *gpu)
{
    (void)gpu;
    struct pt_work *pw = w->user;
    pathtrace_gpu_render(pw->scene, &cam, 7, 0, pw->samples, pw->img, &w->err);
}

static bool render_gpu(struct gpu *gpu, const struct pathtrace_scene *s, int samples,
                       struct pathtrace_image *img)
{
    struct pt_work pw = {.scene = s, .img = img, .samples = samples};
    pw.work.run = pt_run;
    pw.work.user = &pw;
    pw.work.label = "pathtrace test";
    enum refract_code rc = gpu_run_sync(gpu, &pw.work);
    if (rc != REFRACT_E_OK)
        fprintf(stderr, "GPU path tracer: %s\n", pw.work.err.msg);
    return rc == REFRACT_E_OK;
}

/* mean z^2 over the pixels with some variance, and the image-wide z */
static void compare(const struct pathtrace_image *g, const struct pathtrace_image *c,
                    double *mean_z2, double *z_all, int *n)
{
    double z2 = 0.0, dsum = 0.0, vsum = 0.0;
    *n = 0;
    for (int64_t i = 0; i < W * H; i++) {
        double mg[3], vg[3], mc[3], vc[3];
        pathtrace_image_pixel(g, i, mg, vg);
        pathtrace_image_pixel(c, i, mc, vc);
        for (int k = 0; k < 3; k++) {
            dsum += mg[k] - mc[k];
            vsum += vg[k] + vc[k];
            if (vg[k] + vc[k] > 0.0) {
                z2 += (mg[k] - mc[k]) * (mg[k] - mc[k]) / (vg[k] + vc[k]);
                (*n)++;
            }
        }
    }
    *mean_z2 = *n ? z2 / *n : 0.0;
    *z_all = vsum > 0.0 ? dsum / sqrt(vsum) : 0.0;
}

static void gpu_agrees_with_the_cpu_twin_within_their_noise(struct gpu *gpu)
{
    struct pathtrace_scene s = glass_ball_scene();
    int samples = test_sanitized() ? 32 : 64;
    struct pathtrace_image g, c;
    CHECK(pathtrace_image_init(&g, W, H) == 0 && pathtrace_image_init(&c, W, H) == 0);
    CHECK(render_gpu(gpu, &s, samples, &g));
    for (int p = 0; p < samples; p++)
        pathtrace_image_pass(&c, &s, &cam, 3, 0, H);
    double mz2, z;
    int n;
    compare(&g, &c, &mz2, &z, &n);
    printf("glass ball: %d pixel channels, mean z^2 %.3f, image z %.2f\n", n, mz2, z);
    CHECK(n > W * H);
    /* heavy tails (caustic paths) make single-pixel variance estimates low now and then:
     * the upper bound leaves room for that, a systematic error moves both figures */
    CHECK_MSG(mz2 > 0.6 && mz2 < 1.8, "mean z^2 = %.3f", mz2);
    CHECK_MSG(fabs(z) < 4.0, "image-wide z = %.2f", z);
    pathtrace_image_fini(&g);
    pathtrace_image_fini(&c);
}

static void gpu_white_furnace_renders_the_environment(struct gpu *gpu)
{
    struct pathtrace_scene s = glass_ball_scene();
    s.receiver.enabled = false;
    s.light_count = 0;
    ball.medium = (struct pathtrace_medium){1.5, {0, 0, 0}, {2, 2, 2}, 0.5};
    struct pathtrace_image g;
    CHECK(pathtrace_image_init(&g, W, H) == 0);
    CHECK(render_gpu(gpu, &s, 8, &g));
    double worst = 0.0;
    for (int64_t i = 0; i < W * H; i++) {
        double m[3], v[3];
        pathtrace_image_pixel(&g, i, m, v);
        for (int k = 0; k < 3; k++)
            worst = fmax(worst, fabs(m[k] - 0.2) / 0.2);
    }
    /* every path's weight is exactly 1 in exact arithmetic; float leaves ~1e-6 */
    CHECK_MSG(worst < 1e-3, "worst pixel off by %.2e of the sky", worst);
    pathtrace_image_fini(&g);
}

int main(void)
{
    struct gpu *gpu = test_gpu_create("test_pathtrace_gpu");
    gpu_white_furnace_renders_the_environment(gpu);
    gpu_agrees_with_the_cpu_twin_within_their_noise(gpu);
    gpu_destroy(gpu, NULL);
    return test_summary("test_pathtrace_gpu");
}
