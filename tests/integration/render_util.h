/*
 * render_util.h - what the integration tests of pictures share, header-only: a render of a
 * stored scene as EXR (the scene's own camera and settings), decoded to linear RGBA floats.
 */
#ifndef REFRACT_TEST_RENDER_UTIL_H
#define REFRACT_TEST_RENDER_UTIL_H

#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "daemon.h"
#include "io/io_image.h"

/* Renders scene `id` as EXR into rgba (w x h x 4 floats, rows top down). False (with the
 * reason on stderr) when the render fails or its size is not w x h. */
static inline bool test_render_exr(struct test_daemon *d, const char *id, int w, int h, float *rgba)
{
    struct refract_image img = {0};
    if (refract_render(d->client, id, "{\"format\": \"exr\"}", &img) != REFRACT_E_OK) {
        fprintf(stderr, "render: %s\n", refract_errmsg(d->client));
        return false;
    }
    struct io_image px = {0};
    struct err e = {0};
    bool ok = io_image_decode(img.bytes, img.len, 1 << 24, &px, &e) == REFRACT_E_OK;
    refract_image_free(&img);
    if (!ok)
        fprintf(stderr, "decode: %s\n", e.msg);
    ok = ok && px.width == w && px.height == h;
    if (ok)
        memcpy(rgba, px.rgba, sizeof(float) * (size_t)w * (size_t)h * 4);
    io_image_free(&px);
    return ok;
}

#endif
