/*
 * volume_nrrd.c - NRRD volumes (teem's "nearly raw raster data", the format of 3D
 * Slicer, ITK and unu) with attached data, raw or gzip-encoded.
 *
 * Read: the magic "NRRD0001".."NRRD0005"; type (uchar/uint8, ushort/uint16, float,
 * double, with the spec's synonyms); dimension 3 (sizes X Y Z, scalar) or 4 (sizes C X Y
 * Z with C = 1 or 3, the components axis first as in RGB volumes); sizes; endian (little
 * or big; required for samples wider than a byte); encoding raw, or gzip/gz (zlib,
 * streamed). Accepted and not used: space and the other geometry and annotation
 * fields (spacings, space directions, space origin, kinds, ...), comments (#) and
 * key:=value pairs. Refused with a message: detached data ("data file"), line or byte
 * skips, other encodings and types, and any field the spec does not define (a typo
 * must not pass silently). The data must hold exactly what sizes and type say: fewer
 * bytes is a truncated file, more is a header that lies.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <zlib.h>

#include "volume_internal.h"

#define NRRD_MAX_HEADER (64 * 1024)
#define NRRD_INFLATE_CHUNK (256 * 1024)

struct nrrd_header {
    enum io_sample_type type;
    bool has_type, has_dimension, has_sizes, has_encoding, has_endian;
    int dimension;
    long long sizes[4];
    bool gzip, big_endian;
};

static const char *const ignored_fields[] = {"space",
                                             "space dimension",
                                             "space directions",
                                             "space origin",
                                             "space units",
                                             "measurement frame",
                                             "spacings",
                                             "thicknesses",
                                             "axis mins",
                                             "axismins",
                                             "axis maxs",
                                             "axismaxs",
                                             "centers",
                                             "centerings",
                                             "labels",
                                             "units",
                                             "kinds",
                                             "content",
                                             "min",
                                             "max",
                                             "old min",
                                             "oldmin",
                                             "old max",
                                             "oldmax",
                                             "sample units",
                                             "sampleunits",
                                             "block size",
                                             "blocksize",
                                             "number",
                                             NULL};

static bool parse_type(const char *v, enum io_sample_type *t)
{
    static const struct {
        const char *name;
        enum io_sample_type type;
    } types[] = {{"uchar", IO_SAMPLE_UINT8},
                 {"unsigned char", IO_SAMPLE_UINT8},
                 {"uint8", IO_SAMPLE_UINT8},
                 {"uint8_t", IO_SAMPLE_UINT8},
                 {"ushort", IO_SAMPLE_UINT16},
                 {"unsigned short", IO_SAMPLE_UINT16},
                 {"unsigned short int", IO_SAMPLE_UINT16},
                 {"uint16", IO_SAMPLE_UINT16},
                 {"uint16_t", IO_SAMPLE_UINT16},
                 {"float", IO_SAMPLE_FLOAT32},
                 {"double", IO_SAMPLE_FLOAT64}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++) {
        if (strcmp(v, types[i].name) == 0) {
            *t = types[i].type;
            return true;
        }
    }
    return false;
}

static enum refract_code parse_field(struct nrrd_header *h, const char *key, const char *v,
                                     struct err *e)
{
    if (strcmp(key, "type") == 0) {
        if (!parse_type(v, &h->type))
            return err_set(e, REFRACT_E_INVALID_VOLUME,
                           "NRRD type \"%s\" is not accepted; use uchar (uint8), ushort "
                           "(uint16), float or double",
                           v);
        h->has_type = true;
    } else if (strcmp(key, "dimension") == 0) {
        if (sscanf(v, "%d", &h->dimension) != 1 || (h->dimension != 3 && h->dimension != 4))
            return err_set(e, REFRACT_E_INVALID_VOLUME,
                           "NRRD dimension \"%s\": expected 3 (X Y Z) or 4 (components X Y Z)", v);
        h->has_dimension = true;
    } else if (strcmp(key, "sizes") == 0) {
        if (!h->has_dimension)
            return err_set(e, REFRACT_E_INVALID_VOLUME,
                           "NRRD sizes comes before dimension; the spec wants dimension first");
        const char *p = v;
        for (int i = 0; i < h->dimension; i++) {
            char *end = NULL;
            h->sizes[i] = strtoll(p, &end, 10);
            if (end == p || h->sizes[i] < 1 || h->sizes[i] > 1000000)
                return err_set(e, REFRACT_E_INVALID_VOLUME,
                               "NRRD sizes \"%s\": expected %d positive integers", v, h->dimension);
            p = end;
        }
        while (*p == ' ' || *p == '\t')
            p++;
        if (*p != '\0')
            return err_set(e, REFRACT_E_INVALID_VOLUME,
                           "NRRD sizes \"%s\": expected exactly %d integers (dimension %d)", v,
                           h->dimension, h->dimension);
        h->has_sizes = true;
    } else if (strcmp(key, "endian") == 0) {
        if (strcmp(v, "little") != 0 && strcmp(v, "big") != 0)
            return err_set(e, REFRACT_E_INVALID_VOLUME,
                           "NRRD endian \"%s\": expected little or big", v);
        h->big_endian = strcmp(v, "big") == 0;
        h->has_endian = true;
    } else if (strcmp(key, "encoding") == 0) {
        if (strcmp(v, "raw") == 0)
            h->gzip = false;
        else if (strcmp(v, "gzip") == 0 || strcmp(v, "gz") == 0)
            h->gzip = true;
        else
            return err_set(e, REFRACT_E_INVALID_VOLUME,
                           "NRRD encoding \"%s\" is not accepted; use raw or gzip", v);
        h->has_encoding = true;
    } else if (strcmp(key, "data file") == 0 || strcmp(key, "datafile") == 0) {
        return err_set(e, REFRACT_E_INVALID_VOLUME,
                       "NRRD \"data file: %s\": detached data files are not accepted; send one "
                       ".nrrd file with the data attached (e.g. unu save -f nrrd -e gzip)",
                       v);
    } else if (strcmp(key, "line skip") == 0 || strcmp(key, "lineskip") == 0 ||
               strcmp(key, "byte skip") == 0 || strcmp(key, "byteskip") == 0) {
        if (strcmp(v, "0") != 0)
            return err_set(e, REFRACT_E_INVALID_VOLUME,
                           "NRRD \"%s: %s\" is not accepted; the data must follow the header's "
                           "blank line",
                           key, v);
    } else {
        for (const char *const *f = ignored_fields; *f; f++)
            if (strcmp(key, *f) == 0)
                return REFRACT_E_OK;
        return err_set(e, REFRACT_E_INVALID_VOLUME,
                       "NRRD field \"%s\" is not a field of the NRRD format (a typo?); fields "
                       "read: type, dimension, sizes, endian, encoding; space and the geometry "
                       "fields are accepted and not used",
                       key);
    }
    return REFRACT_E_OK;
}

/* Parses the header; *data_offset is the first byte after its blank line. */
static enum refract_code parse_header(const unsigned char *src, size_t len, struct nrrd_header *h,
                                      size_t *data_offset, struct err *e)
{
    if (len < 9 || memcmp(src, "NRRD000", 7) != 0 || src[7] < '1' || src[7] > '5')
        return err_set(e, REFRACT_E_INVALID_VOLUME,
                       "not a NRRD file: it must begin with \"NRRD0001\" .. \"NRRD0005\"; for raw "
                       "samples use ?format=raw");
    size_t pos = 0, limit = len < NRRD_MAX_HEADER ? len : NRRD_MAX_HEADER;
    char line[1024];
    for (int lineno = 1;; lineno++) {
        size_t end = pos;
        while (end < limit && src[end] != '\n')
            end++;
        if (end == limit)
            return err_set(e, REFRACT_E_INVALID_VOLUME,
                           "NRRD header: no blank line ending the header in the first %zu bytes "
                           "(truncated, or not a NRRD file)",
                           limit);
        size_t n = end - pos;
        if (n > 0 && src[end - 1] == '\r')
            n--;
        if (n >= sizeof line)
            return err_set(e, REFRACT_E_INVALID_VOLUME, "NRRD header line %d is too long", lineno);
        memcpy(line, src + pos, n);
        line[n] = '\0';
        pos = end + 1;
        if (lineno == 1)
            continue; /* the magic */
        if (n == 0)
            break;
        if (line[0] == '#' || strstr(line, ":=") != NULL)
            continue;
        char *colon = strstr(line, ": ");
        if (colon == NULL)
            return err_set(e, REFRACT_E_INVALID_VOLUME,
                           "NRRD header line %d \"%s\": expected \"field: value\"", lineno, line);
        *colon = '\0';
        enum refract_code rc = parse_field(h, line, colon + 2, e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    const char *missing = !h->has_type                                          ? "type"
                          : !h->has_dimension                                   ? "dimension"
                          : !h->has_sizes                                       ? "sizes"
                          : !h->has_encoding                                    ? "encoding"
                          : (!h->has_endian && volume_sample_size(h->type) > 1) ? "endian"
                                                                                : NULL;
    if (missing)
        return err_set(e, REFRACT_E_INVALID_VOLUME,
                       "NRRD header: the required field \"%s\" is "
                       "missing",
                       missing);
    *data_offset = pos;
    return REFRACT_E_OK;
}

static enum refract_code inflate_into(const unsigned char *in, size_t in_len, size_t expected,
                                      const struct nrrd_header *h, struct volume_sink *sink,
                                      struct err *e)
{
    size_t size = volume_sample_size(h->type);
    unsigned char *out = malloc(NRRD_INFLATE_CHUNK);
    if (out == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory inflating a NRRD volume");
    z_stream z = {0};
    /* 15 + 32: a zlib or a gzip stream, detected from its header. */
    if (inflateInit2(&z, 15 + 32) != Z_OK) {
        free(out);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "zlib could not start inflating");
    }
    enum refract_code rc = REFRACT_E_OK;
    size_t have = 0, total = 0;
    int zr = Z_OK;
    while (rc == REFRACT_E_OK && zr != Z_STREAM_END) {
        /* zlib counts in uInt: feed at most 1 GiB at a time. */
        if (z.avail_in == 0 && in_len > 0) {
            size_t take = in_len < (1u << 30) ? in_len : (1u << 30);
            z.next_in = (Bytef *)in;
            z.avail_in = (uInt)take;
            in += take;
            in_len -= take;
        }
        z.next_out = out + have;
        z.avail_out = (uInt)(NRRD_INFLATE_CHUNK - have);
        zr = inflate(&z, Z_NO_FLUSH);
        if (zr == Z_BUF_ERROR && z.avail_in == 0 && in_len == 0) {
            rc = err_set(e, REFRACT_E_INVALID_VOLUME,
                         "NRRD gzip data ends after %zu of the %zu bytes the header's sizes and "
                         "type call for (truncated file?)",
                         total + (NRRD_INFLATE_CHUNK - have - z.avail_out), expected);
            break;
        }
        if (zr != Z_OK && zr != Z_STREAM_END && zr != Z_BUF_ERROR) {
            rc = err_set(e, REFRACT_E_INVALID_VOLUME,
                         "NRRD gzip data is corrupt after %lu compressed bytes: %s",
                         (unsigned long)z.total_in, z.msg ? z.msg : "inflate failed");
            break;
        }
        size_t produced = NRRD_INFLATE_CHUNK - have - z.avail_out;
        total += produced;
        if (total > expected) {
            rc = err_set(e, REFRACT_E_INVALID_VOLUME,
                         "NRRD gzip data holds more than the %zu bytes the header's sizes and "
                         "type call for (the header does not describe the data)",
                         expected);
            break;
        }
        size_t all = have + produced, whole = all / size * size;
        rc = volume_sink_put_bytes(sink, h->type, h->big_endian, out, whole / size, e);
        memmove(out, out + whole, all - whole);
        have = all - whole;
    }
    if (rc == REFRACT_E_OK && total != expected)
        rc = err_set(e, REFRACT_E_INVALID_VOLUME,
                     "NRRD gzip data holds %zu bytes but the header's sizes and type call for "
                     "%zu (truncated file, or a header that lies)",
                     total, expected);
    else if (rc == REFRACT_E_OK && (z.avail_in > 0 || in_len > 0))
        rc = err_set(e, REFRACT_E_INVALID_VOLUME,
                     "NRRD: %zu bytes follow the end of the gzip stream; the file must end there",
                     (size_t)z.avail_in + in_len);
    inflateEnd(&z);
    free(out);
    return rc;
}

enum refract_code volume_decode_nrrd(const unsigned char *src, size_t len,
                                     const struct io_volume_desc *d, struct volume_sink *sink,
                                     struct io_volume_info *info, struct err *e)
{
    struct nrrd_header h = {0};
    size_t offset = 0;
    enum refract_code rc = parse_header(src, len, &h, &offset, e);
    if (rc != REFRACT_E_OK)
        return rc;
    int first = h.dimension == 4 ? 1 : 0;
    int comps = h.dimension == 4 ? (int)h.sizes[0] : 1;
    int dims[3] = {(int)h.sizes[first], (int)h.sizes[first + 1], (int)h.sizes[first + 2]};
    rc = volume_check_dims(d, dims, comps, "NRRD sizes", e);
    if (rc != REFRACT_E_OK)
        return rc;
    if (d->components && d->components != comps)
        return err_set(e, REFRACT_E_INVALID_VOLUME,
                       "the query says components=%d but the NRRD file holds %d per voxel",
                       d->components, comps);
    if (d->dims[0] && memcmp(d->dims, dims, sizeof dims) != 0)
        return err_set(e, REFRACT_E_INVALID_VOLUME,
                       "the query says dims=%d,%d,%d but the NRRD sizes are %d %d %d", d->dims[0],
                       d->dims[1], d->dims[2], dims[0], dims[1], dims[2]);
    size_t expected =
        (size_t)dims[0] * dims[1] * dims[2] * (size_t)comps * volume_sample_size(h.type);
    volume_sink_init(sink, sink->fd, dims, comps, d->scale, d->offset);
    info->source_type = h.type;
    const unsigned char *data = src + offset;
    size_t data_len = len - offset;
    if (h.gzip) {
        rc = inflate_into(data, data_len, expected, &h, sink, e);
    } else if (data_len != expected) {
        rc = err_set(e, REFRACT_E_INVALID_VOLUME,
                     data_len < expected
                         ? "NRRD raw data has %zu bytes but the header's sizes and type call for "
                           "%zu (truncated file?)"
                         : "NRRD raw data has %zu bytes but the header's sizes and type call for "
                           "%zu (the header does not describe the data)",
                     data_len, expected);
    } else {
        rc = volume_sink_put_bytes(sink, h.type, h.big_endian, data,
                                   expected / volume_sample_size(h.type), e);
    }
    if (rc == REFRACT_E_OK)
        rc = volume_sink_finish(sink, info, e);
    return rc;
}
