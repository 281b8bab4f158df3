/*
 * render_util.h - what the integration tests of pictures share, header-only: a render of a
 * stored scene as EXR (the scene's own camera and settings), decoded to linear RGBA floats.
 */
#ifndef REFRACT_TEST_RENDER_UTIL_H
#define REFRACT_TEST_RENDER_UTIL_H

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "core/env.h"
#include "daemon.h"
#include "io/io_image.h"

/* The pixel (column, row from the top) a world point lands on in a w x h image of a camera
 * at eye looking at look (up +y, vertical field of view fov_y_deg): env.h's pinhole model,
 * pixel centres. */
static inline void test_project(vec3 eye, vec3 look, double fov_y_deg, int w, int h, vec3 p,
                                int *col, int *row)
{
    vec3 up = {0, 1, 0};
    vec3 f = vec3_normalize(vec3_sub(look, eye)), r = vec3_normalize(vec3_cross(f, up));
    vec3 u = vec3_cross(r, f), v = vec3_sub(p, eye);
    double t = tan(fov_y_deg * M_PI / 360.0), x = vec3_dot(v, r) / vec3_dot(v, f) / t,
           y = vec3_dot(v, u) / vec3_dot(v, f) / t;
    *col = (int)floor((x / ((double)w / h) + 1.0) * 0.5 * w);
    *row = (int)floor((1.0 - y) * 0.5 * h);
}

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
