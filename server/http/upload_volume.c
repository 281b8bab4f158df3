/*
 * upload_volume.c - the volume half of PUT /v1/scenes/{id}/volumes/{name}: the query,
 * the decoding of the streamed body (server/io/io_volume.h: raw, NRRD, OpenEXR) into a
 * canonical blob file, the physical checks against what the scene uses the volume for,
 * and the hand-over to the store. The body is never in memory: server.c streamed it to
 * a file, the decoder maps that file and writes its output in chunks.
 *
 * Physical ranges (value = offset + scale * sample of each layer that names the
 * volume, checked for the volume's min and max): ior 1..5 (no medium here is optically
 * less dense than vacuum; 5 is beyond any transparent material), attenuation and
 * scattering 0..1e5 per world unit, emission 0..1e6, opaque colour 0..1, anisotropy
 * g -0.99..0.99 (Henyey-Greenstein). Volumes that no layer names yet are checked for
 * finite values only; the renderer clamps to the same ranges (scene_field.c) whatever
 * comes later.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "../core/log.h"
#include "../io/io_volume.h"
#include "http_internal.h"

static const double physical_min[SCENE_CH_COUNT] = {1.0, 0.0, 0.0, 0.0, 0.0, -0.99};
static const double physical_max[SCENE_CH_COUNT] = {5.0, 1e5, 1e6, 1.0, 1e5, 0.99};

static bool parse_dims(const char *text, int dims[3])
{
    char *end = NULL;
    for (int a = 0; a < 3; a++) {
        long v = strtol(text, &end, 10);
        if (end == text || v < 1 || v > 1000000)
            return false;
        dims[a] = (int)v;
        if (a < 2) {
            if (*end != ',')
                return false;
            text = end + 1;
        }
    }
    return *end == '\0';
}

static bool parse_real(const char *text, double *out)
{
    char *end = NULL;
    *out = strtod(text, &end);
    return end != text && *end == '\0' && isfinite(*out);
}

static const char *query(struct http_request *req, const char *key)
{
    return MHD_lookup_connection_value(req->conn, MHD_GET_ARGUMENT_KIND, key);
}

/* The format from the query, else from the file's first bytes. */
static bool choose_format(struct http_request *req, enum io_volume_format *f)
{
    const char *text = query(req, "format");
    if (text) {
        if (io_volume_format_parse(text, f))
            return true;
        http_respond_error(req, REFRACT_E_INVALID_FIELD,
                           "query parameter format: expected raw, nrrd or exr, got \"%s\"", text);
        return false;
    }
    unsigned char magic[4] = {0};
    FILE *fp = fopen(req->upload_path, "rb");
    size_t n = fp ? fread(magic, 1, sizeof magic, fp) : 0;
    if (fp)
        fclose(fp);
    *f = n == 4 && memcmp(magic, "NRRD", 4) == 0               ? IO_VOLUME_NRRD
         : n == 4 && memcmp(magic, "\x76\x2f\x31\x01", 4) == 0 ? IO_VOLUME_EXR
                                                               : IO_VOLUME_RAW;
    return true;
}

/* Validates the query into d; answers and returns false on error. A misspelt parameter
 * (?component=3) is an error, not silently the default. */
static bool parse_query(struct http_request *req, struct io_volume_desc *d)
{
    static const char *const allowed[] = {"format", "dims",   "type", "components",
                                          "scale",  "offset", NULL};
    const char *unknown = http_query_unknown(req, allowed);
    if (unknown) {
        http_respond_error(req, REFRACT_E_UNKNOWN_FIELD,
                           "query parameter \"%s\" is not known here; allowed: dims, components, "
                           "type, format, scale, offset",
                           unknown);
        return false;
    }
    *d = (struct io_volume_desc){.scale = 1.0,
                                 .max_resolution = req->cfg->limits.max_resolution,
                                 .max_voxels = req->cfg->limits.max_voxels,
                                 .max_upload_voxels = req->cfg->limits.max_upload_voxels};
    if (!choose_format(req, &d->format))
        return false;
    const char *dims = query(req, "dims"), *type = query(req, "type");
    const char *comps = query(req, "components"), *scale = query(req, "scale");
    const char *offset = query(req, "offset");
    if (dims == NULL && d->format == IO_VOLUME_RAW) {
        http_respond_error(req, REFRACT_E_MISSING_FIELD,
                           "query parameter dims is required for raw volumes, e.g. "
                           "?dims=64,64,64&type=float32 (NRRD and EXR files carry their own)");
        return false;
    }
    if (dims && !parse_dims(dims, d->dims)) {
        http_respond_error(req, REFRACT_E_INVALID_FIELD,
                           "query parameter dims: expected three positive integers X,Y,Z, got "
                           "\"%s\"",
                           dims);
        return false;
    }
    if (type && d->format != IO_VOLUME_RAW) {
        http_respond_error(req, REFRACT_E_INVALID_FIELD,
                           "query parameter type applies to raw volumes only; a %s file says "
                           "its own sample type",
                           io_volume_format_name(d->format));
        return false;
    }
    if (type && !io_sample_type_parse(type, &d->type)) {
        http_respond_error(req, REFRACT_E_INVALID_FIELD,
                           "query parameter type: expected float32, float16, uint8 or uint16, "
                           "got \"%s\"",
                           type);
        return false;
    }
    if (comps && strcmp(comps, "1") != 0 && strcmp(comps, "3") != 0) {
        http_respond_error(req, REFRACT_E_INVALID_FIELD,
                           "query parameter components: expected 1 (scalar) or 3 (RGB), got "
                           "\"%s\"",
                           comps);
        return false;
    }
    d->components = comps ? comps[0] - '0' : 0;
    if ((scale && (!parse_real(scale, &d->scale) || d->scale == 0.0)) ||
        (offset && !parse_real(offset, &d->offset))) {
        http_respond_error(req, REFRACT_E_INVALID_FIELD,
                           "query parameters scale and offset: expected finite numbers (scale "
                           "not 0), got scale=\"%s\" offset=\"%s\"",
                           scale ? scale : "1", offset ? offset : "0");
        return false;
    }
    return true;
}

/* Checks the stored range against every layer of the scene that names the volume. */
static enum refract_code check_physical(const struct scene *sc, const char *name,
                                        const struct io_volume_info *info, struct err *e)
{
    for (size_t i = 0; i < sc->object_count; i++) {
        for (int ch = 0; ch < SCENE_CH_COUNT; ch++) {
            const struct scene_field *f = &sc->objects[i].fields[ch];
            for (size_t k = 0; k < f->count; k++) {
                const struct scene_layer *l = &f->layers[k];
                if (l->kind != SCENE_LAYER_VOLUME || strcmp(l->volume, name) != 0)
                    continue;
                const char *chn = scene_channel_name((enum scene_channel)ch);
                bool scalar = scene_channel_components((enum scene_channel)ch) == 1;
                if (scalar && info->components != 1)
                    return err_set(e, REFRACT_E_INVALID_VOLUME,
                                   "objects[%zu].%s uses volume \"%s\", a scalar channel, but the "
                                   "file holds %d components per voxel; upload 1 component",
                                   i, chn, name, info->components);
                double a = l->volume_offset + l->volume_scale * info->min_all;
                double b = l->volume_offset + l->volume_scale * info->max_all;
                double lo = fmin(a, b), hi = fmax(a, b);
                if (lo < physical_min[ch] || hi > physical_max[ch])
                    return err_set(e, REFRACT_E_INVALID_VOLUME,
                                   "objects[%zu].%s[%zu] uses volume \"%s\": its values %g..%g "
                                   "become %g..%g with the layer's scale %g and offset %g, "
                                   "outside the physical range of %s, %g..%g",
                                   i, chn, k, name, info->min_all, info->max_all, lo, hi,
                                   l->volume_scale, l->volume_offset, chn, physical_min[ch],
                                   physical_max[ch]);
            }
        }
    }
    return REFRACT_E_OK;
}

static void info_to_store(const struct io_volume_info *in, enum io_volume_format format,
                          struct store_upload_info *out)
{
    memset(out, 0, sizeof *out);
    memcpy(out->dims, in->dims, sizeof out->dims);
    out->components = in->components;
    snprintf(out->type, sizeof out->type, "%s", io_sample_type_name(in->source_type));
    snprintf(out->format, sizeof out->format, "%s", io_volume_format_name(format));
    memcpy(out->min, in->min, sizeof out->min);
    memcpy(out->max, in->max, sizeof out->max);
    out->min_all = in->min_all;
    out->max_all = in->max_all;
    out->checksum = in->fnv1a64;
    snprintf(out->sha256, sizeof out->sha256, "%s", in->sha256);
    out->bytes = in->bytes;
    out->created_unix = (int64_t)time(NULL);
}

bool http_volume_upload(struct http_request *req, const char *name, struct store_volume **out,
                        enum MHD_Result *answer)
{
    *out = NULL;
    *answer = MHD_YES;
    struct io_volume_desc d;
    if (!parse_query(req, &d))
        return false;
    struct store_scene *v = http_scene_or_404(req, answer);
    if (v == NULL)
        return false;
    struct err e = {0};
    char blob_path[1024];
    int fd = store_upload_tmp_create(req->app->store, blob_path, sizeof blob_path, &e);
    struct io_volume_info info;
    bool canonical = false;
    double t0 = gpu_time_ms();
    enum refract_code rc =
        fd < 0 ? e.code : io_volume_decode(req->upload_path, &d, fd, &info, &canonical, &e);
    if (fd >= 0)
        close(fd);
    if (rc == REFRACT_E_OK)
        rc = check_physical(v->scene, name, &info, &e);
    store_scene_release(v);
    if (rc == REFRACT_E_OK && canonical) {
        /* The upload is the blob: keep the file and the hash taken as it arrived. */
        snprintf(info.sha256, sizeof info.sha256, "%s", req->upload_sha256);
        unlink(blob_path);
        snprintf(blob_path, sizeof blob_path, "%s", req->upload_path);
        req->upload_path[0] = '\0';
    } else if (fd >= 0 && rc != REFRACT_E_OK) {
        unlink(blob_path);
    }
    double t1 = gpu_time_ms();
    if (rc == REFRACT_E_OK) {
        struct store_upload_info stored;
        info_to_store(&info, d.format, &stored);
        rc = store_volume_put_file(req->app->store, req->params[0], name, &stored, blob_path, out,
                                   &e);
    }
    /* Where an upload's time goes (BENCHMARKS.md): receiving is from the request's start
     * to t0, decoding t0..t1, storing (fsync, rename, commit) after. */
    if (rc == REFRACT_E_OK)
        log_info("http",
                 "volume %s: %zu bytes received in %.0f ms, decoded in %.0f ms, stored in "
                 "%.0f ms",
                 name, req->body_len, t0 - req->started_ms, t1 - t0, gpu_time_ms() - t1);
    if (rc != REFRACT_E_OK) {
        *answer = http_respond_err(req, &e);
        return false;
    }
    return true;
}

cJSON *http_volume_json(const struct store_volume *vol)
{
    const struct store_upload_info *in = &vol->info;
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "name", vol->name);
    cJSON_AddStringToObject(root, "format", in->format);
    cJSON_AddStringToObject(root, "type", in->type);
    cJSON_AddItemToObject(root, "dims", cJSON_CreateIntArray(in->dims, 3));
    cJSON_AddNumberToObject(root, "components", in->components);
    cJSON_AddNumberToObject(root, "bytes", (double)in->bytes);
    cJSON_AddNumberToObject(root, "min", in->min_all);
    cJSON_AddNumberToObject(root, "max", in->max_all);
    cJSON_AddItemToObject(root, "component_min", cJSON_CreateDoubleArray(in->min, in->components));
    cJSON_AddItemToObject(root, "component_max", cJSON_CreateDoubleArray(in->max, in->components));
    char sum[24];
    snprintf(sum, sizeof sum, "%016llx", (unsigned long long)in->checksum);
    cJSON_AddStringToObject(root, "checksum_fnv1a64", sum);
    cJSON_AddStringToObject(root, "sha256", in->sha256);
    return root;
}
