/*
 * pixel_sample.c - where in its pixel view ray s of n goes (pixel_sample.h). Twin of
 * shaders/pixel_sample.glsl: the same hash, and the offsets computed in float as the
 * shader does, so the CPU reference averages exactly the GPU's rays.
 */
#include "pixel_sample.h"

#include <math.h>

uint32_t pixel_hash(uint32_t x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

void pixel_sample(uint32_t col, uint32_t row, uint32_t s, uint32_t n, double *dx, double *dy)
{
    if (n <= 1u) {
        *dx = *dy = 0.5;
        return;
    }
    uint32_t k = (uint32_t)(sqrtf((float)n) + 0.5f);
    uint32_t h = pixel_hash(col ^ pixel_hash(row ^ pixel_hash(s)));
    float jx = (float)(h >> 8) * (1.0f / 16777216.0f);
    float jy = (float)(pixel_hash(h) >> 8) * (1.0f / 16777216.0f);
    *dx = (double)(((float)(s % k) + jx) / (float)k);
    *dy = (double)(((float)(s / k) + jy) / (float)k);
}

double pixel_step_offset(uint32_t s)
{
    float v = 0.5f + 0.6180339887f * (float)s;
    return (double)(v - floorf(v));
}
