/*
 * program.h - compute programs built from the embedded GLSL, in variants.
 *
 * The marching kernels (render_view, trace_rays) are compiled once per variant: the
 * integrator and the optional channels a scene uses (attenuation, emission, opaque) are
 * preprocessor switches, so a scene that has no emission never pays for an emission fetch
 * (tevs2007 sect. 6.1: "some data is not required for proper rendering"). Every variant
 * is compiled and linked at start-up (gpu_programs_build), so a bad shader fails there
 * with the driver's log mapped to our file names, never on the first request.
 *
 * Thread: GPU thread only. Ownership: struct gpu_programs owns its GL programs.
 */
#ifndef REFRACT_GPU_PROGRAM_H
#define REFRACT_GPU_PROGRAM_H

#include "../core/err.h"
#include "gl.h"

enum gpu_kernel {
    GPU_KERNEL_SMOOTH_IOR = 0,   /* smooth_ior.comp: one Gaussian pass along an axis */
    GPU_KERNEL_GRADIENT_IOR = 1, /* gradient_ior.comp: central differences -> ior+grad */
    GPU_KERNEL_RENDER_VIEW = 2,  /* render_view.comp: view rays -> radiance */
    GPU_KERNEL_TRACE_RAYS = 3,   /* trace_rays.comp: optical ray queries */
    GPU_KERNEL_COUNT = 4,
};

/* Variant bits of the marching kernels. */
#define GPU_VARIANT_RK4 1u         /* else explicit Euler */
#define GPU_VARIANT_ATTENUATION 2u /* the scene has an attenuation channel */
#define GPU_VARIANT_EMISSION 4u    /* ... an emission channel (render_view only) */
#define GPU_VARIANT_OPAQUE 8u      /* ... an opaque channel */
#define GPU_VARIANT_COUNT 16

struct gpu_program_desc {
    const char *label;    /* for glObjectLabel and messages */
    const char *main;     /* kernel file name, e.g. "render_view.comp" */
    const char *preamble; /* #defines inserted after #version; may be NULL */
};

struct gpu_programs {
    GLuint program[GPU_KERNEL_COUNT][GPU_VARIANT_COUNT];
};

/* Compiles and links one compute program. Returns the GL name, or 0 with e filled
 * (REFRACT_E_GPU_ERROR, the file:line messages of the driver). */
GLuint gpu_program_create(const struct gpu_program_desc *desc, const char *shader_dir,
                          struct err *e);

/* Builds every kernel in every variant it has. On failure destroys what it built. */
enum refract_code gpu_programs_build(struct gpu_programs *p, const char *shader_dir,
                                     struct err *e);
void gpu_programs_destroy(struct gpu_programs *p);

/* The program of a kernel variant (bits a kernel does not use are ignored). */
GLuint gpu_program_get(const struct gpu_programs *p, enum gpu_kernel kernel, unsigned variant);

#endif
