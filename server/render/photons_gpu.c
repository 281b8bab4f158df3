/*
 * photons_gpu.c - the receiver's photon maps on the GPU side (scene_gpu.h,
 * docs/photons.md): one map per light at unit intensity, the lights' maps one after another
 * in two storage buffers that shaders/photons.glsl reads (light j's from slot
 * photon_dims[j].z), each scaled by its light's colour times intensity there.
 *
 * In refractd the maps come from the irradiance cache (render_view_request.photons_cached:
 * traced ahead on its worker, refined in passes, persisted; docs/photons.md "The cache"), and
 * this file only puts them in the buffers when the set changes. Without the cache (tools,
 * tests) each light's map is traced here at once: its photons on the GPU (photon_trace_gpu;
 * on CPU threads, one per online CPU, for mesh surfaces or when render_desc.photons_on_cpu),
 * gathered on the CPU, and kept with the scene's GPU data until the light's pose or the
 * photon settings change (its key).
 */
#include <math.h>
#include <stdlib.h>
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

/* Light j of the request at unit intensity, as the photon tracer sees it. */
static void unit_light(const struct render_light *l, struct pathtrace_light *out)
{
    static const double unit[3] = {1.0, 1.0, 1.0};
    scene_pathtrace_light(l->kind, l->position, l->direction, l->cos_spot, unit, l->radius,
                          !l->camera_hidden, out);
}

/* The key of a light's own map: its emission and the photon settings. */
static uint64_t own_key(const struct pathtrace_light *l, const struct scene_receiver *rc)
{
    uint64_t h = 1469598103934665603ull;
    int kind = (int)l->kind;
    mix(&h, &kind, sizeof kind);
    const double v[] = {l->position.x,  l->position.y,  l->position.z, l->direction.x,
                        l->direction.y, l->direction.z, l->cos_spot,   l->radius,
                        l->value[0],    l->value[1],    l->value[2]};
    for (size_t i = 0; i < sizeof v / sizeof v[0]; i++)
        mix_double(&h, v[i]);
    mix(&h, &rc->photons, sizeof rc->photons);
    mix_double(&h, rc->photon_radius);
    return h;
}

/* A light's map (ps has that light only) traced on the GPU (photon_trace.comp) when asked
 * and possible, else on CPU threads; then the lattice on the CPU. *where says which traced
 * them. */
static enum refract_code build_map(const struct pathtrace_scene *ps,
                                   const struct scene_receiver *rc, bool on_gpu,
                                   struct photon_grid *g, struct photon_map_stats *st,
                                   const char **where, struct err *e)
{
    uint64_t seed = photon_level_seed(PHOTON_LEVELS - 1);
    bool meshes = false;
    for (int k = 0; k < ps->surface_count; k++)
        meshes = meshes || ps->surfaces[k].geom.kind == GEOM_MESH;
    if (!on_gpu || meshes) {
        long cpus = sysconf(_SC_NPROCESSORS_ONLN);
        *where = "CPU";
        return photon_map_build(ps, rc->photons, rc->photon_radius, seed, cpus > 0 ? (int)cpus : 1,
                                g, st, e);
    }
    *where = "GPU";
    memset(st, 0, sizeof *st);
    struct photon_list l = {0};
    double t0 = gpu_time_ms();
    enum refract_code r = photon_trace_gpu(ps, rc->photons, seed, &l, e);
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

/* Without the cache: each light's own map, traced now unless its key still holds. */
static enum refract_code own_maps(struct scene_gpu *sg, const struct render_scene_source *src,
                                  const struct render_view_request *req, int n,
                                  bool trace_on_gpu, const struct photon_grid **maps,
                                  uint64_t *keys, struct err *e)
{
    const struct scene *s = src->scene;
    static struct scene_pathtrace sp; /* large; GPU thread only */
    enum refract_code rc = scene_pathtrace_geometry(s, src->lookup, src->lookup_ctx, &sp, e);
    for (int j = 0; rc == REFRACT_E_OK && j < n; j++) {
        struct pathtrace_light l;
        unit_light(&req->lights[j], &l);
        keys[j] = own_key(&l, &s->receiver);
        if (sg->photon_own[j] == NULL || sg->photon_own_key[j] != keys[j]) {
            struct pathtrace_scene one;
            photon_scene_one_light(&sp.scene, &l, &one);
            struct photon_grid g;
            struct photon_map_stats st;
            const char *where;
            rc = build_map(&one, &s->receiver, trace_on_gpu, &g, &st, &where, e);
            if (rc != REFRACT_E_OK)
                break;
            if (sg->photon_own[j] == NULL && (sg->photon_own[j] = malloc(sizeof g)) == NULL) {
                photon_grid_free(&g);
                return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a photon map");
            }
            if (sg->photon_own_key[j] != 0)
                photon_grid_free(sg->photon_own[j]);
            *sg->photon_own[j] = g;
            sg->photon_own_key[j] = keys[j];
            log_info("render",
                     "scene %s light %d: photon map of %ld photons (%zu landed) on the %s, radius "
                     "%.4g, %u lattice points (longest probe %u), traced in %.0f ms, gathered in "
                     "%.0f ms",
                     sg->id, j, st.emitted, st.landed, where, st.radius, g.used, g.probe_max,
                     st.trace_ms, st.grid_ms);
        }
        maps[j] = sg->photon_own[j];
    }
    return rc;
}

void photons_gpu_free(struct scene_gpu *sg)
{
    for (int j = 0; j < SCENE_MAX_LIGHTS; j++) {
        if (sg->photon_own[j])
            photon_grid_free(sg->photon_own[j]);
        free(sg->photon_own[j]);
        sg->photon_own[j] = NULL;
        sg->photon_own_key[j] = 0;
    }
}

/* The maps into the two buffers, one after another (a stand-in slot when all are empty). */
static enum refract_code upload(struct scene_gpu *sg, const struct photon_grid **maps, int n,
                                struct err *e)
{
    size_t slots = 0;
    for (int j = 0; j < n; j++)
        slots += maps[j] ? maps[j]->capacity : 0;
    size_t alloc = slots > 0 ? slots : 1;
    float *E = malloc(alloc * 4 * sizeof *E);
    int32_t *keys = malloc(alloc * 2 * sizeof *keys);
    if (E == NULL || keys == NULL) {
        free(E);
        free(keys);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for %zu photon lattice slots",
                       slots);
    }
    memset(E, 0, 4 * sizeof *E);
    keys[0] = keys[1] = PHOTON_EMPTY_KEY;
    memset(sg->photon_grid, 0, sizeof sg->photon_grid);
    memset(sg->photon_dims, 0, sizeof sg->photon_dims);
    size_t first = 0;
    for (int j = 0; j < n; j++) {
        const struct photon_grid *g = maps[j];
        if (g == NULL || g->capacity == 0)
            continue;
        memcpy(E + first * 4, g->E, (size_t)g->capacity * 4 * sizeof *E);
        memcpy(keys + first * 2, g->keys, (size_t)g->capacity * 2 * sizeof *keys);
        sg->photon_grid[j][0] = (float)g->cell;
        sg->photon_grid[j][1] = (float)g->radius;
        sg->photon_dims[j][0] = (int32_t)g->capacity;
        sg->photon_dims[j][1] = (int32_t)g->probe_max;
        sg->photon_dims[j][2] = (int32_t)first;
        first += g->capacity;
    }
    gpu_buffer_destroy(&sg->photons);
    gpu_buffer_destroy(&sg->photon_keys);
    enum refract_code rc =
        gpu_buffer_create("photon lattices", alloc * 4 * sizeof *E, E, &sg->photons, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("photon lattice keys", alloc * 2 * sizeof *keys, keys,
                               &sg->photon_keys, e);
    free(E);
    free(keys);
    return rc;
}

enum refract_code photons_gpu_prepare(struct scene_gpu *sg, const struct render_scene_source *src,
                                      const struct render_view_request *req, bool trace_on_gpu,
                                      struct march_lights *ml, struct err *e)
{
    if (!scene_receiver_shadow_rays(src->scene))
        return REFRACT_E_OK; /* caustics "none": shadow rays, no map (all maps NULL below) */
    int n = req->lights ? req->light_count : 0;
    if (n > SCENE_MAX_LIGHTS)
        n = SCENE_MAX_LIGHTS;
    const struct photon_grid *maps[SCENE_MAX_LIGHTS] = {NULL};
    uint64_t keys[SCENE_MAX_LIGHTS] = {0};
    if (!scene_needs_photon_maps(src->scene)) {
        /* caustics "none": direct light and shadows only */
    } else if (req->photons_cached) {
        for (int j = 0; j < n; j++) {
            maps[j] = req->lights[j].photons;
            keys[j] = maps[j] ? req->lights[j].photon_key : 0;
        }
    } else {
        enum refract_code rc = own_maps(sg, src, req, n, trace_on_gpu, maps, keys, e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    uint64_t key = 1469598103934665603ull;
    mix(&key, &n, sizeof n);
    mix(&key, keys, sizeof keys);
    if (sg->photons.buf == 0 || sg->photon_key != key) {
        sg->photon_key = 0;
        enum refract_code rc = upload(sg, maps, n, e);
        if (rc != REFRACT_E_OK)
            return rc;
        sg->photon_key = key;
        sg->photon_maps = n;
    }
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_PHOTONS, sg->photons.buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_PHOTON_BUCKETS, sg->photon_keys.buf);
    ml->count.z = 1;
    for (int j = 0; j < SCENE_MAX_LIGHTS; j++) {
        ml->photon_grid[j] = (vec4){sg->photon_grid[j][0], sg->photon_grid[j][1], 0.0f, 0.0f};
        ml->photon_dims[j] = (ivec4){sg->photon_dims[j][0], sg->photon_dims[j][1],
                                     sg->photon_dims[j][2], 0};
    }
    return REFRACT_E_OK;
}
