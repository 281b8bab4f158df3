/*
 * volume_sink.c - the end of every volume decoder: each sample is scaled, checked for
 * being finite, folded into the per-component range and the two hashes, and written in
 * 1 MiB chunks as little-endian float32. See volume_internal.h.
 */
#include <errno.h>
#include <math.h>
#include <string.h>
#include <unistd.h>

#include "volume_internal.h"

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the canonical volume blob is little-endian float32, which refractd maps directly"
#endif

uint64_t io_fnv1a64_update(uint64_t h, const void *data, size_t len)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < len; i++) {
        h ^= p[i];
        h *= 1099511628211ull; /* FNV-1a 64 prime */
    }
    return h;
}

void volume_sink_init(struct volume_sink *s, int fd, const int dims[3], int components,
                      double scale, double offset)
{
    s->fd = fd;
    s->scale = scale;
    s->offset = offset;
    s->components = components;
    memcpy(s->dims, dims, sizeof s->dims);
    s->expected = (size_t)dims[0] * (size_t)dims[1] * (size_t)dims[2] * (size_t)components;
    s->written = 0;
    s->used = 0;
    s->comp = 0;
    sha256_init(&s->sha);
    s->fnv = IO_FNV1A64_INIT;
    for (int c = 0; c < 3; c++) {
        s->min[c] = INFINITY;
        s->max[c] = -INFINITY;
    }
}

static enum refract_code flush(struct volume_sink *s, struct err *e)
{
    size_t bytes = s->used * sizeof(float);
    sha256_update(&s->sha, s->buf, bytes);
    s->fnv = io_fnv1a64_update(s->fnv, s->buf, bytes);
    const char *p = (const char *)s->buf;
    while (s->fd >= 0 && bytes > 0) {
        ssize_t n = write(s->fd, p, bytes);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            return err_set(e, REFRACT_E_STORAGE,
                           "writing the volume to the data directory failed: %s (disk full?)",
                           n < 0 ? strerror(errno) : "short write");
        p += n;
        bytes -= (size_t)n;
    }
    s->written += s->used;
    s->used = 0;
    return REFRACT_E_OK;
}

static enum refract_code bad_value(const struct volume_sink *s, double sample, struct err *e)
{
    size_t index = s->written + s->used;
    size_t voxel = index / (size_t)s->components;
    size_t sx = (size_t)s->dims[0], sy = (size_t)s->dims[1];
    return err_set(e, REFRACT_E_INVALID_VOLUME,
                   "value %zu (voxel x=%zu y=%zu z=%zu, component %zu) is %s; volumes must "
                   "hold finite values that fit in float32 after scale and offset",
                   index, voxel % sx, (voxel / sx) % sy, voxel / (sx * sy),
                   index % (size_t)s->components,
                   isnan(sample) ? "NaN" : (isinf(sample) ? "infinite" : "out of float32 range"));
}

/* The hot loop of every decoder (16M calls for a 256^3 volume): no division, the
 * component cycles with a counter. */
enum refract_code volume_sink_put(struct volume_sink *s, double sample, struct err *e)
{
    if (s->written + s->used >= s->expected)
        return err_set(e, REFRACT_E_INVALID_VOLUME,
                       "the file holds more than the %zu values its dimensions %d x %d x %d "
                       "with %d component(s) call for",
                       s->expected, s->dims[0], s->dims[1], s->dims[2], s->components);
    float f = (float)(s->offset + s->scale * sample);
    if (!isfinite(f))
        return bad_value(s, sample, e);
    int c = s->comp;
    if (f < s->min[c])
        s->min[c] = f;
    if (f > s->max[c])
        s->max[c] = f;
    s->comp = c + 1 == s->components ? 0 : c + 1;
    s->buf[s->used++] = f;
    if (s->used == VOLUME_SINK_FLOATS)
        return flush(s, e);
    return REFRACT_E_OK;
}

enum refract_code volume_sink_finish(struct volume_sink *s, struct io_volume_info *info,
                                     struct err *e)
{
    enum refract_code rc = flush(s, e);
    if (rc != REFRACT_E_OK)
        return rc;
    if (s->written != s->expected)
        return err_set(e, REFRACT_E_INVALID_VOLUME,
                       "the file ends after %zu of the %zu values its dimensions %d x %d x %d "
                       "with %d component(s) call for (truncated?)",
                       s->written, s->expected, s->dims[0], s->dims[1], s->dims[2], s->components);
    memcpy(info->dims, s->dims, sizeof info->dims);
    info->components = s->components;
    info->min_all = INFINITY;
    info->max_all = -INFINITY;
    for (int c = 0; c < 3; c++) {
        info->min[c] = c < s->components ? s->min[c] : 0.0;
        info->max[c] = c < s->components ? s->max[c] : 0.0;
        if (c < s->components) {
            info->min_all = fmin(info->min_all, s->min[c]);
            info->max_all = fmax(info->max_all, s->max[c]);
        }
    }
    info->fnv1a64 = s->fnv;
    info->bytes = s->expected * sizeof(float);
    if (s->fd >= 0)
        sha256_final_hex(&s->sha, info->sha256);
    else
        info->sha256[0] = '\0';
    return REFRACT_E_OK;
}

size_t volume_sample_size(enum io_sample_type t)
{
    switch (t) {
    case IO_SAMPLE_UINT8:
        return 1;
    case IO_SAMPLE_FLOAT16:
    case IO_SAMPLE_UINT16:
        return 2;
    case IO_SAMPLE_FLOAT32:
    case IO_SAMPLE_UINT32:
        return 4;
    case IO_SAMPLE_FLOAT64:
        return 8;
    }
    return 4;
}

/* IEEE 754 binary16 -> binary32, exactly (every half is a float). */
float volume_half_to_float(uint16_t h)
{
    int sign = (h >> 15) & 1, exponent = (h >> 10) & 0x1f, mantissa = h & 0x3ff;
    float v;
    if (exponent == 0)
        v = ldexpf((float)mantissa, -24); /* zero or subnormal */
    else if (exponent == 31)
        v = mantissa ? NAN : INFINITY;
    else
        v = ldexpf((float)(mantissa | 0x400), exponent - 25);
    return sign ? -v : v;
}

static uint64_t load_le(const unsigned char *p, size_t n, bool big_endian)
{
    uint64_t u = 0;
    for (size_t i = 0; i < n; i++)
        u |= (uint64_t)p[big_endian ? n - 1 - i : i] << (8 * i);
    return u;
}

enum refract_code volume_sink_put_bytes(struct volume_sink *s, enum io_sample_type t,
                                        bool big_endian, const unsigned char *bytes, size_t n,
                                        struct err *e)
{
    if (t == IO_SAMPLE_FLOAT32 && !big_endian) { /* the common case, without byte loads */
        for (size_t i = 0; i < n; i++) {
            float f;
            memcpy(&f, bytes + 4 * i, 4);
            enum refract_code rc = volume_sink_put(s, f, e);
            if (rc != REFRACT_E_OK)
                return rc;
        }
        return REFRACT_E_OK;
    }
    size_t size = volume_sample_size(t);
    for (size_t i = 0; i < n; i++) {
        uint64_t u = load_le(bytes + i * size, size, big_endian);
        double v;
        switch (t) {
        case IO_SAMPLE_FLOAT32: {
            uint32_t w = (uint32_t)u;
            float f;
            memcpy(&f, &w, 4);
            v = f;
            break;
        }
        case IO_SAMPLE_FLOAT64:
            memcpy(&v, &u, 8);
            break;
        case IO_SAMPLE_FLOAT16:
            v = volume_half_to_float((uint16_t)u);
            break;
        default:
            v = (double)u;
            break;
        }
        enum refract_code rc = volume_sink_put(s, v, e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    return REFRACT_E_OK;
}

enum refract_code volume_check_dims(const struct io_volume_desc *d, const int dims[3],
                                    int components, const char *where, struct err *e)
{
    for (int a = 0; a < 3; a++) {
        if (dims[a] < 1)
            return err_set(e, REFRACT_E_INVALID_VOLUME, "%s: size %d along %c is not positive",
                           where, dims[a], "xyz"[a]);
        if (d->max_resolution > 0 && dims[a] > d->max_resolution)
            return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                           "%s: %d voxels along %c exceed the limit of %d (refractd "
                           "--max-resolution)",
                           where, dims[a], "xyz"[a], d -> max_resolution);
    }
    long long voxels = (long long)dims[0] * dims[1] * dims[2];
    /* Checked from the header, before a byte is decoded; a gzip stream that inflates past
     * what the header says is stopped as it streams (volume_nrrd.c, inflate_into). */
    if (d->max_upload_voxels > 0 && voxels > d->max_upload_voxels)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "%s: %d x %d x %d = %lld voxels exceed the limit of %lld decoded voxels "
                       "per upload (max_upload_voxels; refractd --max-upload-voxels)",
                       where, dims[0], dims[1], dims[2], voxels, d->max_upload_voxels);
    if (d->max_voxels > 0 && voxels > d->max_voxels)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "%s: %lld voxels exceed the limit of %lld (refractd --max-voxels)", where,
                       voxels, d->max_voxels);
    if (components != 1 && components != 3)
        return err_set(e, REFRACT_E_INVALID_VOLUME,
                       "%s: %d components per voxel; volumes hold 1 (scalar) or 3 (RGB)", where,
                       components);
    return REFRACT_E_OK;
}
