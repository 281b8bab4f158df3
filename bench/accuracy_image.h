/*
 * accuracy_image.h - the image part of the speed-against-error report (docs/accuracy.md
 * "Images"): render time against image error for scenes lit through the light simulator,
 * sweeping the irradiance volume's resolution (lightsim.resolution) and the wavefront's
 * tessellation threshold (lightsim.split), against a reference rendered from a finer
 * simulation (the finest settings the bound allows: not a proof of convergence, and the
 * report says so).
 *
 * Thread: the caller's; the GPU work goes through gpu_run_sync.
 */
#ifndef REFRACT_BENCH_ACCURACY_IMAGE_H
#define REFRACT_BENCH_ACCURACY_IMAGE_H

#include <stdbool.h>
#include <stdio.h>

struct gpu;

/* Runs the sweep on proto/examples/ball_lens_caustic.json (a sharp caustic on a receiver)
 * and smoke_spot.json (a volume caustic), writes the section into f and the plot to
 * images_dir/accuracy_images.png. quick: smaller grids and fewer settings. Returns false
 * when something failed (message on stderr). */
bool accuracy_image_report(struct gpu *gpu, bool quick, const char *images_dir, FILE *f);

#endif
