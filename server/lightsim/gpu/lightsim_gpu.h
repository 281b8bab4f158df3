/*
 * lightsim_gpu.h - the light simulator on the GPU (docs/lightsim.md; ziegler2007): patch
 * lists in storage buffers, one compute dispatch chain per wavefront time step (propagate
 * + deposit + fate, exclusive prefix sum, compaction/expansion, indirect dispatch
 * arguments), with no CPU round trip per step. A run is resumable: lightsim_gpu_advance
 * does a bounded number of steps, so the GPU thread can interleave renders between
 * chunks (docs/ARCHITECTURE.md, "One thread owns the GPU").
 *
 * Ownership: a run owns its buffers and textures until lightsim_gpu_run_destroy; the
 * irradiance textures it made can be taken out by lightsim_gpu_take_textures, after which
 * the caller owns them (irradiance_gpu_free).
 * Thread: GPU thread only (every function here makes GL calls).
 */
#ifndef REFRACT_LIGHTSIM_GPU_H
#define REFRACT_LIGHTSIM_GPU_H

#include "../../gpu/queue.h"
#include "../../gpu/resources.h"
#include "../lightsim.h"

/* An irradiance volume on the GPU, as the view renderer samples it. */
struct irradiance_gpu {
    struct gpu_volume irradiance; /* RGBA16F/32F 3D: rgb E (unit light) */
    struct gpu_volume direction;  /* RGBA16F 3D: xyz unit light direction, w = 1 where lit */
    struct light_grid grid;
    size_t bytes;
};

/* Makes the two empty textures of a volume on grid g (irradiance RGBA32F, direction
 * RGBA16F); on failure *out holds none. */
enum refract_code irradiance_gpu_create(const struct light_grid *g, struct irradiance_gpu *out,
                                        struct err *e);
/* Uploads a host volume (e.g. reloaded from disk). */
enum refract_code irradiance_gpu_upload(const struct irradiance_volume *v,
                                        struct irradiance_gpu *out, struct err *e);
void irradiance_gpu_free(struct irradiance_gpu *g);

/* Compiles the simulator's programs (once per process, at start-up, so a shader error
 * stops start-up). Idempotent. */
enum refract_code lightsim_gpu_init(struct gpu *gpu, struct err *e);
/* Releases the programs (in the GPU thread's final work item). */
void lightsim_gpu_shutdown(void);

struct lightsim_gpu_run;

/* Starts a run: uploads the fields (borrowed for the call only) and the initial
 * wavefront (built on the host in double precision, lightsim_gpu_wavefront.h). A light
 * that sends nothing into the domain gives a run that is done at once, with dark volumes.
 * INVALID_FIELD for max_patches outside 1..LS_MAX_PATCHES, LIMIT_EXCEEDED when a buffer
 * would exceed the GPU's largest storage block (lower the resolution), GPU_OUT_OF_MEMORY,
 * OUT_OF_MEMORY. Compiles the programs if lightsim_gpu_init has not. */
enum refract_code lightsim_gpu_begin(struct gpu *gpu, const struct lightsim_fields *f,
                                     const struct scene_light *l, const struct scene_lightsim *set,
                                     struct lightsim_gpu_run **out, struct err *e);
/* Advances at most max_steps time steps (<= 0: until the end); *done is set when the run
 * has ended, and then the result volumes exist. Reads back only the live count and the
 * flux counters at the end of the chunk. */
enum refract_code lightsim_gpu_advance(struct lightsim_gpu_run *run, int max_steps, bool *done,
                                       struct err *e);
/* Statistics as of the last advance (docs/lightsim.md "Energy bookkeeping"). */
void lightsim_gpu_stats(const struct lightsim_gpu_run *run, struct lightsim_stats *out);
/* Reads the result volumes back to the host (new buffers: irradiance_volume_free).
 * CONFLICT before the run is done or after lightsim_gpu_take_textures. */
enum refract_code lightsim_gpu_read(struct lightsim_gpu_run *run, struct irradiance_volume *out,
                                    struct err *e);
/* Moves the result textures out of the run (they become the caller's: irradiance_gpu_free).
 * CONFLICT before the run is done or when already taken. */
enum refract_code lightsim_gpu_take_textures(struct lightsim_gpu_run *run,
                                             struct irradiance_gpu *out, struct err *e);
/* Bytes of GPU memory the run holds now (patch lists, fields, outputs). */
size_t lightsim_gpu_run_bytes(const struct lightsim_gpu_run *run);
/* The most it held at once (while stepping, and while writing the output volumes). */
size_t lightsim_gpu_run_peak_bytes(const struct lightsim_gpu_run *run);
void lightsim_gpu_run_destroy(struct lightsim_gpu_run *run);

#endif
