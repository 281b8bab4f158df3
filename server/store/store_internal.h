/*
 * store_internal.h - what store.c lends the store's other files (store_mesh.c): the
 * version edit under the store's lock, and the store's settings. Not used outside
 * server/store/.
 */
#ifndef REFRACT_STORE_INTERNAL_H
#define REFRACT_STORE_INTERNAL_H

#include "store.h"

/* Under the store's lock: fails with SCENE_NOT_FOUND unless scene `id` exists; runs
 * persist(scene_dir, ctx) when persist is not NULL; makes a new version of the scene (a
 * copy of the current one, with new references to its uploads), lets edit(v, ctx) change
 * it and installs it as current. Any step's error is returned and nothing is installed. */
enum refract_code
store_edit_version(struct store *s, const char *id,
                   enum refract_code (*persist)(const char *scene_dir, void *ctx, struct err *e),
                   enum refract_code (*edit)(struct store_scene *v, void *ctx, struct err *e),
                   void *ctx, struct err *e);

/* The limits the store parses with (store_desc.limits). */
const struct scene_limits *store_limits(const struct store *s);

#endif
