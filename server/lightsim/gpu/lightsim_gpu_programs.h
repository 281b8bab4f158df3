/*
 * lightsim_gpu_programs.h - the light simulator's compute programs (compiled once by
 * lightsim_gpu_init) and the exclusive prefix sum built from three of them.
 *
 * Thread: GPU thread only.
 */
#ifndef REFRACT_LIGHTSIM_GPU_PROGRAMS_H
#define REFRACT_LIGHTSIM_GPU_PROGRAMS_H

#include <stdbool.h>

#include "../../gpu/gl.h"

struct lightsim_gpu_programs {
    GLuint step;    /* lightsim_step.comp */
    GLuint emit;    /* lightsim_emit.comp */
    /* The same with LS_SURFACES 1 (docs/lightsim.md "Surfaces"), for scenes with exact
     * surfaces: the surface code, though never entered, made llvmpipe run the voxel
     * scenes' steps 2-4x slower. */
    GLuint step_surfaces, emit_surfaces;
    /* With LS_MESHES 1 as well, for scenes with mesh surfaces: the BVH traversal (its
     * 64-entry stack) is compiled only where a mesh may be met. */
    GLuint step_meshes, emit_meshes;
    GLuint scan[3]; /* lightsim_scan.comp, LS_SCAN_STAGE 0, 1, 2 */
    GLuint args;    /* lightsim_args.comp */
    GLuint finish;  /* lightsim_finish.comp */
};

/* The programs, or NULL before lightsim_gpu_init. */
const struct lightsim_gpu_programs *lightsim_gpu_programs(void);
/* Whether they were built with compare-and-swap float atomics forced
 * (REFRACT_LIGHTSIM_CAS_ATOMICS=1 when lightsim_gpu_init ran). */
bool lightsim_gpu_programs_use_cas(void);

/* Records the exclusive prefix sum of the uint counts at BIND_SSBO_LS_COUNTS into
 * BIND_SSBO_LS_OFFSETS, using BIND_SSBO_LS_BLOCK_SUMS, for control.counts.x elements
 * (<= LS_MAX_PATCHES); the total lands in control.counts.y. The dispatch sizes come from
 * control.dispatch_blocks (glDispatchComputeIndirect from the buffer bound to
 * GL_DISPATCH_INDIRECT_BUFFER, which must be the control buffer). No CPU round trip. */
void lightsim_gpu_scan_record(const struct lightsim_gpu_programs *p);

#endif
