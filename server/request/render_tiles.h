/*
 * render_tiles.h - a render drawn in tiles of whole rows, one tile per turn of its GPU work
 * item (gpu_work.again), so that work queued behind it runs between its tiles: a small
 * render waits for one tile, not for a whole large image (docs/api.md "Fair sharing",
 * --render-tile-pixels). The one tile loop of single renders (h_render.c), view frames
 * (view_scheduler.c) and batch-job frames (job_runner.c, job_batch.c).
 *
 * The tiles are render_view_rows calls, which draw bit for bit what render_view would, so
 * an image drawn in tiles equals the image drawn at once. What can differ between tiles is
 * the irradiance: other work between two tiles may make a light's volume ready (or read it
 * back from disk). A picture lit by two states of the irradiance would show a seam where
 * the tiles meet, so a tile that gathers other volumes than the first tile did starts the
 * image again (a few times at most; a light changing faster than that is drawn with what it
 * has, as the next render would be).
 *
 * Thread: render_tiles_init anywhere; render_tiles_step on the GPU thread only.
 */
#ifndef REFRACT_RENDER_TILES_H
#define REFRACT_RENDER_TILES_H

#include <stdbool.h>

#include "render_request.h"

/* Rows per tile when --render-tile-pixels is not given (matches the HTTP default). */
#define RENDER_TILES_DEFAULT_PIXELS 65536
/* How many times an image starts again because the irradiance changed under it. */
#define RENDER_TILES_MAX_RESTARTS 3

struct render_tiles {
    int width, height;                                      /* the image's */
    int tile_rows;                                          /* rows per turn: 1..height */
    int next_row;                                           /* the first row of the next tile */
    int restarts;                                           /* times the image started again */
    const struct irradiance_gpu *volumes[SCENE_MAX_LIGHTS]; /* what the first tile used */
    int volume_count;
    uint64_t photon_keys[SCENE_MAX_LIGHTS]; /* the photon maps the first tile used */
    double render_ms; /* the tiles' render time so far (GET /metrics, once all are drawn) */
};

/* Plans a width x height image in tiles of about tile_pixels pixels (whole rows: at least
 * one row, at most the image; tile_pixels <= 0 means RENDER_TILES_DEFAULT_PIXELS). */
void render_tiles_init(struct render_tiles *t, long long tile_pixels, int width, int height);

/* True when the image is drawn in one turn. */
bool render_tiles_at_once(const struct render_tiles *t);

/* GPU thread: draws the next tile of req (whose camera is t's size) from version v into
 * out. On the first turn out->rgba must be NULL or the caller's buffer for the whole image;
 * NULL is allocated here (OUT_OF_MEMORY naming the size). *more is true when rows remain:
 * the caller asks for another turn (gpu_work.again). Once the last tile is drawn the render
 * time is recorded for GET /metrics (metrics_render) and out->total_ms holds it.
 * *irradiance is the last tile's (X-Refract-Irradiance, render_request.h). Errors
 * are render_view's; then *more is false. */
enum refract_code render_tiles_step(struct render_tiles *t, struct render *r,
                                    struct irradiance_cache *c, struct store *store,
                                    struct store_scene *v, struct render_view_request *req,
                                    struct render_light *lights, struct render_view_result *out,
                                    const char **irradiance, bool *more, struct err *e);

#endif
