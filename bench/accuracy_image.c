/*
 * accuracy_image.c - see accuracy_image.h.
 *
 * One measurement: build the light fields (CPU), run the light simulation of the scene's
 * first light to the end on the GPU, take its irradiance textures, render the view at
 * IMAGE_W x IMAGE_H. Time = simulation wall time + the render's GPU time (field building
 * and scene builds excluded: they happen once per scene, not per light pose). Error = the
 * root-mean-square difference of the linear luminance from the reference image, relative
 * to the reference's mean luminance, over the whole image and over the pixels where the
 * reference is brighter than twice its mean (the caustic, where the light simulation is
 * what the pixel shows).
 */
#include "accuracy_image.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "example_scene.h"
#include "gpu/queue.h"
#include "lightsim/gpu/lightsim_gpu.h"
#include "lightsim/lightsim.h"
#include "plot.h"
#include "render/render.h"
#include "scene/scene.h"

#define IMAGE_W 160
#define IMAGE_H 120
#define MAX_RUNS 12

struct image_setting {
    int resolution;
    double split;
};

struct image_run {
    struct gpu_work work;
    struct scene *scene;
    const char *id;
    struct image_setting set;
    double sim_ms, render_ms;
    int patches_peak;
    float *rgba; /* IMAGE_W * IMAGE_H * 4; owned */
};

static void run_on_gpu(struct gpu_work *w, struct gpu *gpu)
{
    struct image_run *r = w->user;
    struct scene *s = r->scene;
    s->lightsim.resolution = r->set.resolution;
    s->lightsim.split_voxels = r->set.split;
    struct lightsim_fields f;
    if (lightsim_fields_build_light(s, s->light_count > 0 ? &s->lights[0] : NULL, NULL, NULL, &f,
                                    &w->err) != REFRACT_E_OK)
        return;
    struct lightsim_gpu_run *run = NULL;
    struct irradiance_gpu vol;
    memset(&vol, 0, sizeof vol);
    struct render *rd = NULL;
    bool done = false;
    enum refract_code rc = lightsim_gpu_init(gpu, &w->err);
    glFinish();
    double t0 = gpu_time_ms();
    if (rc == REFRACT_E_OK)
        rc = lightsim_gpu_begin(gpu, &f, &s->lights[0], &s->lightsim, &run, &w->err);
    while (rc == REFRACT_E_OK && !done)
        rc = lightsim_gpu_advance(run, 64, &done, &w->err);
    glFinish();
    r->sim_ms = gpu_time_ms() - t0;
    if (rc == REFRACT_E_OK) {
        struct lightsim_stats st;
        lightsim_gpu_stats(run, &st);
        r->patches_peak = st.patches_peak;
        rc = lightsim_gpu_take_textures(run, &vol, &w->err);
    }
    struct render_desc desc = {0};
    if (rc == REFRACT_E_OK && (rd = render_create(gpu, &desc, &w->err)) == NULL)
        rc = w->err.code;
    if (rc == REFRACT_E_OK) {
        const struct scene_light *l = &s->lights[0];
        struct render_light rl = {.kind = l->kind,
                                  .position = l->position,
                                  .direction = l->direction,
                                  .cos_spot = cos(l->spot_angle_deg * M_PI / 180.0),
                                  .volume = &vol};
        for (int c = 0; c < 3; c++)
            rl.scale[c] = l->color[c] * l->intensity;
        struct render_view_request req = {
            .camera = s->camera, .settings = s->render, .lights = &rl, .light_count = 1};
        req.camera.width = IMAGE_W;
        req.camera.height = IMAGE_H;
        struct render_scene_source src = {.id = r->id, .generation = 1, .scene = s};
        struct render_view_result out;
        if (render_view(rd, &src, &req, &out, &w->err) == REFRACT_E_OK) {
            r->render_ms = out.gpu_ms;
            r->rgba = out.rgba;
        }
    }
    render_destroy(rd);
    irradiance_gpu_free(&vol);
    lightsim_gpu_run_destroy(run);
    lightsim_fields_free(&f);
}

static double luminance(const float *p)
{
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
}

/* Relative RMS errors: whole image, and the pixels brighter than twice the mean. */
static void image_error(const float *img, const float *ref, double *all, double *bright)
{
    int n = IMAGE_W * IMAGE_H, nb = 0;
    double mean = 0.0, s_all = 0.0, s_b = 0.0;
    for (int i = 0; i < n; i++)
        mean += luminance(ref + 4 * i) / n;
    for (int i = 0; i < n; i++) {
        double yr = luminance(ref + 4 * i), d = luminance(img + 4 * i) - yr;
        s_all += d * d;
        if (yr > 2.0 * mean) {
            s_b += d * d;
            nb++;
        }
    }
    *all = mean > 0.0 ? sqrt(s_all / n) / mean : NAN;
    *bright = mean > 0.0 && nb > 0 ? sqrt(s_b / nb) / mean : NAN;
}

static bool run_one(struct gpu *gpu, struct scene *s, const char *id, struct image_setting set,
                    struct image_run *r)
{
    memset(r, 0, sizeof *r);
    r->scene = s;
    r->id = id;
    r->set = set;
    r->work = (struct gpu_work){.priority = GPU_PRIORITY_BATCH, .run = run_on_gpu, .user = r};
    if (gpu_run_sync(gpu, &r->work) != REFRACT_E_OK || r->rgba == NULL) {
        fprintf(stderr, "refract-accuracy: %s at %d^3, split %g: %s\n", id, set.resolution,
                set.split, r->work.err.msg);
        return false;
    }
    fprintf(stderr, "image %-18s lightsim %3d split %-4g: %8.0f ms simulation, %6.1f ms render\n",
            id, set.resolution, set.split, r->sim_ms, r->render_ms);
    return true;
}

bool accuracy_image_report(struct gpu *gpu, bool quick, const char *images_dir, FILE *f)
{
    static const char *const scenes[2] = {"ball_lens_caustic", "smoke_spot"};
    const struct image_setting ref_set = {quick ? 64 : 128, 1.0};
    const struct image_setting full[] = {{32, 4}, {32, 2}, {32, 1}, {64, 4},
                                         {64, 2}, {64, 1}, {96, 1}};
    const struct image_setting fast[] = {{32, 4}, {32, 2}, {32, 1}, {48, 1}};
    const struct image_setting *sweep = quick ? fast : full;
    int count = quick ? 4 : 7;
    fprintf(f,
            "## Images\n\nRender time against image error for a sharp caustic "
            "(ball_lens_caustic: a ball lens focusing sunlight on a receiver) and a volume "
            "caustic (smoke_spot: a glass sphere focusing a spot light into smoke), sweeping "
            "the irradiance volume's resolution (`lightsim.resolution`) and the tessellation "
            "threshold (`lightsim.split`, voxels: a wavefront patch longer than this splits). "
            "Reference: the same scene simulated at %d^3 with split %g, the finest the bound "
            "allows, so the errors of settings close to it are underestimated. Time: light "
            "simulation (wall) plus the render's GPU time at %dx%d; the simulation runs once "
            "per light pose, the render once per frame. Error: RMS difference of linear "
            "luminance from the reference, relative to the reference's mean, over the whole "
            "image and over the caustic (pixels brighter than twice the mean).\n\n"
            "![images](images/accuracy_images.png)\n\n"
            "| scene | lightsim.resolution | split | simulation ms | render ms | peak patches | "
            "error (image) | error (caustic) |\n|---|---|---|---|---|---|---|---|\n",
            ref_set.resolution, ref_set.split, IMAGE_W, IMAGE_H);
    struct plot_point pts[2 * MAX_RUNS];
    int npts = 0;
    bool ok = true;
    for (int si = 0; si < 2 && ok; si++) {
        char path[256];
        const char *src = getenv("REFRACT_SOURCE_DIR");
        snprintf(path, sizeof path, "%s/proto/examples/%s.json", src ? src : ".", scenes[si]);
        struct scene *s = bench_load_example("refract-accuracy", path, 64);
        if (s == NULL || s->light_count == 0) {
            scene_destroy(s);
            return false;
        }
        struct image_run ref;
        ok = run_one(gpu, s, scenes[si], ref_set, &ref);
        for (int k = 0; ok && k < count; k++) {
            struct image_run r;
            if (!(ok = run_one(gpu, s, scenes[si], sweep[k], &r)))
                break;
            double e_all, e_bright;
            image_error(r.rgba, ref.rgba, &e_all, &e_bright);
            fprintf(f, "| %s | %d | %g | %.0f | %.1f | %d | %.3f | %.3f |\n", scenes[si],
                    sweep[k].resolution, sweep[k].split, r.sim_ms, r.render_ms, r.patches_peak,
                    e_all, e_bright);
            pts[npts++] = (struct plot_point){r.sim_ms + r.render_ms, e_all, si, false};
            free(r.rgba);
        }
        if (ok)
            fprintf(f, "| %s (reference) | %d | %g | %.0f | %.1f | %d | 0 | 0 |\n", scenes[si],
                    ref_set.resolution, ref_set.split, ref.sim_ms, ref.render_ms, ref.patches_peak);
        free(ref.rgba);
        scene_destroy(s);
    }
    fprintf(f, "\n");
    /* Pareto front per scene on (time, image error). */
    for (int i = 0; i < npts; i++) {
        pts[i].front = true;
        for (int j = 0; j < npts && pts[i].front; j++)
            if (j != i && pts[j].series == pts[i].series && pts[j].x <= pts[i].x &&
                pts[j].y <= pts[i].y && (pts[j].x < pts[i].x || pts[j].y < pts[i].y))
                pts[i].front = false;
    }
    struct plot_desc d = {.title = "Images: error vs simulation + render time",
                          .x_label = "light simulation + render time (ms, llvmpipe)",
                          .y_label = "relative RMS luminance error",
                          .series_names = {"ball_lens_caustic", "smoke_spot"},
                          .series_count = 2,
                          .points = pts,
                          .count = npts};
    char png[512];
    snprintf(png, sizeof png, "%s/accuracy_images.png", images_dir);
    struct err e = {0};
    if (ok && plot_write_png(&d, png, &e) != REFRACT_E_OK) {
        fprintf(stderr, "refract-accuracy: %s\n", e.msg);
        ok = false;
    }
    return ok;
}
