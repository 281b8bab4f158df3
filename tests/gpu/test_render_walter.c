/*
 * test_render_walter.c - single scattering by walter2009's exact paths (docs/walter.md) in
 * the view renderer (LIGHT_MODE_WALTER: shaders/walter.glsl in lighting.glsl's
 * light_inscatter) against the CPU double reference (reftrace with
 * reftrace_lighting.walter: core/walter.c), pixel by pixel:
 *   1. peer scene B at 80 x 60: a scattering glass ball lit from behind by a point light;
 *   2. an air bubble (index 1 in water of 1.33, eta < 1) holding a forward-scattering
 *      mist (g 0.6), under a spot light and a directional light;
 *   3. scene B at 4 rays per pixel (each ray's own in-scattering points);
 *   4. a light inside the ball (straight, attenuated light; no boundary to cross).
 * The scenes need no light simulation, and the in-scattered light must matter (the image
 * without it, lights off, is darker).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/reftrace_light.h"
#include "gpu/queue.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/scene_reference.h"
#include "gpu_test_util.h"
#include "unit/scene_test_util.h"
#include "test.h"

struct walter_work {
    struct gpu_work work;
    const struct scene *scene;
    struct render_view_result out;
};

static void render_run(struct gpu_work *w, struct gpu *gpu)
{
    struct walter_work *ww = w->user;
    const struct scene *s = ww->scene;
    struct render_desc desc = {0};
    struct render *r = render_create(gpu, &desc, &w->err);
    if (r == NULL)
        return;
    struct render_light rl[SCENE_MAX_LIGHTS];
    test_render_lights(s, rl);
    struct render_scene_source src = {.id = "walter", .generation = 1, .scene = s};
    struct render_view_request req = {.camera = s->camera,
                                      .settings = s->render,
                                      .lights = rl,
                                      .light_count = (int)s->light_count};
    render_view(r, &src, &req, &ww->out, &w->err);
    render_destroy(r);
}

static void compare(struct gpu *gpu, const char *name, const char *doc, double close_fraction,
                    double mean_bound)
{
    struct scene *s = parse_ok(doc);
    struct scene_walter wa;
    CHECK(scene_walter_sphere(s, &wa));
    CHECK(!scene_needs_light_simulation(s));
    struct walter_work ww = {.scene = s};
    ww.work =
        (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = render_run, .user = &ww};
    CHECK_INT(gpu_run_sync(gpu, &ww.work), REFRACT_E_OK);
    if (ww.out.rgba == NULL) {
        fprintf(stderr, "%s: no image: %s\n", name, ww.work.err.msg);
        CHECK(false);
        scene_destroy(s);
        return;
    }
    struct scene_reference ref;
    struct err e = {0};
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &ref, &e), REFRACT_E_OK);
    struct reftrace_light rl[SCENE_MAX_LIGHTS];
    test_reftrace_lights(s, LIGHT_MODE_WALTER, rl);
    struct reftrace_lighting lt = {
        .lights = rl,
        .count = (int)s->light_count,
        .walter = {.enabled = true,
                   .center = wa.center,
                   .radius = wa.radius,
                   .eta = wa.eta,
                   .sigma_t = {wa.sigma_t[0], wa.sigma_t[1], wa.sigma_t[2]}}};
    struct reftrace_lighting dark = {0};
    struct reftrace_settings unlit = ref.settings;
    ref.settings.lighting = &lt;
    unlit.lighting = &dark;
    const struct scene_camera *cam = &s->camera;
    int w = ww.out.width, h = ww.out.height, total = w * h, close = 0;
    double sum_diff = 0.0, sum_ref = 0.0, sum_unlit = 0.0;
    for (int row = 0; row < h; row++) {
        for (int col = 0; col < w; col++) {
            int n = s->render.samples_per_pixel;
            vec3 r = test_reftrace_pixel(&ref, &ref.settings, cam, w, h, col, row, n, &lt);
            vec3 r0 = test_reftrace_pixel(&ref, &unlit, cam, w, h, col, row, 1, NULL);
            const float *g = &ww.out.rgba[(row * w + col) * 4];
            double want[3] = {r.x, r.y, r.z};
            double base[3] = {r0.x, r0.y, r0.z};
            bool ok = true;
            for (int k = 0; k < 3; k++) {
                double diff = fabs(g[k] - want[k]);
                sum_diff += diff;
                sum_ref += fabs(want[k]);
                sum_unlit += fabs(base[k]);
                ok = ok && diff <= 2e-3 * (1e-3 + fabs(want[k]));
            }
            close += ok;
            if (!ok && getenv("REFRACT_TEST_VERBOSE"))
                fprintf(stderr, "  %s (%d,%d): gpu %.6f %.6f %.6f ref %.6f %.6f %.6f\n", name, col,
                        row, g[0], g[1], g[2], want[0], want[1], want[2]);
        }
    }
    printf("%-26s %dx%d: %5.1f%% of pixels within 2e-3 relative; mean |diff| %.2e of mean "
           "radiance %.4f (%.4f without the lights' in-scattering)\n",
           name, w, h, 100.0 * close / total, sum_diff / (3.0 * total), sum_ref / (3.0 * total),
           sum_unlit / (3.0 * total));
    CHECK_MSG(sum_ref > 1.5 * sum_unlit + 1e-6, "%s: the in-scattering adds too little (%g, %g)",
              name, sum_ref, sum_unlit);
    CHECK_MSG(close >= close_fraction * total, "%s: only %d of %d pixels within 2e-3", name, close,
              total);
    CHECK_MSG(sum_diff < mean_bound * sum_ref, "%s: mean difference %g of %g", name, sum_diff,
              sum_ref);
    scene_reference_free(&ref);
    free(ww.out.rgba);
    scene_destroy(s);
}

/* Peer scene B (proto/examples/peer_scene_b.json) at the image size `size` with `render`
 * settings (string literals). */
#define PEER_B(size, render)                                                                       \
    "{\"camera\": {\"eye\": [0, 2.5, 7], \"look_at\": [0, -0.5, 0], \"fov_y_deg\": 35, " size      \
    "}, \"environment\": {\"intensity\": 0}, " render                                              \
    "\"lights\": [{\"type\": \"point\", \"position\": [0, 1, -5], \"intensity\": 79.5775, "        \
    "\"radius\": 0.1, \"camera_visible\": false}], "                                               \
    "\"surfaces\": [{\"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "                \
    "\"medium\": {\"ior\": 1.5, \"attenuation\": [0.05, 0.05, 0.05], "                             \
    "\"scattering\": [0.5, 0.5, 0.5], \"anisotropy\": 0}}]}"

int main(void)
{
    struct gpu *gpu = test_gpu_create("test_render_walter");
    compare(gpu, "peer scene B", PEER_B("\"width\": 80, \"height\": 60", ""), 0.97, 1e-3);
    compare(
        gpu, "air bubble in water",
        "{\"ambient_ior\": 1.33, \"camera\": {\"eye\": [0.5, 0.8, 3], \"look_at\": [0, 0, 0], "
        "\"fov_y_deg\": 40, \"width\": 64, \"height\": 48}, "
        "\"environment\": {\"intensity\": 0.005}, "
        "\"lights\": [{\"type\": \"spot\", \"position\": [1.5, 2.5, 0.5], "
        "\"direction\": [-0.5, -1, -0.2], \"angle_deg\": 25, \"intensity\": 12, "
        "\"color\": [1, 0.8, 0.6]}, {\"type\": \"directional\", \"direction\": [0.3, -0.2, -1], "
        "\"intensity\": 0.7}], "
        "\"surfaces\": [{\"shape\": \"sphere\", \"center\": [0.1, 0, -0.2], \"radius\": 0.7, "
        "\"medium\": {\"ior\": 1.0, \"attenuation\": [0.1, 0.2, 0.3], "
        "\"scattering\": [0.8, 0.6, 0.4], \"anisotropy\": 0.6}}]}",
        0.97, 1e-3);
    /* 4 rays per pixel: the jittered rays and the shifted in-scattering points
     * (pixel_step_offset) of each sample, the same on both sides. */
    compare(gpu, "peer scene B, 4 rays a pixel",
            PEER_B("\"width\": 40, \"height\": 30", "\"render\": {\"samples_per_pixel\": 4}, "),
            0.97, 1e-3);
    compare(gpu, "lamp inside the ball",
            "{\"camera\": {\"eye\": [0, 1, 4], \"look_at\": [0, 0, 0], \"fov_y_deg\": 40, "
            "\"width\": 48, \"height\": 36}, \"environment\": {\"intensity\": 0}, "
            "\"lights\": [{\"type\": \"point\", \"position\": [0.2, 0.1, 0], \"intensity\": 3}], "
            "\"surfaces\": [{\"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "
            "\"medium\": {\"ior\": 1.5, \"attenuation\": [0.2, 0.2, 0.2], "
            "\"scattering\": [0.6, 0.6, 0.6], \"anisotropy\": -0.3}}]}",
            0.97, 1e-3);
    gpu_destroy(gpu, NULL);
    return test_summary("render_walter");
}
