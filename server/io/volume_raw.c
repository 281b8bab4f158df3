/*
 * volume_raw.c - io_volume_decode (mapping the source file, choosing the decoder) and
 * the raw format: dims, type and components come from the query, samples are
 * little-endian, x fastest. See io_volume.h.
 */
#include <stdlib.h>
#include <string.h>

#include "io_files.h"
#include "volume_internal.h"

static const char *const type_names[] = {"float32", "float16", "uint8",
                                         "uint16",  "float64", "uint32"};
static const char *const format_names[] = {"raw", "nrrd", "exr"};

const char *io_sample_type_name(enum io_sample_type t)
{
    return (unsigned)t < sizeof type_names / sizeof type_names[0] ? type_names[t] : "unknown";
}

bool io_sample_type_parse(const char *text, enum io_sample_type *out)
{
    /* float64 and uint32 exist for NRRD and EXR files, not for raw uploads. */
    for (int t = 0; t <= IO_SAMPLE_UINT16; t++) {
        if (strcmp(text, type_names[t]) == 0) {
            *out = (enum io_sample_type)t;
            return true;
        }
    }
    return false;
}

const char *io_volume_format_name(enum io_volume_format f)
{
    return (unsigned)f < 3 ? format_names[f] : "unknown";
}

bool io_volume_format_parse(const char *text, enum io_volume_format *out)
{
    for (int f = 0; f < 3; f++) {
        if (strcmp(text, format_names[f]) == 0) {
            *out = (enum io_volume_format)f;
            return true;
        }
    }
    return false;
}

enum refract_code volume_decode_raw(const unsigned char *src, size_t len,
                                    const struct io_volume_desc *d, struct volume_sink *sink,
                                    struct io_volume_info *info, struct err *e)
{
    int comps = d->components ? d->components : 1;
    enum refract_code rc = volume_check_dims(d, d->dims, comps, "query parameter dims", e);
    if (rc != REFRACT_E_OK)
        return rc;
    size_t size = volume_sample_size(d->type);
    size_t count = (size_t)d->dims[0] * (size_t)d->dims[1] * (size_t)d->dims[2] * (size_t)comps;
    if (len != count * size)
        return err_set(e, REFRACT_E_INVALID_VOLUME,
                       "the body has %zu bytes but dims=%d,%d,%d with %d component(s) of %s "
                       "need %zu; check dims, components, type and the file",
                       len, d->dims[0], d->dims[1], d->dims[2], comps, io_sample_type_name(d->type),
                       count * size);
    volume_sink_init(sink, sink->fd, d->dims, comps, d->scale, d->offset);
    rc = volume_sink_put_bytes(sink, d->type, false, src, count, e);
    if (rc == REFRACT_E_OK)
        rc = volume_sink_finish(sink, info, e);
    info->source_type = d->type;
    return rc;
}

enum refract_code io_volume_decode(const char *src_path, const struct io_volume_desc *d, int dst_fd,
                                   struct io_volume_info *info, bool *source_is_canonical,
                                   struct err *e)
{
    memset(info, 0, sizeof *info);
    *source_is_canonical = d->format == IO_VOLUME_RAW && d->type == IO_SAMPLE_FLOAT32 &&
                           d->scale == 1.0 && d->offset == 0.0;
    const unsigned char *src = NULL;
    size_t len = 0;
    enum refract_code rc = io_map_file(src_path, (const void **)&src, &len, e);
    if (rc != REFRACT_E_OK)
        return rc;
    /* 1 MiB of output buffer: on the heap, never on an HTTP thread's stack. */
    struct volume_sink *sink = malloc(sizeof *sink);
    if (sink == NULL) {
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory decoding a volume");
    } else {
        sink->fd = *source_is_canonical ? -1 : dst_fd;
        switch (d->format) {
        case IO_VOLUME_RAW:
            rc = volume_decode_raw(src, len, d, sink, info, e);
            break;
        case IO_VOLUME_NRRD:
            rc = volume_decode_nrrd(src, len, d, sink, info, e);
            break;
        case IO_VOLUME_EXR:
            rc = volume_decode_exr(src, len, d, sink, info, e);
            break;
        }
    }
    free(sink);
    io_unmap_file(src, len);
    return rc;
}
