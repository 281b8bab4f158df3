/*
 * h_irradiance.c - GET /v1/scenes/{id}/irradiance (the status of each light's irradiance
 * volume) and GET /v1/scenes/{id}/irradiance/{light}.exr (the volume as OpenEXR), and the
 * glue between store versions and the irradiance cache (server/cache/).
 */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../cache/irradiance_cache.h"
#include "../core/photon.h"
#include "http_internal.h"

static void add_hex(cJSON *o, const char *name, uint64_t v)
{
    char hex[17];
    snprintf(hex, sizeof hex, "%016" PRIx64, v);
    cJSON_AddStringToObject(o, name, hex);
}

cJSON *http_irradiance_status(const struct http_app *app, struct store_scene *v)
{
    struct irradiance_source src;
    render_request_irradiance_source(v, &src);
    struct irradiance_light_status st[SCENE_MAX_LIGHTS];
    int n = irradiance_cache_status(app->irradiance, &src, st);
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "scene", v->id);
    /* Whether each light needs something of the cache: an irradiance volume, or a photon map
     * (receiver.caustics "photons"). */
    cJSON_AddBoolToObject(root, "needed",
                          scene_needs_light_simulation(v->scene) ||
                              scene_needs_photon_maps(v->scene));
    /* Which caustic method the scene's receiver uses (docs/photons.md "Choosing"): "photons"
     * (photon maps and shadow rays, no volume), "volume" (the light simulator's) or "none"
     * (direct light and shadows only, or no receiver). */
    const struct scene_receiver *rc = &v->scene->receiver;
    cJSON_AddStringToObject(root, "caustics",
                            !rc->enabled ? "none" : scene_caustics_words[rc->caustics]);
    /* Whether the daemon chose it ("auto", the default) and why (docs/photons.md
     * "Choosing"). */
    cJSON_AddBoolToObject(root, "caustics_auto", rc->enabled && rc->caustics_auto);
    cJSON_AddStringToObject(root, "caustics_reason",
                            !rc->enabled ? "no receiver" : rc->caustics_reason);
    /* How scattering media get light (docs/walter.md "When"): "walter" (exact paths through
     * the sphere, no volume), "volume" or "none" (nothing scatters). */
    cJSON_AddStringToObject(root, "single_scattering", scene_single_scattering_method(v->scene));
    add_hex(root, "transport_hash", irradiance_transport_hash(&src));
    cJSON_AddNumberToObject(root, "generation", (double)v->generation);
    cJSON *arr = cJSON_AddArrayToObject(root, "lights");
    for (int i = 0; i < n; i++) {
        cJSON *o = cJSON_CreateObject();
        cJSON_AddStringToObject(o, "name", st[i].name);
        cJSON_AddStringToObject(o, "state", irradiance_state_name(st[i].state));
        cJSON_AddNumberToObject(o, "progress", st[i].progress);
        cJSON_AddNumberToObject(o, "patches_live", st[i].patches_live);
        add_hex(o, "key", st[i].key);
        cJSON_AddNumberToObject(o, "gpu_bytes", (double)st[i].gpu_bytes);
        cJSON_AddNumberToObject(o, "host_bytes", (double)st[i].host_bytes);
        cJSON_AddNumberToObject(o, "compute_ms", st[i].compute_ms);
        cJSON_AddBoolToObject(o, "loaded_from_disk", st[i].loaded_from_disk);
        cJSON_AddStringToObject(o, "using", st[i].using_);
        if (st[i].state == IRRADIANCE_FAILED)
            cJSON_AddStringToObject(o, "message", st[i].message);
        if (st[i].has_stats)
            cJSON_AddItemToObject(o, "stats", irradiance_stats_json(&st[i].stats));
        if (st[i].photons) { /* docs/photons.md "The cache" */
            cJSON *p = cJSON_AddObjectToObject(o, "photon_map");
            cJSON_AddNumberToObject(p, "passes", st[i].passes);
            cJSON_AddNumberToObject(p, "passes_total", st[i].passes_total);
            cJSON_AddBoolToObject(p, "refining", st[i].refining);
            cJSON_AddNumberToObject(p, "photons", (double)st[i].photons_emitted);
            cJSON_AddNumberToObject(p, "landed", (double)st[i].photons_landed);
            cJSON_AddNumberToObject(p, "radius", st[i].photon_radius);
        }
        cJSON_AddItemToArray(arr, o);
    }
    struct irradiance_cache_counters k;
    irradiance_cache_counters(app->irradiance, &k);
    cJSON *cache = cJSON_AddObjectToObject(root, "cache");
    cJSON_AddNumberToObject(cache, "entries", k.entries);
    cJSON_AddNumberToObject(cache, "gpu_bytes", (double)k.gpu_bytes);
    cJSON_AddNumberToObject(cache, "host_bytes", (double)k.host_bytes);
    cJSON_AddNumberToObject(cache, "computed", (double)k.computed);
    cJSON_AddNumberToObject(cache, "superseded", (double)k.superseded);
    cJSON_AddNumberToObject(cache, "loaded", (double)k.loaded);
    cJSON_AddNumberToObject(cache, "failed", (double)k.failed);
    cJSON_AddNumberToObject(cache, "evicted_gpu", (double)k.evicted_gpu);
    cJSON_AddNumberToObject(cache, "evicted_host", (double)k.evicted_host);
    cJSON_AddNumberToObject(cache, "evicted_disk", (double)k.evicted_disk);
    cJSON_AddNumberToObject(cache, "disk_bytes", (double)k.disk_bytes);
    return root;
}

enum MHD_Result http_handle_irradiance_get(struct http_request *req)
{
    enum MHD_Result answer = MHD_NO;
    struct store_scene *v = http_scene_or_404(req, &answer);
    if (v == NULL)
        return answer;
    cJSON *root = http_irradiance_status(req->app, v);
    store_scene_release(v);
    return http_respond_json(req, MHD_HTTP_OK, root);
}

enum MHD_Result http_handle_irradiance_exr(struct http_request *req)
{
    enum MHD_Result answer = MHD_NO;
    struct store_scene *v = http_scene_or_404(req, &answer);
    if (v == NULL)
        return answer;
    struct irradiance_source src;
    render_request_irradiance_source(v, &src);
    struct irradiance_volume vol;
    uint64_t key = 0;
    bool previous = false;
    struct err e = {0};
    enum refract_code rc = irradiance_cache_copy(req->app->irradiance, &src, req->params[1], &vol,
                                                 &key, &previous, &e);
    store_scene_release(v);
    if (rc != REFRACT_E_OK)
        return http_respond_err(req, &e);
    void *bytes = NULL;
    size_t len = 0;
    rc = irradiance_volume_encode_exr(&vol, key, &bytes, &len, &e);
    char dims[64], keyhex[17];
    snprintf(dims, sizeof dims, "%dx%dx%d", vol.grid.dims[0], vol.grid.dims[1], vol.grid.dims[2]);
    snprintf(keyhex, sizeof keyhex, "%016" PRIx64, key);
    irradiance_volume_free(&vol);
    if (rc != REFRACT_E_OK)
        return http_respond_err(req, &e);
    const char *headers[] = {
        "X-Irradiance-Key",           keyhex, "X-Irradiance-Dims", dims, "X-Refract-Irradiance",
        previous ? "stale" : "ready", NULL};
    return http_respond_bytes(req, MHD_HTTP_OK, bytes, len, "image/x-exr", headers);
}
