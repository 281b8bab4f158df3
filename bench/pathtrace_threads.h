/*
 * pathtrace_threads.h - the CPU reference path tracer over several threads, for the
 * benchmarks (refract-pathtrace, refract-pictures). Not a test.
 */
#ifndef REFRACT_BENCH_PATHTRACE_THREADS_H
#define REFRACT_BENCH_PATHTRACE_THREADS_H

#include "core/pathtrace_image.h"

/* Adds `samples` paths to every pixel of img, threads (1..64) taking interleaved rows
 * (row r on thread r mod threads), one pass of the whole image per sample so that every
 * pixel has the same count at any time. Returns the wall-clock seconds it took. */
double bench_pathtrace_threads(struct pathtrace_image *img, const struct pathtrace_scene *scene,
                               const struct pathtrace_camera *cam, int threads, int samples);

#endif
