/*
 * test_volume_kernels.c - the scene-load kernels on the GPU (smooth_ior.comp,
 * gradient_ior.comp) against their double-precision references (smooth_gaussian_ref,
 * gradient_central_ref in server/core/smooth.c): the (grad n, n) atlas the GPU builds
 * must match the CPU's to float precision, for non-cubic grids, two objects sharing the
 * atlas, and sigma = 0 (no smoothing).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/smooth.h"
#include "gpu/queue.h"
#include "render/scene_gpu.h"
#include "scene/scene.h"
#include "gpu_test_util.h"
#include "test.h"

static const char *const scene_json =
    "{\"objects\": ["
    " {\"bounds\": {\"min\": [-1, -0.75, -1.25], \"max\": [1, 0.75, 1.25]},"
    "  \"resolution\": [32, 24, 40], \"smoothing_sigma\": 1.3,"
    "  \"ior\": [{\"shape\": \"sphere\", \"radius\": 0.6, \"inside\": 1.5, \"outside\": 1.0},"
    "          {\"shape\": \"box\", \"center\": [0.3, 0, 0.5], \"size\": [0.4, 0.4, 0.4],"
    "           \"inside\": 2.0}]},"
    " {\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": [20, 28, 16],"
    "  \"smoothing_sigma\": 0,"
    "  \"ior\": {\"profile\": \"gaussian\", \"n_peak\": 1.6, \"n_out\": 1.0, \"sigma\": 0.3}}]}";

struct build_work {
    struct gpu_work work;
    const struct scene *scene;
    struct scene_gpu *sg;
    int atlas_size[3];
    float *atlas; /* read back: RGBA per texel */
};

static void build_run(struct gpu_work *w, struct gpu *gpu)
{
    struct build_work *b = w->user;
    struct render_scene_source src = {.id = "kernels", .generation = 1, .scene = b->scene};
    b->sg = scene_gpu_build(gpu, &src, 0, &w->err);
    if (b->sg == NULL)
        return;
    memcpy(b->atlas_size, b->sg->atlas_size, sizeof b->atlas_size);
    size_t texels = (size_t)b->atlas_size[0] * b->atlas_size[1] * b->atlas_size[2];
    b->atlas = calloc(texels * 4, sizeof(float));
    if (b->atlas == NULL)
        return;
    glGetTextureImage(b->sg->ior_grad.tex, 0, GL_RGBA, GL_FLOAT,
                      (GLsizei)(texels * 4 * sizeof(float)), b->atlas);
    scene_gpu_destroy(b->sg);
    b->sg = NULL;
}

/* CPU: field -> smoothing -> gradient, the reference pipeline of docs/tracing.md. */
static double *reference(const struct scene *s, const struct scene_object *o)
{
    size_t n = (size_t)o->resolution[0] * o->resolution[1] * o->resolution[2];
    float *field = malloc(n * sizeof(float));
    double *smooth = malloc(n * sizeof(double));
    double *out = malloc(n * 4 * sizeof(double));
    struct err e = {0};
    CHECK_INT(scene_field_eval(s, o, SCENE_CH_IOR, NULL, NULL, field, &e), REFRACT_E_OK);
    smooth_gaussian_ref(field, o->resolution, o->smoothing_sigma_voxels, smooth);
    gradient_central_ref(smooth, o->resolution, scene_object_voxel_size(o), out);
    free(field);
    free(smooth);
    return out;
}

static void compare_object(const struct scene *s, size_t index, const struct build_work *b)
{
    const struct scene_object *o = &s->objects[index];
    double *ref = reference(s, o);
    const int *r = o->resolution;
    const int *as = b->atlas_size;
    int z0 = 0;
    for (size_t i = 0; i < index; i++)
        z0 += s->objects[i].resolution[2];
    double max_n = 0, max_g = 0, err_n = 0, err_g = 0;
    for (int z = 0; z < r[2]; z++) {
        for (int y = 0; y < r[1]; y++) {
            for (int x = 0; x < r[0]; x++) {
                size_t ri = (((size_t)z * r[1] + y) * r[0] + x) * 4;
                size_t ai = ((((size_t)(z + z0)) * as[1] + y) * as[0] + x) * 4;
                for (int c = 0; c < 3; c++) {
                    max_g = fmax(max_g, fabs(ref[ri + c]));
                    err_g = fmax(err_g, fabs(ref[ri + c] - b->atlas[ai + c]));
                }
                max_n = fmax(max_n, fabs(ref[ri + 3]));
                err_n = fmax(err_n, fabs(ref[ri + 3] - b->atlas[ai + 3]));
            }
        }
    }
    printf("object %zu (%dx%dx%d, sigma %.1f): max |n_gpu - n_ref| = %.2e, "
           "max |grad_gpu - grad_ref| = %.2e (max |grad| %.3f)\n",
           index, r[0], r[1], r[2], o->smoothing_sigma_voxels, err_n, err_g, max_g);
    /* float32 accumulation of <= 2*31+1 normalised weights and differences of n ~ 2:
     * a few ulp of 2 (2.4e-7 each) for n; the gradient divides differences by 2h, so its
     * error is that of n over h (h >= 1/20 here): bound 2e-5 absolute + 1e-5 relative. */
    CHECK_MSG(err_n < 2e-6, "n error %g", err_n);
    CHECK_MSG(err_g < 2e-5 + 1e-5 * max_g, "gradient error %g", err_g);
    CHECK(max_g > 0.1); /* the fields are not flat: the comparison means something */
    free(ref);
}

int main(void)
{
    struct err e = {0};
    struct gpu *gpu = test_gpu_create("test_volume_kernels");
    struct scene *s = NULL;
    struct scene_limits lim = scene_limits_default();
    if (scene_parse(scene_json, strlen(scene_json), &lim, &s, &e) != REFRACT_E_OK) {
        fprintf(stderr, "scene: %s\n", e.msg);
        CHECK(false);
        gpu_destroy(gpu, NULL);
        return test_summary("test_volume_kernels");
    }
    struct build_work b = {.scene = s};
    b.work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = build_run, .user = &b};
    CHECK_INT(gpu_run_sync(gpu, &b.work), REFRACT_E_OK);
    if (b.atlas) {
        compare_object(s, 0, &b);
        compare_object(s, 1, &b);
    }
    free(b.atlas);
    scene_destroy(s);
    gpu_destroy(gpu, NULL);
    return test_summary("test_volume_kernels");
}
