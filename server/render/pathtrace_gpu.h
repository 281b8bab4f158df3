/*
 * pathtrace_gpu.h - the GPU twin of the reference path tracer (shaders/
 * pathtrace_render.comp; docs/pathtracer.md): the same scene (core/pathtrace.h) rendered
 * in float on the GPU, its samples added to a struct pathtrace_image like the CPU's.
 *
 * Not yet: meshes, the procedural environment (a uniform one only). A scene with either
 * is refused (REFRACT_E_CONFLICT). It is tested against the CPU twin
 * (tests/gpu/test_pathtrace_gpu.c); no request uses it yet.
 *
 * Thread: the GPU thread (it calls GL). Ownership: borrows everything until return.
 */
#ifndef REFRACT_PATHTRACE_GPU_H
#define REFRACT_PATHTRACE_GPU_H

#include "../core/err.h"
#include "../core/pathtrace_image.h"

/* Adds samples first_sample .. first_sample + samples - 1 of every pixel to img (whose
 * size must be the camera's). Returns REFRACT_E_OK or the GL error / refusal. */
enum refract_code pathtrace_gpu_render(const struct pathtrace_scene *s,
                                       const struct pathtrace_camera *cam, uint32_t seed,
                                       int first_sample, int samples, struct pathtrace_image *img,
                                       struct err *e);

/* What photon_trace_gpu.c shares: the scene's parameters (pathtrace_types.h pt_params;
 * cam may be NULL: no camera) and the surfaces' records with the lathes' profile points
 * (new arrays the caller frees; false when out of memory). */
struct pt_params;
struct surface_params;
void pathtrace_gpu_pack_params(const struct pathtrace_scene *s, const struct pathtrace_camera *cam,
                               uint32_t seed, struct pt_params *p);
bool pathtrace_gpu_pack_surfaces(const struct pathtrace_scene *s, struct surface_params **sp,
                                 float **pts, size_t *npts);

#endif
