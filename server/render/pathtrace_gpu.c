/*
 * pathtrace_gpu.c - host side of the GPU path tracer (pathtrace_gpu.h): packs the scene
 * into pt_params and surface_params (shaders/pathtrace_types.h, shared_types.h), runs
 * pathtrace_render.comp in dispatches of a few samples per pixel, and adds the float sums
 * to the image's double sums.
 *
 * REALITY: the program is compiled per call (tens of ms on llvmpipe) rather than built
 * with the renderer's kernels at start-up: no request uses it yet, and a bad shader
 * would otherwise stop refractd from starting while this is being developed.
 */
#include "pathtrace_gpu.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../core/geom/geom.h"
#include "../gpu/program.h"
#include "../gpu/resources.h"
#define REFRACT_HOST_C
#include "shared_types.h"
#include "pathtrace_types.h"

_Static_assert(sizeof(struct pt_light) == 64, "pt_light is 4 vec4");
_Static_assert(sizeof(struct pt_medium) == 32, "pt_medium is 2 vec4");

#define SAMPLES_PER_DISPATCH 8

static vec4 v4(vec3 a, double w)
{
    return (vec4){(float)a.x, (float)a.y, (float)a.z, (float)w};
}

static vec4 rgb4(const double c[3], double w)
{
    return (vec4){(float)c[0], (float)c[1], (float)c[2], (float)w};
}

void pathtrace_gpu_pack_params(const struct pathtrace_scene *s, const struct pathtrace_camera *cam,
                               uint32_t seed, struct pt_params *p)
{
    memset(p, 0, sizeof *p);
    if (cam != NULL) {
        vec3 f = vec3_normalize(vec3_sub(cam->look_at, cam->eye));
        vec3 r = vec3_normalize(vec3_cross(f, cam->up));
        vec3 u = vec3_cross(r, f);
        p->eye = v4(cam->eye, tan(0.5 * cam->fov_y_deg * M_PI / 180.0));
        p->forward = v4(f, (double)cam->width / cam->height);
        p->right = v4(r, 0.0);
        p->up = v4(u, 0.0);
        p->image = (ivec4){cam->width, cam->height, 0, 0};
    }
    p->counts = (ivec4){s->surface_count, s->light_count, (int)seed,
                        cam != NULL ? (int)pathtrace_inside_set(s, cam->eye) : 0};
    const struct pathtrace_receiver *rc = &s->receiver;
    p->receiver = (vec4){rc->enabled ? 1.0f : 0.0f, (float)rc->height,
                         isinf(rc->half_size) ? -1.0f : (float)rc->half_size, (float)rc->center[0]};
    p->albedo = rgb4(rc->albedo, rc->center[1]);
    p->env = rgb4(s->env_radiance, 0.0);
    for (int k = 0; k < s->light_count && k < PT_MAX_LIGHTS; k++) {
        const struct pathtrace_light *l = &s->lights[k];
        p->lights[k] = (struct pt_light){{(int)l->kind, l->visible ? 1 : 0, 0, 0},
                                         v4(l->position, l->radius),
                                         v4(l->direction, l->cos_spot),
                                         rgb4(l->value, 0.0)};
    }
    for (int k = 0; k <= s->surface_count; k++) {
        const struct pathtrace_medium *m =
            k < s->surface_count ? &s->surfaces[k].medium : &s->ambient;
        p->media[k] = (struct pt_medium){rgb4(m->sigma_a, m->ior), rgb4(m->sigma_s, m->g)};
    }
}

/* The surfaces' records and the lathes' profile points (at least one, so the buffer
 * exists). Returns new arrays the caller frees. */
bool pathtrace_gpu_pack_surfaces(const struct pathtrace_scene *s, struct surface_params **sp,
                                 float **pts, size_t *npts)
{
    size_t n = 1;
    for (int k = 0; k < s->surface_count; k++)
        if (s->surfaces[k].geom.kind == GEOM_LATHE)
            n += s->surfaces[k].geom.profile_count;
    *sp = calloc((size_t)(s->surface_count > 0 ? s->surface_count : 1), sizeof **sp);
    *pts = calloc(2 * n, sizeof **pts);
    *npts = n;
    if (*sp == NULL || *pts == NULL)
        return false;
    size_t next = 0;
    for (int k = 0; k < s->surface_count; k++) {
        const struct pathtrace_surface *su = &s->surfaces[k];
        const double zero[3] = {0, 0, 0};
        geom_surface_pack(&su->geom, su->medium.ior, su->medium.sigma_a, zero, su->medium.sigma_s,
                          su->medium.g, (int)next, &(*sp)[k]);
        if (su->geom.kind == GEOM_LATHE)
            for (size_t j = 0; j < su->geom.profile_count; j++, next++) {
                (*pts)[2 * next] = (float)su->geom.profile[j][0];
                (*pts)[2 * next + 1] = (float)su->geom.profile[j][1];
            }
    }
    return true;
}

static enum refract_code run(GLuint prog, struct pt_params *p, const struct surface_params *sp,
                             size_t nsp, const float *pts, size_t npts, int first, int samples,
                             float *accum, struct err *e)
{
    int n = p->image.x * p->image.y;
    size_t accum_bytes = (size_t)n * 8 * sizeof(float);
    struct gpu_buffer bp = {0}, bs = {0}, bl = {0}, ba = {0};
    enum refract_code rc = gpu_buffer_create("pathtrace params", sizeof *p, p, &bp, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("pathtrace surfaces", nsp * sizeof *sp, sp, &bs, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("pathtrace profiles", npts * 2 * sizeof(float), pts, &bl, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("pathtrace accum", accum_bytes, accum, &ba, e);
    if (rc == REFRACT_E_OK) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_SURFACES, bs.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_SURFACE_PROFILES, bl.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_PT_ACCUM, ba.buf);
        glUseProgram(prog);
        for (int done = 0; done < samples && rc == REFRACT_E_OK; done += SAMPLES_PER_DISPATCH) {
            p->image.z =
                samples - done < SAMPLES_PER_DISPATCH ? samples - done : SAMPLES_PER_DISPATCH;
            p->image.w = first + done;
            glNamedBufferSubData(bp.buf, 0, sizeof *p, p);
            glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_PT_PARAMS, bp.buf);
            glDispatchCompute(gpu_groups(n, PT_LOCAL_X), 1, 1);
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
            rc = gpu_check("pathtrace_render", e);
        }
        if (rc == REFRACT_E_OK)
            rc = gpu_buffer_read(&ba, accum, accum_bytes, e);
        glUseProgram(0);
    }
    gpu_buffer_destroy(&bp);
    gpu_buffer_destroy(&bs);
    gpu_buffer_destroy(&bl);
    gpu_buffer_destroy(&ba);
    return rc;
}

enum refract_code pathtrace_gpu_render(const struct pathtrace_scene *s,
                                       const struct pathtrace_camera *cam, uint32_t seed,
                                       int first_sample, int samples, struct pathtrace_image *img,
                                       struct err *e)
{
    if (s->env_kind != PATHTRACE_ENV_UNIFORM)
        return err_set(e, REFRACT_E_CONFLICT,
                       "the GPU path tracer has a uniform environment only (docs/pathtracer.md)");
    for (int k = 0; k < s->surface_count; k++)
        if (s->surfaces[k].geom.kind == GEOM_MESH)
            return err_set(e, REFRACT_E_CONFLICT,
                           "the GPU path tracer does not trace mesh surfaces yet (surface %d)", k);
    struct gpu_program_desc desc = {.label = "pathtrace_render", .main = "pathtrace_render.comp"};
    GLuint prog = gpu_program_create(&desc, NULL, e);
    if (prog == 0)
        return e->code;
    struct pt_params *p = calloc(1, sizeof *p);
    struct surface_params *sp = NULL;
    float *pts = NULL, *accum = NULL;
    size_t npts = 0, n = (size_t)cam->width * (size_t)cam->height;
    enum refract_code rc = REFRACT_E_OK;
    if (p == NULL || !pathtrace_gpu_pack_surfaces(s, &sp, &pts, &npts) ||
        (accum = calloc(n * 8, sizeof *accum)) == NULL)
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the GPU path tracer");
    if (rc == REFRACT_E_OK) {
        pathtrace_gpu_pack_params(s, cam, seed, p);
        size_t nsp = s->surface_count > 0 ? (size_t)s->surface_count : 1;
        rc = run(prog, p, sp, nsp, pts, npts, first_sample, samples, accum, e);
    }
    if (rc == REFRACT_E_OK)
        for (size_t i = 0; i < n; i++) {
            for (int c = 0; c < 3; c++) {
                img->sum[3 * i + c] += accum[8 * i + c];
                img->sum_sq[3 * i + c] += accum[8 * i + 4 + c];
            }
            img->samples[i] += (uint32_t)samples;
        }
    glDeleteProgram(prog);
    free(p);
    free(sp);
    free(pts);
    free(accum);
    return rc;
}
