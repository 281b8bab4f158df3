/*
 * render_request.c - store versions as render and irradiance sources, and the render path
 * shared by POST .../render and the view sessions (render_request.h). Moved here from
 * server/http/ so that the view scheduler, which must not depend on HTTP, renders exactly
 * as a single render does.
 */
#include <stdio.h>
#include <string.h>

#include "../store/store_mesh.h"
#include "../request/render_request.h"

struct render_scene_source render_request_scene_source(struct store_scene *v)
{
    return (struct render_scene_source){
        .id = v->id,
        .generation = v->data_generation,
        .scene = v->scene,
        .lookup = store_volume_lookup,
        .lookup_ctx = v,
        .env_rgba = v->env ? v->env->rgba : NULL,
        .env_width = v->env ? v->env->width : 0,
        .env_height = v->env ? v->env->height : 0,
    };
}

static void version_retain(void *ctx)
{
    atomic_fetch_add(&((struct store_scene *)ctx)->refs, 1);
}

static void version_release(void *ctx)
{
    store_scene_release(ctx);
}

/* The channels whose uploads change light transport (scene_transport_hash's list). */
static bool transport_channel(int ch)
{
    return ch == SCENE_CH_IOR || ch == SCENE_CH_ATTENUATION || ch == SCENE_CH_SCATTERING ||
           ch == SCENE_CH_OPAQUE;
}

/* FNV-1a over the content checksums of the uploads the transport uses (objects' volume
 * and mesh layers, mesh surfaces), in the order the scene references them: an upload with
 * new content is a new transport. */
static uint64_t uploads_hash(const struct store_scene *v)
{
    uint64_t h = 14695981039346656037ull;
    const struct scene *s = v->scene;
    for (size_t o = 0; o < s->object_count; o++) {
        for (int ch = 0; ch < SCENE_CH_COUNT; ch++) {
            const struct scene_field *f = &s->objects[o].fields[ch];
            for (size_t i = 0; transport_channel(ch) && i < f->count; i++) {
                const struct scene_layer *l = &f->layers[i];
                bool mesh = l->kind == SCENE_LAYER_SHAPE && l->shape.kind == SCENE_SHAPE_MESH;
                if (l->kind != SCENE_LAYER_VOLUME && !mesh)
                    continue;
                uint64_t sum = 0;
                for (size_t k = 0; !mesh && k < v->volume_count; k++) {
                    if (strcmp(v->volumes[k]->name, l->volume) == 0)
                        sum = v->volumes[k]->checksum;
                }
                for (size_t k = 0; mesh && k < v->mesh_count; k++) {
                    if (strcmp(v->meshes[k]->name, l->shape.mesh) == 0)
                        sum = v->meshes[k]->checksum;
                }
                const unsigned char *p = (const unsigned char *)&sum;
                for (size_t b = 0; b < sizeof sum; b++)
                    h = (h ^ p[b]) * 1099511628211ull;
            }
        }
    }
    /* Mesh surfaces bound media the light simulator traces (docs/lightsim.md "Surfaces"). */
    for (size_t k = 0; k < s->surface_count; k++) {
        if (s->surfaces[k].shape.kind != SCENE_SHAPE_MESH)
            continue;
        uint64_t sum = 0;
        for (size_t i = 0; i < v->mesh_count; i++)
            if (strcmp(v->meshes[i]->name, s->surfaces[k].shape.mesh) == 0)
                sum = v->meshes[i]->checksum;
        const unsigned char *p = (const unsigned char *)&sum;
        for (size_t b = 0; b < sizeof sum; b++)
            h = (h ^ p[b]) * 1099511628211ull;
    }
    return h;
}

void render_request_irradiance_source(struct store_scene *v, struct irradiance_source *out)
{
    *out = (struct irradiance_source){.scene_id = v->id,
                                      .scene = v->scene,
                                      .lookup = store_volume_lookup,
                                      .lookup_ctx = v,
                                      .uploads_hash = uploads_hash(v),
                                      .retain = version_retain,
                                      .release = version_release};
}

/* After a build on the request path, record it like a background build would. */
static void note_build(struct store *store, const struct store_scene *v,
                       const struct render_scene_status *rs)
{
    if (!rs->built_now)
        return;
    struct store_gpu_status st = {
        .generation = v->generation, .gpu_bytes = rs->gpu_bytes, .build_ms = rs->build_ms};
    snprintf(st.state, sizeof st.state, "ready");
    store_gpu_status_set(store, v->id, &st);
}

enum refract_code render_request_version_rows(struct render *r, struct irradiance_cache *c,
                                              struct store *store, struct store_scene *v,
                                              struct render_view_request *req,
                                              struct render_light *lights, int row0, int rows,
                                              struct render_view_result *out,
                                              const char **irradiance, struct err *e)
{
    struct render_scene_source src = render_request_scene_source(v);
    struct irradiance_source isrc;
    render_request_irradiance_source(v, &isrc);
    int count = 0;
    /* Gathered again for every tile: the volumes are borrowed only until the next cache
     * call on the GPU thread, and other work runs between tiles. The caller compares the
     * lights' volumes with the first tile's (a volume read back from disk meanwhile can
     * replace a stale one) and starts again when they differ. */
    *irradiance = irradiance_cache_gather(c, &isrc, lights, &count);
    req->lights = lights;
    req->light_count = count;
    req->photons_cached = true;
    enum refract_code rc = render_view_rows(r, &src, req, row0, rows, out, e);
    if (rc == REFRACT_E_OK)
        note_build(store, v, &out->scene);
    return rc;
}

bool render_request_volumes_changed(const struct render_view_request *req, int row0,
                                    const struct irradiance_gpu **volumes, uint64_t *photon_keys,
                                    int *count)
{
    bool changed = row0 != 0 && req->light_count != *count;
    for (int j = 0; j < req->light_count && j < SCENE_MAX_LIGHTS; j++) {
        const struct render_light *l = &req->lights[j];
        uint64_t pk = l->photons ? l->photon_key : 0;
        if (row0 == 0) {
            volumes[j] = l->volume;
            photon_keys[j] = pk;
        } else if (volumes[j] != l->volume || photon_keys[j] != pk) {
            changed = true;
        }
    }
    if (row0 == 0)
        *count = req->light_count;
    return changed;
}
