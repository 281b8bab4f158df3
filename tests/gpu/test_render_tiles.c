/*
 * test_render_tiles.c - a render drawn in tiles of rows (render_view_rows; the HTTP render
 * path tiles large renders so other work runs between the tiles, issue 13 "Fair sharing")
 * is the same, bit for bit, as the render made at once:
 *   - tiles of 7 rows (not a multiple of the kernel's local size, so the last work group of
 *     each tile reaches past the tile and must not write there) and of 1 row;
 *   - with anti-aliasing (4 jittered rays per pixel: the jitter follows the pixel's place in
 *     the whole image, not in the tile);
 *   - another scene rendered between every two tiles (what the queue does between turns:
 *     other bindings, another camera, another image size);
 *   - a rows argument outside the image is an INTERNAL error, not a write out of bounds.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu/queue.h"
#include "render/render.h"
#include "scene/scene.h"
#include "gpu_test_util.h"
#include "unit/scene_test_util.h"
#include "test.h"

#define BOX "\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, "
#define GLASS                                                                                      \
    "{\"name\": \"glass\", \"camera\": {\"eye\": [0.3, 0.8, 3.6], \"look_at\": [0, 0, 0], "        \
    "\"fov_y_deg\": 40, \"width\": 45, \"height\": 37}, \"render\": {\"samples_per_pixel\": 4}, "  \
    "\"objects\": [{" BOX                                                                          \
    "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.7, \"inside\": 1.5}, \"attenuation\": "        \
    "{\"shape\": \"sphere\", \"radius\": 0.7, \"inside\": [0.5, 1, 2]}}]}"
#define OTHER                                                                                      \
    "{\"name\": \"other\", \"camera\": {\"eye\": [2, 0, 2], \"look_at\": [0, 0, 0], "              \
    "\"fov_y_deg\": 50, \"width\": 20, \"height\": 11}, \"objects\": [{" BOX                       \
    "\"ior\": {\"shape\": \"box\", \"center\": [0, 0, 0], \"size\": [1.0, 0.8, 0.6], \"inside\": " \
    "1.33}}]}"

struct tiles_work {
    struct gpu_work work;
    const struct scene *glass, *other;
    float *whole;          /* render_view */
    float *tiled[2];       /* tiles of 7 rows, of 1 row */
    enum refract_code bad; /* rows past the image */
};

static void source(const struct scene *s, struct render_scene_source *src)
{
    *src = (struct render_scene_source){.id = s->name, .generation = 1, .scene = s};
}

/* Renders glass in tiles of `rows`, rendering `other` between two tiles. */
static float *render_tiled(struct render *r, const struct tiles_work *t, int rows, struct err *e)
{
    struct render_scene_source src, other_src;
    source(t->glass, &src);
    source(t->other, &other_src);
    struct render_view_request req = {.camera = t->glass->camera, .settings = t->glass->render};
    struct render_view_request other = {.camera = t->other->camera, .settings = t->other->render};
    int w = req.camera.width, h = req.camera.height;
    struct render_view_result out = {.rgba = calloc((size_t)w * (size_t)h * 4, sizeof(float))};
    for (int row0 = 0; out.rgba != NULL && row0 < h; row0 += rows) {
        int n = h - row0 < rows ? h - row0 : rows;
        if (render_view_rows(r, &src, &req, row0, n, &out, e) != REFRACT_E_OK) {
            free(out.rgba);
            return NULL;
        }
        struct render_view_result between;
        if (render_view(r, &other_src, &other, &between, e) != REFRACT_E_OK) {
            free(out.rgba);
            return NULL;
        }
        free(between.rgba);
    }
    return out.rgba;
}

static void tiles_run(struct gpu_work *w, struct gpu *gpu)
{
    struct tiles_work *t = w->user;
    struct render_desc desc = {0};
    struct render *r = render_create(gpu, &desc, &w->err);
    if (r == NULL)
        return;
    struct render_scene_source src;
    source(t->glass, &src);
    struct render_view_request req = {.camera = t->glass->camera, .settings = t->glass->render};
    struct render_view_result whole;
    if (render_view(r, &src, &req, &whole, &w->err) == REFRACT_E_OK) {
        t->whole = whole.rgba;
        t->tiled[0] = render_tiled(r, t, 7, &w->err);
        t->tiled[1] = render_tiled(r, t, 1, &w->err);
        struct render_view_result out = {.rgba = whole.rgba};
        struct err e = {0};
        t->bad = render_view_rows(r, &src, &req, req.camera.height - 2, 3, &out, &e);
    }
    render_destroy(r);
}

int main(void)
{
    struct gpu *gpu = test_gpu_create("test_render_tiles");
    struct scene *glass = parse_ok(GLASS);
    struct scene *other = parse_ok(OTHER);
    struct tiles_work t = {.glass = glass, .other = other};
    t.work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = tiles_run, .user = &t};
    enum refract_code rc = gpu_run_sync(gpu, &t.work);
    CHECK_MSG(rc == REFRACT_E_OK, "render failed: %s", t.work.err.msg);
    size_t bytes = (size_t)glass->camera.width * (size_t)glass->camera.height * 4 * sizeof(float);
    if (t.whole != NULL) {
        /* the picture is not empty: the comparison below compares something */
        double sum = 0.0;
        for (size_t i = 0; i < bytes / sizeof(float); i++)
            sum += t.whole[i];
        CHECK(sum > 0.0);
        for (int k = 0; k < 2; k++) {
            CHECK_MSG(t.tiled[k] != NULL, "tiled render %d failed", k);
            if (t.tiled[k] != NULL)
                CHECK_MSG(memcmp(t.whole, t.tiled[k], bytes) == 0,
                          "tiles of %d rows differ from the whole render", k == 0 ? 7 : 1);
        }
    }
    CHECK_INT(t.bad, REFRACT_E_INTERNAL);
    free(t.whole);
    free(t.tiled[0]);
    free(t.tiled[1]);
    scene_destroy(glass);
    scene_destroy(other);
    gpu_destroy(gpu, NULL);
    return test_summary("test_render_tiles");
}
