/*
 * render.c - the renderer's GPU-thread state: the scene cache (LRU under a GPU memory
 * budget), and the render_view / render_trace dispatches. See render.h.
 *
 * INVARIANT: cache[0..cache_count) holds distinct scene ids; cache_bytes is the sum of
 * their bytes.
 */
#include "render.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../core/interface.h"
#include "../core/log.h"
#include "../core/metrics.h"
#include "../core/macrocell.h"
#include "../core/ray_status.h"
#include "../lightsim/gpu/lightsim_gpu.h"
#include "bindings.h"
#include "scene_gpu.h"
#define REFRACT_HOST_C
#include "shared_types.h"

#define RENDER_CACHE_MAX 64

struct render {
    struct gpu *gpu;
    size_t budget_bytes;
    struct scene_gpu *cache[RENDER_CACHE_MAX];
    size_t cache_count;
    size_t cache_bytes;
    struct gpu_buffer params_ubo;
    struct gpu_buffer lights_ubo; /* march_lights */
    bool all_variant_bits;        /* render_desc's benchmark knobs */
    bool photons_on_cpu;
    int skip_cell_voxels;
};

_Static_assert(sizeof(struct object_params) == 2 * 64 + 6 * 16, "object_params layout");
_Static_assert(sizeof(struct march_params) ==
                   11 * 16 + MAX_OBJECTS * (sizeof(struct object_params) + 16),
               "march_params layout");
_Static_assert(sizeof(struct surface_params) == 2 * 64 + 8 * 16, "surface_params layout");
_Static_assert(MAX_SURFACES == SCENE_MAX_SURFACES && MAX_SURFACES == INTERFACE_MAX_SURFACES,
               "one bit per surface in a ray's inside set");
_Static_assert(sizeof(struct volume_params) == 3 * 16 + 8 * 16, "volume_params layout");
_Static_assert(SCENE_STEPPER_EULER == STEPPER_EULER && SCENE_STEPPER_RK4 == STEPPER_RK4 &&
                   SCENE_STEPPER_RK2 == STEPPER_RK2 && SCENE_STEPPER_ADAPTIVE == STEPPER_ADAPTIVE,
               "scene and shader stepper numbers");
_Static_assert(sizeof(struct trace_ray_in) == 32, "trace_ray_in layout");
_Static_assert(sizeof(struct trace_hit_out) == 64, "trace_hit_out layout");
_Static_assert(sizeof(struct trace_event_out) == 64, "trace_event_out layout");
_Static_assert(RENDER_TRACE_MAX_EVENTS == TRACE_MAX_EVENTS, "events per traced ray");
_Static_assert(sizeof(struct light_params) == 5 * 16, "light_params layout");
_Static_assert(sizeof(struct march_lights) == 5 * 16 + 2 * MAX_LIGHTS * 16 +
                                                  2 * (MAX_OBJECTS + MAX_SURFACES) * 16 +
                                                  MAX_LIGHTS * sizeof(struct light_params),
               "march_lights layout");
_Static_assert(MAX_LIGHTS == SCENE_MAX_LIGHTS, "one light slot per scene light");
_Static_assert(UNIT_IRRADIANCE0 + MAX_LIGHTS <= UNIT_LIGHT_DIR0, "irradiance units overlap");
_Static_assert(LIGHT_KIND_DIRECTIONAL == SCENE_LIGHT_DIRECTIONAL &&
                   LIGHT_KIND_POINT == SCENE_LIGHT_POINT && LIGHT_KIND_SPOT == SCENE_LIGHT_SPOT,
               "light kinds");
_Static_assert(BRDF_NONE == SCENE_BRDF_NONE && BRDF_LAMBERT == SCENE_BRDF_LAMBERT &&
                   BRDF_PHONG == SCENE_BRDF_PHONG && BRDF_GGX == SCENE_BRDF_GGX,
               "BRDF kinds");

struct render *render_create(struct gpu *gpu, const struct render_desc *desc, struct err *e)
{
    struct render *r = calloc(1, sizeof *r);
    if (r == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory creating the renderer");
        return NULL;
    }
    r->gpu = gpu;
    r->all_variant_bits = desc->all_variant_bits;
    /* On Mesa's software device the CPU threads trace photons faster than llvmpipe's compute
     * shader (scene A, 2^20 photons: 0.25 s against 0.72 s; docs/photons.md). */
    r->photons_on_cpu = desc->photons_on_cpu || strcmp(gpu_info(gpu)->device_kind, "software") == 0;
    r->skip_cell_voxels = desc->skip_cell_voxels;
    r->budget_bytes = desc->scene_budget_bytes ? desc->scene_budget_bytes : (size_t)2 << 30;
    if (gpu_buffer_create("march params", sizeof(struct march_params), NULL, &r->params_ubo, e) !=
        REFRACT_E_OK) {
        free(r);
        return NULL;
    }
    if (gpu_buffer_create("march lights", sizeof(struct march_lights), NULL, &r->lights_ubo, e) !=
        REFRACT_E_OK) {
        gpu_buffer_destroy(&r->params_ubo);
        free(r);
        return NULL;
    }
    return r;
}

void render_destroy(struct render *r)
{
    if (r == NULL)
        return;
    for (size_t i = 0; i < r->cache_count; i++)
        scene_gpu_destroy(r->cache[i]);
    gpu_buffer_destroy(&r->params_ubo);
    gpu_buffer_destroy(&r->lights_ubo);
    free(r);
}

size_t render_cache_bytes(const struct render *r)
{
    return r->cache_bytes;
}

static void cache_remove_at(struct render *r, size_t i)
{
    r->cache_bytes -= r->cache[i]->bytes;
    scene_gpu_destroy(r->cache[i]);
    r->cache[i] = r->cache[--r->cache_count];
}

void render_scene_forget(struct render *r, const char *id)
{
    for (size_t i = 0; i < r->cache_count; i++) {
        if (strcmp(r->cache[i]->id, id) == 0) {
            cache_remove_at(r, i);
            return;
        }
    }
}

/* Evicts least recently used scenes (never `keep`) until `incoming` more bytes fit. */
static void cache_make_room(struct render *r, size_t incoming, const struct scene_gpu *keep)
{
    while (r->cache_count > 0 &&
           (r->cache_bytes + incoming > r->budget_bytes || r->cache_count >= RENDER_CACHE_MAX)) {
        size_t oldest = r->cache_count;
        for (size_t i = 0; i < r->cache_count; i++) {
            if (r->cache[i] == keep)
                continue;
            if (oldest == r->cache_count ||
                r->cache[i]->last_used_ms < r->cache[oldest]->last_used_ms)
                oldest = i;
        }
        if (oldest == r->cache_count)
            return;
        log_info("render",
                 "evicting scene %s from the GPU (%.1f MiB) to stay within the "
                 "--gpu-scene-budget",
                 r->cache[oldest]->id, (double)r->cache[oldest]->bytes / 1048576.0);
        cache_remove_at(r, oldest);
        metrics_cache(METRICS_CACHE_GPU_SCENE, METRICS_EVICTION);
    }
}

static struct scene_gpu *cache_get(struct render *r, const struct render_scene_source *src,
                                   struct render_scene_status *status, struct err *e)
{
    struct scene_gpu *found = NULL;
    for (size_t i = 0; i < r->cache_count; i++) {
        if (strcmp(r->cache[i]->id, src->id) == 0) {
            if (r->cache[i]->generation == src->generation)
                found = r->cache[i];
            else
                cache_remove_at(r, i);
            break;
        }
    }
    bool built = false;
    metrics_cache(METRICS_CACHE_GPU_SCENE, found ? METRICS_HIT : METRICS_MISS);
    if (found == NULL) {
        found = scene_gpu_build_cells(r->gpu, src, r->budget_bytes, r->skip_cell_voxels, e);
        if (found == NULL)
            return NULL;
        cache_make_room(r, found->bytes, NULL);
        r->cache[r->cache_count++] = found;
        r->cache_bytes += found->bytes;
        built = true;
    }
    found->last_used_ms = gpu_now_ms();
    if (status) {
        status->gpu_bytes = found->bytes;
        status->build_ms = found->build_ms;
        status->built_now = built;
    }
    return found;
}

enum refract_code render_scene_prepare(struct render *r, const struct render_scene_source *src,
                                       struct render_scene_status *out, struct err *e)
{
    return cache_get(r, src, out, e) ? REFRACT_E_OK : e->code;
}

static vec4 v4(vec3 v, double w)
{
    return (vec4){(float)v.x, (float)v.y, (float)v.z, (float)w};
}

static void fill_objects(struct march_params *mp, const struct scene *s, const struct scene_gpu *sg)
{
    for (size_t i = 0; i < s->object_count; i++) {
        const struct scene_object *o = &s->objects[i];
        struct object_params *op = &mp->objects[i];
        xform_to_gl_mat4(&o->world_from_object, op->world_from_object.m, op->object_from_world.m);
        vec3 vs = scene_object_voxel_size(o);
        op->bounds_min = v4(o->bounds_min, o->world_from_object.scale);
        op->bounds_max = v4(o->bounds_max, scene_object_min_voxel(o));
        op->inv_voxel_size = (vec4){(float)(1.0 / vs.x), (float)(1.0 / vs.y), (float)(1.0 / vs.z),
                                    (float)o->smoothing_sigma_voxels};
        op->atlas_offset = (vec4){0.0f, 0.0f, (float)sg->objects[i].atlas_z, (float)o->opaque_ior};
        op->atlas_inv_size =
            (vec4){1.0f / (float)sg->atlas_size[0], 1.0f / (float)sg->atlas_size[1],
                   1.0f / (float)sg->atlas_size[2], 0.0f};
        op->resolution = (ivec4){o->resolution[0], o->resolution[1], o->resolution[2],
                                 (int)sg->objects[i].flags};
        const struct scene_gpu_object *so = &sg->objects[i];
        mp->skip_cells[i] = (ivec4){so->cells[0], so->cells[1], so->cells[2], so->first_cell};
    }
    mp->settings_f3.y = (float)sg->skip_cell_voxels;
    mp->surfaces = (ivec4){(int)sg->surface_count, 0, 0, 0};
}

/* The uint bits of an inside set in a float slot (read back by floatBitsToUint). */
static float set_bits(uint32_t set)
{
    float f;
    memcpy(&f, &set, sizeof f);
    return f;
}

static void fill_settings(struct march_params *mp, const struct scene *s,
                          const struct scene_render_settings *st)
{
    /* enum scene_stepper and STEPPER_* (bindings.h) share their numbers. */
    mp->settings_i = (ivec4){(int)st->stepper, st->max_steps, (int)s->object_count,
                             s->environment.kind == SCENE_ENV_IMAGE ? 1 : 0};
    mp->settings_f = (vec4){(float)st->step_voxels, (float)st->boundary_threshold,
                            (float)s->ambient_ior, (float)s->environment.intensity};
    mp->env = (vec4){(float)s->environment.rotation_deg, 0.0f, 0.0f, 0.0f};
    int spp = st->samples_per_pixel > 1 ? st->samples_per_pixel : 1;
    mp->settings_f2 = (vec4){(float)st->tolerance_voxels, (float)spp, 0.0f, 0.0f};
    mp->settings_f3.x = (float)st->min_throughput;
}

static void fill_camera(struct march_params *mp, const struct scene_camera *c)
{
    vec3 f = vec3_normalize(vec3_sub(c->look_at, c->eye));
    vec3 right = vec3_normalize(vec3_cross(f, c->up));
    vec3 u = vec3_cross(right, f);
    double t = tan(c->fov_y_deg * M_PI / 360.0);
    mp->eye = v4(c->eye, t);
    mp->forward = v4(f, (double)c->width / (double)c->height);
    mp->right = v4(right, 0.0);
    mp->up = v4(u, 0.0);
    mp->image = (ivec4){c->width, c->height, 0, 0};
}

/* The lights block: per light its mode (volume, unshadowed direct light in scenes without
 * light simulation, or nothing), pose, scale and grid; the receiver; the BRDFs. */
static void fill_lights(struct march_lights *ml, const struct scene *s,
                        const struct render_view_request *req)
{
    memset(ml, 0, sizeof *ml);
    bool needs_sim = scene_needs_light_simulation(s);
    struct scene_walter wa;
    bool walter = scene_walter_sphere(s, &wa);
    int count = req->light_count < MAX_LIGHTS ? req->light_count : MAX_LIGHTS;
    if (count < 0 || req->lights == NULL)
        count = 0;
    ml->count = (ivec4){count, s->receiver.enabled ? 1 : 0, 0, walter ? 1 : 0};
    if (walter) { /* docs/walter.md */
        ml->walter_sphere = v4(wa.center, wa.radius);
        ml->walter_medium =
            (vec4){(float)wa.sigma_t[0], (float)wa.sigma_t[1], (float)wa.sigma_t[2], (float)wa.eta};
    }
    const struct scene_receiver *rc = &s->receiver;
    ml->receiver = (vec4){(float)rc->height, isinf(rc->half_size) ? -1.0f : (float)rc->half_size,
                          (float)rc->center[0], (float)rc->center[1]};
    ml->receiver_albedo = (vec4){(float)s->receiver.albedo[0], (float)s->receiver.albedo[1],
                                 (float)s->receiver.albedo[2], 0.0f};
    for (size_t i = 0; i < s->object_count + s->surface_count; i++) {
        bool obj = i < s->object_count;
        size_t slot = obj ? i : MAX_OBJECTS + (i - s->object_count);
        if (slot >= MAX_OBJECTS + MAX_SURFACES || (obj && i >= MAX_OBJECTS))
            continue;
        const struct scene_brdf *b =
            obj ? &s->objects[i].brdf : &s->surfaces[i - s->object_count].brdf;
        ml->brdf[slot] =
            (vec4){(float)b->kind, (float)(b->roughness * b->roughness), (float)b->exponent, 0.0f};
        ml->brdf_color[slot] =
            (vec4){(float)b->color[0], (float)b->color[1], (float)b->color[2], 0.0f};
    }
    for (int j = 0; j < count; j++) {
        const struct render_light *l = &req->lights[j];
        struct light_params *lp = &ml->lights[j];
        int mode = l->volume   ? LIGHT_MODE_VOLUME
                   : walter    ? LIGHT_MODE_WALTER
                   : needs_sim ? LIGHT_MODE_OFF
                               : LIGHT_MODE_DIRECT;
        lp->position = v4(l->position, (double)l->kind);
        lp->direction = v4(l->direction, l->cos_spot);
        lp->scale = (vec4){(float)l->scale[0], (float)l->scale[1], (float)l->scale[2], (float)mode};
        if (l->volume) {
            const struct light_grid *g = &l->volume->grid;
            lp->grid_min = v4(g->bmin, g->voxel);
            lp->grid_size = (vec4){(float)(g->dims[0] * g->voxel), (float)(g->dims[1] * g->voxel),
                                   (float)(g->dims[2] * g->voxel), 0.0f};
        }
        /* The lamp's sphere that rays leaving the scene see (lighting.glsl light_emitter):
         * its radius, negative when camera rays must not see it. */
        lp->grid_size.w = (float)(l->camera_hidden ? -l->radius : l->radius);
    }
}

/* Binds light j's volumes to its units; units of lights without one get a stand-in 3D
 * texture (never sampled: their mode is not LIGHT_MODE_VOLUME). */
static void bind_lights(struct render *r, const struct scene_gpu *sg, const struct march_lights *ml,
                        const struct render_view_request *req)
{
    glNamedBufferSubData(r->lights_ubo.buf, 0, sizeof *ml, ml);
    glBindBufferBase(GL_UNIFORM_BUFFER, BIND_UBO_LIGHTS, r->lights_ubo.buf);
    for (int j = 0; j < MAX_LIGHTS; j++) {
        const struct irradiance_gpu *v = j < ml->count.x ? req->lights[j].volume : NULL;
        glBindTextureUnit(UNIT_IRRADIANCE0 + j, v ? v->irradiance.tex : sg->scattering.tex);
        glBindTextureUnit(UNIT_LIGHT_DIR0 + j, v ? v->direction.tex : sg->scattering.tex);
    }
}

/* The kernel variant for a scene's channels, the chosen stepper and index filter, and
 * empty-space skipping (only where the scene has empty cells); with the all_variant_bits
 * knob every optional channel and the lights are compiled in. */
static unsigned march_variant(const struct render *r, const struct scene_gpu *sg,
                              const struct scene_render_settings *st)
{
    static const unsigned stepper_bits[] = {
        [SCENE_STEPPER_EULER] = 0u,
        [SCENE_STEPPER_RK4] = GPU_VARIANT_RK4,
        [SCENE_STEPPER_RK2] = GPU_VARIANT_RK2,
        [SCENE_STEPPER_ADAPTIVE] = GPU_VARIANT_ADAPTIVE,
    };
    unsigned v = stepper_bits[st->stepper];
    if (st->ior_filter == SCENE_FILTER_TRICUBIC)
        v |= GPU_VARIANT_IOR_TRICUBIC;
    for (size_t i = 0; i < sg->object_count; i++) {
        unsigned f = sg->objects[i].flags;
        if (f & OBJECT_HAS_ATTENUATION)
            v |= GPU_VARIANT_ATTENUATION;
        if (f & OBJECT_HAS_EMISSION)
            v |= GPU_VARIANT_EMISSION;
        if (f & OBJECT_HAS_OPAQUE)
            v |= GPU_VARIANT_OPAQUE;
        if (f & OBJECT_HAS_SCATTERING)
            v |= GPU_VARIANT_SCATTERING;
    }
    /* A map made for trilinear sampling is too narrow for a tricubic request. */
    bool map_fits =
        st->ior_filter != SCENE_FILTER_TRICUBIC || sg->skip_border >= MACROCELL_BORDER_TRICUBIC;
    if (st->empty_space_skipping && sg->empty_cells > 0 && map_fits)
        v |= GPU_VARIANT_SKIP;
    if (sg->surface_count > 0)
        v |= GPU_VARIANT_SURFACES;
    if (sg->surfaces_scatter) /* in-scattering along the surface media's segments */
        v |= GPU_VARIANT_SCATTERING;
    if (r->all_variant_bits)
        v |= GPU_VARIANT_ATTENUATION | GPU_VARIANT_EMISSION | GPU_VARIANT_OPAQUE |
             GPU_VARIANT_SCATTERING | GPU_VARIANT_LIGHTS;
    return v;
}

static void bind_scene(struct render *r, const struct scene_gpu *sg, const struct march_params *mp)
{
    glNamedBufferSubData(r->params_ubo.buf, 0, sizeof *mp, mp);
    glBindBufferBase(GL_UNIFORM_BUFFER, BIND_UBO_RENDER, r->params_ubo.buf);
    glBindTextureUnit(UNIT_IOR_GRAD, sg->ior_grad.tex);
    glBindTextureUnit(UNIT_ATTENUATION, sg->attenuation.tex);
    glBindTextureUnit(UNIT_EMISSION, sg->emission.tex);
    glBindTextureUnit(UNIT_OPAQUE, sg->opaque.tex);
    glBindTextureUnit(UNIT_SCATTERING, sg->scattering.tex);
    glBindTextureUnit(UNIT_ENVIRONMENT, sg->environment.tex);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_SKIP_CELLS, sg->skip_cells.buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_SURFACES, sg->surfaces.buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_SURFACE_PROFILES,
                     sg->surface_profiles.buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_MESH_NODES, sg->mesh_nodes.buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_MESH_TRIS, sg->mesh_tris.buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_MESH_VERTS, sg->mesh_verts.buf);
}

enum refract_code render_view(struct render *r, const struct render_scene_source *src,
                              const struct render_view_request *req, struct render_view_result *out,
                              struct err *e)
{
    memset(out, 0, sizeof *out);
    double t0 = gpu_time_ms();
    int w = req->camera.width, h = req->camera.height;
    size_t bytes = (size_t)w * (size_t)h * 4 * sizeof(float);
    out->rgba = malloc(bytes);
    if (out->rgba == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a %dx%d image", w, h);
    enum refract_code rc = render_view_rows(r, src, req, 0, h, out, e);
    if (rc != REFRACT_E_OK) {
        free(out->rgba);
        out->rgba = NULL;
        return rc;
    }
    out->total_ms = gpu_time_ms() - t0;
    return REFRACT_E_OK;
}

enum refract_code render_view_rows(struct render *r, const struct render_scene_source *src,
                                   const struct render_view_request *req, int row0, int rows,
                                   struct render_view_result *out, struct err *e)
{
    int w = req->camera.width, h = req->camera.height;
    if (row0 < 0 || rows <= 0 || row0 + rows > h || out->rgba == NULL)
        return err_set(e, REFRACT_E_INTERNAL, "render_view_rows: rows %d..%d of a %d-row image",
                       row0, row0 + rows, h);
    struct scene_gpu *sg = cache_get(r, src, &out->scene, e);
    if (sg == NULL)
        return e->code;
    size_t bytes = (size_t)w * (size_t)rows * 4 * sizeof(float);
    struct march_params mp;
    memset(&mp, 0, sizeof mp);
    fill_objects(&mp, src->scene, sg);
    fill_settings(&mp, src->scene, &req->settings);
    fill_camera(&mp, &req->camera);
    mp.image.z = row0;
    mp.image.w = row0 + rows;
    mp.settings_f2.z = 0.0f; /* the first ray of each pixel; one per dispatch (below) */
    mp.settings_f2.w = 1.0f;
    mp.surfaces.y =
        (int)scene_surfaces_inside(src->scene, src->lookup, src->lookup_ctx, req->camera.eye);
    struct gpu_buffer image;
    enum refract_code rc = gpu_buffer_create("render image", bytes, NULL, &image, e);
    if (rc != REFRACT_E_OK)
        return rc;
    struct march_lights ml;
    fill_lights(&ml, src->scene, req);
    rc = photons_gpu_prepare(sg, src, req, !r->photons_on_cpu, &ml, e);
    if (rc != REFRACT_E_OK) {
        gpu_buffer_destroy(&image);
        return rc;
    }
    unsigned variant = march_variant(r, sg, &req->settings);
    if (ml.count.x > 0 || ml.count.y != 0)
        variant |= GPU_VARIANT_LIGHTS;
    GLuint prog = gpu_program_get_e(gpu_programs_get(r->gpu), GPU_KERNEL_RENDER_VIEW, variant, e);
    if (prog == 0) {
        gpu_buffer_destroy(&image);
        return e->code;
    }
    bind_scene(r, sg, &mp);
    bind_lights(r, sg, &ml, req);
    glUseProgram(prog);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_IMAGE_OUT, image.buf);
    double t_dispatch = gpu_time_ms();
    /* One ray per pixel per dispatch, each adding its share (render_view.comp: llvmpipe's
     * limit on a shader invocation's loop iterations). */
    int spp = (int)mp.settings_f2.y;
    for (int first = 0; first < (spp > 1 ? spp : 1); first++) {
        if (first > 0) {
            mp.settings_f2.z = (float)first;
            glNamedBufferSubData(r->params_ubo.buf, 0, sizeof mp, &mp);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
        }
        glDispatchCompute(gpu_groups(w, RENDER_LOCAL_X), gpu_groups(rows, RENDER_LOCAL_Y), 1);
    }
    glFinish();
    out->gpu_ms += gpu_time_ms() - t_dispatch;
    rc = gpu_check("rendering", e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_read(&image, out->rgba + (size_t)row0 * (size_t)w * 4, bytes, e);
    gpu_buffer_destroy(&image);
    if (rc != REFRACT_E_OK)
        return rc;
    out->width = w;
    out->height = h;
    return REFRACT_E_OK;
}

static void copy_xyz(double dst[3], vec4 v)
{
    dst[0] = v.x;
    dst[1] = v.y;
    dst[2] = v.z;
}

enum refract_code render_trace(struct render *r, const struct render_scene_source *src,
                               const struct scene_render_settings *settings,
                               const struct render_trace_ray *rays, size_t count,
                               struct render_trace_hit *hits, double *gpu_ms, struct err *e)
{
    return render_trace_events(r, src, settings, rays, count, hits, NULL, gpu_ms, e);
}

static void copy_events(const struct trace_event_out *in, size_t count,
                        struct render_trace_event *out)
{
    for (size_t i = 0; i < count * RENDER_TRACE_MAX_EVENTS; i++) {
        out[i] = (struct render_trace_event){
            .kind = (int)in[i].point.w,
            .fresnel_R = in[i].normal.w,
            .surface = in[i].media.x,
            .medium_from = in[i].media.y,
            .medium_to = in[i].media.z,
            .n_from = in[i].ior.x,
            .n_to = in[i].ior.y,
        };
        copy_xyz(out[i].point, in[i].point);
        copy_xyz(out[i].normal, in[i].normal);
    }
}

enum refract_code render_trace_events(struct render *r, const struct render_scene_source *src,
                                      const struct scene_render_settings *settings,
                                      const struct render_trace_ray *rays, size_t count,
                                      struct render_trace_hit *hits,
                                      struct render_trace_event *events, double *gpu_ms,
                                      struct err *e)
{
    struct scene_gpu *sg = cache_get(r, src, NULL, e);
    if (sg == NULL)
        return e->code;
    struct trace_ray_in *in = calloc(count ? count : 1, sizeof *in);
    struct trace_hit_out *res = calloc(count ? count : 1, sizeof *res);
    if (in == NULL || res == NULL) {
        free(in);
        free(res);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for %zu rays", count);
    }
    for (size_t i = 0; i < count; i++) {
        vec3 o = {rays[i].origin[0], rays[i].origin[1], rays[i].origin[2]};
        uint32_t inside = rays[i].inside_known
                              ? rays[i].inside
                              : scene_surfaces_inside(src->scene, src->lookup, src->lookup_ctx, o);
        in[i].origin = (vec4){(float)o.x, (float)o.y, (float)o.z, set_bits(inside)};
        in[i].direction = (vec4){(float)rays[i].direction[0], (float)rays[i].direction[1],
                                 (float)rays[i].direction[2], 0.0f};
    }
    struct march_params mp;
    memset(&mp, 0, sizeof mp);
    fill_objects(&mp, src->scene, sg);
    fill_settings(&mp, src->scene, settings);
    mp.image.z = (int)count;
    mp.image.w = events != NULL ? 1 : 0;
    struct gpu_buffer in_buf = {0}, out_buf = {0}, ev_buf = {0};
    size_t ev_bytes =
        (events != NULL ? count * RENDER_TRACE_MAX_EVENTS : 1) * sizeof(struct trace_event_out);
    enum refract_code rc = gpu_buffer_create("trace rays in", count * sizeof *in, in, &in_buf, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("trace hits out", count * sizeof *res, NULL, &out_buf, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("trace events out", ev_bytes, NULL, &ev_buf, e);
    GLuint prog = 0;
    if (rc == REFRACT_E_OK) {
        prog = gpu_program_get_e(gpu_programs_get(r->gpu), GPU_KERNEL_TRACE_RAYS,
                                 march_variant(r, sg, settings), e);
        rc = prog ? REFRACT_E_OK : e->code;
    }
    if (rc == REFRACT_E_OK) {
        bind_scene(r, sg, &mp);
        glUseProgram(prog);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_RAYS_IN, in_buf.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_HITS_OUT, out_buf.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_TRACE_EVENTS, ev_buf.buf);
        double t = gpu_time_ms();
        glDispatchCompute(gpu_groups((int)count, TRACE_LOCAL_X), 1, 1);
        glFinish();
        if (gpu_ms)
            *gpu_ms = gpu_time_ms() - t;
        rc = gpu_check("tracing", e);
    }
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_read(&out_buf, res, count * sizeof *res, e);
    for (size_t i = 0; rc == REFRACT_E_OK && i < count; i++) {
        hits[i].status = (int)res[i].exit_origin.w;
        hits[i].steps = (int)res[i].exit_direction.w;
        hits[i].optical_path_length = res[i].transmittance.w;
        copy_xyz(hits[i].exit_origin, res[i].exit_origin);
        copy_xyz(hits[i].exit_direction, res[i].exit_direction);
        copy_xyz(hits[i].transmittance, res[i].transmittance);
        hits[i].event_count = res[i].events.x;
    }
    if (rc == REFRACT_E_OK && events != NULL) {
        struct trace_event_out *ev = malloc(ev_bytes);
        if (ev == NULL)
            rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the trace events");
        if (rc == REFRACT_E_OK)
            rc = gpu_buffer_read(&ev_buf, ev, ev_bytes, e);
        if (rc == REFRACT_E_OK)
            copy_events(ev, count, events);
        free(ev);
    }
    gpu_buffer_destroy(&in_buf);
    gpu_buffer_destroy(&out_buf);
    gpu_buffer_destroy(&ev_buf);
    free(in);
    free(res);
    return rc;
}
