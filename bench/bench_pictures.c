/*
 * bench_pictures.c - refract-pictures: the fast renderer's pictures against
 * refractd's own reference path tracer (issue 14 item 5; docs/accuracy.md "Pictures against
 * the reference"). Not a test: it asserts nothing.
 *
 *     build/refract-pictures proto/examples/peer_scene_a.json [more scenes]
 *         [--ref-samples 256] [--settings 32:1,64:1,64:4,128:4] [--size 320x240]
 *         [--threads N] [--cache build/reference-cache] [--out section.md]
 *         [--images docs/images] [--ref-max-scatter N]
 *
 * A scene named as `scene.json@N` gets N reference samples per pixel instead of
 * --ref-samples (a scattering medium seen through glass needs far more than a caustic).
 *
 * Per scene: the reference (the CPU double-precision path tracer of docs/pathtracer.md,
 * --ref-samples paths per pixel, cached in --cache by the document's bytes, the size and
 * the sample count, since it takes minutes), then the fast renderer for each setting
 * `R:S` (lightsim.resolution R, render.samples_per_pixel S): every light simulated on the
 * GPU to the end, then one render. Time = light simulation wall time + the render's GPU
 * time (what a new light pose costs; a frame of a known pose costs the render alone).
 * Error = the relative RMSE of issue 14, sqrt(sum (x - r)^2 / sum r^2) over the image's
 * three channels. The reference's own noise enters that figure as sqrt(sum var / sum r^2)
 * (var: the variance of each pixel's mean), printed beside it: an error close to the
 * noise says nothing more than "as good as the reference can tell". "mean fast/ref" is the
 * ratio of the two images' sums over every pixel and channel (too dark below 1).
 * --ref-max-scatter N renders a second reference whose paths have at most N medium
 * scattering events (pathtrace_scene.max_scatter; 1: single scattering, what the fast
 * renderer models) and adds each setting's error and mean ratio against it, so that the
 * share of multiple scattering can be told from the fast renderer's own error.
 * --mask-above X leaves the pixels where the full reference exceeds X (any channel) out of
 * those extra figures (e.g. the refracted image of an emitter the fast renderer does not
 * show); with a mask the extra columns appear against the full reference too. --raw also
 * writes the best setting's picture as linear floats (image_accuracy_<scene>_fast.rgba32f:
 * width x height RGBA, rows top down, host byte order) for analyses of one's own.
 *
 * --ref-plain makes the references without walter2009's exact connections in the path
 * tracer (pathtrace_scene.walter, docs/walter.md "In the path tracer"), the plain
 * unidirectional estimator; references made with them are cached under a "-w" name.
 * --ref-walter-only counts, after a vertex in the walter medium, no lamp hit at all: the
 * image of exactly the connected paths (light that reached the vertex through one
 * crossing of the boundary), what the fast renderer's single scattering models ("-wc").
 *
 * --no-highlights sets every object's and surface's `brdf` to "none" in the fast renderer:
 * its highlights of the `lights` (tevs2007 eq. 5.6) have no counterpart in the reference,
 * which treats a smooth interface as the perfect mirror it is (a point light's reflection
 * in it is a delta no camera ray can hit; a spherical lamp's is its image), so a GGX
 * highlight a jittered ray happens to hit can hold most of an image's squared error.
 *
 * Output: a Markdown table on stdout (or --out), the error-against-time plot
 * images/image_accuracy.png, and per scene the reference and the best setting's picture
 * (images/image_accuracy_<scene>_{reference,fast}.png) with the same exposure.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/pathtrace_image.h"
#include "pathtrace_threads.h"
#include "example_scene.h"
#include "gpu/queue.h"
#include "io/io_image.h"
#include "lightsim/gpu/lightsim_gpu.h"
#include "lightsim/lightsim.h"
#include "plot.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/scene_pathtrace.h"

#define MAX_SETTINGS 16
#define MAX_SCENES 6

struct setting {
    int resolution, spp; /* resolution 0: photons */
    int photons;         /* receiver.caustics "photons" with this many (docs/photons.md) */
};

struct options {
    int ref_samples, threads, width, height;
    int ref_max_scatter; /* > 0: a second reference with at most this many scatterings */
    double mask_above;   /* > 0: the extra figures leave out pixels brighter in the reference */
    bool raw;            /* also write the best picture as linear floats */
    bool ref_plain;      /* references without walter2009's exact connections */
    bool ref_connected;  /* the exact connections only (pathtrace_walter.connected_only) */
    bool no_highlights;  /* every object's and surface's brdf "none" in the fast renderer */
    const char *cache, *out, *images;
    struct setting settings[MAX_SETTINGS];
    int setting_count;
};

/* ---- the reference --------------------------------------------------------------------- */

static uint64_t fnv1a(const char *p, size_t n)
{
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < n; i++)
        h = (h ^ (uint8_t)p[i]) * 1099511628211ull;
    return h;
}

/* mean and var: 3 doubles per pixel each. Reads the cache file when it exists, else renders
 * and writes it. Returns the render's seconds (from the cache: as recorded). */
static bool reference(const struct options *o, const char *text, size_t len, struct scene *s, int w,
                      int h, int max_scatter, double *mean, double *var, double *seconds)
{
    char path[1024];
    char limit[32] = "";
    struct scene_walter wa;
    bool walter = !o->ref_plain && scene_walter_sphere(s, &wa);
    /* "-w": made with the exact connections (pathtrace_scene.walter); "-sN": N scatterings */
    const char *wtag = !walter ? "" : o->ref_connected ? "-wc" : "-w";
    if (max_scatter > 0)
        snprintf(limit, sizeof limit, "%s-s%d", wtag, max_scatter);
    else
        snprintf(limit, sizeof limit, "%s", wtag);
    snprintf(path, sizeof path, "%s/%016llx-%dx%d-%d%s.ref", o->cache,
             (unsigned long long)fnv1a(text, len), w, h, o->ref_samples, limit);
    size_t n = (size_t)w * h * 3;
    FILE *f = fopen(path, "rb");
    if (f) {
        bool ok = fread(seconds, sizeof *seconds, 1, f) == 1 &&
                  fread(mean, sizeof *mean, n, f) == n && fread(var, sizeof *var, n, f) == n;
        fclose(f);
        if (ok) {
            fprintf(stderr, "refract-pictures: reference from %s\n", path);
            return true;
        }
    }
    static struct scene_pathtrace pt;
    struct err e = {0};
    if (scene_pathtrace_init(s, NULL, NULL, &pt, &e) != REFRACT_E_OK) {
        fprintf(stderr, "refract-pictures: %s\n", e.msg);
        return false;
    }
    pt.scene.max_scatter = max_scatter;
    if (o->ref_plain)
        pt.scene.walter.enabled = false;
    pt.scene.walter.connected_only = o->ref_connected;
    const struct scene_camera *c = &s->camera;
    struct pathtrace_camera cam = {c->eye, c->look_at, c->up, c->fov_y_deg, w, h};
    struct pathtrace_image img;
    if (pathtrace_image_init(&img, w, h) != 0)
        return false;
    *seconds = bench_pathtrace_threads(&img, &pt.scene, &cam, o->threads, o->ref_samples);
    for (size_t i = 0; i < (size_t)w * h; i++)
        pathtrace_image_pixel(&img, (int64_t)i, mean + 3 * i, var + 3 * i);
    pathtrace_image_fini(&img);
    mkdir(o->cache, 0755);
    if ((f = fopen(path, "wb")) != NULL) {
        fwrite(seconds, sizeof *seconds, 1, f);
        fwrite(mean, sizeof *mean, n, f);
        fwrite(var, sizeof *var, n, f);
        fclose(f);
    }
    fprintf(stderr, "refract-pictures: reference %dx%d, %d samples%s: %.1f s\n", w, h,
            o->ref_samples, limit, *seconds);
    return true;
}

/* ---- the fast renderer ----------------------------------------------------------------- */

struct fast_run {
    struct gpu_work work;
    struct scene *scene;
    const char *id;
    int width, height;
    double sim_ms, render_ms;
    float *rgba; /* owned */
};

static void fast_on_gpu(struct gpu_work *w, struct gpu *gpu)
{
    struct fast_run *r = w->user;
    struct scene *s = r->scene;
    int nl = (int)s->light_count;
    bool needed = scene_needs_light_simulation(s);
    struct lightsim_fields f;
    memset(&f, 0, sizeof f);
    struct irradiance_gpu vol[SCENE_MAX_LIGHTS];
    memset(vol, 0, sizeof vol);
    struct render *rd = NULL;
    enum refract_code rc = REFRACT_E_OK;
    if (needed && nl > 0) {
        if ((rc = lightsim_fields_build(s, NULL, NULL, &f, &w->err)) == REFRACT_E_OK)
            rc = lightsim_gpu_init(gpu, &w->err);
        glFinish();
        double t0 = gpu_time_ms();
        for (int k = 0; k < nl && rc == REFRACT_E_OK; k++) {
            struct lightsim_gpu_run *run = NULL;
            bool done = false;
            rc = lightsim_gpu_begin(gpu, &f, &s->lights[k], &s->lightsim, &run, &w->err);
            while (rc == REFRACT_E_OK && !done)
                rc = lightsim_gpu_advance(run, 64, &done, &w->err);
            if (rc == REFRACT_E_OK)
                rc = lightsim_gpu_take_textures(run, &vol[k], &w->err);
            lightsim_gpu_run_destroy(run);
        }
        glFinish();
        r->sim_ms = gpu_time_ms() - t0;
    }
    struct render_desc desc = {0};
    if (rc == REFRACT_E_OK && (rd = render_create(gpu, &desc, &w->err)) == NULL)
        rc = w->err.code;
    if (rc == REFRACT_E_OK) {
        struct render_light rl[SCENE_MAX_LIGHTS];
        memset(rl, 0, sizeof rl);
        for (int k = 0; k < nl; k++) {
            const struct scene_light *l = &s->lights[k];
            rl[k] = (struct render_light){.kind = l->kind,
                                          .position = l->position,
                                          .direction = l->direction,
                                          .cos_spot = cos(l->spot_angle_deg * M_PI / 180.0),
                                          .volume = needed ? &vol[k] : NULL,
                                          .radius = l->radius,
                                          .camera_hidden = !l->camera_visible};
            for (int c = 0; c < 3; c++)
                rl[k].scale[c] = l->color[c] * l->intensity;
        }
        struct render_view_request req = {
            .camera = s->camera, .settings = s->render, .lights = rl, .light_count = nl};
        req.camera.width = r->width;
        req.camera.height = r->height;
        struct render_scene_source src = {.id = r->id, .generation = 1, .scene = s};
        struct render_view_result out;
        if (render_view(rd, &src, &req, &out, &w->err) == REFRACT_E_OK) {
            r->render_ms = out.gpu_ms;
            if (s->receiver.enabled && s->receiver.caustics == SCENE_CAUSTICS_PHOTONS)
                r->sim_ms = out.total_ms - out.gpu_ms; /* the photon map (and the read-back) */
            r->rgba = out.rgba;
        }
    }
    render_destroy(rd);
    for (int k = 0; k < nl; k++)
        irradiance_gpu_free(&vol[k]);
    if (needed && nl > 0)
        lightsim_fields_free(&f);
}

/* ---- measures and pictures ------------------------------------------------------------- */

/* The relative RMSE of issue 14: sqrt(sum (x - r)^2 / sum r^2) over the three channels. */
static double relative_rmse(const float *rgba, const double *ref, size_t pixels)
{
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < pixels; i++)
        for (int c = 0; c < 3; c++) {
            double d = (double)rgba[4 * i + c] - ref[3 * i + c];
            num += d * d;
            den += ref[3 * i + c] * ref[3 * i + c];
        }
    return den > 0.0 ? sqrt(num / den) : NAN;
}

/* sum fast / sum reference over every pixel (keep NULL) or the kept ones, all channels. */
static double mean_ratio(const float *rgba, const double *ref, size_t pixels, const bool *keep)
{
    double a = 0.0, b = 0.0;
    for (size_t i = 0; i < pixels; i++)
        for (int c = 0; c < 3 && (keep == NULL || keep[i]); c++) {
            a += rgba[4 * i + c];
            b += ref[3 * i + c];
        }
    return b > 0.0 ? a / b : NAN;
}

/* relative_rmse and reference_noise over the kept pixels. */
static void masked_figures(const float *rgba, const double *ref, const double *var, size_t pixels,
                           const bool *keep, double *rmse, double *noise)
{
    double num = 0.0, den = 0.0, v = 0.0;
    for (size_t i = 0; i < pixels; i++)
        for (int c = 0; c < 3 && keep[i]; c++) {
            double d = (double)rgba[4 * i + c] - ref[3 * i + c];
            num += d * d;
            den += ref[3 * i + c] * ref[3 * i + c];
            v += var[3 * i + c];
        }
    *rmse = den > 0.0 ? sqrt(num / den) : NAN;
    *noise = den > 0.0 ? sqrt(v / den) : NAN;
}

static double reference_noise(const double *ref, const double *var, size_t pixels)
{
    double num = 0.0, den = 0.0;
    for (size_t i = 0; i < 3 * pixels; i++) {
        num += var[i];
        den += ref[i] * ref[i];
    }
    return den > 0.0 ? sqrt(num / den) : NAN;
}

/* An exposure that puts the reference's 95th-percentile luminance at 0.8 (the same for
 * both pictures of a scene, so they compare). */
static double picture_exposure(const double *ref, size_t pixels)
{
    double *y = malloc(pixels * sizeof *y);
    for (size_t i = 0; i < pixels; i++)
        y[i] = 0.2126 * ref[3 * i] + 0.7152 * ref[3 * i + 1] + 0.0722 * ref[3 * i + 2];
    qsort(y, pixels, sizeof *y, bench_compare_doubles);
    double p95 = y[(pixels * 95) / 100];
    free(y);
    return p95 > 0.0 ? log2(0.8 / p95) : 0.0;
}

static void write_picture(const char *path, const float *rgba, int w, int h, double ev)
{
    uint8_t *px = malloc((size_t)w * h * 4);
    void *png = NULL;
    size_t len = 0;
    struct err e = {0};
    io_tonemap_srgb8(rgba, w, h, ev, IO_TONEMAP_CLAMP, px);
    if (io_encode_png(px, w, h, &png, &len, &e) == REFRACT_E_OK) {
        FILE *f = fopen(path, "wb");
        if (f) {
            fwrite(png, 1, len, f);
            fclose(f);
        }
    } else {
        fprintf(stderr, "refract-pictures: %s: %s\n", path, e.msg);
    }
    free(png);
    free(px);
}

static const char *base_name(const char *path)
{
    const char *b = strrchr(path, '/');
    return b ? b + 1 : path;
}

/* "64" (lightsim.resolution) or "p1M" (photons) for tables and messages. */
static const char *setting_name(const struct setting *st, char *buf, size_t size)
{
    if (st->photons <= 0)
        snprintf(buf, size, "%d", st->resolution);
    else if (st->photons % 1048576 == 0)
        snprintf(buf, size, "p%dM", st->photons / 1048576);
    else if (st->photons % 1024 == 0)
        snprintf(buf, size, "p%dk", st->photons / 1024);
    else
        snprintf(buf, size, "p%d", st->photons);
    return buf;
}

static bool parse_settings(const char *arg, struct options *o)
{
    o->setting_count = 0;
    for (const char *p = arg; *p && o->setting_count < MAX_SETTINGS;) {
        struct setting st = {0};
        char unit = 0;
        if (*p == 'p') { /* pN[k|M]:S, photons */
            int n = sscanf(p + 1, "%d%c:%d", &st.photons, &unit, &st.spp);
            if (n == 3 && (unit == 'k' || unit == 'M'))
                st.photons *= unit == 'k' ? 1024 : 1048576;
            else if (sscanf(p + 1, "%d:%d", &st.photons, &st.spp) != 2)
                return false;
            if (st.photons < 1024 || st.photons > SCENE_MAX_PHOTONS || st.spp < 1)
                return false;
        } else if (sscanf(p, "%d:%d", &st.resolution, &st.spp) != 2 || st.resolution < 8 ||
                   st.spp < 1) {
            return false;
        }
        o->settings[o->setting_count++] = st;
        const char *comma = strchr(p, ',');
        p = comma ? comma + 1 : p + strlen(p);
    }
    return o->setting_count > 0;
}

int main(int argc, char **argv)
{
    struct options o = {.ref_samples = 256,
                        .threads = (int)sysconf(_SC_NPROCESSORS_ONLN),
                        .cache = "build/reference-cache",
                        .images = "docs/images"};
    parse_settings("32:1,64:1,64:4,96:4,128:4", &o);
    const char *scenes[MAX_SCENES];
    int scene_samples[MAX_SCENES]; /* "scene.json@N": this scene's reference samples */
    static char scene_paths[MAX_SCENES][1024];
    int scene_count = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(a, "--ref-samples") && v) {
            o.ref_samples = atoi(v);
            i++;
        } else if (!strcmp(a, "--settings") && v) {
            if (!parse_settings(v, &o)) {
                fprintf(stderr, "refract-pictures: --settings wants R:S,... "
                                "(lightsim.resolution >= 8 : samples per pixel >= 1)\n");
                return 2;
            }
            i++;
        } else if (!strcmp(a, "--size") && v) {
            sscanf(v, "%dx%d", &o.width, &o.height);
            i++;
        } else if (!strcmp(a, "--threads") && v) {
            o.threads = atoi(v);
            i++;
        } else if (!strcmp(a, "--ref-max-scatter") && v) {
            o.ref_max_scatter = atoi(v);
            i++;
        } else if (!strcmp(a, "--ref-plain")) {
            o.ref_plain = true;
        } else if (!strcmp(a, "--ref-walter-only")) {
            o.ref_connected = true;
        } else if (!strcmp(a, "--raw")) {
            o.raw = true;
        } else if (!strcmp(a, "--no-highlights")) {
            o.no_highlights = true;
        } else if (!strcmp(a, "--mask-above") && v) {
            o.mask_above = atof(v);
            i++;
        } else if (!strcmp(a, "--cache") && v) {
            o.cache = v;
            i++;
        } else if (!strcmp(a, "--out") && v) {
            o.out = v;
            i++;
        } else if (!strcmp(a, "--images") && v) {
            o.images = v;
            i++;
        } else if (a[0] != '-' && scene_count < MAX_SCENES) {
            snprintf(scene_paths[scene_count], sizeof scene_paths[0], "%s", a);
            char *at = strrchr(scene_paths[scene_count], '@');
            scene_samples[scene_count] = 0;
            if (at != NULL) {
                *at = '\0';
                scene_samples[scene_count] = atoi(at + 1);
                if (scene_samples[scene_count] < 1) {
                    fprintf(stderr,
                            "refract-pictures: %s: after @ comes the reference's "
                            "samples per pixel, a whole number >= 1\n",
                            a);
                    return 2;
                }
            }
            scenes[scene_count] = scene_paths[scene_count];
            scene_count++;
        } else {
            fprintf(stderr, "usage: refract-pictures SCENE.json[@SAMPLES]... [--ref-samples 256] "
                            "[--settings 32:1,64:4] [--size WxH] [--threads N] [--cache DIR] "
                            "[--out FILE.md] [--images DIR] [--ref-max-scatter N] "
                            "[--mask-above X] [--raw] [--no-highlights]\n");
            return 2;
        }
    }
    if (scene_count == 0 || o.ref_samples < 1) {
        fprintf(stderr, "refract-pictures: name at least one scene document\n");
        return 2;
    }
    o.threads = o.threads < 1 ? 1 : (o.threads > 64 ? 64 : o.threads);
    struct err e = {0};
    struct gpu_desc desc = {.context = {.device_index = -1}};
    struct gpu *gpu = gpu_create(&desc, &e);
    if (gpu == NULL) {
        fprintf(stderr, "refract-pictures: %s\n", e.msg);
        return 1;
    }
    FILE *out = o.out ? fopen(o.out, "w") : stdout;
    if (out == NULL) {
        fprintf(stderr, "refract-pictures: cannot write %s: %s\n", o.out, strerror(errno));
        return 1;
    }
    bench_write_header(out, gpu, argc, argv);
    bool extra = o.ref_max_scatter > 0 || o.mask_above > 0.0;
    if (o.mask_above > 0.0)
        fprintf(out, "\n\"masked\": without the pixels where the reference exceeds %g.\n",
                o.mask_above);
    if (o.no_highlights)
        fprintf(out, "\nFast renderer without `brdf` highlights (--no-highlights).\n");
    if (o.ref_max_scatter > 0)
        fprintf(out,
                "\n\"<= %d\": against a reference of the paths with at most %d medium "
                "scattering event%s.\n",
                o.ref_max_scatter, o.ref_max_scatter, o.ref_max_scatter == 1 ? "" : "s");
    fprintf(out,
            "\n| scene | reference (samples, s, own noise) | caustics (lightsim.resolution or pN "
            "photons) | "
            "samples/pixel | light simulation or photon map ms | render ms | relative RMSE | "
            "mean fast/ref |%s\n"
            "| --- | --- | --- | --- | --- | --- | --- | --- |%s\n",
            !extra                   ? ""
            : o.ref_max_scatter == 0 ? " masked RMSE (ref noise) | masked mean fast/ref |"
                                     : " masked RMSE (ref noise) | masked mean fast/ref | <= N: "
                                       "RMSE (ref noise) | <= N: mean fast/ref |",
            !extra                   ? ""
            : o.ref_max_scatter == 0 ? " --- | --- |"
                                     : " --- | --- | --- | --- |");
    struct plot_point pts[MAX_SCENES * MAX_SETTINGS];
    int npts = 0;
    struct plot_desc plot = {.title = "Fast renderer against the reference path tracer",
                             .x_label = "light simulation + render time (ms, llvmpipe)",
                             .y_label = "relative RMSE"};
    int status = 0;
    const int default_ref_samples = o.ref_samples;
    for (int si = 0; si < scene_count; si++) {
        o.ref_samples = scene_samples[si] > 0 ? scene_samples[si] : default_ref_samples;
        FILE *f = fopen(scenes[si], "rb");
        static char text[1 << 20];
        size_t len = f ? fread(text, 1, sizeof text - 1, f) : 0;
        if (f)
            fclose(f);
        struct scene *s = bench_load_example("refract-pictures", scenes[si], 0);
        if (s == NULL || len == 0) {
            status = 1;
            continue;
        }
        if (o.no_highlights) {
            for (size_t k = 0; k < s->object_count; k++)
                s->objects[k].brdf.kind = SCENE_BRDF_NONE;
            for (size_t k = 0; k < s->surface_count; k++)
                s->surfaces[k].brdf.kind = SCENE_BRDF_NONE;
        }
        int w = o.width ? o.width : s->camera.width, h = o.height ? o.height : s->camera.height;
        size_t pixels = (size_t)w * h;
        double *mean = malloc(pixels * 3 * sizeof *mean), *var = malloc(pixels * 3 * sizeof *var);
        double ref_s = 0.0;
        /* the optional second reference (mean1, var1) and the mask */
        double *mean1 = malloc(pixels * 3 * sizeof *mean1),
               *var1 = malloc(pixels * 3 * sizeof *var1);
        bool *keep = malloc(pixels * sizeof *keep);
        double ref1_s = 0.0;
        if (!reference(&o, text, len, s, w, h, 0, mean, var, &ref_s) ||
            (o.ref_max_scatter > 0 &&
             !reference(&o, text, len, s, w, h, o.ref_max_scatter, mean1, var1, &ref1_s))) {
            status = 1;
            free(mean);
            free(var);
            free(mean1);
            free(var1);
            free(keep);
            scene_destroy(s);
            continue;
        }
        for (size_t i = 0; i < pixels; i++) {
            keep[i] = true;
            for (int c = 0; c < 3 && o.mask_above > 0.0; c++)
                keep[i] = keep[i] && mean[3 * i + c] <= o.mask_above;
        }
        double noise = reference_noise(mean, var, pixels), ev = picture_exposure(mean, pixels);
        char name[128];
        snprintf(name, sizeof name, "%s", base_name(scenes[si]));
        char *dot = strrchr(name, '.');
        if (dot)
            *dot = '\0';
        static char series_name[MAX_SCENES][128]; /* the file's stem: paths overflow the legend */
        snprintf(series_name[si], sizeof series_name[si], "%s", name);
        plot.series_names[plot.series_count < PLOT_MAX_SERIES ? plot.series_count : 0] =
            series_name[si];
        int series = plot.series_count < PLOT_MAX_SERIES ? plot.series_count++ : 0;
        char path[1024];
        float *ref_rgba = malloc(pixels * 4 * sizeof *ref_rgba);
        for (size_t i = 0; i < pixels; i++) {
            for (int c = 0; c < 3; c++)
                ref_rgba[4 * i + c] = (float)mean[3 * i + c];
            ref_rgba[4 * i + 3] = 1.0f;
        }
        snprintf(path, sizeof path, "%s/image_accuracy_%s_reference.png", o.images, name);
        write_picture(path, ref_rgba, w, h, ev);
        free(ref_rgba);
        double best = INFINITY;
        /* k = -1: a warm-up with the first setting, not reported (shader compiles on first
         * use would otherwise count against it). */
        char sname[32];
        for (int k = -1; k < o.setting_count; k++) {
            bool warm_up = k < 0;
            if (warm_up)
                k = 0;
            if (o.settings[k].photons > 0) {
                s->receiver.caustics = SCENE_CAUSTICS_PHOTONS;
                s->receiver.photons = o.settings[k].photons;
            } else {
                s->receiver.caustics = SCENE_CAUSTICS_VOLUME;
                s->lightsim.resolution = o.settings[k].resolution;
            }
            s->render.samples_per_pixel = o.settings[k].spp;
            struct fast_run r = {.scene = s, .id = name, .width = w, .height = h};
            r.work =
                (struct gpu_work){.priority = GPU_PRIORITY_BATCH, .run = fast_on_gpu, .user = &r};
            if (gpu_run_sync(gpu, &r.work) != REFRACT_E_OK || r.rgba == NULL) {
                fprintf(stderr, "refract-pictures: %s at %s:%d: %s\n", name,
                        setting_name(&o.settings[k], sname, sizeof sname), o.settings[k].spp,
                        r.work.err.msg);
                status = 1;
                continue;
            }
            if (warm_up) {
                free(r.rgba);
                k = -1;
                continue;
            }
            double err = relative_rmse(r.rgba, mean, pixels);
            double ratio = mean_ratio(r.rgba, mean, pixels, NULL);
            setting_name(&o.settings[k], sname, sizeof sname);
            fprintf(out, "| %s | %d, %.0f s, %.4f | %s | %d | %.0f | %.1f | %.4f | %.3f |", name,
                    o.ref_samples, ref_s, noise, sname, o.settings[k].spp, r.sim_ms, r.render_ms,
                    err, ratio);
            if (extra) {
                double m_err, m_noise, s_err = NAN, s_noise = NAN, s_ratio = NAN;
                masked_figures(r.rgba, mean, var, pixels, keep, &m_err, &m_noise);
                if (o.ref_max_scatter > 0) {
                    masked_figures(r.rgba, mean1, var1, pixels, keep, &s_err, &s_noise);
                    s_ratio = mean_ratio(r.rgba, mean1, pixels, keep);
                }
                fprintf(out, " %.4f (%.4f) | %.3f |", m_err, m_noise,
                        mean_ratio(r.rgba, mean, pixels, keep));
                if (o.ref_max_scatter > 0) /* no columns of nan without that reference */
                    fprintf(out, " %.4f (%.4f) | %.3f |", s_err, s_noise, s_ratio);
            }
            fprintf(out, "\n");
            fflush(out);
            fprintf(stderr, "%s %s:%d: %.0f ms + %.1f ms, relative RMSE %.4f\n", name, sname,
                    o.settings[k].spp, r.sim_ms, r.render_ms, err);
            if (npts < MAX_SCENES * MAX_SETTINGS)
                pts[npts++] = (struct plot_point){r.sim_ms + r.render_ms, err, series, false};
            if (err < best) {
                best = err;
                snprintf(path, sizeof path, "%s/image_accuracy_%s_fast.png", o.images, name);
                write_picture(path, r.rgba, w, h, ev);
                snprintf(path, sizeof path, "%s/image_accuracy_%s_fast.rgba32f", o.images, name);
                FILE *fr = o.raw ? fopen(path, "wb") : NULL;
                if (fr) {
                    fwrite(r.rgba, sizeof *r.rgba, pixels * 4, fr);
                    fclose(fr);
                }
            }
            free(r.rgba);
        }
        free(mean);
        free(var);
        free(mean1);
        free(var1);
        free(keep);
        scene_destroy(s);
    }
    for (int i = 0; i < npts; i++) {
        pts[i].front = true;
        for (int j = 0; j < npts && pts[i].front; j++)
            if (j != i && pts[j].series == pts[i].series && pts[j].x <= pts[i].x &&
                pts[j].y <= pts[i].y && (pts[j].x < pts[i].x || pts[j].y < pts[i].y))
                pts[i].front = false;
    }
    plot.points = pts;
    plot.count = npts;
    char png[1024];
    snprintf(png, sizeof png, "%s/image_accuracy.png", o.images);
    if (npts > 0 && plot_write_png(&plot, png, &e) != REFRACT_E_OK) {
        fprintf(stderr, "refract-pictures: %s\n", e.msg);
        status = 1;
    }
    if (out != stdout)
        fclose(out);
    gpu_destroy(gpu, NULL);
    return status;
}
