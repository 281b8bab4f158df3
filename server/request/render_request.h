/*
 * render_request.h - a stored scene version as the renderer and the irradiance cache see it,
 * and the one render path that single renders (POST /v1/scenes/{id}/render), view
 * sessions and batch jobs use (named after none of them, drawn a tile at a time by
 * render_tiles.h): gather the best irradiance volume of each light, render, record a build
 * made on the way.
 *
 * Ownership: the sources borrow the version (and its uploads) for as long as the caller
 * keeps its reference; nothing here allocates.
 */
#ifndef REFRACT_RENDER_REQUEST_H
#define REFRACT_RENDER_REQUEST_H

#include "../cache/irradiance_cache.h"
#include "../render/render.h"
#include "../store/store.h"

/* The renderer's description of a version (render_scene_source.generation is the
 * version's data_generation: a lights change does not rebuild the scene's GPU data).
 * Any thread. */
struct render_scene_source render_request_scene_source(struct store_scene *v);

/* What the irradiance cache needs of a version (borrowed for as long as v; the cache
 * retains v itself while it builds fields). Any thread. */
void render_request_irradiance_source(struct store_scene *v, struct irradiance_source *out);

/* GPU thread: rows [row0, row0 + rows) of req into out->rgba, which the caller allocated
 * for the whole image (render_view_rows), from the best irradiance the cache has: req's
 * lights are filled in here (lights has SCENE_MAX_LIGHTS entries and must stay alive for
 * the call), and a scene build made on the way is recorded in the store's GPU status like
 * a background build would be. *irradiance (X-Refract-Irradiance) is "ready", "stale",
 * "missing" or "not-needed". Errors are render_view's. Callers draw whole images through
 * render_tiles.h. */
enum refract_code render_request_version_rows(struct render *r, struct irradiance_cache *c,
                                              struct store *store, struct store_scene *v,
                                              struct render_view_request *req,
                                              struct render_light *lights, int row0, int rows,
                                              struct render_view_result *out,
                                              const char **irradiance, struct err *e);

/* A render drawn in tiles: true when the tile at row0 gathered other irradiance volumes or
 * photon maps than the first tile did (one became ready in between), so the picture would
 * show a seam; the first tile (row0 == 0) remembers its volumes in
 * volumes[SCENE_MAX_LIGHTS], *count and its maps' keys in photon_keys[SCENE_MAX_LIGHTS]. */
bool render_request_volumes_changed(const struct render_view_request *req, int row0,
                                    const struct irradiance_gpu **volumes, uint64_t *photon_keys,
                                    int *count);

#endif
