/*
 * photon_trace_gpu.h - caustic photons traced on the GPU (shaders/photon_trace.comp), the
 * float twin of photon_trace (core/photon.h, docs/photons.md "Where it runs"): the same
 * emission, events and storage rule; its own random numbers, so the two agree in
 * distribution (tests/gpu/test_photon_trace_gpu.c). Not yet: mesh surfaces (refused with
 * REFRACT_E_CONFLICT: photons_gpu.c then traces on the CPU).
 *
 * Thread: the GPU thread (it calls GL). Ownership: borrows s; appends to out.
 */
#ifndef REFRACT_PHOTON_TRACE_GPU_H
#define REFRACT_PHOTON_TRACE_GPU_H

#include "../core/photon.h"

/* Traces `count` photons (shared evenly by the lights) under seed and appends the stored
 * ones to out (its emitted, landed and lost sums too). REFRACT_E_OK, CONFLICT (meshes,
 * scattering media, an unbounded optical surface), OUT_OF_MEMORY or a GL error. */
enum refract_code photon_trace_gpu(const struct pathtrace_scene *s, long count, uint32_t seed,
                                   struct photon_list *out, struct err *e);

#endif
