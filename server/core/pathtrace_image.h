/*
 * pathtrace_image.h - a progressive path-traced image (docs/pathtracer.md "Images"): per
 * pixel the running sums of the samples and of their squares, from which the mean (the
 * pixel value) and the variance of that mean (the noise estimate) follow at any time.
 *
 * Each pass adds one sample to every pixel of a row range. Sample i of pixel p uses the
 * random stream (seed, p, i) (pathtrace_rng.h) and a uniformly random point of the pixel
 * (a 1-pixel box filter), so an image is the same whatever the number of threads that
 * split its rows or the order of the passes.
 *
 * Ownership: pathtrace_image_init allocates the sums; pathtrace_image_fini frees them.
 * Thread: passes over disjoint row ranges may run on different threads at once.
 */
#ifndef REFRACT_PATHTRACE_IMAGE_H
#define REFRACT_PATHTRACE_IMAGE_H

#include <stdint.h>

#include "pathtrace.h"

/* An ideal pinhole camera (env.h camera_ray). */
struct pathtrace_camera {
    vec3 eye, look_at, up;
    double fov_y_deg; /* vertical */
    int width, height;
};

struct pathtrace_image {
    int width, height;
    double *sum;       /* 3 per pixel, row 0 at the top */
    double *sum_sq;    /* 3 per pixel */
    uint32_t *samples; /* per pixel */
};

/* Returns 0, or -1 when out of memory (the image is then empty). */
int pathtrace_image_init(struct pathtrace_image *img, int width, int height);
void pathtrace_image_fini(struct pathtrace_image *img);

/* One more sample for every pixel of rows [row_lo, row_hi). */
void pathtrace_image_pass(struct pathtrace_image *img, const struct pathtrace_scene *s,
                          const struct pathtrace_camera *cam, uint64_t seed, int row_lo,
                          int row_hi);

/* One sample of the radiance through the point (x, y) of the image plane, in pixels from
 * the top-left corner (pixel (c, r) covers [c, c+1) x [r, r+1)). */
void pathtrace_camera_sample(const struct pathtrace_scene *s, const struct pathtrace_camera *cam,
                             double x, double y, struct pathtrace_rng *rng, double L[3]);

/* The mean of pixel i's samples and the variance of that mean (sample variance / n; 0
 * with fewer than 2 samples), per channel. */
void pathtrace_image_pixel(const struct pathtrace_image *img, int64_t i, double mean[3],
                           double var_of_mean[3]);

#endif
