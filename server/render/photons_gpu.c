/*
 * photons_gpu.c - the receiver's photon map on the GPU side (scene_gpu.h,
 * docs/photons.md): the scene's surfaces and the request's lights become a pathtrace
 * scene, its photons are traced on the GPU (photon_trace_gpu; on CPU threads, one per online
 * CPU, for mesh surfaces or when render_desc.photons_on_cpu), gathered on the CPU, and the
 * lattice goes to two storage buffers that shaders/photons.glsl reads. The map is kept with the
 * scene's GPU data and rebuilt when the lights' poses, colours or the photon settings
 * change (its key).
 *
 * What it is not yet (issue 15 item 3): part of the irradiance cache (asynchronous,
 * persisted, streamed as it refines); the first render after a light moves waits for it.
 */
#include <math.h>
#include <string.h>
#include <unistd.h>

#include "../core/geom/geom.h"
#include "../core/log.h"
#include "../core/photon.h"
#include "../scene/scene_pathtrace.h"
#include "photon_trace_gpu.h"
#include "scene_gpu.h"
#define REFRACT_HOST_C
#include "shared_types.h"

static void mix(uint64_t *h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        *h ^= p[i];
        *h *= 1099511628211ull;
    }
}

static void mix_double(uint64_t *h, double v)
{
    if (v == 0.0)
        v = 0.0; /* -0 and 0 alike */
    mix(h, &v, sizeof v);
}

/* The request's lights as the photon tracer sees them (scene_pathtrace_light). */
static void lights_from_request(const struct render_view_request *req, struct pathtrace_scene *p)
{
    int n = req->light_count < PATHTRACE_MAX_LIGHTS ? req->light_count : PATHTRACE_MAX_LIGHTS;
    p->light_count = n > 0 && req->lights ? n : 0;
    for (int j = 0; j < p->light_count; j++) {
        const struct render_light *l = &req->lights[j];
        scene_pathtrace_light(l->kind, l->position, l->direction, l->cos_spot, l->scale, l->radius,
                              !l->camera_hidden, &p->lights[j]);
    }
}

static uint64_t map_key(const struct pathtrace_scene *p, const struct scene_receiver *rc)
{
    uint64_t h = 1469598103934665603ull;
    for (int j = 0; j < p->light_count; j++) {
        const struct pathtrace_light *l = &p->lights[j];
        int kind = (int)l->kind;
        mix(&h, &kind, sizeof kind);
        const double v[] = {l->position.x,  l->position.y,  l->position.z, l->direction.x,
                            l->direction.y, l->direction.z, l->cos_spot,   l->radius,
                            l->value[0],    l->value[1],    l->value[2]};
        for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
            mix_double(&h, v[i]);
    }
    mix(&h, &rc->photons, sizeof rc->photons);
    mix_double(&h, rc->photon_radius);
    return h;
}

/* The map's photons traced on the GPU (photon_trace.comp) when asked and possible, else on
 * CPU threads; then the lattice on the CPU. *where says which traced them. */
static enum refract_code build_map(const struct pathtrace_scene *ps,
                                   const struct scene_receiver *rc, bool on_gpu,
                                   struct photon_grid *g, struct photon_map_stats *st,
                                   const char **where, struct err *e)
{
    bool meshes = false;
    for (int k = 0; k < ps->surface_count; k++)
        meshes = meshes || ps->surfaces[k].geom.kind == GEOM_MESH;
    if (!on_gpu || meshes) {
        long cpus = sysconf(_SC_NPROCESSORS_ONLN);
        *where = "CPU";
        return photon_map_build(ps, rc->photons, rc->photon_radius, 1, cpus > 0 ? (int)cpus : 1, g,
                                st, e);
    }
    *where = "GPU";
    memset(st, 0, sizeof *st);
    struct photon_list l = {0};
    double t0 = gpu_time_ms();
    enum refract_code r = photon_trace_gpu(ps, rc->photons, 1, &l, e);
    st->trace_ms = gpu_time_ms() - t0;
    st->emitted = l.emitted;
    st->landed = l.count;
    st->radius = photon_radius(ps, rc->photons, rc->photon_radius);
    if (r == REFRACT_E_OK) {
        double t1 = gpu_time_ms();
        r = photon_grid_build(&l, st->radius, g, e);
        st->grid_ms = gpu_time_ms() - t1;
    }
    photon_list_free(&l);
    return r;
}

enum refract_code photons_gpu_prepare(struct scene_gpu *sg, const struct render_scene_source *src,
                                      const struct render_view_request *req, bool trace_on_gpu,
                                      struct march_lights *ml, struct err *e)
{
    const struct scene *s = src->scene;
    if (!s->receiver.enabled || s->receiver.caustics != SCENE_CAUSTICS_PHOTONS)
        return REFRACT_E_OK;
    static struct scene_pathtrace sp; /* large; GPU thread only */
    enum refract_code rc = scene_pathtrace_geometry(s, src->lookup, src->lookup_ctx, &sp, e);
    if (rc != REFRACT_E_OK)
        return rc;
    lights_from_request(req, &sp.scene);
    uint64_t key = map_key(&sp.scene, &s->receiver);
    if (sg->photons.buf == 0 || sg->photon_key != key) {
        struct photon_grid g;
        struct photon_map_stats st;
        const char *where;
        rc = build_map(&sp.scene, &s->receiver, trace_on_gpu, &g, &st, &where, e);
        if (rc != REFRACT_E_OK)
            return rc;
        static const float zero[4] = {0};
        static const int32_t no_key[2] = {PHOTON_EMPTY_KEY, PHOTON_EMPTY_KEY};
        gpu_buffer_destroy(&sg->photons);
        gpu_buffer_destroy(&sg->photon_keys);
        bool any = g.capacity > 0;
        rc = gpu_buffer_create("photon lattice",
                               any ? (size_t)g.capacity * 4 * sizeof(float) : sizeof zero,
                               any ? (const void *)g.E : (const void *)zero, &sg->photons, e);
        if (rc == REFRACT_E_OK)
            rc = gpu_buffer_create("photon lattice keys",
                                   any ? (size_t)g.capacity * 2 * sizeof(int32_t) : sizeof no_key,
                                   any ? (const void *)g.keys : (const void *)no_key,
                                   &sg->photon_keys, e);
        sg->photon_cell = g.cell;
        sg->photon_radius = st.radius;
        sg->photon_capacity = g.capacity;
        sg->photon_probe_max = g.probe_max;
        sg->photon_build_ms = st.trace_ms + st.grid_ms;
        sg->photon_key = rc == REFRACT_E_OK ? key : 0;
        uint32_t used = g.used;
        photon_grid_free(&g);
        if (rc != REFRACT_E_OK)
            return rc;
        log_info("render",
                 "scene %s: photon map of %ld photons (%zu landed), radius %.4g, %u lattice "
                 "points (longest probe %u), traced in %.0f ms, gathered in %.0f ms",
                 sg->id, st.emitted, st.landed, st.radius, used, sg->photon_probe_max, st.trace_ms,
                 st.grid_ms);
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_PHOTONS, sg->photons.buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_PHOTON_BUCKETS, sg->photon_keys.buf);
    ml->count.z = 1;
    ml->photon_grid = (vec4){(float)sg->photon_cell, (float)sg->photon_radius, 0.0f, 0.0f};
    ml->photon_dims = (ivec4){(int)sg->photon_capacity, (int)sg->photon_probe_max, 0, 0};
    return REFRACT_E_OK;
}
