/*
 * pathtrace_rng.h - the path tracer's random numbers: PCG32 (O'Neill 2014, pcg32_random_r),
 * one stream per (seed, pixel, sample) so that an image is the same whatever the thread
 * count or the order of its samples, and progressive refinement continues a pixel's
 * sequence instead of repeating it. Not cryptographic. Thread: any; the caller owns the
 * state.
 */
#ifndef REFRACT_PATHTRACE_RNG_H
#define REFRACT_PATHTRACE_RNG_H

#include <stdint.h>

struct pathtrace_rng {
    uint64_t state;
    uint64_t inc; /* odd: the stream */
};

/* The stream of sample `sample` of pixel `pixel` under `seed`. */
void pathtrace_rng_init(struct pathtrace_rng *r, uint64_t seed, uint64_t pixel, uint64_t sample);
uint32_t pathtrace_rng_u32(struct pathtrace_rng *r);
/* Uniform in [0, 1), 53 random bits. */
double pathtrace_rng_uniform(struct pathtrace_rng *r);

#endif
