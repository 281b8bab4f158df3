/*
 * pixel_sample.h - anti-aliasing's sample positions (docs/tracing.md "Anti-aliasing"):
 * a pixel split into k x k equal strata (n = k^2 rays), each ray jittered inside its
 * stratum by an integer hash of (col, row, s); the image is their mean (a box filter over
 * the pixel). n = 1 is the pixel's centre. Twin: shaders/pixel_sample.glsl.
 */
#ifndef REFRACT_PIXEL_SAMPLE_H
#define REFRACT_PIXEL_SAMPLE_H

#include <stdint.h>

/* lowbias32 (Chris Wellons): the hash the GPU uses too. */
uint32_t pixel_hash(uint32_t x);
/* Offset of ray s of n from pixel (col, row)'s top-left corner, each in [0, 1): pass
 * col + dx - 0.5, row + dy - 0.5 to camera_ray (which adds the half pixel). */
void pixel_sample(uint32_t col, uint32_t row, uint32_t s, uint32_t n, double *dx, double *dy);

/* Where ray s of a pixel samples the inner steps of a walter scene's in-scattering, in
 * [0, 1) of each step (docs/walter.md "Steps"): the golden-ratio sequence from the
 * midpoint, fract(0.5 + 0.6180339887 s), in float as on the GPU. */
double pixel_step_offset(uint32_t s);

#endif
