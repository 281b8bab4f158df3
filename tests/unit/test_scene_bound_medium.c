/*
 * test_scene_bound_medium.c - the medium "object" form of a surface (docs/scenes.md
 * "Surfaces"): what the parser accepts, what it refuses (the exact code and the JSON path
 * of each refusal), the field continued beyond the surface, and the transport hash.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "scene/scene.h"
#include "scene_test_util.h"
#include "test.h"

#define LENS(bounds)                                                                               \
    "{\"name\": \"lens\", \"bounds\": {\"min\": [-" bounds ", -" bounds ", -" bounds "], "         \
    "\"max\": [" bounds ", " bounds ", " bounds "]}, \"resolution\": 16, \"ior\": {\"profile\": "  \
    "\"luneburg\", \"center\": [0, 0, 0], \"radius\": 1.0}}"
#define BALL(medium)                                                                               \
    "{\"name\": \"ball\", \"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "           \
    "\"medium\": " medium "}"

static void test_accepts_touching_and_margin_bounds(void)
{
    const char *docs[] = {
        "{\"objects\": [" LENS("1") "], \"surfaces\": [" BALL("{\"object\": \"lens\"}") "]}",
        "{\"objects\": [" LENS("1.05") "], \"surfaces\": [" BALL("{\"object\": \"lens\"}") "]}",
    };
    for (int i = 0; i < 2; i++) {
        struct scene *s = parse_ok(docs[i]);
        if (s == NULL)
            continue;
        CHECK(s->surfaces[0].medium.has_object);
        CHECK_INT(s->surfaces[0].medium.object, 0);
        CHECK(s->objects[0].bound);
        CHECK_INT(s->objects[0].bound_surface, 0);
        CHECK_INT(s->objects[0].resolution[1], 20); /* padded by two voxels a side */
        CHECK(!scene_ior_constant(&s->objects[0]));
        scene_destroy(s);
    }
}

static void test_refuses_bad_bindings(void)
{
    const struct bad_case cases[] = {
        {"{\"objects\": [" LENS("1") "], \"surfaces\": [" BALL("{\"object\": \"lense\"}") "]}",
         REFRACT_E_INVALID_FIELD, "surfaces[0].medium.object: no object named \"lense\"",
         "\"lens\""},
        {"{\"objects\": [" LENS("1") "], \"surfaces\": [" BALL("{\"object\": 3}") "]}",
         REFRACT_E_INVALID_FIELD, "surfaces[0].medium.object: expected the name of an object",
         NULL},
        {"{\"objects\": [" LENS("1") "], \"surfaces\": [" BALL(
             "{\"object\": \"lens\", \"ior\": 1.5}") "]}",
         REFRACT_E_INVALID_FIELD, "surfaces[0].medium.ior: not allowed with \"object\"", NULL},
        {"{\"objects\": [" LENS("1") "], \"surfaces\": [" BALL(
             "{\"object\": \"lens\", \"attenuation\": [1, 1, 1]}") "]}",
         REFRACT_E_INVALID_FIELD, "surfaces[0].medium.attenuation: not allowed with \"object\"",
         NULL},
        /* Does not cover the sphere. */
        {"{\"objects\": [" LENS("0.9") "], \"surfaces\": [" BALL("{\"object\": \"lens\"}") "]}",
         REFRACT_E_INVALID_FIELD,
         "surfaces[0].medium.object: objects[0] (\"lens\")'s bounds do "
         "not cover the surface's solid",
         "contain that box"},
        /* One object, two surfaces. */
        {"{\"objects\": [" LENS("3") "], \"surfaces\": [" BALL(
             "{\"object\": \"lens\"}") ", "
                                       "{\"shape\": \"box\", \"center\": [0, 0, 2.5], \"size\": "
                                       "[1, 1, 1], \"medium\": "
                                       "{\"object\": \"lens\"}}]}",
         REFRACT_E_INVALID_FIELD,
         "surfaces[0].medium.object: objects[0] (\"lens\") already fills "
         "surfaces[1]",
         NULL},
        /* A plane's solid is unbounded. */
        {"{\"objects\": [" LENS("1") "], \"surfaces\": [{\"shape\": \"plane\", \"normal\": [0, 1, "
                                     "0], \"medium\": {\"object\": \"lens\"}}]}",
         REFRACT_E_INVALID_FIELD, "surfaces[0].medium.object: the plane's solid is unbounded",
         NULL},
        /* Another surface still may not overlap the bound object. */
        {"{\"objects\": [" LENS("1.5") "], \"surfaces\": [" BALL(
             "{\"object\": \"lens\"}") ", "
                                       "{\"shape\": \"box\", \"center\": [1.2, 0, 0], \"size\": "
                                       "[0.2, 0.2, 0.2], \"medium\": "
                                       "{\"ior\": 1.5}}]}",
         REFRACT_E_INVALID_FIELD, "surfaces[1]: its solid may overlap objects[0] (\"lens\")", NULL},
        /* The light simulator does not bend inside surfaces (asked for explicitly; "auto"
         * then chooses "none", tested below). */
        {"{\"objects\": [" LENS("1") "], \"surfaces\": [" BALL(
             "{\"object\": \"lens\"}") "], "
                                       "\"receiver\": {\"height\": -1.5, \"caustics\": "
                                       "\"volume\"}}",
         REFRACT_E_INVALID_FIELD, "receiver: needs the light simulator", "\"lens\""},
        /* ... nor does a scattering surface medium beside a field-filled surface. */
        {"{\"objects\": [" LENS("1") "], \"surfaces\": [" BALL(
             "{\"object\": \"lens\"}") ", "
                                       "{\"shape\": \"box\", \"center\": [0, 0, 2.5], \"size\": "
                                       "[1, 1, 1], \"medium\": {\"ior\": 1.3, \"scattering\": "
                                       "[0.1, 0.1, 0.1]}}]}",
         REFRACT_E_INVALID_FIELD, "surfaces[1].medium.scattering: needs the light simulator",
         "\"lens\""},
        /* Opaque embeddings are not modelled inside a surface. */
        {"{\"objects\": [{\"name\": \"lens\", " BOUNDS ", \"resolution\": 8, \"ior\": 1.5, "
         "\"opaque\": {\"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 0.2, "
         "\"inside\": [1, 0, 0]}}], \"surfaces\": [" BALL("{\"object\": \"lens\"}") "]}",
         REFRACT_E_INVALID_FIELD, "objects[0].opaque: objects[0] (\"lens\") fills surfaces[0]",
         NULL},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        check_bad(&cases[i], NULL);
}

/* The voxels just outside the sphere continue the inside field linearly: along the +x row
 * through the centre, the first voxel outside is 2 v1 - v2 of the two inside voxels before
 * it (its only axis with two known neighbours), and n keeps falling outwards where the
 * layers say n = 1. */
static void test_field_continues_beyond_surface(void)
{
    struct scene *s = parse_ok(
        "{\"objects\": [" LENS("1.25") "], \"surfaces\": [" BALL("{\"object\": \"lens\"}") "]}");
    struct scene *free_s = parse_ok("{\"objects\": [" LENS("1.25") "]}");
    if (s == NULL || free_s == NULL)
        return;
    float *bound = eval(s, SCENE_CH_IOR, NULL, NULL), *raw = eval(free_s, SCENE_CH_IOR, NULL, NULL);
    const struct scene_object *o = &s->objects[0], *fo = &free_s->objects[0];
    /* The bound grid has two more voxels on each side, at the same voxel centres. */
    CHECK_INT(o->resolution[0], fo->resolution[0] + 4);
    CHECK_NEAR(o->bounds_max.x, fo->bounds_max.x + 2 * 2.5 / 16, 1e-12);
    int j = 8, k = 8, first_out = -1;
    double yz = -1.25 + (j + 0.5) * 2.5 / 16;
    for (int i = 8; i < 16; i++) {
        double x = -1.25 + (i + 0.5) * 2.5 / 16;
        double r = sqrt(x * x + 2.0 * yz * yz);
        size_t vb = voxel_index(o, i + 2, j + 2, k + 2), v = voxel_index(fo, i, j, k);
        if (r < 1.0) {
            CHECK_NEAR(bound[vb], raw[v], 0.0); /* inside: untouched */
            continue;
        }
        CHECK_MSG(raw[v] == 1.0f, "the layers give n = 1 outside, got %g", raw[v]);
        if (first_out < 0) {
            first_out = i;
            CHECK_NEAR(bound[vb], 2.0 * raw[v - 1] - raw[v - 2], 1e-6);
        } else {
            CHECK_MSG(bound[vb] < bound[vb - 1], "x = %g: n %g not below %g", x, bound[vb],
                      bound[vb - 1]);
        }
    }
    CHECK(first_out > 8 && first_out < 15);
    free(bound);
    free(raw);
    scene_destroy(s);
    scene_destroy(free_s);
}

/* The cache key covers the medium reference: the same object bound or free, constant media
 * as before. */
static void test_transport_hash_covers_binding(void)
{
    struct scene *a = parse_ok("{\"objects\": [" LENS(
        "1") ", {\"name\": \"other\", \"bounds\": "
             "{\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, "
             "\"ior\": {\"profile\": \"luneburg\", \"center\": [0, 0, 0], "
             "\"radius\": 1.0}, \"transform\": {\"translate\": [5, 0, 0]}}], "
             "\"surfaces\": [" BALL("{\"object\": \"lens\"}") "]}");
    struct scene *b = parse_ok("{\"objects\": [" LENS(
        "1") ", {\"name\": \"other\", \"bounds\": "
             "{\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, "
             "\"ior\": {\"profile\": \"luneburg\", \"center\": [0, 0, 0], "
             "\"radius\": 1.0}, \"transform\": {\"translate\": [5, 0, 0]}}], "
             "\"surfaces\": [{\"name\": \"ball\", \"shape\": \"sphere\", "
             "\"center\": [5, 0, 0], \"radius\": 1, \"medium\": {\"object\": "
             "\"other\"}}]}");
    struct scene *c = parse_ok("{\"objects\": [" LENS(
        "1") ", {\"name\": \"other\", \"bounds\": "
             "{\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, "
             "\"ior\": {\"profile\": \"luneburg\", \"center\": [0, 0, 0], "
             "\"radius\": 1.0}, \"transform\": {\"translate\": [5, 0, 0]}}], "
             "\"surfaces\": [" BALL("{\"object\": \"lens\"}") "]}");
    /* Only the binding differs between a and b; a and c are the same scene. */
    if (a && b && c) {
        CHECK(scene_transport_hash(a) != scene_transport_hash(b));
        CHECK(scene_transport_hash(a) == scene_transport_hash(c));
    }
    scene_destroy(a);
    scene_destroy(b);
    scene_destroy(c);
}

int main(void)
{
    test_accepts_touching_and_margin_bounds();
    test_refuses_bad_bindings();
    test_field_continues_beyond_surface();
    test_transport_hash_covers_binding();
    return test_summary("test_scene_bound_medium");
}
