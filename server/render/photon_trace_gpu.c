/*
 * photon_trace_gpu.c - the host of shaders/photon_trace.comp (photon_trace_gpu.h): the
 * scene packed as for the GPU path tracer, photons dispatched in chunks of
 * PHOTON_GPU_CHUNK (one invocation each), read back and the stored ones appended.
 */
#include "photon_trace_gpu.h"

#include <stdlib.h>
#include <string.h>

#include "../core/geom/geom.h"
#include "../gpu/program.h"
#include "../gpu/resources.h"
#include "pathtrace_gpu.h"
#define REFRACT_HOST_C
#include "shared_types.h"
#include "pathtrace_types.h"

#define PHOTON_GPU_CHUNK 1048576 /* photons per dispatch: 32 MiB of output */

/* Appends the stored photons of one chunk's output (2 vec4 per photon). */
static enum refract_code collect(const float *o, long n, struct photon_list *out, struct err *e)
{
    struct photon_list part = {0};
    part.items = malloc((size_t)n * sizeof *part.items);
    if (part.items == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "photons: out of memory reading back");
    part.capacity = (size_t)n;
    for (long i = 0; i < n; i++) {
        const float *h = &o[8 * i], *p = &o[8 * i + 4];
        if (h[2] == 2.0f) {
            for (int c = 0; c < 3; c++)
                part.lost[c] += p[c];
        } else if (h[2] == 1.0f) {
            struct photon *ph = &part.items[part.count++];
            ph->x = h[0];
            ph->z = h[1];
            for (int c = 0; c < 3; c++) {
                ph->power[c] = p[c];
                part.landed[c] += p[c];
            }
        }
    }
    part.emitted = n;
    enum refract_code rc = photon_list_merge(out, &part, e);
    photon_list_free(&part);
    return rc;
}

enum refract_code photon_trace_gpu(const struct pathtrace_scene *s, long count, uint32_t seed,
                                   struct photon_list *out, struct err *e)
{
    for (int k = 0; k < s->surface_count; k++) {
        if (s->surfaces[k].geom.kind == GEOM_MESH)
            return err_set(e, REFRACT_E_CONFLICT,
                           "photons: the GPU photon tracer does not trace mesh surfaces yet "
                           "(surface %d)",
                           k);
        if (pathtrace_medium_scatters(&s->surfaces[k].medium))
            return err_set(e, REFRACT_E_CONFLICT,
                           "photons: surface %d's medium scatters; caustic photons do not "
                           "scatter in media yet (docs/photons.md \"Not yet\")",
                           k);
    }
    vec3 c;
    double r;
    int unbounded;
    if (!photon_target(s, &c, &r, &unbounded)) {
        if (unbounded >= 0)
            return err_set(e, REFRACT_E_CONFLICT,
                           "photons: surface %d is unbounded (an infinite plane); caustic "
                           "photons need bounded surfaces (docs/photons.md \"Not yet\")",
                           unbounded);
        return REFRACT_E_OK;
    }
    if (s->light_count <= 0 || count <= 0 || !s->receiver.enabled)
        return REFRACT_E_OK;
    long per_light = count / s->light_count > 0 ? count / s->light_count : 1;
    long total = per_light * s->light_count;
    struct gpu_program_desc desc = {.label = "photon_trace", .main = "photon_trace.comp"};
    GLuint prog = gpu_program_create(&desc, NULL, e);
    if (prog == 0)
        return e->code;
    struct pt_params *p = calloc(1, sizeof *p);
    struct surface_params *sp = NULL;
    float *pts = NULL, *o = NULL;
    size_t npts = 0;
    long chunk = total < PHOTON_GPU_CHUNK ? total : PHOTON_GPU_CHUNK;
    size_t out_bytes = (size_t)chunk * 8 * sizeof(float);
    enum refract_code rc = REFRACT_E_OK;
    if (p == NULL || !pathtrace_gpu_pack_surfaces(s, &sp, &pts, &npts) ||
        (o = malloc(out_bytes)) == NULL)
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "photons: out of memory for the GPU tracer");
    struct gpu_buffer bp = {0}, bs = {0}, bl = {0}, bo = {0};
    size_t nsp = s->surface_count > 0 ? (size_t)s->surface_count : 1;
    if (rc == REFRACT_E_OK) {
        pathtrace_gpu_pack_params(s, NULL, seed, p);
        p->eye = (vec4){(float)c.x, (float)c.y, (float)c.z, (float)r};
        p->image = (ivec4){(int)per_light, 0, 0, 0};
        for (int j = 0; j < s->light_count && j < PT_MAX_LIGHTS; j++) {
            /* where the light's photons start: its centre, or the directional disk's */
            const struct pathtrace_light *l = &s->lights[j];
            vec3 at = l->kind == PATHTRACE_LIGHT_DIRECTIONAL ? vec3_madd(c, l->direction, -2.0 * r)
                                                             : l->position;
            p->lights[j].kind.z = (int)pathtrace_inside_set(s, at);
        }
        rc = gpu_buffer_create("photon params", sizeof *p, p, &bp, e);
    }
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("photon surfaces", nsp * sizeof *sp, sp, &bs, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("photon profiles", npts * 2 * sizeof(float), pts, &bl, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("photons out", out_bytes, NULL, &bo, e);
    if (rc == REFRACT_E_OK) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_SURFACES, bs.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_SURFACE_PROFILES, bl.buf);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_PT_ACCUM, bo.buf);
        glUseProgram(prog);
    }
    for (long first = 0; first < total && rc == REFRACT_E_OK; first += chunk) {
        long n = total - first < chunk ? total - first : chunk;
        p->image.w = (int)first;
        glNamedBufferSubData(bp.buf, 0, sizeof *p, p);
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_PT_PARAMS, bp.buf);
        glDispatchCompute(gpu_groups((int)n, PT_LOCAL_X), 1, 1);
        glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
        rc = gpu_check("photon_trace", e);
        if (rc == REFRACT_E_OK)
            rc = gpu_buffer_read(&bo, o, (size_t)n * 8 * sizeof(float), e);
        if (rc == REFRACT_E_OK)
            rc = collect(o, n, out, e);
    }
    gpu_buffer_destroy(&bp);
    gpu_buffer_destroy(&bs);
    gpu_buffer_destroy(&bl);
    gpu_buffer_destroy(&bo);
    glDeleteProgram(prog);
    free(p);
    free(sp);
    free(pts);
    free(o);
    return rc;
}
