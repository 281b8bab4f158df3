/*
 * scene_test_util.h - what the scene unit tests share: parse a document that must be
 * valid, check that a bad one fails with the expected code and message, evaluate a
 * channel of object 0, and index or locate its voxels. Header-only (static inline, so a
 * test that uses only some of it still builds with -Werror): the unit-test glob picks only
 * test_*.c.
 */
#ifndef REFRACT_SCENE_TEST_UTIL_H
#define REFRACT_SCENE_TEST_UTIL_H

#include <stdlib.h>
#include <string.h>

#include "scene/scene.h"
#include "test.h"

#define BOUNDS "\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}"
/* A document with one object whose keys are BOUNDS plus `fields`. */
#define OBJ(fields) "{\"objects\": [{" BOUNDS ", " fields "}]}"
/* A document with top-level keys `top` and one valid object. */
#define TOP(top) "{" top ", \"objects\": [{" BOUNDS ", \"ior\": 1.5}]}"

/* Parses doc, which must be valid; the caller destroys the scene. */
static inline struct scene *parse_ok(const char *doc)
{
    struct scene *s = NULL;
    struct err e;
    err_clear(&e);
    enum refract_code rc = scene_parse(doc, strlen(doc), NULL, &s, &e);
    CHECK_MSG(rc == REFRACT_E_OK && s != NULL, "%s\n  -> %s", doc, e.msg);
    return s;
}

struct bad_case {
    const char *doc;
    enum refract_code code;
    const char *path; /* the message must start with this */
    const char *also; /* and contain this, when not NULL */
};

/* Parses c->doc under lim (NULL: defaults) and checks the code, that *out stays NULL,
 * and the message. */
static inline void check_bad(const struct bad_case *c, const struct scene_limits *lim)
{
    struct scene *s = (struct scene *)1;
    struct err e;
    err_clear(&e);
    enum refract_code rc = scene_parse(c->doc, strlen(c->doc), lim, &s, &e);
    CHECK_MSG(rc == c->code, "%s\n  -> code %s, expected %s: %s", c->doc, err_code_json(rc),
              err_code_json(c->code), e.msg);
    CHECK_MSG(e.code == rc, "%s: e.code %d != rc %d", c->doc, (int)e.code, (int)rc);
    CHECK_MSG(s == NULL, "%s: *out set on failure", c->doc);
    CHECK_MSG(strncmp(e.msg, c->path, strlen(c->path)) == 0,
              "%s\n  -> \"%s\" should start with \"%s\"", c->doc, e.msg, c->path);
    if (c->also != NULL)
        CHECK_MSG(strstr(e.msg, c->also) != NULL, "%s\n  -> \"%s\" lacks \"%s\"", c->doc, e.msg,
                  c->also);
    if (rc == REFRACT_E_OK)
        scene_destroy(s);
}

static inline size_t voxels(const struct scene_object *o)
{
    return (size_t)o->resolution[0] * o->resolution[1] * o->resolution[2];
}

/* Evaluates channel ch of object 0 into a new buffer; the caller frees it. */
static inline float *eval(const struct scene *s, enum scene_channel ch,
                          scene_volume_lookup_fn lookup, void *ctx)
{
    const struct scene_object *o = &s->objects[0];
    float *out = malloc(voxels(o) * (size_t)scene_channel_components(ch) * sizeof *out);
    struct err e;
    err_clear(&e);
    enum refract_code rc = scene_field_eval(s, o, ch, lookup, ctx, out, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "%s", e.msg);
    return out;
}

static inline size_t voxel_index(const struct scene_object *o, int i, int j, int k)
{
    return ((size_t)k * o->resolution[1] + (size_t)j) * o->resolution[0] + (size_t)i;
}

/* The centre of voxel (i, j, k) in object units. */
static inline vec3 centre(const struct scene_object *o, int i, int j, int k)
{
    vec3 vs = scene_object_voxel_size(o);
    return vec3_make(o->bounds_min.x + (i + 0.5) * vs.x, o->bounds_min.y + (j + 0.5) * vs.y,
                     o->bounds_min.z + (k + 0.5) * vs.z);
}

#endif
