/*
 * test_antialias.c - several jittered view rays per pixel (render.samples_per_pixel,
 * docs/tracing.md "Anti-aliasing"), render_view.comp against the CPU reference:
 *   - the sample positions: n = k^2 rays cover the k x k strata of the pixel, one each,
 *     inside the pixel; n = 1 is the centre;
 *   - a glass sphere over the checkered environment at 4 rays per pixel: every pixel's
 *     mean against the CPU twin's mean of reftrace over the same 4 rays (pixel_sample.c);
 *   - the point of it: at 16 rays per pixel the image is much closer to a converged box
 *     filter of the same view (the same view at 8x the resolution, one ray per pixel,
 *     averaged over 8 x 8 blocks: other positions than the jittered ones) than at one ray.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/env.h"
#include "core/pixel_sample.h"
#include "gpu/queue.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/scene_reference.h"
#include "gpu_test_util.h"
#include "unit/scene_test_util.h"
#include "test.h"

struct view_work {
    struct gpu_work work;
    const struct scene *scene;
    int width, height, spp;
    struct render_view_result out;
};

static void view_run(struct gpu_work *w, struct gpu *gpu)
{
    struct view_work *v = w->user;
    struct render_desc desc = {0};
    struct render *r = render_create(gpu, &desc, &w->err);
    if (r == NULL)
        return;
    struct render_scene_source src = {.id = "aa", .generation = 1, .scene = v->scene};
    struct render_view_request req = {.camera = v->scene->camera, .settings = v->scene->render};
    req.camera.width = v->width;
    req.camera.height = v->height;
    req.settings.samples_per_pixel = v->spp;
    render_view(r, &src, &req, &v->out, &w->err);
    render_destroy(r);
}

static float *render(struct gpu *gpu, const struct scene *s, int w, int h, int spp)
{
    struct view_work v = {.scene = s, .width = w, .height = h, .spp = spp};
    v.work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = view_run, .user = &v};
    CHECK_INT(gpu_run_sync(gpu, &v.work), REFRACT_E_OK);
    return v.out.rgba;
}

static void sample_positions(void)
{
    const uint32_t ns[] = {1, 4, 9, 16, 64};
    int bad = 0;
    for (size_t i = 0; i < sizeof ns / sizeof ns[0]; i++) {
        uint32_t n = ns[i], k = (uint32_t)(sqrt((double)n) + 0.5);
        for (uint32_t px = 0; px < 50; px++) {
            int hits[64] = {0};
            for (uint32_t s = 0; s < n; s++) {
                double dx, dy;
                pixel_sample(px, 7 * px + 3, s, n, &dx, &dy);
                if (!(dx >= 0 && dx < 1 && dy >= 0 && dy < 1)) {
                    bad++;
                    continue;
                }
                hits[(int)(dy * k) * (int)k + (int)(dx * k)]++;
            }
            for (uint32_t c = 0; c < n; c++)
                bad += hits[c] != 1;
        }
    }
    CHECK_INT(bad, 0);
    double dx, dy;
    pixel_sample(3, 4, 0, 1, &dx, &dy);
    CHECK(dx == 0.5 && dy == 0.5);
    /* The jitter differs between pixels (a hash, not one pattern repeated). */
    double ax, ay, bx, by;
    pixel_sample(10, 10, 0, 4, &ax, &ay);
    pixel_sample(11, 10, 0, 4, &bx, &by);
    CHECK(ax != bx || ay != by);
}

static const char *const doc =
    "{\"camera\": {\"eye\": [0.4, 0.9, 3.2], \"look_at\": [0, 0, 0], \"fov_y_deg\": 40,"
    " \"width\": 40, \"height\": 30},"
    " \"surfaces\": [{\"shape\": \"sphere\", \"radius\": 0.8, \"medium\": {\"ior\": 1.5,"
    " \"attenuation\": [0.05, 0.1, 0.2]}}]}";

/* A GRIN ball in voxels marched at 0.03 voxel steps without empty-space skipping: about 2000
 * steps a ray, so 36 rays of a pixel take some 75,000 march steps, past llvmpipe's limit of
 * 65535 loop iterations per shader invocation (LP_MAX_TGSI_LOOP_ITERATIONS), which silently
 * ended the loop over a pixel's rays while the renderer traced them all in one invocation
 * (render_view.comp now traces one ray per pixel per dispatch). */
static const char *const long_doc =
    "{\"camera\": {\"eye\": [0.3, 0.5, 3.4], \"look_at\": [0, 0, 0], \"fov_y_deg\": 30,"
    " \"width\": 12, \"height\": 9},"
    " \"render\": {\"step\": 0.03, \"empty_space_skipping\": false},"
    " \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 64,"
    " \"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.3, \"outside\": 1.0},"
    " \"attenuation\": 0.3}]}";

static void against_cpu_twin(struct gpu *gpu, const struct scene *s, int n, double fraction)
{
    struct scene_reference ref;
    struct err e = {0};
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &ref, &e), REFRACT_E_OK);
    const struct scene_camera *cam = &s->camera;
    float *g = render(gpu, s, cam->width, cam->height, n);
    int within = 0, total = cam->width * cam->height;
    double sum_gpu = 0.0, sum_cpu = 0.0;
    for (int row = 0; row < cam->height && g != NULL; row++)
        for (int col = 0; col < cam->width; col++) {
            double want[3] = {0, 0, 0};
            for (int i = 0; i < n; i++) {
                double dx, dy;
                pixel_sample((uint32_t)col, (uint32_t)row, (uint32_t)i, (uint32_t)n, &dx, &dy);
                vec3 o, dir;
                camera_ray(cam->eye, cam->look_at, cam->up, cam->fov_y_deg, cam->width, cam->height,
                           col + dx - 0.5, row + dy - 0.5, &o, &dir);
                struct reftrace_result r;
                reftrace_ray(ref.objects, ref.count, &ref.settings, o, dir, &r);
                want[0] += r.radiance.x / n;
                want[1] += r.radiance.y / n;
                want[2] += r.radiance.z / n;
            }
            const float *p = &g[(row * cam->width + col) * 4];
            for (int c = 0; c < 3; c++) {
                sum_gpu += p[c];
                sum_cpu += want[c];
            }
            bool ok = true;
            for (int c = 0; c < 3; c++)
                ok = ok && fabs(p[c] - want[c]) <= 1e-3 * (fabs(want[c]) + 0.1);
            within += ok;
        }
    printf("%d rays per pixel, %dx%d: %d of %d pixels within 1e-3 of the CPU twin's mean; "
           "image sums GPU / CPU %.6f\n",
           n, cam->width, cam->height, within, total, sum_gpu / sum_cpu);
    CHECK_MSG(within >= fraction * total, "%d of %d pixels", within, total);
    CHECK_MSG(fabs(sum_gpu / sum_cpu - 1.0) < 2e-3, "image sums GPU / CPU %.6f", sum_gpu / sum_cpu);
    free(g);
    scene_reference_free(&ref);
}

/* Relative RMSE over the three channels: sqrt(sum (x - r)^2 / sum r^2). */
static double rel_rmse(const float *x, const double *r, int pixels)
{
    double num = 0, den = 0;
    for (int i = 0; i < pixels; i++)
        for (int c = 0; c < 3; c++) {
            double d = x[i * 4 + c] - r[i * 3 + c];
            num += d * d;
            den += r[i * 3 + c] * r[i * 3 + c];
        }
    return sqrt(num / den);
}

static void aliasing(struct gpu *gpu, const struct scene *s)
{
    const int w = 40, h = 30, f = 8;
    float *fine = render(gpu, s, w * f, h * f, 1);
    float *one = render(gpu, s, w, h, 1);
    float *sixteen = render(gpu, s, w, h, 16);
    if (fine == NULL || one == NULL || sixteen == NULL) {
        CHECK(false);
        free(fine), free(one), free(sixteen);
        return;
    }
    double *box = calloc((size_t)w * h * 3, sizeof *box);
    for (int y = 0; y < h * f; y++)
        for (int x = 0; x < w * f; x++)
            for (int c = 0; c < 3; c++)
                box[((y / f) * w + x / f) * 3 + c] += fine[(y * w * f + x) * 4 + c] / (f * f);
    double e1 = rel_rmse(one, box, w * h), e16 = rel_rmse(sixteen, box, w * h);
    printf("against a 64-ray box filter (8x the resolution): 1 ray per pixel %.4f, 16 rays "
           "%.4f relative RMSE\n",
           e1, e16);
    CHECK_MSG(e16 < 0.5 * e1, "16 rays %g, 1 ray %g", e16, e1);
    CHECK(e1 > 0.01); /* the sphere's edges and the checker do alias at one ray */
    free(box);
    free(fine), free(one), free(sixteen);
}

int main(void)
{
    sample_positions();
    struct gpu *gpu = test_gpu_create("test_antialias");
    struct scene *s = parse_ok(doc);
    if (s != NULL) {
        against_cpu_twin(gpu, s, 4, 0.97);
        aliasing(gpu, s);
        scene_destroy(s);
    }
    s = parse_ok(long_doc);
    if (s != NULL) {
        /* 2000 steps in float against double: a tenth of the pixels differ by more than
         * 1e-3 (measured 98 of 108 within; before the fix 0 of 108) */
        against_cpu_twin(gpu, s, 36, 0.85);
        scene_destroy(s);
    }
    gpu_destroy(gpu, NULL);
    return test_summary("test_antialias");
}
