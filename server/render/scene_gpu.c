/*
 * scene_gpu.c - building a scene's GPU data (see scene_gpu.h): field evaluation on the
 * CPU (scene_field_eval), then on the GPU the Gaussian pre-smoothing of n and its
 * central-difference gradient (tevs2007 sect. 3.1, eq. 3.1; docs/tracing.md
 * "Precomputation"), and uploads of the other channels and the environment map.
 *
 * Known limit: field evaluation runs on the GPU thread, so a large scene's build delays
 * other GPU work by its evaluation time (about 0.1 s per 128^3 object with a few shapes
 * on one core). Builds are queued at maintenance priority right after a scene is created,
 * so interactive requests rarely wait for them.
 */
#include "scene_gpu.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/half_float.h"
#include "../core/log.h"
#include "../core/macrocell.h"
#include "bindings.h"
#define REFRACT_HOST_C
#include "shared_types.h"

struct build_ctx {
    struct gpu *gpu;
    const struct render_scene_source *src;
    struct scene_gpu *sg;
    struct gpu_buffer field_a, field_b, ubo;
    float *host;      /* scratch: the largest object's voxels * 4 floats */
    size_t max_bytes; /* refuse beyond this (the --gpu-scene-budget); 0 = no cap */
    /* The empty-space map (docs/tracing.md "Empty space"), per object in turn: n and the
     * busy flags of its voxels (macrocell.h), then its cells appended to `cells`. */
    double *skip_n;
    uint8_t *skip_busy;
    uint32_t *cells;
    size_t cell_count, cell_cap;
};

static enum refract_code make_standin(struct gpu_volume *v, const char *label, bool is_3d,
                                      struct err *e)
{
    struct gpu_volume_desc d = {.label = label, .width = 1, .height = 1, .depth = is_3d ? 1 : 0};
    enum refract_code rc = gpu_volume_create(&d, v, e);
    if (rc != REFRACT_E_OK)
        return rc;
    float zero[4] = {0, 0, 0, 0};
    return gpu_volume_upload(v, 0, 0, 0, 1, 1, 1, 4, zero, e);
}

static bool channel_used_anywhere(const struct scene *s, enum scene_channel ch)
{
    for (size_t i = 0; i < s->object_count; i++) {
        if (scene_channel_used(&s->objects[i], ch))
            return true;
    }
    return false;
}

/* Bytes the atlases and the environment will take (stand-ins of a texel not counted). */
static size_t planned_bytes(const struct build_ctx *b)
{
    const struct scene *s = b->src->scene;
    size_t voxels = (size_t)b->sg->atlas_size[0] * b->sg->atlas_size[1] * b->sg->atlas_size[2];
    size_t bytes = voxels * gpu_texel_bytes(GPU_TEXEL_RGBA32F);
    const enum scene_channel others[] = {SCENE_CH_ATTENUATION, SCENE_CH_EMISSION, SCENE_CH_OPAQUE,
                                         SCENE_CH_SCATTERING};
    for (size_t c = 0; c < sizeof others / sizeof others[0]; c++)
        if (channel_used_anywhere(s, others[c]))
            bytes += voxels * gpu_texel_bytes(GPU_TEXEL_RGBA16F);
    if (s->environment.kind == SCENE_ENV_IMAGE && b->src->env_rgba != NULL)
        bytes +=
            (size_t)b->src->env_width * b->src->env_height * gpu_texel_bytes(GPU_TEXEL_DEFAULT);
    return bytes;
}

static enum refract_code check_limits(const struct build_ctx *b, struct err *e)
{
    const struct scene *s = b->src->scene;
    size_t bytes = planned_bytes(b);
    if (b->max_bytes > 0 && bytes > b->max_bytes)
        /* Evicting every other scene would not make it fit: refuse it by name rather
         * than hold more GPU memory than the operator allowed. */
        return err_set(e, REFRACT_E_GPU_OUT_OF_MEMORY,
                       "scene %s needs %.1f MiB of GPU memory, more than the whole "
                       "--gpu-scene-budget of %.1f MiB; raise the budget or lower the scene's "
                       "resolution",
                       b->src->id, (double)bytes / 1048576.0, (double)b->max_bytes / 1048576.0);
    int max3d = gpu_info(b->gpu)->max_3d_texture_size;
    if (s->object_count > MAX_OBJECTS)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "objects: %zu objects, the renderer "
                       "handles at most %d per scene",
                       s->object_count, MAX_OBJECTS);
    for (int a = 0; a < 3; a++) {
        if (b->sg->atlas_size[a] > max3d)
            return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                           "objects: the scene's voxel atlas needs %d texels along %c but this "
                           "GPU allows %d (GL_MAX_3D_TEXTURE_SIZE); lower the objects' "
                           "resolution",
                           b->sg->atlas_size[a], "xyz"[a], max3d);
    }
    return REFRACT_E_OK;
}

static void layout_atlas(struct scene_gpu *sg, const struct scene *s)
{
    int z = 0;
    for (size_t i = 0; i < s->object_count; i++) {
        const int *res = s->objects[i].resolution;
        sg->objects[i].atlas_z = z;
        z += res[2];
        if (res[0] > sg->atlas_size[0])
            sg->atlas_size[0] = res[0];
        if (res[1] > sg->atlas_size[1])
            sg->atlas_size[1] = res[1];
        unsigned flags = 0;
        if (scene_channel_used(&s->objects[i], SCENE_CH_ATTENUATION))
            flags |= OBJECT_HAS_ATTENUATION;
        if (scene_channel_used(&s->objects[i], SCENE_CH_EMISSION))
            flags |= OBJECT_HAS_EMISSION;
        if (scene_channel_used(&s->objects[i], SCENE_CH_OPAQUE))
            flags |= OBJECT_HAS_OPAQUE;
        if (scene_channel_used(&s->objects[i], SCENE_CH_SCATTERING))
            flags |= OBJECT_HAS_SCATTERING;
        if (s->objects[i].bound)
            flags |= OBJECT_BOUND;
        if (scene_ior_constant(&s->objects[i]))
            flags |= OBJECT_IOR_CONSTANT;
        sg->objects[i].flags = flags;
    }
    sg->atlas_size[2] = z;
    sg->object_count = s->object_count;
    if (s->object_count == 0) /* a scene of surfaces only: one stand-in texel */
        sg->atlas_size[0] = sg->atlas_size[1] = sg->atlas_size[2] = 1;
}

static enum refract_code alloc_atlas(struct build_ctx *b, struct gpu_volume *v,
                                     enum scene_channel ch, const char *name, struct err *e)
{
    char label[128];
    snprintf(label, sizeof label, "scene %s / %s atlas", b->sg->id, name);
    if (ch != SCENE_CH_IOR && !channel_used_anywhere(b->src->scene, ch))
        return make_standin(v, label, true, e);
    struct gpu_volume_desc d = {
        .label = label,
        .width = b->sg->atlas_size[0],
        .height = b->sg->atlas_size[1],
        .depth = b->sg->atlas_size[2],
        .format = ch == SCENE_CH_IOR ? GPU_TEXEL_RGBA32F : GPU_TEXEL_RGBA16F,
    };
    return gpu_volume_create(&d, v, e);
}

static void fill_weights(struct volume_params *vp, double sigma)
{
    int radius = (int)ceil(3.0 * sigma);
    if (radius > 31)
        radius = 31;
    double w[32] = {0};
    double sum = 0.0;
    for (int k = 0; k <= radius; k++) {
        w[k] = exp(-(double)(k * k) / (2.0 * sigma * sigma));
        sum += k == 0 ? w[k] : 2.0 * w[k];
    }
    float *dst = &vp->weights[0].x;
    for (int k = 0; k < 32; k++)
        dst[k] = (float)(w[k] / sum);
    vp->atlas_offset.w = radius;
}

static void dispatch_volume(struct build_ctx *b, GLuint program, const struct volume_params *vp,
                            GLuint in, GLuint out)
{
    glNamedBufferSubData(b->ubo.buf, 0, sizeof *vp, vp);
    glUseProgram(program);
    glBindBufferBase(GL_UNIFORM_BUFFER, BIND_UBO_VOLUME, b->ubo.buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_FIELD_IN, in);
    if (out)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_FIELD_OUT, out);
    glDispatchCompute(gpu_groups(vp->resolution.x, VOLUME_LOCAL_X),
                      gpu_groups(vp->resolution.y, VOLUME_LOCAL_Y),
                      gpu_groups(vp->resolution.z, VOLUME_LOCAL_Z));
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                    GL_TEXTURE_FETCH_BARRIER_BIT);
}

/* n: evaluate, smooth (3 passes), gradient into the atlas. */
static enum refract_code build_ior(struct build_ctx *b, size_t i, struct err *e)
{
    const struct scene *s = b->src->scene;
    const struct scene_object *obj = &s->objects[i];
    const struct gpu_programs *progs = gpu_programs_get(b->gpu);
    size_t voxels = (size_t)obj->resolution[0] * obj->resolution[1] * obj->resolution[2];
    enum refract_code rc =
        scene_field_eval(s, obj, SCENE_CH_IOR, b->src->lookup, b->src->lookup_ctx, b->host, e);
    if (rc != REFRACT_E_OK)
        return err_prefix(e, "objects[%zu].ior: ", i);
    glNamedBufferSubData(b->field_a.buf, 0, (GLsizeiptr)(voxels * sizeof(float)), b->host);
    vec3 vs = scene_object_voxel_size(obj);
    struct volume_params vp = {
        .resolution = {obj->resolution[0], obj->resolution[1], obj->resolution[2], 0},
        .voxel_size = {(float)vs.x, (float)vs.y, (float)vs.z, 0.0f},
    };
    GLuint src_buf = b->field_a.buf;
    if (obj->smoothing_sigma_voxels > 0.0) {
        fill_weights(&vp, obj->smoothing_sigma_voxels);
        GLuint bufs[2] = {b->field_a.buf, b->field_b.buf};
        for (int axis = 0; axis < 3; axis++) {
            vp.resolution.w = axis;
            dispatch_volume(b, gpu_program_get(progs, GPU_KERNEL_SMOOTH_IOR, 0), &vp,
                            bufs[axis % 2], bufs[(axis + 1) % 2]);
        }
        src_buf = b->field_b.buf; /* x: a->b, y: b->a, z: a->b */
    }
    vp.atlas_offset = (ivec4){0, 0, b->sg->objects[i].atlas_z, 0};
    glBindImageTexture(IMAGE_IOR_GRAD_OUT, b->sg->ior_grad.tex, 0, GL_TRUE, 0, GL_WRITE_ONLY,
                       GL_RGBA32F);
    dispatch_volume(b, gpu_program_get(progs, GPU_KERNEL_GRADIENT_IOR, 0), &vp, src_buf, 0);
    return gpu_check("computing the index gradient", e);
}

/* Evaluates channel ch of object i into dst (its components per voxel), the error
 * prefixed with the object and channel. */
static enum refract_code eval_channel(struct build_ctx *b, size_t i, enum scene_channel ch,
                                      float *dst, struct err *e)
{
    const struct scene *s = b->src->scene;
    enum refract_code rc =
        scene_field_eval(s, &s->objects[i], ch, b->src->lookup, b->src->lookup_ctx, dst, e);
    if (rc != REFRACT_E_OK)
        return err_prefix(e, "objects[%zu].%s: ", i, scene_channel_name(ch));
    return REFRACT_E_OK;
}

/* Uploads b->host (4 floats per voxel) into object i's box of atlas. */
static enum refract_code upload_object(struct build_ctx *b, size_t i, struct gpu_volume *atlas,
                                       struct err *e)
{
    const struct scene_object *obj = &b->src->scene->objects[i];
    return gpu_volume_upload(atlas, 0, 0, b->sg->objects[i].atlas_z, obj->resolution[0],
                             obj->resolution[1], obj->resolution[2], 4, b->host, e);
}

/* Marks object i's voxels where b->host (4 floats per voxel of channel ch) is not zero as
 * busy for the empty-space map: any rgb for extinction, emission and scattering, the
 * coverage for opaque (macrocell_voxel_busy). */
static void mark_busy(struct build_ctx *b, size_t i, enum scene_channel ch)
{
    const int *r = b->src->scene->objects[i].resolution;
    size_t voxels = (size_t)r[0] * r[1] * r[2];
    const double zero_grad[4] = {0, 0, 0, 0};
    for (size_t v = 0; v < voxels; v++) {
        double t[4] = {b->host[v * 4], b->host[v * 4 + 1], b->host[v * 4 + 2], b->host[v * 4 + 3]};
        bool busy = macrocell_voxel_busy(zero_grad, 1.0, ch == SCENE_CH_ATTENUATION ? t : NULL,
                                         ch == SCENE_CH_EMISSION ? t : NULL,
                                         ch == SCENE_CH_OPAQUE ? t : NULL,
                                         ch == SCENE_CH_SCATTERING ? t : NULL);
        if (busy)
            b->skip_busy[v] = 1;
    }
}

static enum refract_code build_channel(struct build_ctx *b, size_t i, enum scene_channel ch,
                                       struct gpu_volume *atlas, struct err *e)
{
    if (!scene_channel_used(&b->src->scene->objects[i], ch))
        return REFRACT_E_OK;
    enum refract_code rc = eval_channel(b, i, ch, b->host, e);
    if (rc == REFRACT_E_OK)
        mark_busy(b, i, ch);
    return rc != REFRACT_E_OK ? rc : upload_object(b, i, atlas, e);
}

/* Starts object i's empty-space map from its index+gradient atlas box, read back after the
 * gradient kernel (and rounded to half floats for render.ior_texture float16, as the march
 * will see it): n and the gradient test per voxel. The map is built on the CPU, from the
 * same data the march samples, with the code the CPU twin uses (macrocell.c), so the GPU
 * and the reference skip the same cells; one read-back per object at build time. */
static enum refract_code skip_begin(struct build_ctx *b, size_t i, struct err *e)
{
    const struct scene_object *obj = &b->src->scene->objects[i];
    const int *r = obj->resolution;
    size_t voxels = (size_t)r[0] * r[1] * r[2];
    glGetTextureSubImage(b->sg->ior_grad.tex, 0, 0, 0, b->sg->objects[i].atlas_z, r[0], r[1], r[2],
                         GL_RGBA, GL_FLOAT, (GLsizei)(voxels * 4 * sizeof(float)), b->host);
    enum refract_code rc = gpu_check("reading back the index gradient", e);
    if (rc != REFRACT_E_OK)
        return rc;
    bool half = b->src->scene->render.ior_texture == SCENE_IOR_FLOAT16;
    double h_min = scene_object_min_voxel(obj);
    for (size_t v = 0; v < voxels; v++) {
        double t[4];
        for (int c = 0; c < 4; c++)
            t[c] = half ? half_float_round(b->host[v * 4 + c]) : (double)b->host[v * 4 + c];
        b->skip_n[v] = t[3];
        b->skip_busy[v] = macrocell_voxel_busy(t, h_min, NULL, NULL, NULL, NULL) ? 1 : 0;
    }
    return REFRACT_E_OK;
}

/* Builds object i's cells from the voxels' flags and appends them to b->cells. */
static enum refract_code skip_finish(struct build_ctx *b, size_t i, struct err *e)
{
    const struct scene_object *obj = &b->src->scene->objects[i];
    struct macrocell_map m;
    /* The sampling footprint beyond a cell, for the scene's index filter (a tricubic index
     * reads two texels out; scene_reference.c does the same). A render that asks for
     * tricubic on a map built for trilinear does not skip (render.c, march_variant). */
    b->sg->skip_border = b->src->scene->render.ior_filter == SCENE_FILTER_TRICUBIC
                             ? MACROCELL_BORDER_TRICUBIC
                             : MACROCELL_BORDER_TRILINEAR;
    enum refract_code rc = macrocell_build(b->skip_n, b->skip_busy, obj->resolution,
                                           b->sg->skip_cell_voxels, b->sg->skip_border, &m, e);
    if (rc != REFRACT_E_OK)
        return rc;
    size_t n = macrocell_count(&m);
    if (b->cell_count + n > b->cell_cap) {
        size_t cap = (b->cell_count + n) * 2;
        uint32_t *grown = realloc(b->cells, cap * sizeof *grown);
        if (grown == NULL) {
            macrocell_free(&m);
            return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the empty-space map");
        }
        b->cells = grown;
        b->cell_cap = cap;
    }
    struct scene_gpu_object *so = &b->sg->objects[i];
    so->first_cell = (int)b->cell_count;
    memcpy(so->cells, m.dims, sizeof so->cells);
    for (size_t k = 0; k < n; k++)
        b->cells[b->cell_count + k] = m.empty[k];
    b->cell_count += n;
    b->sg->empty_cells += m.empty_count;
    macrocell_free(&m);
    return REFRACT_E_OK;
}

/* The scattering atlas: sigma_s (rgb) from the scattering channel and the Henyey-Greenstein
 * g from the anisotropy channel in alpha (0 when the object has none; tevs2007 eq. 5.5). */
static enum refract_code build_scattering(struct build_ctx *b, size_t i, struct err *e)
{
    const struct scene_object *obj = &b->src->scene->objects[i];
    if (!scene_channel_used(obj, SCENE_CH_SCATTERING))
        return REFRACT_E_OK;
    size_t voxels = (size_t)obj->resolution[0] * obj->resolution[1] * obj->resolution[2];
    enum refract_code rc = eval_channel(b, i, SCENE_CH_SCATTERING, b->host, e);
    if (rc != REFRACT_E_OK)
        return rc;
    if (scene_channel_used(obj, SCENE_CH_ANISOTROPY)) {
        int comps = scene_channel_components(SCENE_CH_ANISOTROPY);
        float *g = malloc(voxels * (size_t)comps * sizeof(float));
        if (g == NULL)
            return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of host memory evaluating fields");
        rc = eval_channel(b, i, SCENE_CH_ANISOTROPY, g, e);
        for (size_t v = 0; rc == REFRACT_E_OK && v < voxels; v++)
            b->host[v * 4 + 3] = g[v * (size_t)comps];
        free(g);
        if (rc != REFRACT_E_OK)
            return rc;
    } else {
        for (size_t v = 0; v < voxels; v++)
            b->host[v * 4 + 3] = 0.0f;
    }
    /* The atlas is RGBA16F: sigma_s beyond the largest half float (the scene allows 1e5)
     * would become infinite; 65504 per world unit is opaque within 1e-4 units anyway. */
    for (size_t v = 0; v < voxels; v++)
        for (int c = 0; c < 3; c++)
            if (b->host[v * 4 + c] > 65504.0f)
                b->host[v * 4 + c] = 65504.0f;
    mark_busy(b, i, SCENE_CH_SCATTERING);
    return upload_object(b, i, &b->sg->scattering, e);
}

static enum refract_code build_environment(struct build_ctx *b, struct err *e)
{
    const struct render_scene_source *src = b->src;
    char label[128];
    snprintf(label, sizeof label, "scene %s / environment", b->sg->id);
    if (src->scene->environment.kind != SCENE_ENV_IMAGE)
        return make_standin(&b->sg->environment, label, false, e);
    if (src->env_rgba == NULL)
        return err_set(e, REFRACT_E_CONFLICT,
                       "environment.type is \"image\" but no environment image was uploaded; "
                       "upload one with PUT /v1/scenes/%s/environment",
                       src->id);
    struct gpu_volume_desc d = {
        .label = label, .width = src->env_width, .height = src->env_height, .wrap_repeat_s = 1};
    enum refract_code rc = gpu_volume_create(&d, &b->sg->environment, e);
    if (rc != REFRACT_E_OK)
        return rc;
    return gpu_volume_upload(&b->sg->environment, 0, 0, 0, src->env_width, src->env_height, 1, 4,
                             src->env_rgba, e);
}

static enum refract_code alloc_scratch(struct build_ctx *b, struct err *e)
{
    size_t max_voxels = 1;
    const struct scene *s = b->src->scene;
    for (size_t i = 0; i < s->object_count; i++) {
        const int *r = s->objects[i].resolution;
        size_t n = (size_t)r[0] * r[1] * r[2];
        if (n > max_voxels)
            max_voxels = n;
    }
    b->host = malloc(max_voxels * 4 * sizeof(float));
    b->skip_n = malloc(max_voxels * sizeof *b->skip_n);
    b->skip_busy = malloc(max_voxels);
    if (b->host == NULL || b->skip_n == NULL || b->skip_busy == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of host memory evaluating fields");
    enum refract_code rc =
        gpu_buffer_create("field scratch a", max_voxels * sizeof(float), NULL, &b->field_a, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("field scratch b", max_voxels * sizeof(float), NULL, &b->field_b, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("volume params", sizeof(struct volume_params), NULL, &b->ubo, e);
    return rc;
}

/* render.ior_texture "float16": the index+gradient atlas is computed in RGBA32F (the
 * gradient kernel's image format) and then narrowed to RGBA16F through host memory, once
 * per build. Each value is rounded to the nearest half here (half_float.h says why the
 * driver must not do it). Half the memory and
 * bandwidth of the march's most frequent fetch, for 11 significant bits in n and grad n
 * (docs/tracing.md "Precision"; docs/accuracy.md measures what it costs). */
static enum refract_code narrow_ior_atlas(struct build_ctx *b, struct err *e)
{
    struct gpu_volume *v = &b->sg->ior_grad;
    size_t texels = (size_t)v->width * v->height * v->depth;
    float *host = malloc(texels * 4 * sizeof(float));
    if (host == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory narrowing the ior atlas of %s",
                       b->sg->id);
    glGetTextureImage(v->tex, 0, GL_RGBA, GL_FLOAT, (GLsizei)(texels * 4 * sizeof(float)), host);
    for (size_t k = 0; k < texels * 4; k++)
        host[k] = (float)half_float_round(host[k]);
    char label[128];
    snprintf(label, sizeof label, "scene %s / ior+grad atlas (float16)", b->sg->id);
    struct gpu_volume_desc d = {.label = label,
                                .width = v->width,
                                .height = v->height,
                                .depth = v->depth,
                                .format = GPU_TEXEL_RGBA16F};
    struct gpu_volume half;
    enum refract_code rc = gpu_check("reading back the ior atlas", e);
    if (rc == REFRACT_E_OK)
        rc = gpu_volume_create(&d, &half, e);
    if (rc == REFRACT_E_OK) {
        rc = gpu_volume_upload(&half, 0, 0, 0, v->width, v->height, v->depth, 4, host, e);
        if (rc == REFRACT_E_OK) {
            gpu_volume_destroy(v);
            *v = half;
        } else {
            gpu_volume_destroy(&half);
        }
    }
    free(host);
    return rc;
}

static enum refract_code build_all(struct build_ctx *b, struct err *e)
{
    const struct scene *s = b->src->scene;
    char missing[256];
    if (scene_missing_volumes(s, b->src->lookup, b->src->lookup_ctx, missing, sizeof missing) > 0)
        return err_set(e, REFRACT_E_CONFLICT,
                       "the scene references volumes that were not uploaded: %s; upload them "
                       "with PUT /v1/scenes/%s/volumes/{name}",
                       missing, b->src->id);
    layout_atlas(b->sg, s);
    enum refract_code rc = check_limits(b, e);
    if (rc == REFRACT_E_OK)
        rc = alloc_scratch(b, e);
    if (rc == REFRACT_E_OK)
        rc = alloc_atlas(b, &b->sg->ior_grad, SCENE_CH_IOR, "ior+grad", e);
    if (rc == REFRACT_E_OK)
        rc = alloc_atlas(b, &b->sg->attenuation, SCENE_CH_ATTENUATION, "attenuation", e);
    if (rc == REFRACT_E_OK)
        rc = alloc_atlas(b, &b->sg->emission, SCENE_CH_EMISSION, "emission", e);
    if (rc == REFRACT_E_OK)
        rc = alloc_atlas(b, &b->sg->opaque, SCENE_CH_OPAQUE, "opaque", e);
    if (rc == REFRACT_E_OK)
        rc = alloc_atlas(b, &b->sg->scattering, SCENE_CH_SCATTERING, "scattering", e);
    for (size_t i = 0; rc == REFRACT_E_OK && i < s->object_count; i++) {
        rc = build_ior(b, i, e);
        if (rc == REFRACT_E_OK)
            rc = skip_begin(b, i, e);
        if (rc == REFRACT_E_OK)
            rc = build_channel(b, i, SCENE_CH_ATTENUATION, &b->sg->attenuation, e);
        if (rc == REFRACT_E_OK)
            rc = build_channel(b, i, SCENE_CH_EMISSION, &b->sg->emission, e);
        if (rc == REFRACT_E_OK)
            rc = build_channel(b, i, SCENE_CH_OPAQUE, &b->sg->opaque, e);
        if (rc == REFRACT_E_OK)
            rc = build_scattering(b, i, e);
        if (rc == REFRACT_E_OK)
            rc = skip_finish(b, i, e);
    }
    static const uint32_t none = 0; /* a scene without cells still binds a buffer */
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create(
            "skip cells", b->cell_count ? b->cell_count * sizeof(uint32_t) : sizeof none,
            b->cell_count ? (const void *)b->cells : &none, &b->sg->skip_cells, e);
    if (rc == REFRACT_E_OK)
        rc = surfaces_gpu_build(b->src, b->sg, e);
    b->sg->surface_count = s->surface_count;
    for (size_t k = 0; k < s->surface_count; k++)
        b->sg->surfaces_scatter |= scene_surface_scatters(&s->surfaces[k]);
    if (rc == REFRACT_E_OK)
        rc = build_environment(b, e);
    if (rc == REFRACT_E_OK && s->render.ior_texture == SCENE_IOR_FLOAT16)
        rc = narrow_ior_atlas(b, e);
    if (rc == REFRACT_E_OK) {
        glFinish();
        rc = gpu_check("building the scene", e);
    }
    return rc;
}

struct scene_gpu *scene_gpu_build(struct gpu *gpu, const struct render_scene_source *src,
                                  size_t max_bytes, struct err *e)
{
    return scene_gpu_build_cells(gpu, src, max_bytes, 0, e);
}

struct scene_gpu *scene_gpu_build_cells(struct gpu *gpu, const struct render_scene_source *src,
                                        size_t max_bytes, int skip_cell_voxels, struct err *e)
{
    double t0 = gpu_time_ms();
    struct scene_gpu *sg = calloc(1, sizeof *sg);
    if (sg == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory building scene %s", src->id);
        return NULL;
    }
    snprintf(sg->id, sizeof sg->id, "%s", src->id);
    sg->generation = src->generation;
    sg->skip_cell_voxels = skip_cell_voxels > 0 ? skip_cell_voxels : MACROCELL_DEFAULT_CELL;
    struct build_ctx b = {.gpu = gpu, .src = src, .sg = sg, .max_bytes = max_bytes};
    enum refract_code rc = build_all(&b, e);
    gpu_buffer_destroy(&b.field_a);
    gpu_buffer_destroy(&b.field_b);
    gpu_buffer_destroy(&b.ubo);
    free(b.host);
    free(b.skip_n);
    free(b.skip_busy);
    free(b.cells);
    if (rc != REFRACT_E_OK) {
        scene_gpu_destroy(sg);
        return NULL;
    }
    sg->bytes = sg->ior_grad.bytes + sg->attenuation.bytes + sg->emission.bytes + sg->opaque.bytes +
                sg->scattering.bytes + sg->environment.bytes + sg->skip_cells.bytes +
                sg->surfaces.bytes + sg->surface_profiles.bytes + sg->mesh_nodes.bytes +
                sg->mesh_tris.bytes + sg->mesh_verts.bytes;
    sg->build_ms = gpu_time_ms() - t0;
    log_info("render",
             "built scene %s (generation %llu): %zu objects, atlas %dx%dx%d, %.1f MiB, "
             "%zu of %zu macro cells empty, %.0f ms",
             sg->id, (unsigned long long)sg->generation, sg->object_count, sg->atlas_size[0],
             sg->atlas_size[1], sg->atlas_size[2], (double)sg->bytes / 1048576.0, sg->empty_cells,
             b.cell_count, sg->build_ms);
    return sg;
}

void scene_gpu_destroy(struct scene_gpu *sg)
{
    if (sg == NULL)
        return;
    gpu_volume_destroy(&sg->ior_grad);
    gpu_volume_destroy(&sg->attenuation);
    gpu_volume_destroy(&sg->emission);
    gpu_volume_destroy(&sg->opaque);
    gpu_volume_destroy(&sg->scattering);
    gpu_volume_destroy(&sg->environment);
    gpu_buffer_destroy(&sg->skip_cells);
    gpu_buffer_destroy(&sg->surfaces);
    gpu_buffer_destroy(&sg->surface_profiles);
    gpu_buffer_destroy(&sg->mesh_nodes);
    gpu_buffer_destroy(&sg->mesh_tris);
    gpu_buffer_destroy(&sg->mesh_verts);
    gpu_buffer_destroy(&sg->photons);
    gpu_buffer_destroy(&sg->photon_keys);
    photons_gpu_free(sg);
    free(sg);
}
