/*
 * pathtrace_image.c - progressive accumulation of path-traced samples (pathtrace_image.h).
 */
#include "pathtrace_image.h"

#include <stdlib.h>

#include "env.h"

int pathtrace_image_init(struct pathtrace_image *img, int width, int height)
{
    size_t n = (size_t)width * (size_t)height;
    img->width = width;
    img->height = height;
    img->sum = calloc(3 * n, sizeof *img->sum);
    img->sum_sq = calloc(3 * n, sizeof *img->sum_sq);
    img->samples = calloc(n, sizeof *img->samples);
    if (img->sum == NULL || img->sum_sq == NULL || img->samples == NULL) {
        pathtrace_image_fini(img);
        return -1;
    }
    return 0;
}

void pathtrace_image_fini(struct pathtrace_image *img)
{
    free(img->sum);
    free(img->sum_sq);
    free(img->samples);
    img->sum = img->sum_sq = NULL;
    img->samples = NULL;
    img->width = img->height = 0;
}

void pathtrace_camera_sample(const struct pathtrace_scene *s, const struct pathtrace_camera *cam,
                             double x, double y, struct pathtrace_rng *rng, double L[3])
{
    vec3 o, d;
    /* camera_ray adds the half pixel to (col, row) */
    camera_ray(cam->eye, cam->look_at, cam->up, cam->fov_y_deg, cam->width, cam->height, x - 0.5,
               y - 0.5, &o, &d);
    pathtrace_radiance(s, o, d, pathtrace_inside_set(s, o), true, rng, L);
}

void pathtrace_image_pass(struct pathtrace_image *img, const struct pathtrace_scene *s,
                          const struct pathtrace_camera *cam, uint64_t seed, int row_lo, int row_hi)
{
    for (int r = row_lo; r < row_hi; r++) {
        for (int c = 0; c < img->width; c++) {
            size_t i = (size_t)r * (size_t)img->width + (size_t)c;
            struct pathtrace_rng rng;
            pathtrace_rng_init(&rng, seed, i, img->samples[i]);
            double x = c + pathtrace_rng_uniform(&rng);
            double y = r + pathtrace_rng_uniform(&rng);
            double L[3];
            pathtrace_camera_sample(s, cam, x, y, &rng, L);
            for (int k = 0; k < 3; k++) {
                img->sum[3 * i + k] += L[k];
                img->sum_sq[3 * i + k] += L[k] * L[k];
            }
            img->samples[i]++;
        }
    }
}

void pathtrace_image_pixel(const struct pathtrace_image *img, int64_t i, double mean[3],
                           double var_of_mean[3])
{
    double n = (double)img->samples[i];
    for (int k = 0; k < 3; k++) {
        mean[k] = n > 0.0 ? img->sum[3 * i + k] / n : 0.0;
        double v = n > 1.0 ? (img->sum_sq[3 * i + k] - n * mean[k] * mean[k]) / (n - 1.0) : 0.0;
        var_of_mean[k] = n > 1.0 && v > 0.0 ? v / n : 0.0;
    }
}
