/*
 * bench_pathtrace.c - refract-pathtrace: the CPU reference path tracer's speed and noise on
 * a scene document (docs/pathtracer.md "Measured"). Not a test: it asserts nothing.
 *
 *     build/refract-pathtrace proto/examples/peer_scene_a.json [--samples 16,64]
 *         [--threads N] [--size 320x240]
 *
 * For each sample count it renders the whole image from scratch on N threads (default:
 * the online CPUs) and prints the time, the paths per second, and three noise figures of
 * the green channel: the image's sum of per-pixel standard errors over the sum of its
 * means (X-Reference-Noise of the HTTP answer), and the median and 90th percentile of the
 * per-pixel relative standard error over the pixels whose mean is above 1e-3 of the
 * image's largest. The time to 2 % follows from the 1 / sqrt(n) law: t (noise / 0.02)^2.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/pathtrace_image.h"
#include "pathtrace_threads.h"
#include "scene/scene_pathtrace.h"

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void report(const struct pathtrace_image *img, int samples, double dt)
{
    int64_t n = (int64_t)img->width * img->height;
    double *rel = malloc((size_t)n * sizeof *rel);
    double sum_m = 0.0, sum_sd = 0.0, max_m = 0.0;
    for (int64_t i = 0; i < n; i++) {
        double m[3], v[3];
        pathtrace_image_pixel(img, i, m, v);
        max_m = fmax(max_m, m[1]);
    }
    int k = 0;
    for (int64_t i = 0; i < n; i++) {
        double m[3], v[3];
        pathtrace_image_pixel(img, i, m, v);
        sum_m += m[1];
        sum_sd += sqrt(v[1]);
        if (m[1] > 1e-3 * max_m)
            rel[k++] = sqrt(v[1]) / m[1];
    }
    qsort(rel, (size_t)k, sizeof *rel, cmp);
    double img_noise = sum_m > 0 ? sum_sd / sum_m : 0.0;
    double med = k ? rel[k / 2] : 0.0, p90 = k ? rel[(k * 9) / 10] : 0.0;
    printf("| %d | %.2f | %.0f | %.4f | %.4f | %.4f | %.1f | %.1f |\n", samples, dt,
           (double)samples * (double)n / dt, img_noise, med, p90,
           dt * (img_noise / 0.02) * (img_noise / 0.02), dt * (med / 0.02) * (med / 0.02));
    free(rel);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: refract-pathtrace SCENE.json [--samples 16,64] [--threads N] "
                        "[--size WxH]\n");
        return 2;
    }
    const char *samples_arg = "16,64";
    int threads = (int)sysconf(_SC_NPROCESSORS_ONLN), w = 0, h = 0;
    for (int i = 2; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--samples"))
            samples_arg = argv[i + 1];
        else if (!strcmp(argv[i], "--threads"))
            threads = atoi(argv[i + 1]);
        else if (!strcmp(argv[i], "--size"))
            sscanf(argv[i + 1], "%dx%d", &w, &h);
    }
    threads = threads < 1 ? 1 : (threads > 64 ? 64 : threads);
    FILE *f = fopen(argv[1], "rb");
    if (f == NULL) {
        fprintf(stderr, "refract-pathtrace: cannot open %s\n", argv[1]);
        return 1;
    }
    static char text[1 << 20];
    size_t len = fread(text, 1, sizeof text - 1, f);
    fclose(f);
    struct scene *s = NULL;
    struct err e = {0};
    if (scene_parse(text, len, NULL, &s, &e) != REFRACT_E_OK) {
        fprintf(stderr, "refract-pathtrace: %s: %s\n", argv[1], e.msg);
        return 1;
    }
    static struct scene_pathtrace pt;
    if (scene_pathtrace_init(s, NULL, NULL, &pt, &e) != REFRACT_E_OK) {
        fprintf(stderr, "refract-pathtrace: %s\n", e.msg);
        return 1;
    }
    const struct scene_camera *c = &s->camera;
    struct pathtrace_camera cam = {c->eye,       c->look_at,       c->up,
                                   c->fov_y_deg, w ? w : c->width, h ? h : c->height};
    printf("%s, %dx%d, %d threads\n\n", argv[1], cam.width, cam.height, threads);
    printf("| samples/pixel | s | paths/s | image noise | median pixel | p90 pixel | "
           "s to 2 %% (image) | s to 2 %% (median pixel) |\n|---|---|---|---|---|---|---|---|\n");
    for (const char *p = samples_arg; *p;) {
        int samples = atoi(p);
        struct pathtrace_image img;
        if (samples < 1 || pathtrace_image_init(&img, cam.width, cam.height) != 0)
            return 1;
        report(&img, samples, bench_pathtrace_threads(&img, &pt.scene, &cam, threads, samples));
        pathtrace_image_fini(&img);
        const char *comma = strchr(p, ',');
        p = comma ? comma + 1 : p + strlen(p);
    }
    scene_destroy(s);
    return 0;
}
