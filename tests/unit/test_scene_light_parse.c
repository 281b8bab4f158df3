/*
 * test_scene_light_parse.c - scene_parse of the keys issue 3 added: "lights", "receiver",
 * "lightsim", each object's "brdf", the "scattering" and "anisotropy" channels and the
 * bumpy_sphere shape. Defaults (also when the key is absent), what every key becomes,
 * and the exact code and path of every validation rule.
 */
#include <string.h>

#include "scene/scene.h"
#include "scene_test_util.h"
#include "test.h"

#define LIGHTS(list) TOP("\"lights\": [" list "]")
#define SUN "{\"type\": \"directional\", \"direction\": [0, -1, 0]}"
#define BUMPY "\"shape\": \"bumpy_sphere\", \"radius\": 0.5"

/* clang-format off */
static const struct bad_case bad_cases[] = {
    /* lights */
    {TOP("\"lights\": {}"), REFRACT_E_INVALID_FIELD, "lights: expected an array of 0..4", NULL},
    {LIGHTS(SUN "," SUN "," SUN "," SUN "," SUN), REFRACT_E_INVALID_FIELD, "lights:",
     "an array of 5 values"},
    {LIGHTS("7"), REFRACT_E_INVALID_FIELD, "lights[0]: expected a light object", NULL},
    {LIGHTS("{\"direction\": [0, -1, 0]}"), REFRACT_E_MISSING_FIELD,
     "lights[0]: missing required field \"type\"", NULL},
    {LIGHTS("{\"type\": \"area\"}"), REFRACT_E_INVALID_FIELD, "lights[0].type",
     "\"directional\", \"point\", \"spot\""},
    {LIGHTS("{\"type\": \"directional\"}"), REFRACT_E_MISSING_FIELD,
     "lights[0]: missing required field \"direction\"", NULL},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, 0, 0]}"), REFRACT_E_INVALID_FIELD,
     "lights[0].direction", "non-zero"},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1]}"), REFRACT_E_INVALID_FIELD,
     "lights[0].direction", NULL},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1, 0], \"position\": [0, 1, 0]}"),
     REFRACT_E_UNKNOWN_FIELD, "lights[0]: unknown field \"position\"",
     "allowed: name, type, direction, color, intensity"},
    {LIGHTS("{\"type\": \"point\"}"), REFRACT_E_MISSING_FIELD,
     "lights[0]: missing required field \"position\"", NULL},
    {LIGHTS("{\"type\": \"point\", \"position\": [0, 2, 0], \"direction\": [0, -1, 0]}"),
     REFRACT_E_UNKNOWN_FIELD, "lights[0]: unknown field \"direction\"",
     "allowed: name, type, position, color, intensity"},
    {LIGHTS("{\"type\": \"point\", \"position\": [0, 2e7, 0]}"), REFRACT_E_INVALID_FIELD,
     "lights[0].position[1]", NULL},
    {LIGHTS("{\"type\": \"spot\", \"position\": [0, 2, 0]}"), REFRACT_E_MISSING_FIELD,
     "lights[0]: missing required field \"direction\"", NULL},
    {LIGHTS("{\"type\": \"spot\", \"direction\": [0, -1, 0]}"), REFRACT_E_MISSING_FIELD,
     "lights[0]: missing required field \"position\"", NULL},
    {LIGHTS("{\"type\": \"spot\", \"position\": [0, 2, 0], \"direction\": [0, -1, 0], "
            "\"angle_deg\": 90}"),
     REFRACT_E_INVALID_FIELD, "lights[0].angle_deg", "1..89"},
    {LIGHTS("{\"type\": \"spot\", \"position\": [0, 2, 0], \"direction\": [0, -1, 0], "
            "\"angle_deg\": 0.5}"),
     REFRACT_E_INVALID_FIELD, "lights[0].angle_deg", NULL},
    {LIGHTS("{\"type\": \"spot\", \"position\": [0, 2, 0], \"direction\": [0, -1, 0], "
            "\"angle\": 20}"),
     REFRACT_E_UNKNOWN_FIELD, "lights[0]: unknown field \"angle\"",
     "allowed: name, type, position, direction, angle_deg, color, intensity"},
    {LIGHTS("{\"type\": \"directional\", \"angle_deg\": 20, \"direction\": [0, -1, 0]}"),
     REFRACT_E_UNKNOWN_FIELD, "lights[0]: unknown field \"angle_deg\"", NULL},
    {LIGHTS(SUN ", {\"type\": \"directional\", \"direction\": [0, -1, 0], \"color\": 1001}"),
     REFRACT_E_INVALID_FIELD, "lights[1].color", "0..1000"},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1, 0], \"color\": [1, -1, 1]}"),
     REFRACT_E_INVALID_FIELD, "lights[0].color[1]", NULL},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1, 0], \"color\": [1, 1]}"),
     REFRACT_E_INVALID_FIELD, "lights[0].color", "[r, g, b]"},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1, 0], \"color\": \"white\"}"),
     REFRACT_E_INVALID_FIELD, "lights[0].color", "got \"white\""},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1, 0], \"intensity\": -1}"),
     REFRACT_E_INVALID_FIELD, "lights[0].intensity", "0..1000000"},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1, 0], \"intensity\": 2e6}"),
     REFRACT_E_INVALID_FIELD, "lights[0].intensity", NULL},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1, 0], \"name\": \"Sun\"}"),
     REFRACT_E_INVALID_FIELD, "lights[0].name", "a-z 0-9 _ -"},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1, 0], \"name\": \"\"}"),
     REFRACT_E_INVALID_FIELD, "lights[0].name", "1..63"},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1, 0], \"name\": \"a/b\"}"),
     REFRACT_E_INVALID_FIELD, "lights[0].name", NULL},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1, 0], \"name\": "
            "\"a234567890123456789012345678901234567890123456789012345678901234\"}"),
     REFRACT_E_INVALID_FIELD, "lights[0].name", NULL},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1, 0], \"name\": 3}"),
     REFRACT_E_INVALID_FIELD, "lights[0].name", "got 3"},
    {LIGHTS("{\"type\": \"directional\", \"direction\": [0, -1, 0], \"name\": \"sun\"},"
            "{\"type\": \"point\", \"position\": [0, 2, 0], \"name\": \"sun\"}"),
     REFRACT_E_INVALID_FIELD, "lights[1].name: \"sun\" is already the name of lights[0]", NULL},
    /* an explicit name that equals another light's default name */
    {LIGHTS(SUN ", {\"type\": \"point\", \"position\": [0, 2, 0], \"name\": \"light0\"}"),
     REFRACT_E_INVALID_FIELD, "lights[1].name: \"light0\"", "unique"},
    /* receiver */
    {TOP("\"receiver\": {}"), REFRACT_E_MISSING_FIELD,
     "receiver: missing required field \"height\"", NULL},
    {TOP("\"receiver\": true"), REFRACT_E_INVALID_FIELD, "receiver: expected an object", NULL},
    {TOP("\"receiver\": {\"height\": \"low\"}"), REFRACT_E_INVALID_FIELD, "receiver.height",
     NULL},
    {TOP("\"receiver\": {\"height\": -1, \"half_size\": 0}"), REFRACT_E_INVALID_FIELD,
     "receiver.half_size", "> 0"},
    {TOP("\"receiver\": {\"height\": -1, \"albedo\": 1.2}"), REFRACT_E_INVALID_FIELD,
     "receiver.albedo", "0..1"},
    /* A plane through an object's bounds would be unseen inside them (a square hole). */
    {TOP("\"receiver\": {\"height\": -0.5}"), REFRACT_E_INVALID_FIELD,
     "receiver.height: -0.5 is above the bottom of object 0", "at or below y = -1"},
    {TOP("\"receiver\": {\"height\": -1, \"albedo\": [0.5, 0.5, 2]}"), REFRACT_E_INVALID_FIELD,
     "receiver.albedo[2]", NULL},
    {TOP("\"receiver\": {\"height\": -1, \"photons\": 4096, \"photons_max\": 2048}"),
     REFRACT_E_INVALID_FIELD, "receiver.photons_max", "4096"},
    {TOP("\"receiver\": {\"height\": -1, \"photons_max\": 1e9}"), REFRACT_E_INVALID_FIELD,
     "receiver.photons_max", "67108864"},
    {TOP("\"receiver\": {\"height\": -1, \"size\": 2}"), REFRACT_E_UNKNOWN_FIELD,
     "receiver: unknown field \"size\"", "allowed: height, half_size, center, albedo"},
    /* lightsim */
    {TOP("\"lightsim\": []"), REFRACT_E_INVALID_FIELD, "lightsim: expected an object", NULL},
    {TOP("\"lightsim\": {\"resolution\": 4}"), REFRACT_E_INVALID_FIELD, "lightsim.resolution",
     "8..512"},
    {TOP("\"lightsim\": {\"resolution\": 64.5}"), REFRACT_E_INVALID_FIELD,
     "lightsim.resolution", NULL},
    {TOP("\"lightsim\": {\"resolution\": 513}"), REFRACT_E_INVALID_FIELD, "lightsim.resolution",
     NULL},
    {TOP("\"lightsim\": {\"step\": 0.01}"), REFRACT_E_INVALID_FIELD, "lightsim.step",
     "0.05..4"},
    {TOP("\"lightsim\": {\"initial_patches\": 1}"), REFRACT_E_INVALID_FIELD,
     "lightsim.initial_patches", "2..1024"},
    {TOP("\"lightsim\": {\"max_level\": 13}"), REFRACT_E_INVALID_FIELD, "lightsim.max_level",
     "0..12"},
    {TOP("\"lightsim\": {\"split\": 9}"), REFRACT_E_INVALID_FIELD, "lightsim.split", "0.1..8"},
    {TOP("\"lightsim\": {\"energy_threshold\": 1.5}"), REFRACT_E_INVALID_FIELD,
     "lightsim.energy_threshold", "0..1"},
    {TOP("\"lightsim\": {\"point_radius\": 0}"), REFRACT_E_INVALID_FIELD,
     "lightsim.point_radius", "> 0 and <= 1000"},
    {TOP("\"lightsim\": {\"deposit\": \"sum\"}"), REFRACT_E_INVALID_FIELD, "lightsim.deposit",
     "\"flux\", \"max\""},
    {TOP("\"lightsim\": {\"cull_flipped\": 1}"), REFRACT_E_INVALID_FIELD,
     "lightsim.cull_flipped", NULL},
    {TOP("\"lightsim\": {\"max_patches\": 1000}"), REFRACT_E_INVALID_FIELD,
     "lightsim.max_patches", "1024..1048576"},
    {TOP("\"lightsim\": {\"patches\": 64}"), REFRACT_E_UNKNOWN_FIELD,
     "lightsim: unknown field \"patches\"",
     "allowed: resolution, step, initial_patches, max_level, split, energy_threshold, "
     "point_radius, deposit, cull_flipped, max_patches"},
    /* brdf */
    {OBJ("\"ior\": 1.5, \"brdf\": \"ggx\""), REFRACT_E_INVALID_FIELD,
     "objects[0].brdf: expected an object", NULL},
    {OBJ("\"ior\": 1.5, \"brdf\": {\"type\": \"blinn\"}"), REFRACT_E_INVALID_FIELD,
     "objects[0].brdf.type", "\"none\", \"lambert\", \"phong\", \"ggx\""},
    {OBJ("\"ior\": 1.5, \"brdf\": {\"roughness\": 0}"), REFRACT_E_INVALID_FIELD,
     "objects[0].brdf.roughness", "0.01..1"},
    {OBJ("\"ior\": 1.5, \"brdf\": {\"exponent\": 0.5}"), REFRACT_E_INVALID_FIELD,
     "objects[0].brdf.exponent", "1..10000"},
    {OBJ("\"ior\": 1.5, \"brdf\": {\"color\": [1, 1, 1.5]}"), REFRACT_E_INVALID_FIELD,
     "objects[0].brdf.color[2]", "0..1"},
    {OBJ("\"ior\": 1.5, \"brdf\": {\"colour\": 1}"), REFRACT_E_UNKNOWN_FIELD,
     "objects[0].brdf: unknown field \"colour\"", "allowed: type, color, roughness, exponent"},
    /* scattering and anisotropy */
    {OBJ("\"scattering\": -0.1"), REFRACT_E_INVALID_FIELD, "objects[0].scattering",
     "0..100000"},
    {OBJ("\"scattering\": [0.1, 0.2, 2e5]"), REFRACT_E_INVALID_FIELD,
     "objects[0].scattering[2]", NULL},
    {OBJ("\"scattering\": \"fog\""), REFRACT_E_INVALID_FIELD, "objects[0].scattering",
     "a number or [r, g, b]"},
    {OBJ("\"scattering\": {\"profile\": \"luneburg\", \"radius\": 1}"), REFRACT_E_INVALID_FIELD,
     "objects[0].scattering: GRIN profiles apply only to ior", NULL},
    {OBJ("\"scattering\": 1, \"anisotropy\": 1"), REFRACT_E_INVALID_FIELD,
     "objects[0].anisotropy", "-0.99..0.99"},
    {OBJ("\"scattering\": 1, \"anisotropy\": -0.995"), REFRACT_E_INVALID_FIELD,
     "objects[0].anisotropy", NULL},
    /* an array of numbers is a list of constant layers in a scalar channel, as in ior */
    {OBJ("\"scattering\": 1, \"anisotropy\": [0.2, 0.3, 1.5]"), REFRACT_E_INVALID_FIELD,
     "objects[0].anisotropy[2]", "-0.99..0.99"},
    {OBJ("\"scattering\": 1, \"anisotropy\": {" BUMPY ", \"inside\": 0.5, \"outside\": 2}"),
     REFRACT_E_INVALID_FIELD, "objects[0].anisotropy.outside", NULL},
    {OBJ("\"anisotropy\": 0.3"), REFRACT_E_MISSING_FIELD,
     "objects[0]: an object needs at least one of ior, attenuation, emission, opaque, "
     "scattering",
     NULL},
    {OBJ("\"ior\": 1.5, \"anisotropy\": 0.3"), REFRACT_E_INVALID_FIELD,
     "objects[0].anisotropy: has no effect without scattering", NULL},
    /* bumpy_sphere */
    {OBJ("\"ior\": {\"shape\": \"bumpy_sphere\", \"inside\": 1.5}"), REFRACT_E_MISSING_FIELD,
     "objects[0].ior: missing required field \"radius\"", NULL},
    {OBJ("\"ior\": {\"shape\": \"bumpy_sphere\", \"radius\": -1, \"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.radius", NULL},
    {OBJ("\"ior\": {" BUMPY ", \"bump_amplitude\": 0.3, \"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.bump_amplitude", "0..0.25"},
    {OBJ("\"ior\": {" BUMPY ", \"bump_amplitude\": -0.1, \"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.bump_amplitude", NULL},
    {OBJ("\"ior\": {" BUMPY ", \"bump_frequency\": 0, \"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.bump_frequency", "1..32"},
    {OBJ("\"ior\": {" BUMPY ", \"bump_frequency\": 33, \"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.bump_frequency", NULL},
    {OBJ("\"ior\": {" BUMPY ", \"bump_frequency\": 2.5, \"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.bump_frequency", "integer"},
    {OBJ("\"ior\": {" BUMPY ", \"size\": [1, 1, 1], \"inside\": 1.5}"), REFRACT_E_UNKNOWN_FIELD,
     "objects[0].ior: unknown field \"size\"",
     "allowed: shape, center, radius, bump_amplitude, bump_frequency, inside, outside"},
    {OBJ("\"ior\": {\"shape\": \"blob\", \"radius\": 0.5, \"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.shape", "\"bumpy_sphere\""},
};
/* clang-format on */

static void rejects_each_bad_document_with_exact_code_and_path(void)
{
    for (size_t i = 0; i < sizeof bad_cases / sizeof bad_cases[0]; i++)
        check_bad(&bad_cases[i], NULL);
}

static void without_the_new_keys_there_are_no_lights_no_receiver_and_default_settings(void)
{
    struct scene *s = parse_ok(OBJ("\"ior\": 1.5"));
    if (s == NULL)
        return;
    CHECK_INT(s->light_count, 0);
    CHECK(!s->receiver.enabled);
    const struct scene_lightsim *ls = &s->lightsim;
    CHECK_INT(ls->resolution, 64);
    CHECK_NEAR(ls->step_voxels, 0.5, 0);
    CHECK_INT(ls->initial_patches, 64);
    CHECK_INT(ls->max_level, 6);
    CHECK_NEAR(ls->split_voxels, 1.0, 0);
    CHECK_NEAR(ls->energy_threshold, 1e-4, 0);
    CHECK_NEAR(ls->point_radius, 0.01, 0);
    CHECK_INT(ls->deposit, SCENE_DEPOSIT_FLUX);
    CHECK(!ls->cull_flipped);
    CHECK_INT(ls->max_patches, 262144);
    const struct scene_brdf *b = &s->objects[0].brdf;
    CHECK_INT(b->kind, SCENE_BRDF_GGX);
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(b->color[c], 1.0, 0);
    CHECK_NEAR(b->roughness, 0.1, 0);
    CHECK_NEAR(b->exponent, 200.0, 0);
    CHECK(!scene_channel_used(&s->objects[0], SCENE_CH_SCATTERING));
    CHECK(!scene_channel_used(&s->objects[0], SCENE_CH_ANISOTROPY));
    scene_destroy(s);
}

static void reads_each_light_type_with_defaults(void)
{
    struct scene *s = parse_ok(LIGHTS(
        "{\"type\": \"directional\", \"direction\": [0, -2, 0]},"
        "{\"name\": \"bulb\", \"type\": \"point\", \"position\": [1, 2, 3], \"color\": 0.5, "
        "\"intensity\": 7},"
        "{\"type\": \"spot\", \"position\": [0, 2, 0], \"direction\": [3, -4, 0]},"
        "{\"name\": \"s-2_b\", \"type\": \"spot\", \"position\": [0, 2, 0], \"direction\": [0, -1, "
        "0], \"angle_deg\": 25, \"color\": [1, 0.5, 1000]}"));
    if (s == NULL)
        return;
    CHECK_INT(s->light_count, 4);
    const struct scene_light *l = s->lights;
    CHECK_STR(l[0].name, "light0");
    CHECK_INT(l[0].kind, SCENE_LIGHT_DIRECTIONAL);
    CHECK_NEAR(l[0].direction.y, -1.0, 1e-15); /* normalised */
    CHECK_NEAR(l[0].intensity, 1.0, 0);
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(l[0].color[c], 1.0, 0);
    CHECK_STR(l[1].name, "bulb");
    CHECK_INT(l[1].kind, SCENE_LIGHT_POINT);
    CHECK_NEAR(l[1].position.z, 3.0, 0);
    CHECK_NEAR(l[1].color[2], 0.5, 0); /* a number is grey */
    CHECK_NEAR(l[1].intensity, 7.0, 0);
    CHECK_STR(l[2].name, "light2");
    CHECK_INT(l[2].kind, SCENE_LIGHT_SPOT);
    CHECK_NEAR(l[2].spot_angle_deg, 30.0, 0);
    CHECK_NEAR(l[2].direction.x, 0.6, 1e-15);
    CHECK_NEAR(l[2].direction.y, -0.8, 1e-15);
    CHECK_STR(l[3].name, "s-2_b");
    CHECK_NEAR(l[3].spot_angle_deg, 25.0, 0);
    CHECK_NEAR(l[3].color[1], 0.5, 0);
    CHECK_NEAR(l[3].color[2], 1000.0, 0);
    scene_destroy(s);

    s = parse_ok(TOP("\"lights\": []"));
    if (s != NULL)
        CHECK_INT(s->light_count, 0);
    scene_destroy(s);
}

static void receiver_defaults_follow_the_objects_world_bounds(void)
{
    /* Object bounds [-1, 1]^3 scaled by 2 and moved by (3, 0, -0.5): x reaches 5, z 2.5. */
    struct scene *s = parse_ok(
        "{\"receiver\": {\"height\": -2}, \"objects\": [{" BOUNDS ", \"ior\": 1.5, "
        "\"transform\": {\"translate\": [3, 0, -0.5], \"scale\": 2}}, {\"bounds\": {\"min\": "
        "[0, 0, -4], \"max\": [1, 1, -3]}, \"opaque\": 1}]}");
    if (s != NULL) {
        CHECK(s->receiver.enabled);
        CHECK_NEAR(s->receiver.height, -2.0, 0);
        CHECK_NEAR(s->receiver.half_size, 1.5 * 5.0, 1e-12);
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(s->receiver.albedo[c], 0.8, 0);
        /* docs/photons.md "Choosing": a voxel object's caustics are the light simulator's */
        CHECK_INT((int)s->receiver.caustics, SCENE_CAUSTICS_VOLUME);
        CHECK(s->receiver.caustics_auto);
        CHECK_INT(s->receiver.photons, 1048576);
        CHECK_NEAR(s->receiver.photon_radius, 0.0, 0);
        CHECK(scene_needs_light_simulation(s));
        scene_destroy(s);
    }
    /* The second object's z = -4 now reaches further than the first's x. */
    s = parse_ok(
        "{\"receiver\": {\"height\": -2, \"albedo\": [0.1, 0.2, 0.3]}, \"objects\": [{" BOUNDS
        ", \"ior\": 1.5}, {\"bounds\": {\"min\": [0, 0, -4], \"max\": [1, 1, -3]}, "
        "\"opaque\": 1}]}");
    if (s != NULL) {
        CHECK_NEAR(s->receiver.half_size, 6.0, 1e-12);
        CHECK_NEAR(s->receiver.albedo[0], 0.1, 0);
        CHECK_NEAR(s->receiver.albedo[2], 0.3, 0);
        scene_destroy(s);
    }
    s = parse_ok("{\"receiver\": {\"height\": -1.5, \"half_size\": 2, \"albedo\": 0.25, "
                 "\"caustics\": \"photons\", \"photons\": 4096, \"photon_radius\": 0.01}, "
                 "\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": "
                 "{\"ior\": 1.5}}]}");
    if (s != NULL) {
        CHECK_INT((int)s->receiver.caustics, SCENE_CAUSTICS_PHOTONS);
        CHECK_INT(s->receiver.photons, 4096);
        CHECK_INT(s->receiver.photons_max, 4096); /* default: photons, no further passes */
        CHECK_NEAR(s->receiver.photon_radius, 0.01, 0);
        CHECK(!scene_needs_light_simulation(s)); /* photons and shadow rays: no volume */
        CHECK_NEAR(s->receiver.half_size, 2.0, 0);
        CHECK_NEAR(s->receiver.albedo[1], 0.25, 0);
        scene_destroy(s);
    }
}

/* The receiver's "auto" caustics (the default; docs/photons.md "Choosing"): the method the
 * scene needs, and why; an explicit method is kept (or refused when it cannot work). */
static void auto_caustics_choose_what_the_scene_needs(void)
{
#define RECV "\"receiver\": {\"height\": -2}"
#define LENS_OBJ                                                                                  \
    "{\"name\": \"lens\", \"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "            \
    "\"resolution\": 8, \"ior\": {\"profile\": \"luneburg\", \"center\": [0, 0, 0], \"radius\": 1}}"
    static const struct {
        const char *doc;
        enum scene_caustics want;
        const char *reason;
    } cases[] = {
        {"{" RECV ", \"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": "
         "{\"ior\": 1.5}}]}",
         SCENE_CAUSTICS_PHOTONS, "exact surfaces"},
        {"{" RECV ", \"surfaces\": [{\"shape\": \"box\", \"size\": [1, 1, 1], \"medium\": "
         "{\"ior\": 1, \"attenuation\": [0.5, 0, 0]}}]}", /* absorbing only: still optical */
         SCENE_CAUSTICS_PHOTONS, "exact surfaces"},
        {"{" RECV ", \"objects\": [{" BOUNDS ", \"ior\": 1.5}]}", SCENE_CAUSTICS_VOLUME,
         "volume object"},
        {"{" RECV ", \"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": "
         "{\"ior\": 1.3, \"scattering\": [0.5, 0.5, 0.5]}}]}",
         SCENE_CAUSTICS_VOLUME, "scattering"},
        {"{\"receiver\": {\"height\": -2, \"half_size\": 3}, \"surfaces\": [{\"shape\": "
         "\"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0], \"medium\": {\"ior\": "
         "1.33}}]}",
         SCENE_CAUSTICS_VOLUME, "infinite"},
        {"{" RECV ", \"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": "
         "{\"ior\": 1}}]}", /* index-matched, clear: nothing to trace */
         SCENE_CAUSTICS_NONE, "no surface"},
        {"{" RECV ", \"objects\": [" LENS_OBJ "], \"surfaces\": [{\"shape\": \"sphere\", "
         "\"radius\": 1, \"medium\": {\"object\": \"lens\"}}]}",
         SCENE_CAUSTICS_NONE, "field"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        struct scene *s = parse_ok(cases[i].doc);
        if (s == NULL)
            continue;
        CHECK_MSG(s->receiver.caustics == cases[i].want && s->receiver.caustics_auto,
                  "case %zu: caustics %d (%s), want %d", i, (int)s->receiver.caustics,
                  s->receiver.caustics_reason, (int)cases[i].want);
        CHECK_CONTAINS(s->receiver.caustics_reason, cases[i].reason);
        CHECK(scene_needs_light_simulation(s) == (cases[i].want == SCENE_CAUSTICS_VOLUME));
        CHECK(scene_needs_photon_maps(s) == (cases[i].want == SCENE_CAUSTICS_PHOTONS));
        CHECK(scene_receiver_shadow_rays(s) == (cases[i].want != SCENE_CAUSTICS_VOLUME));
        scene_destroy(s);
    }
    /* Explicit methods are kept: "volume" for exact surfaces, "none". */
    struct scene *s = parse_ok("{\"receiver\": {\"height\": -2, \"caustics\": \"volume\"}, "
                               "\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, "
                               "\"medium\": {\"ior\": 1.5}}]}");
    if (s != NULL) {
        CHECK_INT((int)s->receiver.caustics, SCENE_CAUSTICS_VOLUME);
        CHECK(!s->receiver.caustics_auto);
        CHECK_CONTAINS(s->receiver.caustics_reason, "document");
        scene_destroy(s);
    }
    s = parse_ok("{\"receiver\": {\"height\": -2, \"caustics\": \"none\"}, \"surfaces\": "
                 "[{\"shape\": \"sphere\", \"radius\": 1, \"medium\": {\"ior\": 1.5}}]}");
    if (s != NULL) {
        CHECK_INT((int)s->receiver.caustics, SCENE_CAUSTICS_NONE);
        CHECK(!scene_needs_photon_maps(s) && !scene_needs_light_simulation(s));
        CHECK(scene_receiver_shadow_rays(s));
        scene_destroy(s);
    }
#undef RECV
#undef LENS_OBJ
}

static void reads_every_lightsim_setting(void)
{
    struct scene *s = parse_ok(
        TOP("\"lightsim\": {\"resolution\": 96, \"step\": 0.25, \"initial_patches\": 128, "
            "\"max_level\": 0, \"split\": 2.5, \"energy_threshold\": 0, \"point_radius\": 0.5, "
            "\"deposit\": \"max\", \"cull_flipped\": true, \"max_patches\": 1024}"));
    if (s == NULL)
        return;
    const struct scene_lightsim *ls = &s->lightsim;
    CHECK_INT(ls->resolution, 96);
    CHECK_NEAR(ls->step_voxels, 0.25, 0);
    CHECK_INT(ls->initial_patches, 128);
    CHECK_INT(ls->max_level, 0);
    CHECK_NEAR(ls->split_voxels, 2.5, 0);
    CHECK_NEAR(ls->energy_threshold, 0.0, 0);
    CHECK_NEAR(ls->point_radius, 0.5, 0);
    CHECK_INT(ls->deposit, SCENE_DEPOSIT_MAX);
    CHECK(ls->cull_flipped);
    CHECK_INT(ls->max_patches, 1024);
    scene_destroy(s);
    /* A partial block keeps the other defaults. */
    s = parse_ok(TOP("\"lightsim\": {\"max_level\": 12}"));
    if (s != NULL) {
        CHECK_INT(s->lightsim.max_level, 12);
        CHECK_INT(s->lightsim.resolution, 64);
        CHECK_INT(s->lightsim.max_patches, 262144);
        scene_destroy(s);
    }
}

static void reads_each_brdf_type(void)
{
    static const struct {
        const char *name;
        enum scene_brdf_kind kind;
    } types[] = {{"none", SCENE_BRDF_NONE},
                 {"lambert", SCENE_BRDF_LAMBERT},
                 {"phong", SCENE_BRDF_PHONG},
                 {"ggx", SCENE_BRDF_GGX}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++) {
        char doc[512];
        snprintf(doc, sizeof doc,
                 OBJ("\"ior\": 1.5, \"brdf\": {\"type\": \"%s\", \"color\": [0.5, 0.25, 1], "
                     "\"roughness\": 0.01, \"exponent\": 10000}"),
                 types[i].name);
        struct scene *s = parse_ok(doc);
        if (s == NULL)
            continue;
        const struct scene_brdf *b = &s->objects[0].brdf;
        CHECK_INT(b->kind, types[i].kind);
        CHECK_NEAR(b->color[1], 0.25, 0);
        CHECK_NEAR(b->roughness, 0.01, 0);
        CHECK_NEAR(b->exponent, 10000.0, 0);
        scene_destroy(s);
    }
}

static void reads_scattering_and_anisotropy_values_and_layers(void)
{
    struct scene *s = parse_ok(OBJ("\"scattering\": 0.3"));
    if (s != NULL) {
        const struct scene_layer *l = &s->objects[0].fields[SCENE_CH_SCATTERING].layers[0];
        CHECK_INT(l->kind, SCENE_LAYER_CONSTANT);
        CHECK_NEAR(l->inside[0], 0.3, 0);
        CHECK_NEAR(l->inside[2], 0.3, 0); /* grey */
        CHECK_NEAR(l->inside[3], 0.0, 0);
        scene_destroy(s);
    }
    s = parse_ok(OBJ("\"ior\": 1.5, \"scattering\": [[0.1, 0.2, 0.3], {\"shape\": \"sphere\", "
                     "\"radius\": 0.5, \"inside\": 0}], \"anisotropy\": [-0.5, {" BUMPY
                     ", \"inside\": 0.99}]"));
    if (s != NULL) {
        const struct scene_field *f = &s->objects[0].fields[SCENE_CH_SCATTERING];
        CHECK_INT(f->count, 2);
        CHECK_NEAR(f->layers[0].inside[1], 0.2, 0);
        CHECK_INT(f->layers[1].kind, SCENE_LAYER_SHAPE);
        const struct scene_field *g = &s->objects[0].fields[SCENE_CH_ANISOTROPY];
        CHECK_INT(g->count, 2);
        CHECK_NEAR(g->layers[0].inside[0], -0.5, 0);
        CHECK_NEAR(g->layers[0].inside[1], 0.0, 0); /* scalar, not grey */
        CHECK_NEAR(g->layers[1].inside[0], 0.99, 0);
        CHECK_INT(g->layers[1].shape.kind, SCENE_SHAPE_BUMPY_SPHERE);
        scene_destroy(s);
    }
    s = parse_ok(OBJ("\"scattering\": {\"volume\": \"smoke\", \"scale\": 2}, \"anisotropy\": "
                     "{\"volume\": \"g\"}"));
    if (s != NULL) {
        CHECK_STR(s->objects[0].fields[SCENE_CH_SCATTERING].layers[0].volume, "smoke");
        CHECK_STR(s->objects[0].fields[SCENE_CH_ANISOTROPY].layers[0].volume, "g");
        scene_destroy(s);
    }
}

static void reads_bumpy_sphere_parameters_with_defaults(void)
{
    struct scene *s = parse_ok(OBJ("\"ior\": {\"shape\": \"bumpy_sphere\", \"center\": [0.1, 0, "
                                   "0], \"radius\": 0.6, \"inside\": 1.5}"));
    if (s != NULL) {
        const struct scene_shape *sh = &s->objects[0].fields[SCENE_CH_IOR].layers[0].shape;
        CHECK_INT(sh->kind, SCENE_SHAPE_BUMPY_SPHERE);
        CHECK_NEAR(sh->center.x, 0.1, 0);
        CHECK_NEAR(sh->radius, 0.6, 0);
        CHECK_NEAR(sh->bump_amplitude, 0.06, 1e-15);
        CHECK_INT(sh->bump_frequency, 6);
        scene_destroy(s);
    }
    s = parse_ok(OBJ("\"ior\": {" BUMPY ", \"bump_amplitude\": 0.25, \"bump_frequency\": 32, "
                     "\"inside\": 1.5}"));
    if (s != NULL) {
        const struct scene_shape *sh = &s->objects[0].fields[SCENE_CH_IOR].layers[0].shape;
        CHECK_NEAR(sh->bump_amplitude, 0.25, 0);
        CHECK_INT(sh->bump_frequency, 32);
        scene_destroy(s);
    }
    s = parse_ok(OBJ("\"ior\": {" BUMPY ", \"bump_amplitude\": 0, \"inside\": 1.5}"));
    if (s != NULL) {
        CHECK_NEAR(s->objects[0].fields[SCENE_CH_IOR].layers[0].shape.bump_amplitude, 0.0, 0);
        scene_destroy(s);
    }
}

int main(void)
{
    rejects_each_bad_document_with_exact_code_and_path();
    without_the_new_keys_there_are_no_lights_no_receiver_and_default_settings();
    reads_each_light_type_with_defaults();
    receiver_defaults_follow_the_objects_world_bounds();
    auto_caustics_choose_what_the_scene_needs();
    reads_every_lightsim_setting();
    reads_each_brdf_type();
    reads_scattering_and_anisotropy_values_and_layers();
    reads_bumpy_sphere_parameters_with_defaults();
    return test_summary("test_scene_light_parse");
}
