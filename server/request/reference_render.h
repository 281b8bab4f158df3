/*
 * reference_render.h - a path-traced reference image on CPU threads (docs/pathtracer.md,
 * "Over HTTP" and "In jobs"): what POST .../render with "mode": "reference" and a batch job
 * with "mode": "reference" share.
 *
 * DESIGN: `threads` workers take interleaved rows (index, index + threads, ...) and add one
 * sample per pixel per pass until every pixel has `samples`, the deadline passes or the
 * daemon stops; the first pass always completes, so every pixel has a value. One reference
 * render runs at a time in the process (it uses every core): reference_begin claims the
 * slot, reference_end gives it back, reference_cancel_all ends every render at its next
 * row (shutdown). The image is the same whatever the thread count (pathtrace_image.h).
 * Thread: any thread may run a render; the slot and the cancel flag are atomics.
 */
#ifndef REFRACT_REFERENCE_RENDER_H
#define REFRACT_REFERENCE_RENDER_H

#include <stdbool.h>
#include <stdint.h>

#include "../core/pathtrace_image.h"

#define REFERENCE_MAX_THREADS 64
#define REFERENCE_DEFAULT_SAMPLES 64

/* True when this caller now holds the one reference slot (release with reference_end). */
bool reference_begin(void);
void reference_end(void);
/* Every running and later render stops at its next row; for shutdown. */
void reference_cancel_all(void);
bool reference_cancelled(void);

/* Runs fn(arg) on a detached thread of its own (a reference render's coordinator, so that
 * neither an HTTP thread nor the view scheduler waits for it). False when none could be
 * started. */
bool reference_start_detached(void *(*fn)(void *), void *arg);

/* Online CPUs, 1..REFERENCE_MAX_THREADS. */
int reference_threads(void);

/* Renders into img (initialised at cam's size) with `threads` threads until each pixel
 * has `samples` samples or gpu_time_ms() reaches deadline_ms; an image that has samples
 * already (a view refining) goes on from them, each row getting at least one more unless
 * it is done. Returns the wall time in ms; *cancelled tells whether reference_cancel_all
 * stopped it. */
double reference_render(const struct pathtrace_scene *s, const struct pathtrace_camera *cam,
                        struct pathtrace_image *img, int samples, double deadline_ms,
                        uint64_t seed, int threads, bool *cancelled);

/* The image as floats: rgba (A = 1) and, when exr7 is not NULL, 7 channels a pixel (R, G,
 * B, A, and the variance of each pixel's mean). New arrays the caller frees; false when out
 * of memory. min_n, max_n: the fewest and most samples of a pixel; rel_noise: the summed
 * standard errors over the summed means. */
bool reference_image_floats(const struct pathtrace_image *img, float **rgba, float **exr7,
                            uint32_t *min_n, uint32_t *max_n, double *rel_noise);

#endif
