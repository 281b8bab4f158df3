/*
 * render_tiles.c - one image drawn a tile of rows per GPU turn (render_tiles.h).
 */
#include "render_tiles.h"

#include <stdlib.h>

#include "../core/metrics.h"
#include "../gpu/queue.h"

void render_tiles_init(struct render_tiles *t, long long tile_pixels, int width, int height)
{
    *t = (struct render_tiles){.width = width, .height = height};
    if (tile_pixels <= 0)
        tile_pixels = RENDER_TILES_DEFAULT_PIXELS;
    long long rows = tile_pixels / (width > 0 ? width : 1);
    t->tile_rows = rows < 1 ? 1 : rows > height ? height : (int)rows;
}

bool render_tiles_at_once(const struct render_tiles *t)
{
    return t->tile_rows >= t->height;
}

enum refract_code render_tiles_step(struct render_tiles *t, struct render *r,
                                    struct irradiance_cache *c, struct store *store,
                                    struct store_scene *v, struct render_view_request *req,
                                    struct render_light *lights, struct render_view_result *out,
                                    const char **irradiance, bool *more, struct err *e)
{
    *more = false;
    if (out->rgba == NULL) {
        out->rgba = malloc((size_t)t->width * (size_t)t->height * 4 * sizeof(float));
        if (out->rgba == NULL)
            return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                           "out of memory for a %dx%d image; render it smaller", t->width,
                           t->height);
    }
    int row0 = t->next_row;
    int rows = t->height - row0 < t->tile_rows ? t->height - row0 : t->tile_rows;
    double t0 = gpu_time_ms();
    enum refract_code rc =
        render_request_version_rows(r, c, store, v, req, lights, row0, rows, out, irradiance, e);
    if (rc != REFRACT_E_OK)
        return rc;
    t->render_ms += gpu_time_ms() - t0;
    if (render_request_volumes_changed(req, row0, t->volumes, t->photon_keys, &t->volume_count) &&
        t->restarts < RENDER_TILES_MAX_RESTARTS) {
        t->restarts++;
        t->next_row = 0;
        t->render_ms = 0.0;
        out->gpu_ms = 0.0;
        *more = true;
        return REFRACT_E_OK;
    }
    t->next_row = row0 + rows;
    *more = t->next_row < t->height;
    if (!*more) {
        out->total_ms = t->render_ms;
        metrics_render(t->render_ms * 1e-3); /* GET /metrics: one render, all its tiles */
    }
    return REFRACT_E_OK;
}
