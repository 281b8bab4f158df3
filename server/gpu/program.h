/*
 * program.h - compute programs built from the embedded GLSL, in variants.
 *
 * The marching kernels (render_view, trace_rays) are compiled once per variant: the
 * stepper, the optional channels a scene uses (attenuation, emission, opaque,
 * scattering), the lights and empty-space skipping are preprocessor switches, so a scene
 * that has no emission never pays for an emission fetch (tevs2007 sect. 6.1: "some data
 * is not required for proper rendering"). Every variant
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
/* The stepper is two bits, RK4 and STEPPER_HI: none = Euler, RK4 = RK4, HI = RK2
 * (midpoint), both = adaptive (Bogacki-Shampine 3(2)); use the names below. */
#define GPU_VARIANT_RK4 1u
#define GPU_VARIANT_STEPPER_HI 64u
#define GPU_VARIANT_RK2 GPU_VARIANT_STEPPER_HI
#define GPU_VARIANT_ADAPTIVE (GPU_VARIANT_STEPPER_HI | GPU_VARIANT_RK4)
#define GPU_VARIANT_STEPPER_BITS GPU_VARIANT_ADAPTIVE
#define GPU_VARIANT_ATTENUATION 2u /* the scene has an attenuation channel */
#define GPU_VARIANT_EMISSION 4u    /* ... an emission channel (render_view only) */
#define GPU_VARIANT_OPAQUE 8u      /* ... an opaque channel */
#define GPU_VARIANT_SCATTERING                                                                     \
    16u /* ... a scattering channel: extinction sigma_a + sigma_s,                                 \
           in-scattering L_s (tevs2007 eq. 5.4/5.5) */
#define GPU_VARIANT_LIGHTS                                                                         \
    32u /* lights or a receiver: reflected light L_r at Fresnel                                    \
           events (eq. 5.6/5.8) and the receiver (render_view) */
#define GPU_VARIANT_SKIP                                                                           \
    128u /* empty-space skipping: render.empty_space_skipping and the                              \
            scene has empty macro cells (docs/tracing.md "Empty space") */
#define GPU_VARIANT_IOR_TRICUBIC                                                                   \
    256u /* tricubic Catmull-Rom index, its exact gradient (render.ior_filter) */
#define GPU_VARIANT_SURFACES 512u /* the scene has exact surfaces (docs/tracing.md "Surfaces") */
#define GPU_VARIANT_COUNT 1024
/* Variants with any of these bits, or without GPU_VARIANT_SKIP (skipping off is for
 * comparisons), are compiled on first use (gpu_program_get), not at start-up: doubling the
 * variant count five times would make the start-up 32 times longer. One variant with every
 * bit (the adaptive stepper) is compiled at start-up, so a shader error still stops it. */
#define GPU_VARIANT_LAZY                                                                           \
    (GPU_VARIANT_SCATTERING | GPU_VARIANT_LIGHTS | GPU_VARIANT_STEPPER_HI |                        \
     GPU_VARIANT_IOR_TRICUBIC | GPU_VARIANT_SURFACES)

struct gpu_program_desc {
    const char *label;    /* for glObjectLabel and messages */
    const char *main;     /* kernel file name, e.g. "render_view.comp" */
    const char *preamble; /* #defines inserted after #version; may be NULL */
};

struct gpu_programs_lazy; /* program.c: shader directory for variants built on first use */

struct gpu_programs {
    GLuint program[GPU_KERNEL_COUNT][GPU_VARIANT_COUNT];
    /* Owned; mutable through a const struct gpu_programs (a cache of lazily built
     * variants, GPU thread only). */
    struct gpu_programs_lazy *lazy;
};

/* Compiles and links one compute program. Returns the GL name, or 0 with e filled
 * (REFRACT_E_GPU_ERROR, the file:line messages of the driver). */
GLuint gpu_program_create(const struct gpu_program_desc *desc, const char *shader_dir,
                          struct err *e);

/* Builds every kernel in every variant it has. On failure destroys what it built. */
enum refract_code gpu_programs_build(struct gpu_programs *p, const char *shader_dir, struct err *e);
void gpu_programs_destroy(struct gpu_programs *p);

/* The program of a kernel variant (bits a kernel does not use are ignored). A variant
 * with GPU_VARIANT_LAZY bits is compiled here on its first use (tens of ms on llvmpipe)
 * and cached. Returns 0 only when that compilation fails (it compiled at start-up in its
 * all-bits form, so this means a driver problem); gpu_program_get_e says why. */
GLuint gpu_program_get(const struct gpu_programs *p, enum gpu_kernel kernel, unsigned variant);
GLuint gpu_program_get_e(const struct gpu_programs *p, enum gpu_kernel kernel, unsigned variant,
                         struct err *e);

#endif
