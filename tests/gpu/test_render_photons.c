/*
 * test_render_photons.c - the receiver's "photons" caustics (docs/photons.md) in the view
 * renderer (render_view: photons_gpu.c, shaders/photons.glsl) against the CPU double
 * reference (reftrace with reftrace_lighting.photons: the same photon map, gathered in
 * double, and the same shadow rays through the exact surfaces), pixel by pixel:
 *   1. a glass ball over a floor under a small lamp (point light with a radius): the
 *      caustic seen directly and through the ball, the shadow's edge, the lamp hidden;
 *   2. a tinted (absorbing) glass box under a spot light and a directional light, with an
 *      index-matched clear box beside it (not optical: no shadow, no photons).
 * And the photon part must matter: the same picture with an empty photon map differs.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/env.h"
#include "core/photon.h"
#include "core/pixel_sample.h"
#include "gpu/queue.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/scene_pathtrace.h"
#include "scene/scene_reference.h"
#include "gpu_test_util.h"
#include "unit/scene_test_util.h"
#include "test.h"

struct photon_work {
    struct gpu_work work;
    const struct scene *scene;
    const char *name;
    struct render_view_result out;
};

static void render_run(struct gpu_work *w, struct gpu *gpu)
{
    struct photon_work *pw = w->user;
    const struct scene *s = pw->scene;
    struct render_desc desc = {.photons_on_cpu = true}; /* the CPU twin's very map */
    struct render *r = render_create(gpu, &desc, &w->err);
    if (r == NULL)
        return;
    struct render_light rl[SCENE_MAX_LIGHTS];
    test_render_lights(s, rl);
    struct render_scene_source src = {.id = pw->name, .generation = 1, .scene = s};
    struct render_view_request req = {.camera = s->camera,
                                      .settings = s->render,
                                      .lights = rl,
                                      .light_count = (int)s->light_count};
    render_view(r, &src, &req, &pw->out, &w->err);
    render_destroy(r);
}

static void compare(struct gpu *gpu, const char *name, const char *doc, double close_fraction)
{
    struct scene *s = parse_ok(doc);
    CHECK(!scene_needs_light_simulation(s)); /* no light simulator: photons and shadow rays */
    struct photon_work pw = {.scene = s, .name = name};
    pw.work =
        (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = render_run, .user = &pw};
    CHECK_INT(gpu_run_sync(gpu, &pw.work), REFRACT_E_OK);
    if (pw.out.rgba == NULL) {
        fprintf(stderr, "%s: no image: %s\n", name, pw.work.err.msg);
        CHECK(false);
        scene_destroy(s);
        return;
    }
    /* The CPU side: the same photon maps, one per light at unit intensity (photons_gpu.c's
     * final-pass seed; the set does not depend on the thread count), gathered in double. */
    static struct scene_pathtrace sp;
    struct err e = {0};
    CHECK_INT(scene_pathtrace_geometry(s, NULL, NULL, &sp, &e), REFRACT_E_OK);
    struct photon_grid grids[SCENE_MAX_LIGHTS];
    struct photon_map_stats st = {0};
    size_t landed = 0;
    bool maps = scene_needs_photon_maps(s); /* "none": shadow rays only, no map */
    for (size_t j = 0; maps && j < s->light_count; j++) {
        struct pathtrace_light l;
        scene_pathtrace_light_unit(&s->lights[j], &l);
        struct pathtrace_scene one;
        photon_scene_one_light(&sp.scene, &l, &one);
        CHECK_INT(photon_map_build(&one, s->receiver.photons, s->receiver.photon_radius,
                                   photon_level_seed(PHOTON_LEVELS - 1), 2, &grids[j], &st, &e),
                  REFRACT_E_OK);
        landed += st.landed;
    }
    CHECK(!maps || landed > 1000);
    struct scene_reference ref;
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &ref, &e), REFRACT_E_OK);
    struct reftrace_light rl[SCENE_MAX_LIGHTS];
    test_reftrace_lights(s, LIGHT_MODE_DIRECT, rl);
    struct reftrace_lighting lt = {
        .lights = rl,
        .count = (int)s->light_count,
        .receiver = {.enabled = true,
                     .height = s->receiver.height,
                     .half_size = s->receiver.half_size,
                     .albedo = {s->receiver.albedo[0], s->receiver.albedo[1],
                                s->receiver.albedo[2]},
                     .center = {s->receiver.center[0], s->receiver.center[1]}},
        .photon_scene = &sp.scene};
    struct reftrace_light rl_none[SCENE_MAX_LIGHTS];
    for (size_t j = 0; j < s->light_count; j++) {
        rl_none[j] = rl[j];
        rl[j].photons = maps ? &grids[j] : NULL;
    }
    struct reftrace_lighting lt_none = lt;
    lt_none.lights = rl_none;
    struct reftrace_settings no_photons = ref.settings;
    ref.settings.lighting = &lt;
    no_photons.lighting = &lt_none;
    const struct scene_camera *cam = &s->camera;
    int w = pw.out.width, h = pw.out.height, total = w * h, close = 0;
    double sum_diff = 0.0, sum_ref = 0.0, sum_photons = 0.0, max_photons = 0.0, max_base = 0.0;
    for (int row = 0; row < h; row++) {
        for (int col = 0; col < w; col++) {
            vec3 r = test_reftrace_pixel(&ref, &ref.settings, cam, w, h, col, row,
                                         s->render.samples_per_pixel, NULL);
            vec3 r0 = test_reftrace_pixel(&ref, &no_photons, cam, w, h, col, row, 1, NULL);
            const float *g = &pw.out.rgba[(row * w + col) * 4];
            double want[3] = {r.x, r.y, r.z};
            double base[3] = {r0.x, r0.y, r0.z};
            bool ok = true;
            for (int k = 0; k < 3; k++) {
                double diff = fabs(g[k] - want[k]);
                sum_diff += diff;
                sum_ref += fabs(want[k]);
                sum_photons += fabs(want[k] - base[k]);
                max_photons = fmax(max_photons, want[k] - base[k]);
                max_base = fmax(max_base, base[k]);
                ok = ok && diff <= 1e-3 * (1.0 + fabs(want[k]));
            }
            close += ok;
            if (!ok && getenv("REFRACT_TEST_VERBOSE"))
                fprintf(stderr, "  %s (%d,%d): gpu %.5f %.5f %.5f ref %.5f %.5f %.5f\n", name, col,
                        row, g[0], g[1], g[2], want[0], want[1], want[2]);
        }
    }
    printf("%-28s %dx%d, %ld photons per light (%zu landed, radius %.4f): %5.1f%% of pixels "
           "within 1e-3 relative; mean |diff| %.1e of mean radiance %.3f, of which photons %.3f\n",
           name, w, h, st.emitted, landed, st.radius, 100.0 * close / total,
           sum_diff / (3.0 * total), sum_ref / (3.0 * total), sum_photons / (3.0 * total));
    /* A caustic is small but bright: the photons' brightest pixel outshines the rest. */
    printf("%-28s brightest photon radiance %.3f, brightest without photons %.3f\n", name,
           max_photons, max_base);
    if (maps)
        CHECK_MSG(sum_photons > 1e-3 * sum_ref && max_photons > max_base,
                  "%s: the photons add %g of %g, at most %g (%g without)", name, sum_photons,
                  sum_ref, max_photons, max_base);
    CHECK_MSG(close >= close_fraction * total, "%s: only %d of %d pixels within 1e-3", name, close,
              total);
    CHECK_MSG(sum_diff < 1e-3 * sum_ref, "%s: mean difference %g of %g", name, sum_diff, sum_ref);
    scene_reference_free(&ref);
    for (size_t j = 0; maps && j < s->light_count; j++)
        photon_grid_free(&grids[j]);
    free(pw.out.rgba);
    scene_destroy(s);
}

int main(void)
{
    struct gpu *gpu = test_gpu_create("test_render_photons");
    /* Pixels on a shadow's edge may fall on either side in float and double. */
    bool software = strstr(gpu_info(gpu)->renderer, "llvmpipe") != NULL;
    double close = software ? 0.98 : 0.95;
    compare(
        gpu, "ball under a lamp",
        "{\"camera\": {\"eye\": [-2.5, 1.6, 2.5], \"look_at\": [-0.2, -0.8, 0], \"fov_y_deg\": 45, "
        "\"width\": 64, \"height\": 48}, \"environment\": {\"intensity\": 0.1}, "
        "\"lights\": [{\"type\": \"point\", \"position\": [1, 4, 0.5], \"intensity\": 20, "
        "\"radius\": 0.05, \"camera_visible\": false}], "
        "\"receiver\": {\"height\": -1, \"half_size\": 3, \"caustics\": \"photons\", "
        "\"photons\": 200000}, "
        "\"surfaces\": [{\"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 0.6, "
        "\"medium\": {\"ior\": 1.5}, \"brdf\": {\"type\": \"none\"}}]}",
        close);
    /* "none" (docs/photons.md "Choosing"): the same ball casts its shadow, no caustic. */
    compare(
        gpu, "ball, caustics none",
        "{\"camera\": {\"eye\": [-2.5, 1.6, 2.5], \"look_at\": [-0.2, -0.8, 0], \"fov_y_deg\": 45, "
        "\"width\": 64, \"height\": 48}, \"environment\": {\"intensity\": 0.1}, "
        "\"lights\": [{\"type\": \"point\", \"position\": [1, 4, 0.5], \"intensity\": 20}], "
        "\"receiver\": {\"height\": -1, \"half_size\": 3, \"caustics\": \"none\"}, "
        "\"surfaces\": [{\"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 0.6, "
        "\"medium\": {\"ior\": 1.5}, \"brdf\": {\"type\": \"none\"}}]}",
        close);
    compare(gpu, "tinted box, spot, sun",
            "{\"camera\": {\"eye\": [0.5, 3, 3], \"look_at\": [0, -0.5, 0], \"fov_y_deg\": 50, "
            "\"width\": 64, \"height\": 48}, \"environment\": {\"intensity\": 0}, "
            "\"lights\": [{\"type\": \"spot\", \"position\": [0.3, 3, 0.2], \"direction\": [0, "
            "-1, 0], \"angle_deg\": 35, \"intensity\": 8, \"color\": [1, 0.8, 0.6]}, "
            "{\"type\": \"directional\", \"direction\": [0.3, -1, 0.2], \"intensity\": 0.5}], "
            "\"receiver\": {\"height\": -0.5, \"half_size\": \"infinite\", \"caustics\": "
            "\"photons\", \"photons\": 200000, \"photon_radius\": 0.05}, "
            "\"surfaces\": [{\"shape\": \"box\", \"center\": [-0.3, 0, 0], \"size\": [0.6, 0.4, "
            "0.8], \"medium\": {\"ior\": 1.6, \"attenuation\": [0.2, 1, 3]}, \"brdf\": {\"type\": "
            "\"none\"}}, "
            "{\"shape\": \"box\", \"center\": [0.6, 0, 0], \"size\": [0.4, 0.4, 0.4], "
            "\"medium\": {\"ior\": 1}, \"brdf\": {\"type\": \"none\"}}]}",
            close);
    /* Scene A of the peer scenes with 2^22 photons at 16 rays per pixel: the caustic seen
     * beside the ball needs thousands of photons per pixel, and a gather loop over photons
     * ran into llvmpipe's limit of 65535 loop iterations per shader invocation (all loops
     * together: LP_MAX_TGSI_LOOP_ITERATIONS), which silently dropped the pixel's later rays;
     * the lattice lookup is a few probes (docs/photons.md "Density estimate"). */
    compare(
        gpu, "scene A, 16 rays per pixel",
        "{\"camera\": {\"eye\": [0, 2.5, 7], \"look_at\": [0, -0.5, 0], \"fov_y_deg\": 35, "
        "\"width\": 160, \"height\": 120}, \"environment\": {\"intensity\": 0}, \"render\": "
        "{\"samples_per_pixel\": 16}, "
        "\"lights\": [{\"type\": \"point\", \"position\": [2, 6, 1], \"intensity\": 79.5775, "
        "\"radius\": 0.1, \"camera_visible\": false}], "
        "\"receiver\": {\"height\": -1, \"half_size\": \"infinite\", \"caustics\": \"photons\", "
        "\"photons\": 4194304}, "
        "\"surfaces\": [{\"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "
        "\"medium\": {\"ior\": 1.5}, \"brdf\": {\"type\": \"none\"}}]}",
        close);
    gpu_destroy(gpu, NULL);
    return test_summary("test_render_photons");
}
