/*
 * cache_disk.c - irradiance volumes in the data directory and as EXR bytes.
 *
 *     <data>/irradiance/<key>.exr   the volume (layout in irradiance_cache.h, docs/api.md)
 *     <data>/irradiance/<key>.pmap  or a light's photon map (cache_photons.c)
 *     <data>/irradiance/<key>.json  sidecar: {"key", "grid": {"dims", "bmin", "voxel"},
 *                                   "compute_ms", "stats": {...}}, or for a photon map
 *                                   {"key", "kind": "photons", "compute_ms", "photons",
 *                                   "landed", "radius"}
 *
 * Both are written to a temporary name, fsynced and renamed, the data file first, so a
 * sidecar always names a complete volume or map; the start-up index (cache_index.c) trusts
 * only pairs.
 */
#include <cjson/cJSON.h>
#include <dirent.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../core/log.h"
#include "../io/io_exr.h"
#include "../io/io_files.h"
#include "cache_internal.h"

static const char *const channel_names[] = {"R", "G", "B", "dir.X", "dir.Y", "dir.Z", "dir.W"};
#define IRR_CHANNELS 7
#define IRR_MAX_FILE ((size_t)2 << 30)

void irr_volume_path(const struct irradiance_cache *c, uint64_t key, const char *ext, char *out,
                     size_t size)
{
    snprintf(out, size, "%s/%016" PRIx64 ".%s", c->dir, key, ext);
}

const char *irr_data_ext(const struct irradiance_cache *c, uint64_t key)
{
    char path[700];
    irr_volume_path(c, key, "pmap", path, sizeof path);
    return access(path, F_OK) == 0 ? "pmap" : "exr";
}

static cJSON *grid_object(const struct light_grid *g)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddItemToObject(o, "dims", cJSON_CreateIntArray(g->dims, 3));
    double b[3] = {g->bmin.x, g->bmin.y, g->bmin.z};
    cJSON_AddItemToObject(o, "bmin", cJSON_CreateDoubleArray(b, 3));
    cJSON_AddNumberToObject(o, "voxel", g->voxel);
    return o;
}

static char *grid_json(const struct light_grid *g)
{
    cJSON *o = grid_object(g);
    char *s = cJSON_PrintUnformatted(o);
    cJSON_Delete(o);
    return s;
}

/* Reads "dims", "bmin", "voxel" of a grid object; false when any is missing or bad. */
static bool grid_from_json(const cJSON *o, struct light_grid *g)
{
    const cJSON *dims = cJSON_GetObjectItemCaseSensitive(o, "dims");
    const cJSON *bmin = cJSON_GetObjectItemCaseSensitive(o, "bmin");
    const cJSON *voxel = cJSON_GetObjectItemCaseSensitive(o, "voxel");
    if (!cJSON_IsArray(dims) || cJSON_GetArraySize(dims) != 3 || !cJSON_IsArray(bmin) ||
        cJSON_GetArraySize(bmin) != 3 || !cJSON_IsNumber(voxel) || !(voxel->valuedouble > 0))
        return false;
    double b[3];
    for (int a = 0; a < 3; a++) {
        const cJSON *d = cJSON_GetArrayItem(dims, a), *m = cJSON_GetArrayItem(bmin, a);
        if (!cJSON_IsNumber(d) || d->valuedouble < 1 || d->valuedouble > 4096 || !cJSON_IsNumber(m))
            return false;
        g->dims[a] = (int)d->valuedouble;
        b[a] = m->valuedouble;
    }
    g->bmin = (vec3){b[0], b[1], b[2]};
    g->voxel = voxel->valuedouble;
    return true;
}

enum refract_code irradiance_volume_encode_exr(const struct irradiance_volume *v, uint64_t key,
                                               void **bytes, size_t *len, struct err *e)
{
    const int *d = v->grid.dims;
    size_t n = (size_t)d[0] * d[1] * d[2];
    float *px = malloc(n * IRR_CHANNELS * sizeof *px);
    char *grid = grid_json(&v->grid);
    if (px == NULL || grid == NULL) {
        free(px);
        cJSON_free(grid);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory encoding a volume");
    }
    /* The volume's x-fastest, then y, then z order is the image's row order when the
     * slices are stacked vertically with z = 0 at the top. */
    for (size_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++)
            px[i * IRR_CHANNELS + (size_t)k] = v->irradiance[i * 4 + (size_t)k];
        for (int k = 0; k < 4; k++)
            px[i * IRR_CHANNELS + 3 + (size_t)k] = v->direction[i * 4 + (size_t)k];
    }
    char keyhex[17];
    snprintf(keyhex, sizeof keyhex, "%016" PRIx64, key);
    const char *attrs[] = {"refract.grid", grid, "refract.key", keyhex, NULL};
    enum refract_code rc = io_encode_exr_channels(px, d[0], d[1] * d[2], IRR_CHANNELS,
                                                  channel_names, attrs, bytes, len, e);
    free(px);
    cJSON_free(grid);
    return rc;
}

enum refract_code irradiance_volume_decode_exr(const void *bytes, size_t len,
                                               struct irradiance_volume *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    float *px = NULL;
    int w = 0, h = 0;
    char grid_text[1024];
    enum refract_code rc =
        io_decode_exr_channels(bytes, len, IRR_CHANNELS, channel_names, 1ll << 30, &px, &w, &h,
                               "refract.grid", grid_text, sizeof grid_text, e);
    if (rc != REFRACT_E_OK)
        return rc;
    cJSON *g = cJSON_Parse(grid_text);
    bool ok = g && grid_from_json(g, &out->grid);
    cJSON_Delete(g);
    const int *d = out->grid.dims;
    if (!ok || d[0] != w || (long long)d[1] * d[2] != h) {
        free(px);
        memset(out, 0, sizeof *out);
        return err_set(e, REFRACT_E_INVALID_IMAGE,
                       "EXR: refract.grid is missing or does not match the %d x %d image", w, h);
    }
    size_t n = (size_t)w * (size_t)h;
    out->irradiance = malloc(n * 4 * sizeof(float));
    out->direction = malloc(n * 4 * sizeof(float));
    if (out->irradiance == NULL || out->direction == NULL) {
        free(px);
        irradiance_volume_free(out);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory decoding a volume");
    }
    for (size_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++)
            out->irradiance[i * 4 + (size_t)k] = px[i * IRR_CHANNELS + (size_t)k];
        out->irradiance[i * 4 + 3] = 0.0f;
        for (int k = 0; k < 4; k++)
            out->direction[i * 4 + (size_t)k] = px[i * IRR_CHANNELS + 3 + (size_t)k];
    }
    free(px);
    return REFRACT_E_OK;
}

static void add_triplet(cJSON *o, const char *name, const double v[3])
{
    cJSON_AddItemToObject(o, name, cJSON_CreateDoubleArray(v, 3));
}

struct cJSON *irradiance_stats_json(const struct lightsim_stats *s)
{
    cJSON *o = cJSON_CreateObject();
    add_triplet(o, "flux_in", s->flux_in);
    add_triplet(o, "flux_out", s->flux_out);
    add_triplet(o, "flux_reflected", s->flux_reflected);
    add_triplet(o, "flux_absorbed", s->flux_absorbed);
    add_triplet(o, "flux_culled", s->flux_culled);
    add_triplet(o, "flux_live", s->flux_live);
    cJSON_AddNumberToObject(o, "steps", (double)s->steps);
    cJSON_AddNumberToObject(o, "patch_steps", (double)s->patch_steps);
    cJSON_AddNumberToObject(o, "splits", (double)s->splits);
    cJSON_AddNumberToObject(o, "culled_energy", (double)s->culled_energy);
    cJSON_AddNumberToObject(o, "culled_level", (double)s->culled_level);
    cJSON_AddNumberToObject(o, "culled_flip", (double)s->culled_flip);
    cJSON_AddNumberToObject(o, "culled_capacity", (double)s->culled_capacity);
    cJSON_AddNumberToObject(o, "patches_initial", s->patches_initial);
    cJSON_AddNumberToObject(o, "patches_peak", s->patches_peak);
    return o;
}

static void read_triplet(const cJSON *o, const char *name, double v[3])
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(o, name);
    for (int k = 0; k < 3; k++) {
        const cJSON *x = cJSON_IsArray(a) ? cJSON_GetArrayItem(a, k) : NULL;
        v[k] = cJSON_IsNumber(x) ? x->valuedouble : 0.0;
    }
}

static double read_number(const cJSON *o, const char *name)
{
    const cJSON *x = cJSON_GetObjectItemCaseSensitive(o, name);
    return cJSON_IsNumber(x) ? x->valuedouble : 0.0;
}

static void stats_from_json(const cJSON *o, struct lightsim_stats *s)
{
    memset(s, 0, sizeof *s);
    read_triplet(o, "flux_in", s->flux_in);
    read_triplet(o, "flux_out", s->flux_out);
    read_triplet(o, "flux_reflected", s->flux_reflected);
    read_triplet(o, "flux_absorbed", s->flux_absorbed);
    read_triplet(o, "flux_culled", s->flux_culled);
    read_triplet(o, "flux_live", s->flux_live);
    s->steps = (long long)read_number(o, "steps");
    s->patch_steps = (long long)read_number(o, "patch_steps");
    s->splits = (long long)read_number(o, "splits");
    s->culled_energy = (long long)read_number(o, "culled_energy");
    s->culled_level = (long long)read_number(o, "culled_level");
    s->culled_flip = (long long)read_number(o, "culled_flip");
    s->culled_capacity = (long long)read_number(o, "culled_capacity");
    s->patches_initial = (int)read_number(o, "patches_initial");
    s->patches_peak = (int)read_number(o, "patches_peak");
    s->progress = 1.0;
    s->done = true;
}

enum refract_code irr_disk_write(const struct irradiance_cache *c, const struct irr_entry *en,
                                 struct err *e)
{
    char path[700];
    enum refract_code rc;
    bool photons = en->kind == IRR_KIND_PHOTONS;
    irr_volume_path(c, en->key, photons ? "pmap" : "exr", path, sizeof path);
    if (photons) {
        rc = irr_photons_write(path, &en->host, e);
    } else {
        void *bytes = NULL;
        size_t len = 0;
        rc = irradiance_volume_encode_exr(&en->host.volume, en->key, &bytes, &len, e);
        if (rc == REFRACT_E_OK)
            rc = io_write_atomic(path, bytes, len, e);
        free(bytes);
    }
    if (rc != REFRACT_E_OK)
        return rc;
    cJSON *o = cJSON_CreateObject();
    char keyhex[17];
    snprintf(keyhex, sizeof keyhex, "%016" PRIx64, en->key);
    cJSON_AddStringToObject(o, "key", keyhex);
    cJSON_AddNumberToObject(o, "compute_ms", en->compute_ms);
    if (photons) {
        const struct irr_pmap *m = en->host.photons;
        cJSON_AddStringToObject(o, "kind", "photons");
        cJSON_AddNumberToObject(o, "photons", (double)m->emitted);
        cJSON_AddNumberToObject(o, "landed", (double)m->landed);
        cJSON_AddNumberToObject(o, "radius", m->grid.radius);
    } else {
        cJSON_AddItemToObject(o, "grid", grid_object(&en->host.volume.grid));
        cJSON_AddItemToObject(o, "stats", irradiance_stats_json(&en->host.volume.stats));
    }
    char *text = cJSON_Print(o);
    cJSON_Delete(o);
    if (text == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory writing a sidecar");
    irr_volume_path(c, en->key, "json", path, sizeof path);
    rc = io_write_atomic(path, text, strlen(text), e);
    cJSON_free(text);
    return rc;
}

enum refract_code irr_disk_read(const struct irradiance_cache *c, uint64_t key,
                                struct irr_host *out, enum irr_kind *kind, double *compute_ms,
                                struct err *e)
{
    memset(out, 0, sizeof *out);
    char path[700];
    char *text = NULL, *bytes = NULL;
    size_t len = 0;
    irr_volume_path(c, key, "json", path, sizeof path);
    enum refract_code rc = io_read_file(path, IRR_MAX_FILE, &text, &len, e);
    cJSON *side = rc == REFRACT_E_OK ? cJSON_Parse(text) : NULL;
    free(text);
    if (rc == REFRACT_E_OK && side == NULL)
        rc = err_set(e, REFRACT_E_STORAGE, "%s is not JSON", path);
    const cJSON *k = side ? cJSON_GetObjectItemCaseSensitive(side, "kind") : NULL;
    *kind = cJSON_IsString(k) && strcmp(k->valuestring, "photons") == 0 ? IRR_KIND_PHOTONS
                                                                          : IRR_KIND_VOLUME;
    irr_volume_path(c, key, *kind == IRR_KIND_PHOTONS ? "pmap" : "exr", path, sizeof path);
    if (rc == REFRACT_E_OK && *kind == IRR_KIND_PHOTONS) {
        rc = irr_photons_read(path, out, e);
        if (rc == REFRACT_E_OK) {
            out->photons->emitted = (long)read_number(side, "photons");
            out->photons->landed = (size_t)read_number(side, "landed");
        }
    } else if (rc == REFRACT_E_OK) {
        rc = io_read_file(path, IRR_MAX_FILE, &bytes, &len, e);
        if (rc == REFRACT_E_OK)
            rc = irradiance_volume_decode_exr(bytes, len, &out->volume, e);
        if (rc == REFRACT_E_OK)
            stats_from_json(cJSON_GetObjectItemCaseSensitive(side, "stats"), &out->volume.stats);
    }
    free(bytes);
    if (rc == REFRACT_E_OK)
        *compute_ms = read_number(side, "compute_ms");
    cJSON_Delete(side);
    return rc;
}

size_t irr_disk_list_pairs(const struct irradiance_cache *c, uint64_t **keys)
{
    *keys = NULL;
    DIR *d = opendir(c->dir);
    if (d == NULL)
        return 0;
    size_t count = 0, cap = 0;
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        const char *n = ent->d_name;
        if (strlen(n) != 21 || strcmp(n + 16, ".json") != 0)
            continue;
        char *end = NULL;
        uint64_t key = strtoull(n, &end, 16);
        char data[700];
        irr_volume_path(c, key, irr_data_ext(c, key), data, sizeof data);
        if (end != n + 16 || access(data, R_OK) != 0)
            continue;
        if (count == cap) {
            size_t grown_cap = cap ? 2 * cap : 64;
            uint64_t *grown = realloc(*keys, grown_cap * sizeof *grown);
            if (grown == NULL)
                break;
            *keys = grown;
            cap = grown_cap;
        }
        (*keys)[count++] = key;
    }
    closedir(d);
    return count;
}
