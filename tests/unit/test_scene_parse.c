/*
 * test_scene_parse.c - scene_parse: defaults, what a valid document becomes, the exact
 * code and path of every validation rule, limits and their flags, and robustness
 * against truncated, mistyped, huge and deeply nested input (run it under ASan/valgrind
 * to check that no path leaks).
 */
#include <stdint.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "scene/scene.h"
#include "scene_test_util.h"
#include "test.h"

#define SPHERE "\"shape\": \"sphere\", \"radius\": 0.5"

static const struct bad_case bad_cases[] = {
    /* the document */
    {"", REFRACT_E_INVALID_JSON, "invalid JSON", "empty"},
    {"{\"objects\": [", REFRACT_E_INVALID_JSON, "invalid JSON", "line 1"},
    {OBJ("\"ior\": 1.5") " trailing", REFRACT_E_INVALID_JSON, "invalid JSON", "after the JSON"},
    {"[]", REFRACT_E_INVALID_FIELD, "(root): expected an object", NULL},
    {TOP("\"light\": []"), REFRACT_E_UNKNOWN_FIELD, "(root): unknown field \"light\"",
     "allowed: name, description, ambient_ior, environment, camera, render, objects, lights, "
     "receiver, lightsim"},
    {"{}", REFRACT_E_MISSING_FIELD, "(root): missing required field \"objects\"", NULL},
    {"{\"objects\": []}", REFRACT_E_INVALID_FIELD, "objects: expected an array of 1..8", NULL},
    {"{\"objects\": {}}", REFRACT_E_INVALID_FIELD, "objects:", "got an object"},
    {TOP("\"name\": \"\""), REFRACT_E_INVALID_FIELD, "name: expected a string of 1..127", NULL},
    {TOP("\"name\": 7"), REFRACT_E_INVALID_FIELD, "name:", "got 7"},
    {TOP("\"description\": false"), REFRACT_E_INVALID_FIELD, "description:", NULL},
    {TOP("\"ambient_ior\": 0.5"), REFRACT_E_INVALID_FIELD,
     "ambient_ior: expected a finite number in 1..4", "got 0.5"},
    {TOP("\"ambient_ior\": \"1\""), REFRACT_E_INVALID_FIELD, "ambient_ior:", "got \"1\""},
    {TOP("\"ambient_ior\": 1e999"), REFRACT_E_INVALID_FIELD, "ambient_ior:", "inf"},
    {TOP("\"objects\": []"), REFRACT_E_INVALID_FIELD, "objects: duplicate field", NULL},
    /* environment */
    {TOP("\"environment\": {\"type\": \"hdr\"}"), REFRACT_E_INVALID_FIELD, "environment.type",
     "\"procedural\", \"image\""},
    {TOP("\"environment\": {\"intensity\": -1}"), REFRACT_E_INVALID_FIELD, "environment.intensity",
     NULL},
    {TOP("\"environment\": {\"rotation\": 1}"), REFRACT_E_UNKNOWN_FIELD, "environment: unknown",
     "allowed: type, intensity, rotation_deg"},
    {TOP("\"environment\": \"sky\""), REFRACT_E_INVALID_FIELD, "environment: expected an object",
     NULL},
    /* camera */
    {TOP("\"camera\": {\"fov\": 40}"), REFRACT_E_UNKNOWN_FIELD, "camera: unknown field \"fov\"",
     "allowed: eye, look_at, up, fov_y_deg, width, height"},
    {TOP("\"camera\": {\"fov_y_deg\": 0.1}"), REFRACT_E_INVALID_FIELD, "camera.fov_y_deg",
     "> 0.1 and <= 179"},
    {TOP("\"camera\": {\"fov_y_deg\": 180}"), REFRACT_E_INVALID_FIELD, "camera.fov_y_deg", NULL},
    {TOP("\"camera\": {\"width\": 0}"), REFRACT_E_INVALID_FIELD, "camera.width", "1..4096"},
    {TOP("\"camera\": {\"height\": 100.5}"), REFRACT_E_INVALID_FIELD, "camera.height", NULL},
    {TOP("\"camera\": {\"width\": 5000}"), REFRACT_E_LIMIT_EXCEEDED, "camera.width",
     "max_image_dim = 4096; start refractd with --max-image-dim"},
    {TOP("\"camera\": {\"eye\": [1, 2, 3], \"look_at\": [1, 2, 3]}"), REFRACT_E_INVALID_FIELD,
     "camera.look_at: equals camera.eye", NULL},
    {TOP("\"camera\": {\"eye\": [0, 5, 0]}"), REFRACT_E_INVALID_FIELD, "camera.up",
     "parallel to the viewing direction"},
    {TOP("\"camera\": {\"up\": [0, 0, 0]}"), REFRACT_E_INVALID_FIELD, "camera.up",
     "non-zero direction"},
    {TOP("\"camera\": {\"eye\": [0, 0]}"), REFRACT_E_INVALID_FIELD, "camera.eye",
     "array of 3 numbers"},
    {TOP("\"camera\": {\"eye\": [0, 1e999, 4]}"), REFRACT_E_INVALID_FIELD, "camera.eye[1]", "inf"},
    {TOP("\"camera\": {\"look_at\": [0, 0, 2e6]}"), REFRACT_E_INVALID_FIELD, "camera.look_at[2]",
     "-1000000..1000000"},
    /* render */
    {TOP("\"render\": {\"stepper\": \"rk5\"}"), REFRACT_E_INVALID_FIELD, "render.stepper",
     "\"euler\", \"rk4\""},
    /* renamed: the old key "integrator" is read like "stepper", but not both */
    {TOP("\"render\": {\"integrator\": \"rk5\"}"), /* renamed: */
     REFRACT_E_INVALID_FIELD, "render.integrator", /* renamed: */
     "\"euler\", \"rk4\""},                                              /* renamed: the old key */
    {TOP("\"render\": {\"stepper\": \"rk4\", \"integrator\": \"rk2\"}"), /* renamed: */
     REFRACT_E_INVALID_FIELD, "render.integrator", "old name of \"stepper\""}, /* renamed: */
    {TOP("\"render\": {\"step\": 12}"), REFRACT_E_INVALID_FIELD,
     "render.step: expected a finite number in 0.01..8, got 12", NULL},
    {TOP("\"render\": {\"max_steps\": 1000000}"), REFRACT_E_LIMIT_EXCEEDED, "render.max_steps",
     "--max-steps"},
    {TOP("\"render\": {\"max_steps\": 0}"), REFRACT_E_INVALID_FIELD, "render.max_steps", NULL},
    {TOP("\"render\": {\"boundary_threshold\": 0}"), REFRACT_E_INVALID_FIELD,
     "render.boundary_threshold", "> 0 and <= 10"},
    {TOP("\"render\": {\"tonemap\": \"aces\"}"), REFRACT_E_INVALID_FIELD, "render.tonemap", NULL},
    {TOP("\"render\": {\"ior_filter\": \"bicubic\"}"), REFRACT_E_INVALID_FIELD,
     "render.ior_filter: expected one of", "\"trilinear\", \"tricubic\""},
    {TOP("\"render\": {\"ior_filter\": 3}"), REFRACT_E_INVALID_FIELD, "render.ior_filter", NULL},
    {TOP("\"render\": {\"exposure\": 21}"), REFRACT_E_INVALID_FIELD, "render.exposure", NULL},
    {TOP("\"render\": {\"min_throughput\": 0.6}"), REFRACT_E_INVALID_FIELD,
     "render.min_throughput: expected a finite number in 0..0.5", "got 0.6"},
    {TOP("\"render\": {\"min_throughput\": -1e-6}"), REFRACT_E_INVALID_FIELD,
     "render.min_throughput", NULL},
    {TOP("\"render\": {\"empty_space_skipping\": 1}"), REFRACT_E_INVALID_FIELD,
     "render.empty_space_skipping", NULL},
    {TOP("\"render\": {\"steps\": 1}"), REFRACT_E_UNKNOWN_FIELD, "render: unknown field", NULL},
    /* object */
    {"{\"objects\": [{\"ior\": 1.5}]}", REFRACT_E_MISSING_FIELD,
     "objects[0]: missing required field \"bounds\"", NULL},
    {"{\"objects\": [7]}", REFRACT_E_INVALID_FIELD, "objects[0]: expected an object", NULL},
    {"{\"objects\": [{\"bounds\": {\"min\": [0, 1, 0], \"max\": [1, 1, 1]}, \"ior\": 1.5}]}",
     REFRACT_E_INVALID_FIELD, "objects[0].bounds", "on y"},
    {"{\"objects\": [{\"bounds\": {\"min\": [0, 0, 0]}, \"ior\": 1.5}]}", REFRACT_E_MISSING_FIELD,
     "objects[0].bounds: missing required field \"max\"", NULL},
    {"{\"objects\": [{\"bounds\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1], \"mid\": 0}, \"ior\": "
     "1}]}",
     REFRACT_E_UNKNOWN_FIELD, "objects[0].bounds: unknown field \"mid\"", "allowed: min, max"},
    {OBJ("\"ior\": 1.5, \"iro\": 1"), REFRACT_E_UNKNOWN_FIELD, "objects[0]: unknown field \"iro\"",
     "allowed: name, bounds, resolution, transform, smoothing_sigma, ior, attenuation, emission, "
     "opaque, opaque_ior, scattering, anisotropy, brdf"},
    {OBJ("\"name\": \"x\""), REFRACT_E_MISSING_FIELD,
     "objects[0]: an object needs at least one of ior, attenuation, emission, opaque, scattering",
     NULL},
    {OBJ("\"ior\": 1.5, \"resolution\": 1"), REFRACT_E_INVALID_FIELD, "objects[0].resolution",
     "2..512"},
    {OBJ("\"ior\": 1.5, \"resolution\": 1024"), REFRACT_E_LIMIT_EXCEEDED, "objects[0].resolution",
     "max_resolution = 512; start refractd with --max-resolution"},
    {OBJ("\"ior\": 1.5, \"resolution\": [64, 64]"), REFRACT_E_INVALID_FIELD,
     "objects[0].resolution", "array of 3 integers"},
    {OBJ("\"ior\": 1.5, \"resolution\": [64, 64.5, 64]"), REFRACT_E_INVALID_FIELD,
     "objects[0].resolution[1]", "got 64.5"},
    {OBJ("\"ior\": 1.5, \"resolution\": [64, 64, 600]"), REFRACT_E_LIMIT_EXCEEDED,
     "objects[0].resolution[2]", "--max-resolution"},
    {"{\"objects\": [{" BOUNDS ", \"ior\": 1.5, \"resolution\": 400}, {" BOUNDS
     ", \"ior\": 1.5, \"resolution\": 200}]}",
     REFRACT_E_LIMIT_EXCEEDED, "objects[1]",
     "max_voxels = 67108864; start refractd with --max-voxels"},
    {OBJ("\"ior\": 1.5, \"transform\": {\"scale\": 0}"), REFRACT_E_INVALID_FIELD,
     "objects[0].transform.scale", NULL},
    {OBJ("\"ior\": 1.5, \"transform\": {\"rotate\": {\"axis\": [0, 0, 0], \"angle_deg\": 3}}"),
     REFRACT_E_INVALID_FIELD, "objects[0].transform.rotate.axis", "non-zero"},
    {OBJ("\"ior\": 1.5, \"transform\": {\"rotate\": {\"axis\": [0, 1, 0]}}"),
     REFRACT_E_MISSING_FIELD, "objects[0].transform.rotate: missing required field \"angle_deg\"",
     NULL},
    {OBJ("\"ior\": 1.5, \"transform\": {\"rotate\": {\"axis\": [0, 1, 0], \"angle_deg\": 4000}}"),
     REFRACT_E_INVALID_FIELD, "objects[0].transform.rotate.angle_deg", NULL},
    {OBJ("\"ior\": 1.5, \"transform\": {\"translate\": [0, 0, 0], \"shear\": 1}"),
     REFRACT_E_UNKNOWN_FIELD, "objects[0].transform: unknown field \"shear\"", NULL},
    {OBJ("\"ior\": 1.5, \"smoothing_sigma\": 9"), REFRACT_E_INVALID_FIELD,
     "objects[0].smoothing_sigma", "0..8"},
    {OBJ("\"ior\": 1.5, \"opaque_ior\": 0.9"), REFRACT_E_INVALID_FIELD, "objects[0].opaque_ior",
     NULL},
    {OBJ("\"ior\": 1.5, \"ior\": 1.4"), REFRACT_E_INVALID_FIELD, "objects[0].ior: duplicate", NULL},
    /* values */
    {OBJ("\"ior\": 6"), REFRACT_E_INVALID_FIELD,
     "objects[0].ior: expected a finite number in 0.2..5", "got 6"},
    {OBJ("\"ior\": [1.5, \"x\"]"), REFRACT_E_INVALID_FIELD, "objects[0].ior[1]", "got \"x\""},
    {OBJ("\"ior\": []"), REFRACT_E_INVALID_FIELD, "objects[0].ior", "empty array"},
    {OBJ("\"ior\": \"glass\""), REFRACT_E_INVALID_FIELD, "objects[0].ior", "got \"glass\""},
    {OBJ("\"ior\": 1e999"), REFRACT_E_INVALID_FIELD, "objects[0].ior", "inf"},
    {OBJ("\"attenuation\": [1, 2]"), REFRACT_E_INVALID_FIELD, "objects[0].attenuation",
     "a number or [r, g, b], each in 0..100000"},
    {OBJ("\"attenuation\": [1, -2, 3]"), REFRACT_E_INVALID_FIELD, "objects[0].attenuation[1]",
     "0..100000"},
    {OBJ("\"emission\": 2e6"), REFRACT_E_INVALID_FIELD, "objects[0].emission", "0..1000000"},
    {OBJ("\"opaque\": [0.5, 0.5, 2]"), REFRACT_E_INVALID_FIELD, "objects[0].opaque[2]", "0..1"},
    {OBJ("\"opaque\": [[[[[[[[1]]]]]]]]"), REFRACT_E_INVALID_FIELD, "objects[0].opaque[0]", NULL},
    /* shape layers */
    {OBJ("\"ior\": {\"shape\": \"sphere\", \"radious\": 1, \"inside\": 1.5}"),
     REFRACT_E_UNKNOWN_FIELD,
     "objects[0].ior: unknown field \"radious\"; allowed: shape, center, radius, inside, outside",
     NULL},
    {OBJ("\"ior\": {\"shape\": \"sphere\", \"Radius\": 1, \"inside\": 1.5}"),
     REFRACT_E_UNKNOWN_FIELD, "objects[0].ior: unknown field \"Radius\"", NULL},
    {OBJ("\"ior\": {\"shape\": \"sphere\", \"inside\": 1.5}"), REFRACT_E_MISSING_FIELD,
     "objects[0].ior: missing required field \"radius\"", NULL},
    {OBJ("\"ior\": {\"shape\": \"sphere\", \"radius\": 0, \"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.radius", "> 0"},
    {OBJ("\"ior\": {" SPHERE "}"), REFRACT_E_MISSING_FIELD,
     "objects[0].ior: missing required field \"inside\"", NULL},
    {OBJ("\"ior\": {" SPHERE ", \"inside\": 1.5, \"outside\": 9}"), REFRACT_E_INVALID_FIELD,
     "objects[0].ior.outside", NULL},
    {OBJ("\"ior\": {\"shape\": \"cube\", \"inside\": 1.5}"), REFRACT_E_INVALID_FIELD,
     "objects[0].ior.shape",
     "\"sphere\", \"box\", \"rounded_box\", \"cylinder\", \"lathe\", \"text\""},
    {OBJ("\"ior\": {}"), REFRACT_E_MISSING_FIELD, "objects[0].ior: a layer object needs one of",
     NULL},
    {OBJ("\"ior\": [1.0, {\"inside\": 1.5}]"), REFRACT_E_MISSING_FIELD, "objects[0].ior[1]", NULL},
    {OBJ("\"ior\": {" SPHERE ", \"profile\": \"luneburg\", \"inside\": 1.5}"),
     REFRACT_E_UNKNOWN_FIELD, "objects[0].ior: unknown field \"profile\"", NULL},
    {OBJ("\"ior\": {" SPHERE ", \"volume\": \"v\", \"inside\": 1.5}"), REFRACT_E_INVALID_FIELD,
     "objects[0].ior", "both \"shape\" and \"volume\""},
    {OBJ("\"ior\": {\"shape\": \"box\", \"size\": [1, 0, 1], \"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.size[1]", NULL},
    {OBJ("\"ior\": {\"shape\": \"box\", \"size\": 1, \"inside\": 1.5}"), REFRACT_E_INVALID_FIELD,
     "objects[0].ior.size", NULL},
    {OBJ("\"ior\": {\"shape\": \"rounded_box\", \"size\": [1, 1, 0.4], \"radius\": 0.3, "
         "\"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.radius", "more than half the smallest size (0.2)"},
    {OBJ("\"ior\": {\"shape\": \"cylinder\", \"radius\": 1, \"height\": 1, \"axis\": \"w\", "
         "\"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.axis", NULL},
    {OBJ("\"ior\": {\"shape\": \"cylinder\", \"radius\": 1, \"inside\": 1.5}"),
     REFRACT_E_MISSING_FIELD, "objects[0].ior: missing required field \"height\"", NULL},
    {OBJ("\"ior\": {\"shape\": \"lathe\", \"profile\": [[0, 0], [1, 0]], \"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.profile", "3..1024"},
    {OBJ("\"ior\": {\"shape\": \"lathe\", \"profile\": [[0, 0], [-1, 0], [0, 1]], \"inside\": "
         "1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.profile[1][0]", NULL},
    {OBJ("\"ior\": {\"shape\": \"lathe\", \"profile\": [[0, 0], [1], [0, 1]], \"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.profile[1]", "[r, h]"},
    {OBJ("\"ior\": {\"shape\": \"lathe\", \"profile\": [[0, 0], [1, 1], [1, 0], [0, 1]], "
         "\"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.profile", "simple"},
    {OBJ("\"ior\": {\"shape\": \"lathe\", \"profile\": [[0, 0], [1, 0], [2, 0]], \"inside\": "
         "1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.profile", NULL},
    {OBJ("\"ior\": {\"shape\": \"lathe\", \"profile\": [[0, 0], [1, 0], [1, 0], [0, 1]], "
         "\"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.profile", "the same"},
    {OBJ("\"ior\": {\"shape\": \"text\", \"text\": \"a\\nb\", \"height\": 1, \"depth\": 1, "
         "\"inside\": 1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.text", "byte 0x0a"},
    {OBJ("\"ior\": {\"shape\": \"text\", \"text\": \"\", \"height\": 1, \"depth\": 1, \"inside\": "
         "1.5}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.text", NULL},
    {OBJ("\"ior\": {\"shape\": \"text\", \"text\": "
         "\"0123456789012345678901234567890123456789012345678901234567890123X\", \"height\": 1, "
         "\"depth\": 1, \"inside\": 1.5}"),
     REFRACT_E_LIMIT_EXCEEDED, "objects[0].ior.text",
     "max_text_length = 64; start refractd with "
     "--max-text-length"},
    {OBJ("\"ior\": {\"shape\": \"text\", \"text\": \"A\", \"height\": 1, \"inside\": 1.5}"),
     REFRACT_E_MISSING_FIELD, "objects[0].ior: missing required field \"depth\"", NULL},
    {OBJ("\"opaque\": {" SPHERE ", \"inside\": [1, 0, 0], \"outside\": 0}"),
     REFRACT_E_INVALID_FIELD, "objects[0].opaque.outside", "not allowed in opaque"},
    {OBJ("\"opaque\": {" SPHERE ", \"inside\": [1, 0, 0], \"outsid\": 0}"), REFRACT_E_UNKNOWN_FIELD,
     "objects[0].opaque: unknown field \"outsid\"", "allowed: shape, center, radius, inside"},
    /* profile layers */
    {OBJ("\"attenuation\": [0, {\"profile\": \"luneburg\", \"radius\": 1}]"),
     REFRACT_E_INVALID_FIELD, "objects[0].attenuation[1]: GRIN profiles apply only to ior", NULL},
    {OBJ("\"ior\": [1.0, {\"profile\": \"luneberg\", \"radius\": 1}]"), REFRACT_E_INVALID_FIELD,
     "objects[0].ior[1].profile", "\"luneburg\", \"maxwell_fisheye\", \"linear\", \"gaussian\""},
    {OBJ("\"ior\": {\"profile\": \"luneburg\", \"radius\": -1}"), REFRACT_E_INVALID_FIELD,
     "objects[0].ior.radius", NULL},
    {OBJ("\"ior\": {\"profile\": \"luneburg\", \"radius\": 1, \"n0\": 2}"), REFRACT_E_UNKNOWN_FIELD,
     "objects[0].ior: unknown field \"n0\"", "allowed: profile, center, radius"},
    {OBJ("\"ior\": {\"profile\": \"luneburg\", \"radius\": 1, \"inside\": 2}"),
     REFRACT_E_UNKNOWN_FIELD, "objects[0].ior: unknown field \"inside\"", NULL},
    {OBJ("\"ior\": {\"profile\": \"maxwell_fisheye\", \"radius\": 1, \"n0\": 6}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.n0", NULL},
    {OBJ("\"ior\": {\"profile\": \"linear\"}"), REFRACT_E_MISSING_FIELD,
     "objects[0].ior: missing required field \"gradient\"", NULL},
    {OBJ("\"ior\": {\"profile\": \"linear\", \"n0\": 1.5, \"gradient\": [2, 0, 0]}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.gradient", "n = -0.5"},
    {OBJ("\"ior\": {\"profile\": \"gaussian\", \"n_peak\": 1.6, \"sigma\": 0}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.sigma", NULL},
    {OBJ("\"ior\": {\"profile\": \"gaussian\", \"sigma\": 1}"), REFRACT_E_MISSING_FIELD,
     "objects[0].ior: missing required field \"n_peak\"", NULL},
    /* volume layers */
    {OBJ("\"ior\": {\"volume\": \"a b\"}"), REFRACT_E_INVALID_FIELD, "objects[0].ior.volume",
     "A-Z a-z 0-9 _ -"},
    {OBJ("\"ior\": {\"volume\": \"0123456789012345678901234567890123456789012345678901234567890123"
         "\"}"),
     REFRACT_E_INVALID_FIELD, "objects[0].ior.volume", NULL},
    {OBJ("\"ior\": {\"volume\": \"density\", \"scale\": \"x\"}"), REFRACT_E_INVALID_FIELD,
     "objects[0].ior.scale", NULL},
    {OBJ("\"ior\": {\"volume\": \"density\", \"inside\": 1}"), REFRACT_E_UNKNOWN_FIELD,
     "objects[0].ior: unknown field \"inside\"", "allowed: volume, scale, offset"},
};

static void rejects_each_bad_document_with_exact_code_and_path(void)
{
    size_t n = sizeof bad_cases / sizeof bad_cases[0];
    CHECK(n >= 40);
    for (size_t i = 0; i < n; i++)
        check_bad(&bad_cases[i], NULL);
}

static void rejects_more_objects_than_max_objects(void)
{
    char doc[4096];
    size_t o = (size_t)snprintf(doc, sizeof doc, "{\"objects\": [");
    for (int i = 0; i < 9; i++)
        o += (size_t)snprintf(doc + o, sizeof doc - o,
                              "%s{" BOUNDS ", \"resolution\": 2, \"ior\": 1}", i ? ", " : "");
    snprintf(doc + o, sizeof doc - o, "]}");
    struct bad_case c = {doc, REFRACT_E_LIMIT_EXCEEDED, "objects: 9 objects",
                         "max_objects = 8; start refractd with --max-objects"};
    check_bad(&c, NULL);
}

static void rejects_limits_set_lower_naming_the_configured_value(void)
{
    struct scene_limits lim = scene_limits_default();
    lim.max_layers = 2;
    lim.max_profile_points = 3;
    lim.max_voxels = 1000;
    lim.max_text_length = 3;
    struct bad_case cases[] = {
        {OBJ("\"resolution\": 8, \"ior\": [1, 1.1, 1.2]"), REFRACT_E_LIMIT_EXCEEDED,
         "objects[0].ior: 3 layers", "max_layers = 2; start refractd with --max-layers"},
        {OBJ("\"resolution\": 8, \"ior\": {\"shape\": \"lathe\", \"profile\": [[0, 0], [1, 0], [1, "
             "1], [0, 1]], \"inside\": 1.5}"),
         REFRACT_E_LIMIT_EXCEEDED, "objects[0].ior.profile: 4 points",
         "max_profile_points = 3; start refractd with --max-profile-points"},
        {OBJ("\"resolution\": 11, \"ior\": 1.5"), REFRACT_E_LIMIT_EXCEEDED, "objects[0]",
         "max_voxels = 1000"},
        {OBJ("\"resolution\": 8, \"ior\": {\"shape\": \"text\", \"text\": \"ABCD\", \"height\": 1, "
             "\"depth\": 1, \"inside\": 1.5}"),
         REFRACT_E_LIMIT_EXCEEDED, "objects[0].ior.text: 4 characters", "--max-text-length"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        check_bad(&cases[i], &lim);
    /* Exactly at the limit is fine. */
    const char *at = OBJ("\"resolution\": 10, \"ior\": [1, 1.1]");
    struct scene *s = NULL;
    struct err e;
    CHECK_INT(scene_parse(at, strlen(at), &lim, &s, &e), REFRACT_E_OK);
    scene_destroy(s);
}

static void applies_defaults_to_a_minimal_document(void)
{
    struct scene *s = parse_ok(OBJ("\"ior\": 1.5"));
    if (s == NULL)
        return;
    CHECK_STR(s->name, "untitled");
    CHECK_NEAR(s->ambient_ior, 1.0, 0);
    CHECK_INT(s->environment.kind, SCENE_ENV_PROCEDURAL);
    CHECK_NEAR(s->environment.intensity, 1.0, 0);
    CHECK_NEAR(s->environment.rotation_deg, 0.0, 0);
    CHECK_NEAR(s->camera.eye.z, 4.0, 0);
    CHECK_NEAR(s->camera.look_at.x, 0.0, 0);
    CHECK_NEAR(s->camera.up.y, 1.0, 0);
    CHECK_NEAR(s->camera.fov_y_deg, 40.0, 0);
    CHECK_INT(s->camera.width, 640);
    CHECK_INT(s->camera.height, 480);
    CHECK_INT(s->render.stepper, SCENE_STEPPER_RK4);
    CHECK_NEAR(s->render.step_voxels, 0.5, 0);
    CHECK_INT(s->render.max_steps, 20000);
    CHECK_NEAR(s->render.exposure_ev, 0.0, 0);
    CHECK_NEAR(s->render.boundary_threshold, 0.02, 0);
    CHECK_INT(s->render.tonemap, SCENE_TONEMAP_CLAMP);
    CHECK(s->render.empty_space_skipping);
    CHECK_NEAR(s->render.min_throughput, 1e-6, 0);
    CHECK_INT(s->render.ior_filter, SCENE_FILTER_TRILINEAR);
    CHECK_INT(s->object_count, 1);
    const struct scene_object *o = &s->objects[0];
    CHECK_STR(o->name, "object0");
    CHECK_INT(o->resolution[0], 128);
    CHECK_INT(o->resolution[1], 128);
    CHECK_INT(o->resolution[2], 128);
    CHECK_NEAR(o->smoothing_sigma_voxels, 1.0, 0);
    CHECK_NEAR(o->opaque_ior, 1.5, 0);
    CHECK_NEAR(o->world_from_object.scale, 1.0, 0);
    CHECK_NEAR(o->world_from_object.rot[0][0], 1.0, 0);
    CHECK_NEAR(o->world_from_object.translate.x, 0.0, 0);
    CHECK(scene_channel_used(o, SCENE_CH_IOR));
    CHECK(!scene_channel_used(o, SCENE_CH_ATTENUATION));
    CHECK(!scene_channel_used(o, SCENE_CH_EMISSION));
    CHECK(!scene_channel_used(o, SCENE_CH_OPAQUE));
    CHECK_INT(o->fields[SCENE_CH_IOR].count, 1);
    CHECK_INT(o->fields[SCENE_CH_IOR].layers[0].kind, SCENE_LAYER_CONSTANT);
    CHECK_NEAR(o->fields[SCENE_CH_IOR].layers[0].inside[0], 1.5, 0);
    scene_destroy(s);
}

static void defaults_stay_within_lowered_limits(void)
{
    struct scene_limits lim = scene_limits_default();
    lim.max_resolution = 64;
    lim.max_image_dim = 256;
    lim.max_steps = 1000;
    const char *doc = OBJ("\"ior\": 1.5");
    struct scene *s = NULL;
    struct err e;
    CHECK_INT(scene_parse(doc, strlen(doc), &lim, &s, &e), REFRACT_E_OK);
    if (s == NULL)
        return;
    CHECK_INT(s->objects[0].resolution[0], 64);
    CHECK_INT(s->camera.width, 256);
    CHECK_INT(s->render.max_steps, 1000);
    scene_destroy(s);
}

/* renamed: a document that still says "integrator" (the stepper's old key) keeps working. */
static void reads_the_steppers_old_key(void)
{
    struct scene *s = parse_ok("{\"render\": {\"integrator\": \"rk2\"}, " /* renamed: */
                               "\"objects\": [{" BOUNDS
                               ", \"ior\": 1.5}]}");
    if (s == NULL)
        return;
    CHECK_INT(s->render.stepper, SCENE_STEPPER_RK2);
    scene_destroy(s);
}

static void reads_every_field_of_a_full_document(void)
{
    const char *doc =
        "{\"name\": \"full\", \"description\": \"d\", \"ambient_ior\": 1.33,"
        " \"environment\": {\"type\": \"image\", \"intensity\": 2, \"rotation_deg\": 90},"
        " \"camera\": {\"eye\": [1, 2, 3], \"look_at\": [0, 1, 0], \"up\": [0, 2, 0],"
        "   \"fov_y_deg\": 30, \"width\": 320, \"height\": 200},"
        " \"render\": {\"stepper\": \"euler\", \"step\": 0.25, \"max_steps\": 500,"
        "   \"exposure\": -1, \"boundary_threshold\": 0.1, \"tonemap\": \"filmic\","
        "   \"empty_space_skipping\": false, \"min_throughput\": 0.01,"
        "   \"ior_filter\": \"tricubic\"},"
        " \"objects\": [{\"name\": \"lens\", " BOUNDS ", \"resolution\": [16, 32, 8],"
        "   \"transform\": {\"translate\": [1, 0, 0], \"rotate\": {\"axis\": [0, 0, 2],"
        "   \"angle_deg\": 90}, \"scale\": 2}, \"smoothing_sigma\": 0, \"opaque_ior\": 2,"
        "   \"ior\": {\"profile\": \"gaussian\", \"n_peak\": 1.6, \"sigma\": 0.3},"
        "   \"attenuation\": [0.1, 0.2, 0.3], \"emission\": 0.5,"
        "   \"opaque\": {\"shape\": \"box\", \"size\": [0.2, 0.2, 0.2], \"inside\": 0.5}}]}";
    struct scene *s = parse_ok(doc);
    if (s == NULL)
        return;
    CHECK_STR(s->name, "full");
    CHECK_NEAR(s->ambient_ior, 1.33, 0);
    CHECK_INT(s->environment.kind, SCENE_ENV_IMAGE);
    CHECK_NEAR(s->environment.rotation_deg, 90, 0);
    CHECK_NEAR(s->camera.up.y, 1.0, 1e-15);
    CHECK_INT(s->camera.height, 200);
    CHECK_INT(s->render.stepper, SCENE_STEPPER_EULER);
    CHECK_INT(s->render.tonemap, SCENE_TONEMAP_FILMIC);
    CHECK_INT(s->render.ior_filter, SCENE_FILTER_TRICUBIC);
    CHECK_INT(s->render.max_steps, 500);
    CHECK(!s->render.empty_space_skipping);
    CHECK_NEAR(s->render.min_throughput, 0.01, 0);
    const struct scene_object *o = &s->objects[0];
    CHECK_STR(o->name, "lens");
    CHECK_INT(o->resolution[1], 32);
    /* 90 degrees about z, scale 2, then translate: object +x maps to world (1, 2, 0). */
    vec3 w = xform_point_to_world(&o->world_from_object, vec3_make(1, 0, 0));
    CHECK_NEAR(w.x, 1.0, 1e-12);
    CHECK_NEAR(w.y, 2.0, 1e-12);
    const struct scene_layer *ior = &o->fields[SCENE_CH_IOR].layers[0];
    CHECK_INT(ior->kind, SCENE_LAYER_PROFILE);
    CHECK_INT(ior->profile.kind, GRIN_GAUSSIAN);
    /* n_out defaults to the scene's ambient_ior. */
    CHECK_NEAR(ior->profile.n_out, 1.33, 0);
    const struct scene_layer *att = &o->fields[SCENE_CH_ATTENUATION].layers[0];
    CHECK_NEAR(att->inside[2], 0.3, 0);
    CHECK_NEAR(att->inside[3], 0.0, 0);
    const struct scene_layer *em = &o->fields[SCENE_CH_EMISSION].layers[0];
    CHECK_NEAR(em->inside[1], 0.5, 0); /* a grey number fills r, g and b */
    const struct scene_layer *op = &o->fields[SCENE_CH_OPAQUE].layers[0];
    CHECK_INT(op->kind, SCENE_LAYER_SHAPE);
    CHECK_NEAR(op->inside[0], 0.5, 0);
    CHECK_NEAR(op->inside[3], 1.0, 0); /* opaque coverage */
    scene_destroy(s);
}

static void reads_layer_lists_and_shape_parameters(void)
{
    const char *doc = OBJ(
        "\"ior\": [1.1, {\"shape\": \"cylinder\", \"radius\": 0.5, \"height\": 1, \"axis\": "
        "\"z\", \"inside\": 1.5, \"outside\": 1.2}, {\"shape\": \"lathe\", \"base\": [0, -1, 0], "
        "\"profile\": [[0, 0], [0.5, 0], [0.5, 1], [0, 1]], \"inside\": 1.4}, {\"shape\": "
        "\"text\", "
        "\"text\": \"Hi!\", \"height\": 0.5, \"depth\": 0.2, \"inside\": 1.6}, {\"volume\": "
        "\"dens-1\", \"scale\": 0.5, \"offset\": 1}], \"attenuation\": [[1, 2, 3], {\"shape\": "
        "\"rounded_box\", \"size\": [1, 1, 1], \"radius\": 0.5, \"inside\": 0}]");
    struct scene *s = parse_ok(doc);
    if (s == NULL)
        return;
    const struct scene_field *f = &s->objects[0].fields[SCENE_CH_IOR];
    CHECK_INT(f->count, 5);
    CHECK_INT(f->layers[0].kind, SCENE_LAYER_CONSTANT);
    CHECK_INT(f->layers[1].shape.kind, SCENE_SHAPE_CYLINDER);
    CHECK_INT(f->layers[1].shape.axis, 2);
    CHECK(f->layers[1].has_outside);
    CHECK_NEAR(f->layers[1].outside[0], 1.2, 0);
    CHECK_INT(f->layers[2].shape.profile_count, 4);
    CHECK_NEAR(f->layers[2].shape.base.y, -1, 0);
    CHECK_INT(f->layers[2].shape.axis, 1);
    CHECK_STR(f->layers[3].shape.text, "Hi!");
    CHECK_INT(f->layers[4].kind, SCENE_LAYER_VOLUME);
    CHECK_STR(f->layers[4].volume, "dens-1");
    CHECK_NEAR(f->layers[4].volume_scale, 0.5, 0);
    CHECK_NEAR(f->layers[4].volume_offset, 1, 0);
    const struct scene_field *a = &s->objects[0].fields[SCENE_CH_ATTENUATION];
    CHECK_INT(a->count, 2);
    CHECK_NEAR(a->layers[0].inside[1], 2, 0);
    CHECK_NEAR(a->layers[1].shape.radius, 0.5, 0);
    scene_destroy(s);
}

static void an_ior_array_of_numbers_is_a_list_of_constant_layers(void)
{
    struct scene *s = parse_ok(OBJ("\"ior\": [1.2, 1.3, 1.4]"));
    if (s == NULL)
        return;
    CHECK_INT(s->objects[0].fields[SCENE_CH_IOR].count, 3);
    scene_destroy(s);
    s = parse_ok(OBJ("\"emission\": [1.2, 1.3, 1.4]"));
    if (s == NULL)
        return;
    CHECK_INT(s->objects[0].fields[SCENE_CH_EMISSION].count, 1);
    scene_destroy(s);
}

/* ---- robustness ---- */

static int fuzz_runs;

static void parse_anything(const char *doc, size_t len)
{
    struct scene *s = NULL;
    struct err e;
    err_clear(&e);
    enum refract_code rc = scene_parse(doc, len, NULL, &s, &e);
    fuzz_runs++;
    if (rc == REFRACT_E_OK) {
        CHECK(s != NULL);
        scene_destroy(s);
        return;
    }
    /* Every failure is a client error with a message, never OK-with-NULL or internal. */
    CHECK_MSG(s == NULL && e.msg[0] != '\0' && err_code_http_status(rc) / 100 == 4,
              "rc %d msg \"%s\" for %.*s", (int)rc, e.msg, (int)len, doc);
}

static const char *fuzz_seed =
    "{\"name\": \"seed\", \"camera\": {\"eye\": [0, 1, 4], \"width\": 64, \"height\": 48},"
    " \"render\": {\"step\": 0.5}, \"environment\": {\"type\": \"procedural\"},"
    " \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 4,"
    "  \"transform\": {\"rotate\": {\"axis\": [0, 1, 0], \"angle_deg\": 10}},"
    "  \"ior\": [1.0, {\"shape\": \"lathe\", \"profile\": [[0, 0], [1, 0], [0, 1]], \"inside\": "
    "1.5},"
    "   {\"profile\": \"linear\", \"gradient\": [0.1, 0, 0]}, {\"volume\": \"v\"}],"
    "  \"attenuation\": {\"shape\": \"text\", \"text\": \"AB\", \"height\": 1, \"depth\": 1,"
    "   \"inside\": [1, 2, 3]}, \"opaque\": {\"shape\": \"sphere\", \"radius\": 1, \"inside\": "
    "1},"
    "  \"scattering\": [0.3, {\"shape\": \"bumpy_sphere\", \"radius\": 0.5, \"bump_amplitude\": "
    "0.1, \"bump_frequency\": 4, \"inside\": [1, 2, 3]}], \"anisotropy\": 0.3,"
    "  \"brdf\": {\"type\": \"phong\", \"color\": [1, 1, 1], \"roughness\": 0.2, \"exponent\": "
    "50}}],"
    " \"lights\": [{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0, -1, 0]},"
    "  {\"type\": \"point\", \"position\": [0, 2, 0], \"color\": 2, \"intensity\": 3},"
    "  {\"type\": \"spot\", \"position\": [0, 2, 0], \"direction\": [0, -1, 0], \"angle_deg\": "
    "20}],"
    " \"receiver\": {\"height\": -1, \"half_size\": 2, \"albedo\": [0.5, 0.5, 0.5]},"
    " \"lightsim\": {\"resolution\": 16, \"deposit\": \"max\", \"cull_flipped\": true}}";

static void survives_every_truncation_of_a_valid_document(void)
{
    size_t n = strlen(fuzz_seed);
    struct scene *seed = parse_ok(fuzz_seed); /* the seed itself is valid */
    scene_destroy(seed);
    parse_anything(fuzz_seed, n);
    for (size_t len = 0; len < n; len++) {
        /* A private copy of exactly len bytes, so reading past it is caught by ASan. */
        char *copy = malloc(len ? len : 1);
        memcpy(copy, fuzz_seed, len);
        parse_anything(copy, len);
        free(copy);
    }
}

/* Replaces every value in the seed, one at a time, by each of several wrong values. */
static void survives_wrong_types_at_every_level(void)
{
    static const char *const replacements[] = {"null",
                                               "true",
                                               "\"x\"",
                                               "1e999",
                                               "-1e999",
                                               "-1",
                                               "0",
                                               "[]",
                                               "{}",
                                               "[[[[[[1]]]]]]",
                                               "{\"a\": {\"b\": {\"c\": 1}}}",
                                               "[1, 2, 3]",
                                               "1e308",
                                               "2147483648",
                                               "\"\""};
    cJSON *root = cJSON_Parse(fuzz_seed);
    CHECK(root != NULL);
    /* Walk the tree depth-first with an explicit stack. */
    cJSON *stack[256];
    int top = 0;
    stack[top++] = root;
    while (top > 0) {
        cJSON *node = stack[--top];
        for (cJSON *c = node->child; c != NULL; c = c->next) {
            for (size_t r = 0; r < sizeof replacements / sizeof replacements[0]; r++) {
                /* Swap c for a wrong value under the same key, parse, swap back (the
                 * swaps free what they replace, so c becomes the restored copy). */
                cJSON *with = cJSON_Parse(replacements[r]);
                cJSON *old = cJSON_Duplicate(c, 1);
                if (c->string != NULL)
                    with->string = strdup(c->string);
                cJSON_ReplaceItemViaPointer(node, c, with);
                char *text = cJSON_PrintUnformatted(root);
                parse_anything(text, strlen(text));
                cJSON_free(text);
                cJSON_ReplaceItemViaPointer(node, with, old);
                c = old;
            }
            if (top < 256)
                stack[top++] = c;
        }
    }
    cJSON_Delete(root);
}

/* Overwrites 1..3 random bytes of the seed with JSON-significant characters. */
static void survives_random_byte_mutations(void)
{
    static const char alphabet[] = "{}[]\":,0123456789.eE+-nulltruefalse \\x\x01\xff\0";
    size_t n = strlen(fuzz_seed);
    unsigned st = 12345;
    char *copy = malloc(n);
    for (int run = 0; run < 3000; run++) {
        memcpy(copy, fuzz_seed, n);
        int edits = 1 + (int)(st % 3);
        for (int k = 0; k < edits; k++) {
            st = st * 1664525u + 1013904223u;
            size_t at = (st >> 8) % n;
            st = st * 1664525u + 1013904223u;
            copy[at] = alphabet[(st >> 8) % (sizeof alphabet - 1)];
        }
        parse_anything(copy, n);
    }
    free(copy);
}

static void survives_deep_nesting_and_huge_numbers(void)
{
    size_t depth = 5000;
    size_t cap = 2 * depth + 200;
    char *doc = malloc(cap);
    size_t o = (size_t)snprintf(doc, cap, "{\"objects\": ");
    memset(doc + o, '[', depth);
    o += depth;
    memset(doc + o, ']', depth);
    o += depth;
    doc[o++] = '}';
    parse_anything(doc, o);
    free(doc);
    const char *big = OBJ("\"resolution\": 1e300, \"ior\": 1.5");
    parse_anything(big, strlen(big));
    const char *neg = OBJ("\"resolution\": [-1e300, 2, 2], \"ior\": 1.5");
    parse_anything(neg, strlen(neg));
    const char *longnum = OBJ("\"ior\": 1.5000000000000000000000000000000000000000000000000000000"
                              "000000000000000000000000000000001");
    parse_anything(longnum, strlen(longnum));
    const char *nul = "{\"objects\": [{\"name\": \"a\\u0000b\", " BOUNDS ", \"ior\": 1.5}]}";
    parse_anything(nul, strlen(nul));
    const char *bytes = "{\"objects\": [{\"name\": \"\xff\xfe\x01\", " BOUNDS ", \"ior\": 1.5}]}";
    parse_anything(bytes, strlen(bytes));
    CHECK(fuzz_runs > 100);
}

int main(void)
{
    rejects_each_bad_document_with_exact_code_and_path();
    rejects_more_objects_than_max_objects();
    rejects_limits_set_lower_naming_the_configured_value();
    applies_defaults_to_a_minimal_document();
    defaults_stay_within_lowered_limits();
    reads_every_field_of_a_full_document();
    reads_the_steppers_old_key();
    reads_layer_lists_and_shape_parameters();
    an_ior_array_of_numbers_is_a_list_of_constant_layers();
    survives_every_truncation_of_a_valid_document();
    survives_wrong_types_at_every_level();
    survives_random_byte_mutations();
    survives_deep_nesting_and_huge_numbers();
    printf("fuzzed %d documents\n", fuzz_runs);
    return test_summary("test_scene_parse");
}
