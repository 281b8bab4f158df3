/*
 * volume_exr.c - OpenEXR volumes, read with OpenEXR's C API from the mapped upload:
 *   - a multi-part file is one slice per part: part z is slice z, every part X x Y
 *     pixels with the same channels, so dims are (X, Y, parts);
 *   - a single-part file is a slice atlas: width X, height Y*Z, slice z in rows
 *     z*Y .. z*Y+Y-1 (the layout of the irradiance EXRs, docs/api.md); Z is not in the
 *     file, so the query's dims=X,Y,Z are required and checked against it.
 * Channels: R, G, B for 3 components (the default when the file has them); for 1
 * component Y, else the file's only channel. HALF, FLOAT and UINT channels are
 * converted to float32 by the library's decoder; subsampled channels, tiled and deep
 * parts are refused. Decoding goes one chunk (1..256 scanlines) at a time into the
 * sink, in the canonical order, so the volume is never whole in memory.
 */
#include <openexr.h>
#include <stdlib.h>
#include <string.h>

#include "exr_mem.h"
#include "volume_internal.h"

static enum refract_code fail(struct exr_mem_src *s, exr_result_t rv, const char *what)
{
    if (!s->have_error) {
        s->have_error = true;
        err_set(s->e,
                rv == EXR_ERR_OUT_OF_MEMORY ? REFRACT_E_OUT_OF_MEMORY : REFRACT_E_INVALID_VOLUME,
                "EXR volume: %s failed: %s (truncated or corrupt file?)", what,
                exr_get_default_error_message(rv));
    }
    return s->e->code;
}

static bool has_channel(const exr_attr_chlist_t *chl, const char *name)
{
    for (int i = 0; i < chl->num_channels; i++)
        if (strcmp(chl->entries[i].name.str, name) == 0)
            return true;
    return false;
}

/* Chooses the channels of part 0 for the requested components (0 = from the file). */
static enum refract_code choose_channels(const exr_attr_chlist_t *chl, int want,
                                         const char *names[3], int *comps, struct err *e)
{
    bool rgb = has_channel(chl, "R") && has_channel(chl, "G") && has_channel(chl, "B");
    if (want == 3 || (want == 0 && rgb)) {
        if (!rgb)
            return err_set(e, REFRACT_E_INVALID_VOLUME,
                           "EXR volume: components=3 needs channels R, G and B");
        names[0] = "R";
        names[1] = "G";
        names[2] = "B";
        *comps = 3;
    } else if (has_channel(chl, "Y")) {
        names[0] = "Y";
        *comps = 1;
    } else if (chl->num_channels == 1) {
        names[0] = chl->entries[0].name.str;
        *comps = 1;
    } else {
        return err_set(e, REFRACT_E_INVALID_VOLUME,
                       "EXR volume: %d channels and none named Y; a scalar volume has channel Y "
                       "(or a single channel), an RGB one R, G, B",
                       chl->num_channels);
    }
    for (int c = 0; c < *comps; c++) {
        for (int i = 0; i < chl->num_channels; i++) {
            const exr_attr_chlist_entry_t *ce = &chl->entries[i];
            if (strcmp(ce->name.str, names[c]) == 0 && (ce->x_sampling != 1 || ce->y_sampling != 1))
                return err_set(e, REFRACT_E_INVALID_VOLUME,
                               "EXR volume: channel %s is subsampled; every channel must be "
                               "full resolution",
                               names[c]);
        }
    }
    return REFRACT_E_OK;
}

struct part_shape {
    int width, height, y0;
};

static enum refract_code part_shape(exr_context_t ctxt, int part, struct part_shape *ps,
                                    struct exr_mem_src *s)
{
    exr_storage_t storage;
    exr_attr_box2i_t dw;
    exr_result_t rv = exr_get_storage(ctxt, part, &storage);
    if (rv != EXR_ERR_SUCCESS)
        return fail(s, rv, "reading a part's storage");
    if (storage != EXR_STORAGE_SCANLINE)
        return err_set(s->e, REFRACT_E_INVALID_VOLUME,
                       "EXR volume: part %d is tiled or deep; only scanline parts are read", part);
    if ((rv = exr_get_data_window(ctxt, part, &dw)) != EXR_ERR_SUCCESS)
        return fail(s, rv, "reading a part's data window");
    long long w = (long long)dw.max.x - dw.min.x + 1, h = (long long)dw.max.y - dw.min.y + 1;
    if (w < 1 || h < 1 || w > 1000000 || h > 1000000000)
        return err_set(s->e, REFRACT_E_INVALID_VOLUME, "EXR volume: part %d is %lld x %lld pixels",
                       part, w, h);
    ps->width = (int)w;
    ps->height = (int)h;
    ps->y0 = dw.min.y;
    return REFRACT_E_OK;
}

static int wanted(const char *const names[3], int comps, const char *name)
{
    for (int c = 0; c < comps; c++)
        if (strcmp(names[c], name) == 0)
            return c;
    return -1;
}

/* Decodes all rows of one part into the sink, chunk by chunk. */
static enum refract_code read_part(exr_context_t ctxt, int part, const struct part_shape *ps,
                                   const char *const names[3], int comps, struct volume_sink *sink,
                                   struct exr_mem_src *s)
{
    int32_t lines = 0;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, part, &lines);
    if (rv != EXR_ERR_SUCCESS || lines < 1 || lines > 256)
        return fail(s, rv, "exr_get_scanlines_per_chunk");
    const exr_attr_chlist_t *chl = NULL;
    if (exr_get_channels(ctxt, part, &chl) != EXR_ERR_SUCCESS || chl == NULL)
        return err_set(s->e, REFRACT_E_INVALID_VOLUME, "EXR volume: part %d has no channels", part);
    for (int c = 0; c < comps; c++)
        if (!has_channel(chl, names[c]))
            return err_set(s->e, REFRACT_E_INVALID_VOLUME,
                           "EXR volume: part %d lacks channel %s, which part 0 has", part,
                           names[c]);
    size_t row_floats = (size_t)ps->width * (size_t)comps;
    float *buf = malloc(row_floats * (size_t)lines * sizeof *buf);
    /* Channels the volume does not use are decoded into a scratch row block rather than
     * skipped with a NULL destination: Debian 12's OpenEXRCore 3.1 writes through a NULL
     * decode_to_ptr in some unpackers (found by fuzz_exr: a B44A file with an unused
     * channel crashed the reader, docs/fuzzing.md). */
    float *scratch = malloc((size_t)ps->width * (size_t)lines * sizeof *scratch);
    if (buf == NULL || scratch == NULL) {
        free(buf);
        free(scratch);
        return err_set(s->e, REFRACT_E_OUT_OF_MEMORY, "out of memory decoding an EXR volume");
    }
    exr_decode_pipeline_t pipe = EXR_DECODE_PIPELINE_INITIALIZER;
    bool have_pipe = false;
    enum refract_code rc = REFRACT_E_OK;
    for (int y = 0; y < ps->height && rc == REFRACT_E_OK; y += lines) {
        exr_chunk_info_t cinfo;
        rv = exr_read_scanline_chunk_info(ctxt, part, ps->y0 + y, &cinfo);
        if (rv == EXR_ERR_SUCCESS) {
            rv = have_pipe ? exr_decoding_update(ctxt, part, &cinfo, &pipe)
                           : exr_decoding_initialize(ctxt, part, &cinfo, &pipe);
            have_pipe = have_pipe || rv == EXR_ERR_SUCCESS;
        }
        int first_row = cinfo.start_y - ps->y0;
        int rows = cinfo.height;
        if (rv == EXR_ERR_SUCCESS && (first_row != y || rows < 1 || rows > lines)) {
            rc = err_set(s->e, REFRACT_E_INVALID_VOLUME,
                         "EXR volume: part %d's chunk at row %d is malformed", part, y);
            break;
        }
        if (rv == EXR_ERR_SUCCESS) {
            for (int c = 0; c < pipe.channel_count; c++) {
                exr_coding_channel_info_t *ch = &pipe.channels[c];
                int k = wanted(names, comps, ch->channel_name);
                ch->user_bytes_per_element = 4;
                ch->user_data_type = EXR_PIXEL_FLOAT;
                if (k < 0) {
                    ch->user_pixel_stride = (int32_t)sizeof(float);
                    ch->user_line_stride = (int32_t)((size_t)ps->width * sizeof(float));
                    ch->decode_to_ptr = (uint8_t *)scratch;
                    continue;
                }
                ch->user_pixel_stride = comps * (int32_t)sizeof(float);
                ch->user_line_stride = (int32_t)(row_floats * sizeof(float));
                ch->decode_to_ptr = (uint8_t *)(buf + k);
            }
            rv = exr_decoding_choose_default_routines(ctxt, part, &pipe);
        }
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_decoding_run(ctxt, part, &pipe);
        if (rv != EXR_ERR_SUCCESS) {
            rc = fail(s, rv, "decoding a chunk");
            break;
        }
        size_t n = row_floats * (size_t)rows;
        for (size_t i = 0; i < n && rc == REFRACT_E_OK; i++)
            rc = volume_sink_put(sink, buf[i], s->e);
    }
    if (have_pipe)
        exr_decoding_destroy(ctxt, &pipe);
    free(buf);
    free(scratch);
    return rc;
}

static enum refract_code decode(exr_context_t ctxt, const struct io_volume_desc *d,
                                struct volume_sink *sink, struct io_volume_info *info,
                                struct exr_mem_src *s)
{
    int parts = 0;
    exr_result_t rv = exr_get_count(ctxt, &parts);
    if (rv != EXR_ERR_SUCCESS || parts < 1)
        return fail(s, rv, "counting parts");
    struct part_shape ps;
    enum refract_code rc = part_shape(ctxt, 0, &ps, s);
    const exr_attr_chlist_t *chl = NULL;
    if (rc == REFRACT_E_OK && (exr_get_channels(ctxt, 0, &chl) != EXR_ERR_SUCCESS || chl == NULL))
        rc = err_set(s->e, REFRACT_E_INVALID_VOLUME, "EXR volume: part 0 has no channel list");
    const char *names[3] = {0};
    int comps = 0;
    if (rc == REFRACT_E_OK)
        rc = choose_channels(chl, d->components, names, &comps, s->e);
    if (rc != REFRACT_E_OK)
        return rc;
    int dims[3] = {ps.width, ps.height, parts};
    if (parts == 1) {
        if (d->dims[0] == 0)
            return err_set(s->e, REFRACT_E_MISSING_FIELD,
                           "a single-part EXR is read as a slice atlas (width X, height Y*Z) and "
                           "needs ?dims=X,Y,Z; a file with one part per slice needs no dims");
        if (d->dims[0] != ps.width || (long long)d->dims[1] * d->dims[2] != ps.height)
            return err_set(s->e, REFRACT_E_INVALID_VOLUME,
                           "the query says dims=%d,%d,%d, so the slice atlas must be %d x %lld "
                           "pixels, but the EXR is %d x %d",
                           d->dims[0], d->dims[1], d->dims[2], d->dims[0],
                           (long long)d->dims[1] * d->dims[2], ps.width, ps.height);
        memcpy(dims, d->dims, sizeof dims);
    } else if (d->dims[0] && memcmp(d->dims, dims, sizeof dims) != 0) {
        return err_set(s->e, REFRACT_E_INVALID_VOLUME,
                       "the query says dims=%d,%d,%d but the EXR holds %d parts of %d x %d "
                       "pixels",
                       d->dims[0], d->dims[1], d->dims[2], parts, ps.width, ps.height);
    }
    rc = volume_check_dims(d, dims, comps, "EXR volume", s->e);
    if (rc != REFRACT_E_OK)
        return rc;
    volume_sink_init(sink, sink->fd, dims, comps, d->scale, d->offset);
    info->source_type = IO_SAMPLE_FLOAT32;
    for (int p = 0; p < parts && rc == REFRACT_E_OK; p++) {
        struct part_shape pp = ps;
        if (p > 0) {
            rc = part_shape(ctxt, p, &pp, s);
            if (rc == REFRACT_E_OK && (pp.width != ps.width || pp.height != ps.height))
                rc = err_set(s->e, REFRACT_E_INVALID_VOLUME,
                             "EXR volume: part %d is %d x %d but part 0 is %d x %d; every slice "
                             "must have the same size",
                             p, pp.width, pp.height, ps.width, ps.height);
        }
        if (rc == REFRACT_E_OK)
            rc = read_part(ctxt, p, &pp, names, comps, sink, s);
    }
    if (rc == REFRACT_E_OK)
        rc = volume_sink_finish(sink, info, s->e);
    return rc;
}

enum refract_code volume_decode_exr(const unsigned char *src, size_t len,
                                    const struct io_volume_desc *d, struct volume_sink *sink,
                                    struct io_volume_info *info, struct err *e)
{
    struct exr_mem_src s = {
        .bytes = src, .len = len, .e = e, .bad_input = REFRACT_E_INVALID_VOLUME};
    if (len < 4 || memcmp(src, "\x76\x2f\x31\x01", 4) != 0)
        return err_set(e, REFRACT_E_INVALID_VOLUME,
                       "not an OpenEXR file (bad magic number); say ?format=raw or nrrd for "
                       "other files");
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_mem_src_attach(&init, &s);
    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_start_read(&ctxt, "volume.exr", &init);
    enum refract_code rc = rv == EXR_ERR_SUCCESS ? decode(ctxt, d, sink, info, &s)
                                                 : fail(&s, rv, "reading the header");
    exr_finish(&ctxt);
    return rc;
}
