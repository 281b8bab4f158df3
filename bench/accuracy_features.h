/*
 * accuracy_features.h - the "Only what a scene needs" part of the speed-against-error
 * report (docs/accuracy.md): each optimization that makes the march do only what a scene
 * needs, alone and together, against the all-features path on the example scenes.
 *
 * Configurations (render core knobs, render_desc and the scene's render settings):
 *   all features: every optional channel and the lights compiled into the march
 *                 (render_desc.all_variant_bits; unused channels read their 1x1x1
 *                 stand-ins), no empty-space skipping, no early termination;
 *   variants:     the kernel variant of the scene's channels (the default), alone;
 *   skipping:     render.empty_space_skipping with 4^3 and 8^3 macro cells, alone;
 *   termination:  render.min_throughput 1e-6 (the default), 1e-4, 1e-2, alone;
 *   all on:       the defaults (variants, 4^3 skipping, 1e-6).
 * Per scene and configuration: GPU ms per frame (the fastest of a few renders after a
 * warm-up), the speedup over the all-features path, integration steps per ray (trace_rays
 * on the same camera rays), and the image's difference from the all-features image.
 *
 * Thread: the caller's; the GPU work goes through gpu_run_sync.
 */
#ifndef REFRACT_BENCH_ACCURACY_FEATURES_H
#define REFRACT_BENCH_ACCURACY_FEATURES_H

#include <stdbool.h>
#include <stdio.h>

struct gpu;

/* Renders every scene of proto/examples/ (under $REFRACT_SOURCE_DIR, else .), two with
 * much empty space and two absorbing ones, and writes the section into f. quick: coarser grids,
 * smaller images, fewer runs. Returns false when something failed (message on stderr). */
bool accuracy_features_report(struct gpu *gpu, bool quick, FILE *f);

#endif
