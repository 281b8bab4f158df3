/*
 * resources.h - GPU textures and buffers made from descriptors (sokol style: a zero
 * field means "default"), with out-of-memory turned into an error value and every
 * object labelled for KHR_debug.
 *
 * Ownership: the module that creates a resource owns it and destroys it; the desc's
 * comment in the owner names it. Destroying a zero resource is a no-op.
 * Thread: GPU thread only.
 */
#ifndef REFRACT_GPU_RESOURCES_H
#define REFRACT_GPU_RESOURCES_H

#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"
#include "gl.h"

enum gpu_texel_format {
    GPU_TEXEL_DEFAULT = 0, /* = RGBA32F */
    GPU_TEXEL_RGBA32F = 1,
    GPU_TEXEL_RGBA16F = 2,
    GPU_TEXEL_R32F = 3,
};

/* Bytes per texel of a format (GPU_TEXEL_DEFAULT is RGBA32F). */
size_t gpu_texel_bytes(enum gpu_texel_format format);

struct gpu_volume_desc {
    const char *label;
    int width, height, depth;     /* depth 0 = a 2D texture */
    enum gpu_texel_format format; /* 0 = RGBA32F */
    int nearest;                  /* 0 = trilinear filtering, 1 = nearest */
    int wrap_repeat_s;            /* 0 = clamp to edge in s, 1 = repeat (environment u) */
};

/* A 2D or 3D texture. */
struct gpu_volume {
    GLuint tex;
    GLenum target;
    int width, height, depth;
    enum gpu_texel_format format;
    size_t bytes;
};

struct gpu_buffer {
    GLuint buf;
    size_t bytes;
};

/* Creates storage (contents undefined). REFRACT_E_GPU_OUT_OF_MEMORY when the driver
 * cannot allocate, naming the label and the size. */
enum refract_code gpu_volume_create(const struct gpu_volume_desc *desc, struct gpu_volume *out,
                                    struct err *e);
void gpu_volume_destroy(struct gpu_volume *v);
/* Uploads floats (1 or 4 per texel as `components`) into the box at (x, y, z). */
enum refract_code gpu_volume_upload(struct gpu_volume *v, int x, int y, int z, int w, int h, int d,
                                    int components, const float *data, struct err *e);

/* A storage buffer of `bytes`, optionally initialised from `data`. */
enum refract_code gpu_buffer_create(const char *label, size_t bytes, const void *data,
                                    struct gpu_buffer *out, struct err *e);
void gpu_buffer_destroy(struct gpu_buffer *b);
/* Reads `bytes` from offset 0 into dst. */
enum refract_code gpu_buffer_read(const struct gpu_buffer *b, void *dst, size_t bytes,
                                  struct err *e);

/* Bytes currently held by volumes and buffers made here. */
size_t gpu_memory_in_use(void);

/* Checks glGetError after a sequence of calls: OUT_OF_MEMORY -> GPU_OUT_OF_MEMORY, any
 * other error -> GPU_ERROR, naming `what`. */
enum refract_code gpu_check(const char *what, struct err *e);

/* Work groups needed to cover n items with groups of `local` invocations. */
static inline unsigned gpu_groups(int n, int local)
{
    return (unsigned)((n + local - 1) / local);
}

#endif
