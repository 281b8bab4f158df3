/*
 * resources.c - textures and buffers from descriptors; see resources.h.
 */
#include "resources.h"

#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

static atomic_size_t memory_in_use;

size_t gpu_memory_in_use(void)
{
    return atomic_load(&memory_in_use);
}

enum refract_code gpu_check(const char *what, struct err *e)
{
    GLenum first = glGetError();
    if (first == GL_NO_ERROR)
        return REFRACT_E_OK;
    while (glGetError() != GL_NO_ERROR)
        ;
    if (first == GL_OUT_OF_MEMORY)
        return err_set(e, REFRACT_E_GPU_OUT_OF_MEMORY,
                       "%s: the GPU is out of memory; lower the scene's resolution or free "
                       "scenes (DELETE /v1/scenes/{id})",
                       what);
    return err_set(e, REFRACT_E_GPU_ERROR, "%s: GL error 0x%x", what, first);
}

static GLenum internal_format(enum gpu_texel_format f, size_t *texel_bytes)
{
    switch (f) {
    case GPU_TEXEL_RGBA16F:
        *texel_bytes = 8;
        return GL_RGBA16F;
    case GPU_TEXEL_R32F:
        *texel_bytes = 4;
        return GL_R32F;
    case GPU_TEXEL_DEFAULT:
    case GPU_TEXEL_RGBA32F:
        break;
    }
    *texel_bytes = 16;
    return GL_RGBA32F;
}

size_t gpu_texel_bytes(enum gpu_texel_format format)
{
    size_t bytes = 0;
    internal_format(format, &bytes);
    return bytes;
}

enum refract_code gpu_volume_create(const struct gpu_volume_desc *desc, struct gpu_volume *out,
                                    struct err *e)
{
    memset(out, 0, sizeof *out);
    size_t texel_bytes = 0;
    GLenum ifmt = internal_format(desc->format, &texel_bytes);
    bool is_3d = desc->depth > 0;
    out->target = is_3d ? GL_TEXTURE_3D : GL_TEXTURE_2D;
    out->width = desc->width;
    out->height = desc->height;
    out->depth = is_3d ? desc->depth : 1;
    out->format = desc->format ? desc->format : GPU_TEXEL_RGBA32F;
    out->bytes = (size_t)desc->width * (size_t)desc->height * (size_t)out->depth * texel_bytes;
    while (glGetError() != GL_NO_ERROR)
        ;
    glCreateTextures(out->target, 1, &out->tex);
    if (is_3d)
        glTextureStorage3D(out->tex, 1, ifmt, desc->width, desc->height, desc->depth);
    else
        glTextureStorage2D(out->tex, 1, ifmt, desc->width, desc->height);
    GLint filter = desc->nearest ? GL_NEAREST : GL_LINEAR;
    glTextureParameteri(out->tex, GL_TEXTURE_MIN_FILTER, filter);
    glTextureParameteri(out->tex, GL_TEXTURE_MAG_FILTER, filter);
    glTextureParameteri(out->tex, GL_TEXTURE_WRAP_S,
                        desc->wrap_repeat_s ? GL_REPEAT : GL_CLAMP_TO_EDGE);
    glTextureParameteri(out->tex, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTextureParameteri(out->tex, GL_TEXTURE_WRAP_R, GL_CLAMP_TO_EDGE);
    if (desc->label)
        glObjectLabel(GL_TEXTURE, out->tex, -1, desc->label);
    char what[160];
    snprintf(what, sizeof what, "allocating texture \"%s\" (%dx%dx%d, %zu bytes)",
             desc->label ? desc->label : "?", desc->width, desc->height, out->depth, out->bytes);
    enum refract_code rc = gpu_check(what, e);
    if (rc != REFRACT_E_OK) {
        glDeleteTextures(1, &out->tex);
        memset(out, 0, sizeof *out);
        return rc;
    }
    atomic_fetch_add(&memory_in_use, out->bytes);
    return REFRACT_E_OK;
}

void gpu_volume_destroy(struct gpu_volume *v)
{
    if (v->tex == 0)
        return;
    glDeleteTextures(1, &v->tex);
    atomic_fetch_sub(&memory_in_use, v->bytes);
    memset(v, 0, sizeof *v);
}

enum refract_code gpu_volume_upload(struct gpu_volume *v, int x, int y, int z, int w, int h, int d,
                                    int components, const float *data, struct err *e)
{
    GLenum fmt = components == 1 ? GL_RED : GL_RGBA;
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    if (v->target == GL_TEXTURE_3D)
        glTextureSubImage3D(v->tex, 0, x, y, z, w, h, d, fmt, GL_FLOAT, data);
    else
        glTextureSubImage2D(v->tex, 0, x, y, w, h, fmt, GL_FLOAT, data);
    return gpu_check("uploading texture data", e);
}

enum refract_code gpu_buffer_create(const char *label, size_t bytes, const void *data,
                                    struct gpu_buffer *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    while (glGetError() != GL_NO_ERROR)
        ;
    glCreateBuffers(1, &out->buf);
    glNamedBufferData(out->buf, (GLsizeiptr)bytes, data, GL_DYNAMIC_COPY);
    if (label)
        glObjectLabel(GL_BUFFER, out->buf, -1, label);
    char what[160];
    snprintf(what, sizeof what, "allocating buffer \"%s\" (%zu bytes)", label ? label : "?", bytes);
    enum refract_code rc = gpu_check(what, e);
    if (rc != REFRACT_E_OK) {
        glDeleteBuffers(1, &out->buf);
        memset(out, 0, sizeof *out);
        return rc;
    }
    out->bytes = bytes;
    atomic_fetch_add(&memory_in_use, bytes);
    return REFRACT_E_OK;
}

void gpu_buffer_destroy(struct gpu_buffer *b)
{
    if (b->buf == 0)
        return;
    glDeleteBuffers(1, &b->buf);
    atomic_fetch_sub(&memory_in_use, b->bytes);
    memset(b, 0, sizeof *b);
}

enum refract_code gpu_buffer_read(const struct gpu_buffer *b, void *dst, size_t bytes,
                                  struct err *e)
{
    glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
    glGetNamedBufferSubData(b->buf, 0, (GLsizeiptr)bytes, dst);
    return gpu_check("reading back a GPU buffer", e);
}
