/*
 * accuracy_features.c - see accuracy_features.h.
 */
#include "accuracy_features.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/env.h"
#include "example_scene.h"
#include "gpu/queue.h"
#include "render/render.h"
#include "scene/scene.h"

/* The report's tolerance for an optimization's change to the image: what float32 already
 * costs against the double-precision reference (tests/integration/test_render_reference.c
 * bounds): mean |difference| at most 1e-3 of the mean radiance and at least 96% of the
 * pixels within 1e-3 relative (+1e-4 absolute). */
#define TOL_MEAN 1e-3
#define TOL_PIXELS 0.96

/* The example scenes (proto/examples/<name>.json at the report's resolution), then two
 * with much empty space, where skipping has work to do: a small glass sphere in a large
 * box and a Gaussian GRIN lens whose index decays to the ambient value; and two absorbing
 * ones, where early termination has: dark tinted glass (throughput down to 1e-8 through
 * the middle) and the same with emission. */
static const char *const examples[] = {"glass_sphere_voxels",
                                       "gaussian_lens",
                                       "luneburg_lens",
                                       "maxwell_fisheye",
                                       "bumpy_sphere",
                                       "wine_glass_voxels",
                                       "ball_lens_caustic_voxels",
                                       "rounded_cube_three_layers_voxels",
                                       "glass_block_lettering_voxels",
                                       "smoke_spot"};
#define EXAMPLE_COUNT (int)(sizeof examples / sizeof examples[0])
#define SPARSE_CAMERA                                                                              \
    "\"camera\": {\"eye\": [0.3, 0.8, 3.6], \"look_at\": [0, 0, 0], \"fov_y_deg\": 40}"
static const struct {
    const char *name, *json; /* %d: the resolution */
} sparse[] = {
    {"small sphere in a large box",
     "{\"name\": \"sparse_sphere\", " SPARSE_CAMERA ", \"objects\": [{\"bounds\": {\"min\": "
     "[-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": %d, \"ior\": {\"shape\": \"sphere\", "
     "\"center\": [0.1, 0, 0], \"radius\": 0.25, \"inside\": 1.5}, \"attenuation\": {\"shape\": "
     "\"sphere\", \"center\": [0.1, 0, 0], \"radius\": 0.25, \"inside\": [0.5, 1, 2]}}]}"},
    {"GRIN lens in a large box",
     "{\"name\": \"sparse_grin\", " SPARSE_CAMERA ", \"objects\": [{\"bounds\": {\"min\": "
     "[-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": %d, \"smoothing_sigma\": 0, \"ior\": "
     "{\"profile\": \"gaussian\", \"center\": [0, 0, 0], \"n_peak\": 1.5, \"n_out\": 1.0, "
     "\"sigma\": 0.15}}]}"},
    {"dark glass sphere",
     "{\"name\": \"dark_sphere\", " SPARSE_CAMERA ", \"objects\": [{\"bounds\": {\"min\": "
     "[-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": %d, \"ior\": {\"shape\": \"sphere\", "
     "\"radius\": 0.9, \"inside\": 1.5}, \"attenuation\": {\"shape\": \"sphere\", \"radius\": "
     "0.9, \"inside\": [6, 9, 12]}}]}"},
    {"dark glowing sphere",
     "{\"name\": \"dark_glow\", " SPARSE_CAMERA ", \"objects\": [{\"bounds\": {\"min\": "
     "[-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": %d, \"ior\": {\"shape\": \"sphere\", "
     "\"radius\": 0.9, \"inside\": 1.5}, \"attenuation\": {\"shape\": \"sphere\", \"radius\": "
     "0.9, \"inside\": [6, 9, 12]}, \"emission\": {\"shape\": \"sphere\", \"radius\": 0.9, "
     "\"inside\": [2, 1, 0.5]}}]}"},
};
#define SPARSE_COUNT (int)(sizeof sparse / sizeof sparse[0])
#define SCENE_COUNT (EXAMPLE_COUNT + SPARSE_COUNT)

enum knob { RENDER_ALL_BITS, RENDER_ALL_BITS_CELL8, RENDER_DEFAULT, RENDER_COUNT };

struct config {
    const char *name;
    enum knob render;
    bool skip;
    double min_throughput;
};

static const struct config configs[] = {
    {"all features (baseline)", RENDER_ALL_BITS, false, 0.0},
    {"variants", RENDER_DEFAULT, false, 0.0},
    {"skipping 4^3", RENDER_ALL_BITS, true, 0.0},
    {"skipping 8^3", RENDER_ALL_BITS_CELL8, true, 0.0},
    {"termination 1e-6", RENDER_ALL_BITS, false, 1e-6},
    {"termination 1e-4", RENDER_ALL_BITS, false, 1e-4},
    {"termination 1e-2", RENDER_ALL_BITS, false, 1e-2},
    {"all on (default)", RENDER_DEFAULT, true, 1e-6},
};
#define CONFIG_COUNT (int)(sizeof configs / sizeof configs[0])

struct run {
    double ms, steps, mean_err, max_err, close;
    bool ok;
};

struct scene_runs {
    struct gpu_work work;
    const struct scene *s;
    const char *id;
    int width, height, repeats;
    struct run runs[CONFIG_COUNT];
    size_t bytes, all_channel_bytes;
    double build_ms;
    bool failed;
};

/* The lights of the scene without irradiance volumes: in scenes that need no light
 * simulation they light by the unshadowed direct mode, otherwise they add nothing; the
 * light simulation itself is not part of this measurement. */
static int scene_lights(const struct scene *s, struct render_light *rl)
{
    int n = (int)s->light_count;
    for (int j = 0; j < n; j++) {
        const struct scene_light *l = &s->lights[j];
        rl[j] = (struct render_light){.kind = l->kind,
                                      .position = l->position,
                                      .direction = l->direction,
                                      .cos_spot = cos(l->spot_angle_deg * M_PI / 180.0)};
        for (int c = 0; c < 3; c++)
            rl[j].scale[c] = l->color[c] * l->intensity;
    }
    return n;
}

/* The image's difference from the baseline: mean and largest |difference| over the mean
 * |baseline| radiance, and the fraction of pixel channels within 1e-3 relative + 1e-4. */
static void image_error(const float *img, const float *ref, int pixels, struct run *r)
{
    double sum_ref = 0.0, sum_diff = 0.0, worst = 0.0;
    int close = 0;
    for (int i = 0; i < pixels; i++) {
        bool ok = true;
        for (int c = 0; c < 3; c++) {
            double d = fabs((double)img[4 * i + c] - ref[4 * i + c]);
            sum_ref += fabs(ref[4 * i + c]);
            sum_diff += d;
            worst = fmax(worst, d);
            ok = ok && d <= 1e-3 * fabs(ref[4 * i + c]) + 1e-4;
        }
        close += ok;
    }
    double mean = sum_ref / (3.0 * pixels);
    r->mean_err = mean > 0.0 ? sum_diff / (3.0 * pixels) / mean : 0.0;
    r->max_err = mean > 0.0 ? worst / mean : 0.0;
    r->close = (double)close / pixels;
}

/* Mean integration steps per camera ray: trace_rays on the pixels' view rays. */
static bool steps_per_ray(struct render *rd, const struct render_scene_source *src,
                          const struct scene_render_settings *st, const struct scene_camera *cam,
                          double *steps, struct err *e)
{
    size_t n = (size_t)cam->width * cam->height;
    struct render_trace_ray *rays = calloc(n, sizeof *rays);
    struct render_trace_hit *hits = calloc(n, sizeof *hits);
    bool ok = rays && hits;
    for (int row = 0; ok && row < cam->height; row++)
        for (int col = 0; col < cam->width; col++) {
            vec3 o, d;
            camera_ray(cam->eye, cam->look_at, cam->up, cam->fov_y_deg, cam->width, cam->height,
                       col, row, &o, &d);
            struct render_trace_ray *r = &rays[(size_t)row * cam->width + col];
            r->origin[0] = o.x, r->origin[1] = o.y, r->origin[2] = o.z;
            r->direction[0] = d.x, r->direction[1] = d.y, r->direction[2] = d.z;
        }
    ok = ok && render_trace(rd, src, st, rays, n, hits, NULL, e) == REFRACT_E_OK;
    double sum = 0.0;
    for (size_t i = 0; ok && i < n; i++)
        sum += hits[i].steps;
    *steps = ok ? sum / (double)n : NAN;
    free(rays);
    free(hits);
    return ok;
}

static size_t atlas_voxels(const struct scene *s)
{
    int mx = 0, my = 0, sz = 0;
    for (size_t i = 0; i < s->object_count; i++) {
        const int *r = s->objects[i].resolution;
        mx = r[0] > mx ? r[0] : mx;
        my = r[1] > my ? r[1] : my;
        sz += r[2];
    }
    return (size_t)mx * my * sz;
}

static void scene_run(struct gpu_work *w, struct gpu *gpu)
{
    struct scene_runs *sr = w->user;
    struct render *rd[RENDER_COUNT] = {NULL};
    const struct render_desc descs[RENDER_COUNT] = {
        [RENDER_ALL_BITS] = {.all_variant_bits = true},
        [RENDER_ALL_BITS_CELL8] = {.all_variant_bits = true, .skip_cell_voxels = 8},
        [RENDER_DEFAULT] = {0},
    };
    for (int k = 0; k < RENDER_COUNT; k++)
        if ((rd[k] = render_create(gpu, &descs[k], &w->err)) == NULL)
            sr->failed = true;
    struct render_scene_source src = {.id = sr->id, .generation = 1, .scene = sr->s};
    struct render_scene_status status = {0};
    if (!sr->failed &&
        render_scene_prepare(rd[RENDER_DEFAULT], &src, &status, &w->err) != REFRACT_E_OK)
        sr->failed = true;
    sr->bytes = status.gpu_bytes;
    sr->build_ms = status.build_ms;
    /* every channel allocated: the ior+gradient atlas (RGBA32F) and four RGBA16F atlases */
    sr->all_channel_bytes = atlas_voxels(sr->s) * (16 + 4 * 8);
    struct render_light rl[SCENE_MAX_LIGHTS];
    struct render_view_request req = {.camera = sr->s->camera, .lights = rl};
    req.light_count = scene_lights(sr->s, rl);
    req.camera.width = sr->width;
    req.camera.height = sr->height;
    float *images[CONFIG_COUNT] = {NULL};
    for (int c = 0; c < CONFIG_COUNT; c++)
        sr->runs[c].ms = INFINITY;
    /* Round k = 0 compiles each variant (and builds the scene in each renderer); the
     * configurations then take turns, so a change in the machine's load spreads over all
     * of them, and each keeps its fastest frame. */
    for (int k = 0; k <= sr->repeats && !sr->failed; k++) {
        for (int c = 0; c < CONFIG_COUNT && !sr->failed; c++) {
            req.settings = sr->s->render;
            req.settings.empty_space_skipping = configs[c].skip;
            req.settings.min_throughput = configs[c].min_throughput;
            struct render_view_result out;
            if (render_view(rd[configs[c].render], &src, &req, &out, &w->err) != REFRACT_E_OK) {
                sr->failed = true;
                break;
            }
            if (k > 0)
                sr->runs[c].ms = fmin(sr->runs[c].ms, out.gpu_ms);
            free(images[c]);
            images[c] = out.rgba;
        }
    }
    for (int c = 0; c < CONFIG_COUNT && !sr->failed; c++) {
        struct run *run = &sr->runs[c];
        image_error(images[c], images[0], sr->width * sr->height, run);
        req.settings = sr->s->render;
        req.settings.empty_space_skipping = configs[c].skip;
        req.settings.min_throughput = configs[c].min_throughput;
        run->ok = steps_per_ray(rd[configs[c].render], &src, &req.settings, &req.camera,
                                &run->steps, &w->err);
        sr->failed = !run->ok;
    }
    for (int c = 0; c < CONFIG_COUNT; c++)
        free(images[c]);
    for (int k = 0; k < RENDER_COUNT; k++)
        render_destroy(rd[k]);
}

static const char *scene_name(int i)
{
    return i < EXAMPLE_COUNT ? examples[i] : sparse[i - EXAMPLE_COUNT].name;
}

static bool within(const struct run *r)
{
    return r->mean_err <= TOL_MEAN && r->close >= TOL_PIXELS;
}

bool accuracy_features_report(struct gpu *gpu, bool quick, FILE *f)
{
    const int res = quick ? 32 : 64, width = quick ? 96 : 160, height = quick ? 72 : 120;
    const int repeats = quick ? 3 : 5;
    static struct scene_runs all[SCENE_COUNT];
    const char *src_dir = getenv("REFRACT_SOURCE_DIR");
    bool ok = true;
    const char *only = getenv("REFRACT_FEATURES_ONLY"); /* comma list: to look at a few */
    for (int i = 0; i < SCENE_COUNT && ok; i++) {
        if (only && !strstr(only, scene_name(i))) {
            all[i].runs[0].ms = NAN;
            continue;
        }
        struct scene *s = NULL;
        if (i < EXAMPLE_COUNT) {
            char path[512];
            snprintf(path, sizeof path, "%s/proto/examples/%s.json", src_dir ? src_dir : ".",
                     examples[i]);
            s = bench_load_example("refract-accuracy", path, res);
        } else {
            char json[1024];
            snprintf(json, sizeof json, sparse[i - EXAMPLE_COUNT].json, res);
            struct scene_limits lim = scene_limits_default();
            struct err e = {0};
            if (scene_parse(json, strlen(json), &lim, &s, &e) != REFRACT_E_OK)
                fprintf(stderr, "refract-accuracy: %s\n", e.msg);
        }
        if (s == NULL)
            return false;
        all[i] = (struct scene_runs){
            .s = s, .id = scene_name(i), .width = width, .height = height, .repeats = repeats};
        all[i].work =
            (struct gpu_work){.priority = GPU_PRIORITY_BATCH, .run = scene_run, .user = &all[i]};
        enum refract_code rc = gpu_run_sync(gpu, &all[i].work);
        if (rc != REFRACT_E_OK || all[i].failed) {
            fprintf(stderr, "refract-accuracy: %s: %s\n", scene_name(i), all[i].work.err.msg);
            ok = false;
        }
        scene_destroy(s);
        all[i].s = NULL;
    }
    if (!ok)
        return false;
    fprintf(f,
            "## Only what a scene needs\n\n"
            "Each optimization that makes the march do only what a scene needs, alone and all "
            "together, against the **all-features path**: every optional channel (attenuation, "
            "emission, opaque, scattering) and the lights compiled into the march whatever the "
            "scene uses (unused channels read their 1x1x1 stand-ins), no empty-space "
            "skipping, no early termination (`render.min_throughput` 0). **variants**: the "
            "kernel variant of the scene's channels; **skipping**: `render.empty_space_skipping` "
            "with macro cells of 4^3 or 8^3 voxels (docs/tracing.md \"Empty space\"); "
            "**termination**: `render.min_throughput` at 1e-6 (the default), 1e-4 and 1e-2. "
            "Every example scene at %d^3 voxels, %dx%d pixels, its own camera and render "
            "settings, its lights without irradiance volumes (the light simulation is not "
            "measured here). **ms** is the GPU time of one frame, the fastest of %d renders "
            "after a warm-up (llvmpipe: CPU time, it moves with the machine's load); "
            "**speedup** is the baseline's ms over the configuration's, from the same run; "
            "**steps/ray** the mean integration steps of the camera rays (trace_rays; a jump "
            "over empty space counts as one). **error** compares the image with the "
            "baseline's: mean and largest |difference| over the baseline's mean radiance, and "
            "the pixels whose channels are all within 1e-3 relative (+1e-4).\n\n"
            "**Tolerance**: an optimization may change the image by no more than float32 "
            "arithmetic already moves it from the double-precision reference "
            "(tests/integration/test_render_reference.c): mean error at most %.0e and at "
            "least %.0f%% of the pixels within 1e-3. **ok** says whether a configuration "
            "stays within it.\n\n",
            res, width, height, repeats, TOL_MEAN, 100.0 * TOL_PIXELS);
    /* Summary: per configuration, the geometric mean speedup and the worst error. */
    fprintf(f,
            "### Summary over the %d example scenes\n\n"
            "| configuration | speedup (geometric mean) | speedup (range) | worst mean error | "
            "worst max error | fewest pixels within 1e-3 | within tolerance |\n"
            "|---|---|---|---|---|---|---|\n",
            EXAMPLE_COUNT);
    for (int c = 1; c < CONFIG_COUNT; c++) {
        double log_sum = 0.0, lo = INFINITY, hi = 0.0, wm = 0.0, wx = 0.0, wc = 1.0;
        int in = 0;
        for (int i = 0; i < EXAMPLE_COUNT; i++) {
            const struct run *r = &all[i].runs[c];
            double sp = all[i].runs[0].ms / r->ms;
            log_sum += log(sp);
            lo = fmin(lo, sp);
            hi = fmax(hi, sp);
            wm = fmax(wm, r->mean_err);
            wx = fmax(wx, r->max_err);
            wc = fmin(wc, r->close);
            in += within(r);
        }
        fprintf(f, "| %s | %.2fx | %.2f-%.2fx | %.1e | %.1e | %.1f%% | %d of %d scenes |\n",
                configs[c].name, exp(log_sum / EXAMPLE_COUNT), lo, hi, wm, wx, 100.0 * wc, in,
                EXAMPLE_COUNT);
    }
    /* One look: speedups per scene and configuration. */
    fprintf(f, "\n### Speedups at a glance\n\n"
               "The all-features path's ms per frame over each configuration's; `*` marks a "
               "configuration outside the tolerance on that scene. The last four scenes are not "
               "examples: a small sphere and a GRIN lens in a box 4 to 8 times their size, "
               "where most of the box is empty space, and a dark glass sphere (sigma_a 6, 9, "
               "12 per unit over up to 1.8 units: throughput down to 1e-8), alone and glowing, "
               "where rays are absorbed.\n\n| scene | baseline ms |");
    for (int c = 1; c < CONFIG_COUNT; c++)
        fprintf(f, " %s |", configs[c].name);
    fprintf(f, "\n|---|---|");
    for (int c = 1; c < CONFIG_COUNT; c++)
        fprintf(f, "---|");
    fprintf(f, "\n");
    for (int i = 0; i < SCENE_COUNT; i++) {
        fprintf(f, "| %s | %.1f |", scene_name(i), all[i].runs[0].ms);
        for (int c = 1; c < CONFIG_COUNT; c++)
            fprintf(f, " %.2fx%s |", all[i].runs[0].ms / all[i].runs[c].ms,
                    within(&all[i].runs[c]) ? "" : " *");
        fprintf(f, "\n");
    }
    fprintf(f, "\n### Per scene\n\n"
               "| scene | configuration | ms | speedup | steps/ray | mean error | max error | "
               "pixels within 1e-3 | ok |\n|---|---|---|---|---|---|---|---|---|\n");
    for (int i = 0; i < SCENE_COUNT; i++) {
        for (int c = 0; c < CONFIG_COUNT; c++) {
            const struct run *r = &all[i].runs[c];
            fprintf(f, "| %s | %s | %.1f | %.2fx | %.1f | %.1e | %.1e | %.1f%% | %s |\n",
                    c == 0 ? scene_name(i) : "", configs[c].name, r->ms, all[i].runs[0].ms / r->ms,
                    r->steps, r->mean_err, r->max_err, 100.0 * r->close,
                    c == 0      ? ""
                    : within(r) ? "yes"
                                : "**no**");
        }
    }
    fprintf(f, "\n### GPU memory per scene\n\n"
               "`gpu.memory_bytes` of the scene status (channels no object uses are not "
               "allocated) against every channel allocated, and the scene build (field "
               "evaluation, smoothing, gradient, the other channels, the empty-space map).\n\n"
               "| scene | memory (used channels) | every channel | build ms |\n"
               "|---|---|---|---|\n");
    for (int i = 0; i < SCENE_COUNT; i++)
        fprintf(f, "| %s | %.2f MiB | %.2f MiB | %.0f |\n", scene_name(i),
                (double)all[i].bytes / 1048576.0, (double)all[i].all_channel_bytes / 1048576.0,
                all[i].build_ms);
    fprintf(f, "\n");
    return true;
}
