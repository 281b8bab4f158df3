/*
 * exr_read.c - io_decode_exr_channels: named float channels of an OpenEXR file held in
 * memory, with OpenEXR's C API (the reverse of exr_write.c). See io_exr.h.
 *
 * The file is read through the context's custom read_fn (pread semantics over the
 * buffer), chunk by chunk with a decode pipeline whose channels point straight into the
 * interleaved output, so no intermediate copy is made. Any compression OpenEXR knows is
 * accepted; only FLOAT channels are, so values come back bit-exact.
 */
#include <openexr.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "exr_mem.h"
#include "io_exr.h"

static enum refract_code fail(struct exr_mem_src *mb, exr_result_t rv, const char *what)
{
    if (!mb->have_error) {
        mb->have_error = true;
        err_set(mb->e,
                rv == EXR_ERR_OUT_OF_MEMORY ? REFRACT_E_OUT_OF_MEMORY : REFRACT_E_INVALID_IMAGE,
                "OpenEXR: %s failed: %s", what, exr_get_default_error_message(rv));
    }
    return mb->e->code;
}

/* Checks that every wanted channel exists as full-resolution FLOAT. */
static enum refract_code check_channels(exr_context_t ctxt, int nch, const char *const *names,
                                        struct err *e)
{
    const exr_attr_chlist_t *chl = NULL;
    if (exr_get_channels(ctxt, 0, &chl) != EXR_ERR_SUCCESS || chl == NULL)
        return err_set(e, REFRACT_E_INVALID_IMAGE, "EXR: the file has no channel list");
    for (int c = 0; c < nch; c++) {
        bool found = false;
        for (int i = 0; i < chl->num_channels; i++) {
            const exr_attr_chlist_entry_t *ce = &chl->entries[i];
            if (strcmp(ce->name.str, names[c]) != 0)
                continue;
            if (ce->pixel_type != EXR_PIXEL_FLOAT || ce->x_sampling != 1 || ce->y_sampling != 1)
                return err_set(e, REFRACT_E_INVALID_IMAGE,
                               "EXR: channel %s must be full-resolution 32-bit FLOAT", names[c]);
            found = true;
        }
        if (!found)
            return err_set(e, REFRACT_E_INVALID_IMAGE, "EXR: channel %s is missing", names[c]);
    }
    return REFRACT_E_OK;
}

static int wanted_index(int nch, const char *const *names, const char *name)
{
    for (int c = 0; c < nch; c++) {
        if (strcmp(names[c], name) == 0)
            return c;
    }
    return -1;
}

static enum refract_code read_chunks(exr_context_t ctxt, int nch, const char *const *names,
                                     float *out, int width, int height, int y0,
                                     struct exr_mem_src *mb)
{
    int32_t lines = 0;
    exr_result_t rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines);
    if (rv != EXR_ERR_SUCCESS || lines < 1)
        return fail(mb, rv, "exr_get_scanlines_per_chunk");
    exr_decode_pipeline_t pipe = EXR_DECODE_PIPELINE_INITIALIZER;
    bool have_pipe = false;
    enum refract_code code = REFRACT_E_OK;
    for (int y = 0; y < height && code == REFRACT_E_OK; y += lines) {
        exr_chunk_info_t cinfo;
        rv = exr_read_scanline_chunk_info(ctxt, 0, y0 + y, &cinfo);
        if (rv == EXR_ERR_SUCCESS) {
            if (!have_pipe) {
                rv = exr_decoding_initialize(ctxt, 0, &cinfo, &pipe);
                have_pipe = rv == EXR_ERR_SUCCESS;
            } else {
                rv = exr_decoding_update(ctxt, 0, &cinfo, &pipe);
            }
        }
        if (rv == EXR_ERR_SUCCESS) {
            int row = cinfo.start_y - y0;
            for (int c = 0; c < pipe.channel_count; c++) {
                exr_coding_channel_info_t *ch = &pipe.channels[c];
                int k = wanted_index(nch, names, ch->channel_name);
                if (k < 0) {
                    ch->decode_to_ptr = NULL; /* not wanted: skipped */
                    continue;
                }
                ch->user_bytes_per_element = 4;
                ch->user_data_type = EXR_PIXEL_FLOAT;
                ch->user_pixel_stride = nch * (int32_t)sizeof(float);
                ch->user_line_stride = nch * (int32_t)sizeof(float) * width;
                ch->decode_to_ptr = (uint8_t *)(out + ((size_t)row * width * nch + (size_t)k));
            }
            if (y == 0)
                rv = exr_decoding_choose_default_routines(ctxt, 0, &pipe);
        }
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_decoding_run(ctxt, 0, &pipe);
        if (rv != EXR_ERR_SUCCESS)
            code = fail(mb, rv, "decoding a chunk");
    }
    if (have_pipe)
        exr_decoding_destroy(ctxt, &pipe);
    return code;
}

enum refract_code io_decode_exr_channels(const void *bytes, size_t len, int nch,
                                         const char *const *names, long long max_pixels,
                                         float **out_pixels, int *width, int *height,
                                         const char *attr_name, char *attr_value, size_t attr_size,
                                         struct err *e)
{
    *out_pixels = NULL;
    *width = *height = 0;
    if (attr_value && attr_size)
        attr_value[0] = '\0';
    struct err local;
    struct exr_mem_src mb = {
        .bytes = bytes, .len = len, .e = e ? e : &local, .bad_input = REFRACT_E_INVALID_IMAGE};
    if (len < 4 || memcmp(bytes, "\x76\x2f\x31\x01", 4) != 0)
        return err_set(mb.e, REFRACT_E_INVALID_IMAGE, "not an OpenEXR file (bad magic number)");
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    exr_mem_src_attach(&init, &mb);
    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_start_read(&ctxt, "volume.exr", &init);
    if (rv != EXR_ERR_SUCCESS) {
        exr_finish(&ctxt);
        return fail(&mb, rv, "exr_start_read");
    }
    exr_attr_box2i_t dw;
    enum refract_code code = REFRACT_E_OK;
    exr_storage_t storage;
    if (exr_get_storage(ctxt, 0, &storage) != EXR_ERR_SUCCESS || storage != EXR_STORAGE_SCANLINE)
        code = err_set(mb.e, REFRACT_E_INVALID_IMAGE, "EXR: only scanline files are read");
    else if ((rv = exr_get_data_window(ctxt, 0, &dw)) != EXR_ERR_SUCCESS)
        code = fail(&mb, rv, "exr_get_data_window");
    long long w = code == REFRACT_E_OK ? (long long)dw.max.x - dw.min.x + 1 : 0;
    long long h = code == REFRACT_E_OK ? (long long)dw.max.y - dw.min.y + 1 : 0;
    if (code == REFRACT_E_OK && (w < 1 || h < 1 || w * h > max_pixels))
        code = err_set(mb.e, REFRACT_E_LIMIT_EXCEEDED, "EXR: %lld x %lld pixels, at most %lld", w,
                       h, max_pixels);
    if (code == REFRACT_E_OK)
        code = check_channels(ctxt, nch, names, mb.e);
    float *px = NULL;
    if (code == REFRACT_E_OK) {
        px = calloc((size_t)(w * h) * (size_t)nch, sizeof *px);
        if (px == NULL)
            code = err_set(mb.e, REFRACT_E_OUT_OF_MEMORY, "out of memory decoding an EXR");
    }
    if (code == REFRACT_E_OK)
        code = read_chunks(ctxt, nch, names, px, (int)w, (int)h, dw.min.y, &mb);
    if (code == REFRACT_E_OK && attr_name && attr_value && attr_size) {
        const char *str = NULL;
        int32_t slen = 0;
        if (exr_attr_get_string(ctxt, 0, attr_name, &slen, &str) == EXR_ERR_SUCCESS && str) {
            size_t n = (size_t)slen < attr_size - 1 ? (size_t)slen : attr_size - 1;
            memcpy(attr_value, str, n);
            attr_value[n] = '\0';
        }
    }
    exr_finish(&ctxt);
    if (code != REFRACT_E_OK) {
        free(px);
        return code;
    }
    *out_pixels = px;
    *width = (int)w;
    *height = (int)h;
    return REFRACT_E_OK;
}
