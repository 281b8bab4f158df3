/*
 * test_bad_input_scenes.c - bad input to the router and to the scene resource gets exactly
 * the error it should, and the daemon survives it. Each case checks the HTTP status, the
 * JSON error.code and the words of the message that name the JSON path, the key or the
 * limit; a case that accepted any non-2xx answer would prove little.
 *
 * Covered here: routing (404 not_found, 405 method_not_allowed); POST /v1/scenes (syntax,
 * types at several depths, unknown and missing fields, ranges, non-finite numbers, each
 * limit, the body size limit, the scene count); GET and DELETE /v1/scenes/{id}.
 * test_bad_input_requests.c covers uploads, render and trace; test_bad_input_fuzz.c sends
 * random and mutated documents.
 *
 * The daemon runs with small limits so that every limit is reached by a small request.
 * Each case is one row or one call; a failing case prints its file:line, the request, what
 * was expected and the body that came back.
 */
#include <cjson/cJSON.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon.h"
#include "expect.h"
#include "test.h"

/* The daemon's limits; the cases below are written against them. */
/* clang-format off */
static const char *const daemon_args[] = {
    "--max-resolution", "64",
    "--max-objects", "2",
    "--max-json-bytes", "65536",
    "--max-upload-bytes", "100000",
    "--max-rays", "4",
    "--max-image-dim", "256",
    "--max-scenes", "3",
    NULL,
};
/* clang-format on */

#define BOUNDS "\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}"
/* A valid object; cases replace one part of it at a time. */
#define OBJ "{" BOUNDS ", \"resolution\": 8, \"ior\": 1.5}"
#define VALID_SCENE                                                                                \
    "{\"name\": \"ok\", \"camera\": {\"width\": 32, \"height\": 24}, \"objects\": [" OBJ "]}"

/* ---- helpers beyond the checks in expect.h -------------------------------------------- */

/* Creates a scene; writes its id into id (REFRACT_ID_SIZE bytes). */
static bool create_scene(struct test_daemon *d, const char *json, char *id)
{
    id[0] = '\0';
    return test_create_scene(d, json, id);
}

/* Deletes every scene the daemon holds; returns how many it deleted. */
static int delete_all_scenes(struct test_daemon *d)
{
    char *body = NULL;
    int deleted = 0;
    if (test_request(d, "GET", "/v1/scenes", NULL, &body) != 200) {
        free(body);
        return -1;
    }
    cJSON *root = cJSON_Parse(body);
    const cJSON *s;
    cJSON_ArrayForEach(s, cJSON_GetObjectItemCaseSensitive(root, "scenes"))
    {
        const cJSON *id = cJSON_GetObjectItemCaseSensitive(s, "id");
        if (cJSON_IsString(id) && refract_scene_delete(d->client, id->valuestring) == 0)
            deleted++;
    }
    cJSON_Delete(root);
    free(body);
    return deleted;
}

static int scene_count(struct test_daemon *d)
{
    char *body = NULL;
    int n = -1;
    if (test_request(d, "GET", "/v1/scenes", NULL, &body) == 200) {
        cJSON *root = cJSON_Parse(body);
        n = cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "scenes"));
        cJSON_Delete(root);
    }
    free(body);
    return n;
}

/* ---- routing ----------------------------------------------------------------------------- */

static void unknown_paths_are_404_and_wrong_methods_are_405(struct test_daemon *d)
{
    section("routing");
    EXPECT_ERROR(d, "GET", "/v1/nope", NULL, 404, "not_found", "no route GET /v1/nope");
    EXPECT_ERROR(d, "GET", "/index.html", NULL, 404, "not_found", "no route GET /index.html");
    EXPECT_ERROR(d, "POST", "/", "{}", 405, "method_not_allowed", "POST is not allowed on /",
                 "allowed: GET");
    EXPECT_ERROR(d, "GET", "/viewer/no_such_scene", NULL, 404, "scene_not_found",
                 "no scene with id \"no_such_scene\" to view");
    EXPECT_ERROR(d, "GET", "/assets/nope.css", NULL, 404, "not_found", "/assets/nope.css",
                 "viewer.js");
    EXPECT_ERROR(d, "POST", "/v2/scenes", VALID_SCENE, 404, "not_found", "/v2/scenes");
    EXPECT_ERROR(d, "GET", "/v1/scenes/", NULL, 404, "not_found", "/v1/scenes/");
    EXPECT_ERROR(d, "GET", "/v1/scenes/abc/volumes", NULL, 404, "not_found",
                 "/v1/scenes/abc/volumes");
    EXPECT_ERROR(d, "PATCH", "/v1/scenes", "{}", 405, "method_not_allowed",
                 "PATCH is not allowed on /v1/scenes", "allowed: GET, POST");
    EXPECT_ERROR(d, "PUT", "/v1/health", "{}", 405, "method_not_allowed",
                 "PUT is not allowed on /v1/health", "allowed: GET");
    EXPECT_ERROR(d, "DELETE", "/v1/health", NULL, 405, "method_not_allowed", "allowed: GET");
    EXPECT_ERROR(d, "OPTIONS", "/v1/scenes", NULL, 405, "method_not_allowed", "allowed: GET, POST");
    /* HEAD is not served either (proto/openapi.yaml); its answer has no body to check. */
    struct refract_response head;
    section_cases++;
    if (refract_request(d->client, "HEAD", "/v1/health", NULL, 0, NULL, &head) == REFRACT_E_OK) {
        CHECK_INT(head.status, 405);
        refract_response_free(&head);
    } else {
        CHECK_MSG(false, "HEAD /v1/health: no answer (%s)", refract_errmsg(d->client));
    }
    EXPECT_ERROR(d, "PUT", "/v1/scenes/abc", VALID_SCENE, 405, "method_not_allowed",
                 "allowed: GET, DELETE");
    EXPECT_ERROR(d, "GET", "/v1/scenes/abc/render", NULL, 405, "method_not_allowed",
                 "allowed: POST");
    EXPECT_ERROR(d, "GET", "/v1/scenes/abc/trace", NULL, 405, "method_not_allowed",
                 "allowed: POST");
    EXPECT_ERROR(d, "GET", "/v1/scenes/abc/volumes/v", NULL, 405, "method_not_allowed",
                 "allowed: PUT");
    EXPECT_ERROR(d, "POST", "/v1/scenes/abc/environment", "{}", 405, "method_not_allowed",
                 "allowed: PUT");
}

/* ---- POST /v1/scenes ---------------------------------------------------------------------- */

/* Scene documents and the error each must get; the limits are daemon_args'. */
/* clang-format off */
static const struct json_error_case scene_cases[] = {
    /* syntax */
    {__LINE__, "", 400, "invalid_json", {"empty"}},
    {__LINE__, "  \n\t ", 400, "invalid_json", {"empty"}},
    {__LINE__, "{\"objects\": [", 400, "invalid_json",
     {"at byte 12 (line 1, column 13)", "truncated"}},
    {__LINE__, "{\"objects\": [" OBJ "]} xyz", 400, "invalid_json",
     {"unexpected text after the JSON document", "near \"xyz\""}},
    {__LINE__, "{\n  \"name\": \"x\",\n  \"objects\": [1,,]\n}", 400, "invalid_json",
     {"at byte 33 (line 3, column 17)"}},
    {__LINE__, "{\"objects\": [" OBJ "],}", 400, "invalid_json", {"line 1"}},
    {__LINE__, "{'objects': []}", 400, "invalid_json", {"invalid JSON at byte", "line 1"}},
    /* the document's shape and types, at several depths */
    {__LINE__, "[1, 2]", 400, "invalid_field", {"(root): expected an object", "an array of 2"}},
    {__LINE__, "\"scene\"", 400, "invalid_field", {"(root): expected an object"}},
    {__LINE__, "{\"objects\": {}}", 400, "invalid_field",
     {"objects: expected an array of 1..2 objects", "got an object"}},
    {__LINE__, "{\"objects\": []}", 400, "invalid_field",
     {"objects: expected an array of 1..2 objects", "got an array of 0 values"}},
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"resolution\": \"big\", \"ior\": 1.5}]}", 400,
     "invalid_field", {"objects[0].resolution: expected an integer", "got \"big\""}},
    {__LINE__, "{\"camera\": {\"eye\": [0, 0]}, \"objects\": [" OBJ "]}", 400, "invalid_field",
     {"camera.eye: expected an array of 3 numbers", "got an array of 2 values"}},
    {__LINE__, "{\"camera\": null, \"objects\": [" OBJ "]}", 400, "invalid_field",
     {"camera: expected an object, got null"}},
    {__LINE__, "{\"name\": 7, \"objects\": [" OBJ "]}", 400, "invalid_field",
     {"name: expected a string", "got 7"}},
    {__LINE__, "{\"objects\": [" OBJ ", 5]}", 400, "invalid_field",
     {"objects[1]: expected an object", "got 5"}},
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"ior\": [1.5, \"glass\"]}]}", 400, "invalid_field",
     {"objects[0].ior[1]: expected a value", "got \"glass\""}},
    {__LINE__,
     "{\"objects\": [{" BOUNDS ", \"ior\": 1.5, \"transform\": {\"rotate\": {\"axis\": \"y\", "
     "\"angle_deg\": 10}}}]}",
     400, "invalid_field", {"objects[0].transform.rotate.axis: expected an array of 3 numbers"}},
    {__LINE__,
     "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": true}, \"ior\": 1.5}]}", 400,
     "invalid_field", {"objects[0].bounds.max: expected an array of 3 numbers", "got true"}},
    /* unknown fields: the path and the allowed keys */
    {__LINE__, "{\"colour\": 1, \"objects\": [" OBJ "]}", 400, "unknown_field",
     {"(root): unknown field \"colour\"",
      "allowed: name, description, ambient_ior, environment, camera, render, objects"}},
    {__LINE__, "{\"Objects\": [" OBJ "]}", 400, "unknown_field",
     {"(root): unknown field \"Objects\"", "allowed: "}},
    {__LINE__, "{\"camera\": {\"fov\": 30}, \"objects\": [" OBJ "]}", 400, "unknown_field",
     {"camera: unknown field \"fov\"", "allowed: eye, look_at, up, fov_y_deg, width, height"}},
    {__LINE__, "{\"render\": {\"steps\": 1}, \"objects\": [" OBJ "]}", 400, "unknown_field",
     {"render: unknown field \"steps\"", "allowed: stepper, step, tolerance, max_steps"}},
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"colour\": 1, \"ior\": 1.5}]}", 400, "unknown_field",
     {"objects[0]: unknown field \"colour\"", "allowed: name, bounds, resolution, transform"}},
    {__LINE__,
     "{\"objects\": [{" BOUNDS ", \"ior\": [1.0, {\"shape\": \"sphere\", \"radius\": 0.5, "
     "\"inside\": 1.5, \"radiuss\": 2}]}]}",
     400, "unknown_field",
     {"objects[0].ior[1]: unknown field \"radiuss\"",
      "allowed: shape, center, radius, inside, outside"}},
    {__LINE__,
     "{\"objects\": [{" BOUNDS ", \"ior\": {\"profile\": \"luneburg\", \"radius\": 1, "
     "\"n0\": 2}}]}",
     400, "unknown_field",
     {"objects[0].ior: unknown field \"n0\"", "allowed: profile, center, radius"}},
    {__LINE__, "{\"name\": \"a\", \"name\": \"b\", \"objects\": [" OBJ "]}", 400, "invalid_field",
     {"name: duplicate field"}},
    /* missing fields */
    {__LINE__, "{\"name\": \"x\"}", 400, "missing_field",
     {"(root): missing required field \"objects\""}},
    {__LINE__, "{\"objects\": [{\"ior\": 1.5}]}", 400, "missing_field",
     {"objects[0]: missing required field \"bounds\""}},
    {__LINE__, "{\"objects\": [{\"bounds\": {\"min\": [0, 0, 0]}, \"ior\": 1.5}]}", 400,
     "missing_field", {"objects[0].bounds: missing required field \"max\""}},
    {__LINE__, "{\"objects\": [" OBJ ", {" BOUNDS "}]}", 400, "missing_field",
     {"objects[1]: an object needs at least one of ior, attenuation, emission, opaque"}},
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"ior\": {\"shape\": \"sphere\", \"radius\": 0.5}}]}",
     400, "missing_field", {"objects[0].ior: missing required field \"inside\""}},
    /* out of range */
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"ior\": 99}]}", 400, "invalid_field",
     {"objects[0].ior: expected a finite number in 0.2..5, got 99"}},
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"resolution\": 1, \"ior\": 1.5}]}", 400,
     "invalid_field", {"objects[0].resolution: expected an integer in 2..64, got 1"}},
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"resolution\": 8.5, \"ior\": 1.5}]}", 400,
     "invalid_field", {"objects[0].resolution", "got 8.5"}},
    {__LINE__, "{\"camera\": {\"fov_y_deg\": 0}, \"objects\": [" OBJ "]}", 400, "invalid_field",
     {"camera.fov_y_deg: expected a finite number > 0.1 and <= 179, got 0"}},
    {__LINE__,
     "{\"objects\": [{" BOUNDS ", \"ior\": {\"shape\": \"sphere\", \"radius\": -1, "
     "\"inside\": 1.5}}]}",
     400, "invalid_field", {"objects[0].ior.radius: expected a finite number > 0", "got -1"}},
    {__LINE__,
     "{\"objects\": [{\"bounds\": {\"min\": [1, 1, 1], \"max\": [1, 2, 2]}, \"ior\": 1.5}]}",
     400, "invalid_field", {"objects[0].bounds: max must be greater than min", "on x"}},
    {__LINE__, "{\"camera\": {\"eye\": [0, 0, 0], \"look_at\": [0, 0, 0]}, \"objects\": [" OBJ "]}",
     400, "invalid_field", {"camera.look_at: equals camera.eye"}},
    {__LINE__, "{\"render\": {\"stepper\": \"verlet\"}, \"objects\": [" OBJ "]}", 400,
     "invalid_field", {"render.stepper: expected one of \"euler\", \"rk4\", \"rk2\", \"adaptive\", got \"verlet\""}},
    /* huge numbers overflow to infinity and are rejected with their path */
    {__LINE__, "{\"ambient_ior\": 1e999, \"objects\": [" OBJ "]}", 400, "invalid_field",
     {"ambient_ior: expected a finite number in 1..4", "got inf"}},
    {__LINE__, "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1e999, 1, 1]}, "
               "\"ior\": 1.5}]}",
     400, "invalid_field", {"objects[0].bounds.max[0]: expected a finite number", "got inf"}},
    {__LINE__, "{\"camera\": {\"eye\": [0, 0, -1e999]}, \"objects\": [" OBJ "]}", 400,
     "invalid_field", {"camera.eye[2]: expected a finite number", "got -inf"}},
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"resolution\": [8, 8, 1e999], \"ior\": 1.5}]}", 400,
     "invalid_field", {"objects[0].resolution[2]: expected an integer", "got inf"}},
    /* limits: the limit and the flag that raises it */
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"resolution\": 65, \"ior\": 1.5}]}", 422,
     "limit_exceeded",
     {"objects[0].resolution: 65 exceeds the limit max_resolution = 64", "--max-resolution"}},
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"resolution\": [8, 8, 1000], \"ior\": 1.5}]}", 422,
     "limit_exceeded", {"objects[0].resolution[2]: 1000 exceeds", "--max-resolution"}},
    {__LINE__, "{\"objects\": [" OBJ ", " OBJ ", " OBJ "]}", 422, "limit_exceeded",
     {"objects: 3 objects exceeds the limit max_objects = 2", "--max-objects"}},
    {__LINE__, "{\"camera\": {\"width\": 300}, \"objects\": [" OBJ "]}", 422, "limit_exceeded",
     {"camera.width: 300 exceeds the limit max_image_dim = 256", "--max-image-dim"}},
    /* lights, receiver, lightsim, brdf, the scattering channels and the bumpy sphere */
    {__LINE__, "{\"lights\": [{\"direction\": [0, -1, 0]}], \"objects\": [" OBJ "]}", 400,
     "missing_field", {"lights[0]: missing required field \"type\""}},
    {__LINE__,
     "{\"lights\": [{\"type\": \"point\", \"position\": [0, 2, 0], \"angle_deg\": 20}], "
     "\"objects\": [" OBJ "]}",
     400, "unknown_field",
     {"lights[0]: unknown field \"angle_deg\"", "allowed: name, type, position, color, intensity"}},
    {__LINE__,
     "{\"lights\": [{\"type\": \"directional\", \"direction\": [0, -1, 0], \"name\": \"a\"}, "
     "{\"type\": \"point\", \"position\": [0, 2, 0], \"name\": \"a\"}], \"objects\": [" OBJ "]}",
     400, "invalid_field", {"lights[1].name: \"a\" is already the name of lights[0]"}},
    {__LINE__,
     "{\"lights\": [{\"type\": \"spot\", \"position\": [0, 2, 0], \"direction\": [0, -1, 0], "
     "\"angle_deg\": 95}], \"objects\": [" OBJ "]}",
     400, "invalid_field", {"lights[0].angle_deg: expected a finite number in 1..89, got 95"}},
    {__LINE__, "{\"lights\": 3, \"objects\": [" OBJ "]}", 400, "invalid_field",
     {"lights: expected an array of 0..4 light objects", "got 3"}},
    {__LINE__, "{\"receiver\": {\"half_size\": 2}, \"objects\": [" OBJ "]}", 400,
     "missing_field", {"receiver: missing required field \"height\""}},
    {__LINE__, "{\"receiver\": {\"height\": -2, \"albedo\": [1, 2, 1]}, \"objects\": [" OBJ "]}",
     400, "invalid_field", {"receiver.albedo[1]: expected a finite number in 0..1, got 2"}},
    {__LINE__, "{\"lightsim\": {\"resolution\": 1024}, \"objects\": [" OBJ "]}", 400,
     "invalid_field", {"lightsim.resolution: expected an integer in 8..512, got 1024"}},
    {__LINE__, "{\"lightsim\": {\"deposit\": 1}, \"objects\": [" OBJ "]}", 400, "invalid_field",
     {"lightsim.deposit", "\"flux\", \"max\""}},
    {__LINE__, "{\"lightsim\": {\"cull\": true}, \"objects\": [" OBJ "]}", 400, "unknown_field",
     {"lightsim: unknown field \"cull\"", "cull_flipped"}},
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"ior\": 1.5, \"brdf\": {\"type\": \"blinn\"}}]}", 400,
     "invalid_field", {"objects[0].brdf.type: expected one of", "got \"blinn\""}},
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"scattering\": [0.1, 0.2]}]}", 400, "invalid_field",
     {"objects[0].scattering: expected a number or [r, g, b]", "got an array of 2 values"}},
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"scattering\": 1, \"anisotropy\": 1}]}", 400,
     "invalid_field", {"objects[0].anisotropy: expected a finite number in -0.99..0.99, got 1"}},
    {__LINE__, "{\"objects\": [{" BOUNDS ", \"ior\": 1.5, \"anisotropy\": 0.5}]}", 400,
     "invalid_field", {"objects[0].anisotropy: has no effect without scattering"}},
    {__LINE__,
     "{\"objects\": [{" BOUNDS ", \"ior\": {\"shape\": \"bumpy_sphere\", \"radius\": 0.5, "
     "\"bump_frequency\": 40, \"inside\": 1.5}}]}",
     400, "invalid_field", {"objects[0].ior.bump_frequency: expected an integer in 1..32, got 40"}},
    /* A name that JSON can carry but a C string cannot: "\u0000" would cut it short,
     * silently storing a different name ("never lost data"). */
    {__LINE__, "{\"name\": \"a\\u0000b\", \"objects\": [" OBJ "]}", 400, "invalid_field",
     {"name"}},
};
/* clang-format on */

static void each_bad_scene_document_gets_its_error(struct test_daemon *d)
{
    section("POST /v1/scenes");
    EXPECT_JSON_ERROR_CASES(d, "POST", "/v1/scenes", scene_cases);
}

/* Cases whose bodies a string literal cannot hold: deep nesting, a raw NUL byte, a body
 * over the size limit. */
static void unusual_scene_bodies_get_their_errors(struct test_daemon *d)
{
    size_t depth = 2000;
    char *deep = malloc(2 * depth + 1);
    memset(deep, '[', depth);
    memset(deep + depth, ']', depth);
    deep[2 * depth] = '\0';
    EXPECT_ERROR(d, "POST", "/v1/scenes", deep, 400, "invalid_json",
                 "at byte 1000 (line 1, column 1001)", "nesting deeper than 1000 levels");
    free(deep);

    /* RFC 8259 sect. 7: control characters must be escaped inside strings. A raw NUL is
     * not JSON, and accepting it silently cuts the name at the NUL. */
    static const char raw_nul[] = "{\"name\": \"a\0b\", \"objects\": [" OBJ "]}";
    EXPECT_RAW_ERROR(d, "POST", "/v1/scenes", raw_nul, sizeof raw_nul - 1, "application/json", 400,
                     "invalid_json", "byte 11");

    /* Valid JSON, over --max-json-bytes (65536). */
    size_t n = 70000;
    char *big = malloc(n + 1);
    memset(big, ' ', n);
    memcpy(big, "{\"name\": \"", 10);
    memset(big + 10, 'a', n - 20);
    memcpy(big + n - 10, "\"}        ", 10);
    big[n] = '\0';
    EXPECT_ERROR(d, "POST", "/v1/scenes", big, 413, "body_too_large",
                 "exceeds the limit of 65536 bytes", "--max-json-bytes");
    free(big);
}

/* ---- GET and DELETE /v1/scenes/{id} -------------------------------------------------------- */

static void unknown_and_deleted_scenes_are_404(struct test_daemon *d)
{
    section("GET/DELETE /v1/scenes/{id}");
    CHECK(delete_all_scenes(d) >= 0); /* room under --max-scenes 3 */
    EXPECT_ERROR(d, "GET", "/v1/scenes/nope", NULL, 404, "scene_not_found", "\"nope\"");
    EXPECT_ERROR(d, "DELETE", "/v1/scenes/nope", NULL, 404, "scene_not_found", "\"nope\"");
    /* An id that cannot exist is still an id on a known route: scene_not_found, not a
     * missing route. */
    char path[160], long_id[71];
    memset(long_id, 'a', 70);
    long_id[70] = '\0';
    snprintf(path, sizeof path, "/v1/scenes/%s", long_id);
    EXPECT_ERROR(d, "GET", path, NULL, 404, "scene_not_found", long_id);

    char id[REFRACT_ID_SIZE], keep[REFRACT_ID_SIZE];
    CHECK(create_scene(d, VALID_SCENE, keep));
    CHECK(create_scene(d, VALID_SCENE, id));
    snprintf(path, sizeof path, "/v1/scenes/%s", id);
    free(EXPECT_STATUS(d, "DELETE", path, NULL, 204));
    EXPECT_ERROR(d, "DELETE", path, NULL, 404, "scene_not_found", id);
    EXPECT_ERROR(d, "GET", path, NULL, 404, "scene_not_found", id);
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    EXPECT_ERROR(d, "POST", path, "{}", 404, "scene_not_found", id);
    snprintf(path, sizeof path, "/v1/scenes/%s/trace", id);
    EXPECT_ERROR(d, "POST", path,
                 "{\"rays\": [{\"origin\": [0, 0, 4], \"direction\": [0, 0, -1]}]}", 404,
                 "scene_not_found", id);

    /* Path segments that look like directories name no scene, and delete nothing. */
    EXPECT_ERROR(d, "DELETE", "/v1/scenes/..", NULL, 404, "scene_not_found", "\"..\"");
    EXPECT_ERROR(d, "DELETE", "/v1/scenes/.", NULL, 404, "scene_not_found", "\".\"");
    /* %00 decodes to a NUL byte: "<keep>%00xyz" is another id, and deleting it must not
     * delete <keep> (never lost data). */
    char want[REFRACT_ID_SIZE + 8];
    snprintf(path, sizeof path, "/v1/scenes/%s%%00xyz", keep);
    snprintf(want, sizeof want, "\"%s", keep);
    EXPECT_ERROR(d, "DELETE", path, NULL, 404, "scene_not_found", want);
    snprintf(path, sizeof path, "/v1/scenes/%s", keep);
    free(EXPECT_STATUS(d, "GET", path, NULL, 200));
}

/* ---- --max-scenes ---------------------------------------------------------------------------- */

static void scenes_beyond_max_scenes_are_refused_and_nothing_is_lost(struct test_daemon *d)
{
    section("POST /v1/scenes: --max-scenes");
    CHECK(delete_all_scenes(d) >= 0);
    CHECK_INT(scene_count(d), 0);
    char ids[3][REFRACT_ID_SIZE];
    for (int i = 0; i < 3; i++)
        CHECK(create_scene(d, VALID_SCENE, ids[i]));
    EXPECT_ERROR(d, "POST", "/v1/scenes", VALID_SCENE, 422, "limit_exceeded", "3 scenes",
                 "--max-scenes");
    CHECK_INT(scene_count(d), 3);
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s", ids[0]);
    free(EXPECT_STATUS(d, "DELETE", path, NULL, 204));
    CHECK(create_scene(d, VALID_SCENE, ids[0]));
    EXPECT_ERROR(d, "POST", "/v1/scenes", VALID_SCENE, 422, "limit_exceeded", "--max-scenes");
    CHECK_INT(scene_count(d), 3);
}

/* ---- after all of it ------------------------------------------------------------------------- */

static void daemon_still_answers_and_renders(struct test_daemon *d)
{
    section("");
    free(EXPECT_STATUS(d, "GET", "/v1/health", NULL, 200));
    char id[REFRACT_ID_SIZE];
    CHECK(delete_all_scenes(d) >= 0);
    CHECK(create_scene(d, VALID_SCENE, id));
    struct refract_image img = {0};
    int rc = refract_render(d->client, id, "{\"format\": \"png\"}", &img);
    CHECK_MSG(rc == REFRACT_E_OK, "render after bad input: %s", refract_errmsg(d->client));
    CHECK_STR(img.content_type, "image/png");
    CHECK(img.len > 8 && memcmp(img.bytes, "\x89PNG", 4) == 0);
    refract_image_free(&img);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, daemon_args))
        test_setup_failed("test_bad_input_scenes", d.why);
    printf("cases per endpoint:\n");
    unknown_paths_are_404_and_wrong_methods_are_405(&d);
    each_bad_scene_document_gets_its_error(&d);
    unusual_scene_bodies_get_their_errors(&d);
    unknown_and_deleted_scenes_are_404(&d);
    scenes_beyond_max_scenes_are_refused_and_nothing_is_lost(&d);
    daemon_still_answers_and_renders(&d);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_bad_input_scenes");
}
