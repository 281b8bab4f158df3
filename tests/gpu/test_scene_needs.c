/*
 * test_scene_needs.c - only what a scene needs (issue 6) in the render core:
 *
 *   - GPU memory: a scene's gpu_bytes (the status behind gpu.memory_bytes) holds the
 *     index+gradient atlas (RGBA32F), one RGBA16F atlas per channel some object uses and
 *     1x1x1 stand-ins for the others, the environment stand-in and the empty-space map;
 *     adding two channels adds exactly their two atlases less their stand-ins.
 *   - Kernel variants: compiling the unused channels and the lights out of the march
 *     changes nothing in the image: the default variant against the all-features one
 *     (render_desc.all_variant_bits), with skipping and termination off in both.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu/queue.h"
#include "render/render.h"
#include "scene/scene.h"
#include "gpu_test_util.h"
#include "unit/scene_test_util.h"
#include "test.h"

#define RES 16
#define CAMERA                                                                                     \
    "\"camera\": {\"eye\": [0.3, 0.8, 3.6], \"look_at\": [0, 0, 0], \"fov_y_deg\": 40, "           \
    "\"width\": 40, \"height\": 30}, "
#define BOX "\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, "
#define GLASS "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.7, \"inside\": 1.5}"
#define PLAIN "{\"name\": \"plain\", " CAMERA "\"objects\": [{" BOX GLASS "}]}"
#define TINTED                                                                                     \
    "{\"name\": \"tinted\", " CAMERA "\"objects\": [{" BOX GLASS ", \"attenuation\": "             \
    "{\"shape\": \"sphere\", \"radius\": 0.7, \"inside\": [0.5, 1, 2]}, \"emission\": "            \
    "{\"shape\": \"sphere\", \"radius\": 0.3, \"inside\": [1, 0.5, 0.2]}}]}"

struct needs_work {
    struct gpu_work work;
    const struct scene *scene;
    bool all_bits;
    size_t gpu_bytes;
    float *rgba;
};

static void needs_run(struct gpu_work *w, struct gpu *gpu)
{
    struct needs_work *n = w->user;
    struct render_desc desc = {.all_variant_bits = n->all_bits};
    struct render *r = render_create(gpu, &desc, &w->err);
    if (r == NULL)
        return;
    struct render_scene_source src = {.id = n->scene->name, .generation = 1, .scene = n->scene};
    struct render_view_request req = {.camera = n->scene->camera, .settings = n->scene->render};
    req.settings.empty_space_skipping = false;
    req.settings.min_throughput = 0.0;
    struct render_view_result out;
    if (render_view(r, &src, &req, &out, &w->err) == REFRACT_E_OK) {
        n->gpu_bytes = out.scene.gpu_bytes;
        n->rgba = out.rgba;
    }
    render_destroy(r);
}

static void render(struct gpu *gpu, const struct scene *s, bool all_bits, struct needs_work *n)
{
    *n = (struct needs_work){.scene = s, .all_bits = all_bits};
    n->work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = needs_run, .user = n};
    CHECK_INT(gpu_run_sync(gpu, &n->work), REFRACT_E_OK);
    CHECK(n->rgba != NULL);
}

/* Largest |a - b| over the largest |b|. */
static double image_gap(const float *a, const float *b, int pixels)
{
    double worst = 0.0, peak = 0.0;
    for (int i = 0; i < pixels * 4; i++) {
        worst = fmax(worst, fabs((double)a[i] - b[i]));
        peak = fmax(peak, fabs((double)b[i]));
    }
    return worst / fmax(peak, 1e-30);
}

int main(void)
{
    struct gpu *gpu = test_gpu_create("test_scene_needs");
    struct scene *plain = parse_ok(PLAIN), *tinted = parse_ok(TINTED);
    if (plain && tinted) {
        struct needs_work p, pa, t, ta;
        render(gpu, plain, false, &p);
        render(gpu, plain, true, &pa);
        render(gpu, tinted, false, &t);
        render(gpu, tinted, true, &ta);
        const size_t voxels = RES * RES * RES, ior = voxels * 16, channel = voxels * 8;
        printf("gpu_bytes: ior only %zu, with attenuation and emission %zu (atlas %zu + %zu "
               "per channel)\n",
               p.gpu_bytes, t.gpu_bytes, ior, channel);
        /* stand-ins (a texel each), the environment's and the map (64 cells) are small */
        CHECK(p.gpu_bytes >= ior && p.gpu_bytes <= ior + 1024);
        size_t added = t.gpu_bytes - p.gpu_bytes;
        CHECK_MSG(added <= 2 * channel && added >= 2 * channel - 2 * 16,
                  "two channels added %zu bytes, expected %zu less two stand-ins", added,
                  2 * channel);
        int pixels = plain->camera.width * plain->camera.height;
        double gap_plain = image_gap(p.rgba, pa.rgba, pixels);
        double gap_tinted = image_gap(t.rgba, ta.rgba, pixels);
        printf("scene variant against the all-features variant: largest difference %.3g "
               "(ior only), %.3g (attenuation, emission)\n",
               gap_plain, gap_tinted);
        /* The same arithmetic on the same data: only the compiler's freedom to reorder the
         * float operations of the compiled-out terms differs (seen: 0). */
        CHECK(gap_plain <= 1e-6);
        CHECK(gap_tinted <= 1e-6);
        /* the tinted sphere is darker where it absorbs: the channels are really in use */
        CHECK(image_gap(t.rgba, p.rgba, pixels) > 1e-2);
        free(p.rgba);
        free(pa.rgba);
        free(t.rgba);
        free(ta.rgba);
    }
    scene_destroy(plain);
    scene_destroy(tinted);
    gpu_destroy(gpu, NULL);
    return test_summary("test_scene_needs");
}
