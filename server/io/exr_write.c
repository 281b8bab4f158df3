/*
 * exr_write.c - io_encode_exr: linear RGBA float -> an OpenEXR file in memory, with
 * OpenEXR's C API (OpenEXRCore).
 *
 * The file is one scanline part, channels (A, B, G, R for a frame) as 32-bit FLOAT (EXR stores
 * channels sorted by name; the library sorts them and the encode pipeline reads each
 * one from its offset in our interleaved RGBA pixels), ZIP compression (16 lines per
 * chunk), INCREASING_Y line order, dataWindow = displayWindow = (0,0)-(w-1,h-1). EXR's
 * y axis points down, so row 0 of the buffer is row 0 of the file: the top.
 *
 * The bytes go to a growable malloc'd buffer through the context's custom write_fn,
 * which has pwrite semantics: the library writes the header, then the chunks, then
 * goes back to fill in the chunk offset table at exr_finish().
 *
 * Cost: zlib dominates (86% of the time in perf); ZIP on 32-bit floats saves only
 * about 30% of the 33 MB a 1080p frame holds, and one frame takes about 0.6 s on one
 * core. Chunks are compressed on the calling thread, one after another; OpenEXR can
 * encode chunks on several threads, which this does not do yet.
 *
 * io_encode_exr_channels writes any set of named float channels (the irradiance volumes'
 * R, G, B, dir.X..dir.W) and string header attributes; io_encode_exr is its RGBA case.
 *
 * io_encode_exr_parts writes `parts` parts of the same size and channels (one volume
 * slice per part, the layout volume_exr.c reads).
 *
 * Not here: reading (exr_read.c), half floats, tiles.
 */
#include "io_exr.h"
#include "io_image.h"

#include <openexr.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The memory stream behind the context, and where library errors are recorded. */
struct exr_membuf {
    uint8_t *bytes; /* owned until handed to the caller */
    size_t len;     /* highest byte written + 1 */
    size_t cap;
    struct err *e; /* borrowed; receives the library's first error message */
    int have_error;
};

/* Our code for an OpenEXR result: running out of memory is the one failure of writing
 * to memory that is not a bug. */
static enum refract_code code_for(exr_result_t rv)
{
    return rv == EXR_ERR_OUT_OF_MEMORY ? REFRACT_E_OUT_OF_MEMORY : REFRACT_E_INTERNAL;
}

/* OpenEXR reports errors through this callback (with the message it formatted) and
 * also returns a code; keep the first message, which names the root cause. */
static void on_exr_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *ud = NULL;
    if (ctxt == NULL || exr_get_user_data(ctxt, &ud) != EXR_ERR_SUCCESS || ud == NULL)
        return;
    struct exr_membuf *mb = ud;
    if (mb->have_error)
        return;
    mb->have_error = 1;
    err_set(mb->e, code_for(code), "OpenEXR: %s (%s)", msg ? msg : "",
            exr_get_error_code_as_string(code));
}

/* pwrite into the growable buffer; the capacity doubles so the whole file costs
 * O(size) copies. */
static int64_t write_mem(exr_const_context_t ctxt, void *userdata, const void *buffer, uint64_t sz,
                         uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    struct exr_membuf *mb = userdata;
    if (offset > SIZE_MAX - sz) {
        error_cb(ctxt, EXR_ERR_OUT_OF_MEMORY, "write past addressable memory");
        return -1;
    }
    size_t end = (size_t)(offset + sz);
    if (end > mb->cap) {
        size_t cap = mb->cap ? mb->cap : 64 * 1024;
        while (cap < end)
            cap = cap > SIZE_MAX / 2 ? end : cap * 2;
        uint8_t *grown = realloc(mb->bytes, cap);
        if (grown == NULL) {
            error_cb(ctxt, EXR_ERR_OUT_OF_MEMORY, "cannot grow output buffer to %zu bytes", cap);
            return -1;
        }
        mb->bytes = grown;
        mb->cap = cap;
    }
    if (offset > mb->len) /* a gap the library fills later; keep it deterministic */
        memset(mb->bytes + mb->len, 0, (size_t)offset - mb->len);
    memcpy(mb->bytes + offset, buffer, (size_t)sz);
    if (end > mb->len)
        mb->len = end;
    return (int64_t)sz;
}

/* Turns a failed OpenEXR call into the error; the callback usually has a better
 * message already, so this only fills in when it has not. */
static enum refract_code exr_fail(struct exr_membuf *mb, exr_result_t rv, const char *what)
{
    if (!mb->have_error) {
        mb->have_error = 1;
        err_set(mb->e, code_for(rv), "OpenEXR: %s failed: %s", what,
                exr_get_default_error_message(rv));
    }
    return mb->e ? mb->e->code : REFRACT_E_INTERNAL;
}

/* The interleaved image being written: nch named channels per pixel. */
struct exr_layout {
    const float *pixels;
    int width, height, nch;
    const char *const *names;
};

/* Index of a channel name in the layout, or -1. */
static int channel_index(const struct exr_layout *lo, const char *name)
{
    for (int c = 0; c < lo->nch; c++) {
        if (strcmp(lo->names[c], name) == 0)
            return c;
    }
    return -1;
}

/* Declares the one scanline part: required attributes, the channels and the string
 * attributes (name, value pairs). Colour channels (R, G, B) are perceptually
 * logarithmic; everything else is linear data. */
static exr_result_t define_part(exr_context_t ctxt, const struct exr_layout *lo,
                                const char *const *attrs, int parts)
{
    int part = 0;
    char name[32] = "rgba";
    if (parts > 1)
        snprintf(name, sizeof name, "slice%d",
                 exr_get_count(ctxt, &part) == EXR_ERR_SUCCESS ? part : 0);
    exr_result_t rv = exr_add_part(ctxt, name, EXR_STORAGE_SCANLINE, &part);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_initialize_required_attr_simple(ctxt, part, lo->width, lo->height,
                                                 EXR_COMPRESSION_ZIP);
    for (int c = 0; c < lo->nch && rv == EXR_ERR_SUCCESS; c++) {
        const char *n = lo->names[c];
        bool colour = strlen(n) == 1 && strchr("RGB", n[0]) != NULL;
        rv = exr_add_channel(ctxt, part, n, EXR_PIXEL_FLOAT,
                             colour ? EXR_PERCEPTUALLY_LOGARITHMIC : EXR_PERCEPTUALLY_LINEAR, 1, 1);
    }
    for (int a = 0; attrs && attrs[a] && rv == EXR_ERR_SUCCESS; a += 2)
        rv = exr_attr_set_string(ctxt, part, attrs[a], attrs[a + 1]);
    return rv;
}

/* Points each of the pipeline's channels (in the file's order, sorted by name) at its
 * component of the chunk's first pixel in our interleaved buffer. */
static void bind_channels(exr_encode_pipeline_t *pipe, const struct exr_layout *lo, int y)
{
    const float *row = lo->pixels + (size_t)y * (size_t)lo->width * (size_t)lo->nch;
    for (int c = 0; c < pipe->channel_count; c++) {
        exr_coding_channel_info_t *ch = &pipe->channels[c];
        int comp = channel_index(lo, ch->channel_name);
        ch->user_bytes_per_element = 4;
        ch->user_data_type = EXR_PIXEL_FLOAT;
        ch->user_pixel_stride = lo->nch * (int32_t)sizeof(float);
        ch->user_line_stride = lo->nch * (int32_t)sizeof(float) * lo->width;
        ch->encode_from_ptr = (const uint8_t *)(row + (comp < 0 ? 0 : comp));
    }
}

/* Encodes and writes every chunk of the part, top to bottom. */
static enum refract_code write_chunks(exr_context_t ctxt, int part, const struct exr_layout *lo,
                                      struct exr_membuf *mb)
{
    int32_t lines_per_chunk = 0;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, part, &lines_per_chunk);
    if (rv != EXR_ERR_SUCCESS || lines_per_chunk < 1)
        return exr_fail(mb, rv, "exr_get_scanlines_per_chunk");

    exr_encode_pipeline_t pipe = EXR_ENCODE_PIPELINE_INITIALIZER;
    int have_pipe = 0;
    enum refract_code code = REFRACT_E_OK;
    for (int y = 0; y < lo->height && code == REFRACT_E_OK; y += lines_per_chunk) {
        exr_chunk_info_t cinfo;
        rv = exr_write_scanline_chunk_info(ctxt, part, y, &cinfo);
        if (rv != EXR_ERR_SUCCESS) {
            code = exr_fail(mb, rv, "exr_write_scanline_chunk_info");
            break;
        }
        if (!have_pipe) {
            rv = exr_encoding_initialize(ctxt, part, &cinfo, &pipe);
            have_pipe = rv == EXR_ERR_SUCCESS;
        } else {
            rv = exr_encoding_update(ctxt, part, &cinfo, &pipe);
        }
        if (rv == EXR_ERR_SUCCESS) {
            bind_channels(&pipe, lo, y);
            if (y == 0)
                rv = exr_encoding_choose_default_routines(ctxt, part, &pipe);
        }
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_encoding_run(ctxt, part, &pipe);
        if (rv != EXR_ERR_SUCCESS)
            code = exr_fail(mb, rv, "encoding a chunk");
    }
    if (have_pipe)
        exr_encoding_destroy(ctxt, &pipe);
    return code;
}

/* Contract in io_exr.h. Errors: REFRACT_E_INVALID_FIELD for a size OpenEXR cannot
 * hold, REFRACT_E_OUT_OF_MEMORY, REFRACT_E_INTERNAL with OpenEXR's message. */
enum refract_code io_encode_exr_channels(const float *pixels, int width, int height, int nch,
                                         const char *const *names, const char *const *attrs,
                                         void **out_bytes, size_t *out_len, struct err *e)
{
    return io_encode_exr_parts(pixels, width, height, 1, nch, names, attrs, out_bytes, out_len, e);
}

enum refract_code io_encode_exr_parts(const float *pixels, int width, int height, int parts,
                                      int nch, const char *const *names, const char *const *attrs,
                                      void **out_bytes, size_t *out_len, struct err *e)
{
    *out_bytes = NULL;
    *out_len = 0;
    if (width < 1 || height < 1 || parts < 1)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "EXR encode: image is %d x %d x %d parts; each must be at least 1", width,
                       height, parts);

    struct err local;
    struct exr_membuf mb = {.e = e ? e : &local};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_exr_error;
    init.user_data = &mb;
    init.write_fn = write_mem;
    /* zlib level 1 instead of the library's 4: a 1920x1080 frame (2-core EPYC) takes
     * 0.61 s of CPU instead of 0.82 s when smooth, 0.57 s instead of 0.61 s when noisy,
     * and the file grows by 0.2%; float mantissas barely compress at any level. */
    init.zip_level = 1;

    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_start_write(&ctxt, "frame.exr", EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS) {
        exr_finish(&ctxt);
        free(mb.bytes);
        return exr_fail(&mb, rv, "exr_start_write");
    }

    enum refract_code code = REFRACT_E_OK;
    struct exr_layout lo = {
        .pixels = pixels, .width = width, .height = height, .nch = nch, .names = names};
    rv = EXR_ERR_SUCCESS;
    for (int p = 0; p < parts && rv == EXR_ERR_SUCCESS; p++)
        rv = define_part(ctxt, &lo, attrs, parts);
    if (rv == EXR_ERR_SUCCESS)
        rv = exr_write_header(ctxt);
    if (rv != EXR_ERR_SUCCESS)
        code = exr_fail(&mb, rv, "writing the header");
    size_t part_floats = (size_t)width * (size_t)height * (size_t)nch;
    for (int p = 0; p < parts && code == REFRACT_E_OK; p++) {
        lo.pixels = pixels + (size_t)p * part_floats;
        code = write_chunks(ctxt, p, &lo, &mb);
    }
    /* exr_finish writes the chunk offset table, so its result matters. */
    rv = exr_finish(&ctxt);
    if (code == REFRACT_E_OK && rv != EXR_ERR_SUCCESS)
        code = exr_fail(&mb, rv, "exr_finish");
    if (code == REFRACT_E_OK && mb.have_error)
        code = mb.e->code; /* the library complained but still returned success */

    if (code != REFRACT_E_OK) {
        free(mb.bytes);
        return code;
    }
    *out_bytes = mb.bytes;
    *out_len = mb.len;
    return REFRACT_E_OK;
}

enum refract_code io_encode_exr(const float *rgba, int width, int height, void **out_bytes,
                                size_t *out_len, struct err *e)
{
    static const char *const names[] = {"R", "G", "B", "A"};
    return io_encode_exr_channels(rgba, width, height, 4, names, NULL, out_bytes, out_len, e);
}
