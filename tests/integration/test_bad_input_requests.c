/*
 * test_bad_input_requests.c - bad uploads, render and trace requests get exactly the error
 * they should, and the daemon survives them. Each case checks the HTTP status, the JSON
 * error.code and the words of the message that name the parameter, JSON path or limit.
 *
 * Covered here: PUT /v1/scenes/{id}/volumes/{name} (query, size, values, limits, media
 * type, names), PUT /v1/scenes/{id}/environment (undecodable images), POST
 * /v1/scenes/{id}/render (syntax, fields, ranges, limits, the camera, missing uploads) and
 * POST /v1/scenes/{id}/trace (the rays), PUT /v1/scenes/{id}/lights and .../lights/{name}
 * (syntax, the body's shape, every light field through the scene parser's JSON paths; a
 * failed change leaves the lights as they were). A failed upload must leave what was stored
 * before untouched ("never lost data"). test_bad_input_scenes.c covers routing and the
 * scene resource; test_bad_input_fuzz.c sends random and mutated documents.
 *
 * The daemon runs with small limits so that every limit is reached by a small request.
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
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
    "--max-steps", "5000",
    "--max-scenes", "8",
    NULL,
};
/* clang-format on */

#define BOUNDS "\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}"
/* A glass sphere on 16^3 voxels, 32 x 24 pixels by default. */
#define VALID_SCENE                                                                                \
    "{\"name\": \"ok\", \"camera\": {\"eye\": [0, 0, 4], \"width\": 32, \"height\": 24}, "         \
    "\"objects\": [{" BOUNDS ", \"resolution\": 16, "                                              \
    "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}}]}"
#define ONE_RAY "{\"origin\": [0, 0, 4], \"direction\": [0, 0, -1]}"

static const char *const octet = "application/octet-stream";

/* ---- helpers beyond the checks in expect.h -------------------------------------------- */

/* A raw upload expected to succeed with status; returns the parsed JSON answer (caller
 * deletes) or NULL. */
static cJSON *expect_upload_at(const char *file, int line, struct test_daemon *d, const char *path,
                               const void *bytes, size_t len, long status)
{
    struct refract_response r;
    int rc = refract_request(d->client, "PUT", path, bytes, len, octet, &r);
    cJSON *json = NULL;
    if (rc == REFRACT_E_OK && r.status == status)
        json = cJSON_ParseWithLength(r.body, r.body_len);
    if (json != NULL) {
        test_passed_count++;
    } else {
        test_failed_count++;
        fprintf(stderr, "%s:%d: PUT %s: expected HTTP %ld with JSON, got %ld: %s\n", file, line,
                path, status, rc == REFRACT_E_OK ? r.status : -1L,
                rc == REFRACT_E_OK ? r.body : refract_errmsg(d->client));
    }
    if (rc == REFRACT_E_OK)
        refract_response_free(&r);
    return json;
}
#define EXPECT_UPLOAD(d, path, bytes, len, status)                                                 \
    expect_upload_at(__FILE__, __LINE__, (d), (path), (bytes), (len), (status))

/* GET /v1/scenes/{id} as JSON (caller deletes), or NULL. */
static cJSON *scene_details(struct test_daemon *d, const char *id)
{
    char *body = NULL;
    cJSON *json = NULL;
    if (refract_scene_get(d->client, id, &body) == REFRACT_E_OK)
        json = cJSON_Parse(body);
    refract_free(body);
    return json;
}

/* The entry of the scene's "volumes" list named name, or NULL. Borrows scene. */
static const cJSON *volume_entry(const cJSON *scene, const char *name)
{
    const cJSON *v;
    cJSON_ArrayForEach(v, cJSON_GetObjectItemCaseSensitive(scene, "volumes"))
    {
        const cJSON *n = cJSON_GetObjectItemCaseSensitive(v, "name");
        if (cJSON_IsString(n) && strcmp(n->valuestring, name) == 0)
            return v;
    }
    return NULL;
}

static double number_at(const cJSON *obj, const char *key)
{
    const cJSON *n = cJSON_GetObjectItemCaseSensitive(obj, key);
    return cJSON_IsNumber(n) ? n->valuedouble : NAN;
}

static const char *path_of(char *buf, size_t size, const char *id, const char *rest)
{
    snprintf(buf, size, "/v1/scenes/%s%s", id, rest);
    return buf;
}

/* FNV-1a, 64 bits, over len bytes: what refractd reports as checksum_fnv1a64. */
static uint64_t fnv1a64(const void *data, size_t len)
{
    const unsigned char *p = data;
    uint64_t h = 14695981039346656037ull;
    for (size_t i = 0; i < len; i++) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

/* Deterministic bytes (xorshift64), so a failure reproduces. */
static void fill_random(unsigned char *out, size_t len, uint64_t seed)
{
    uint64_t x = seed;
    for (size_t i = 0; i < len; i++) {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        out[i] = (unsigned char)(x >> 24);
    }
}

/* ---- PUT /v1/scenes/{id}/volumes/{name} --------------------------------------------------- */

static void bad_volume_uploads_get_their_errors(struct test_daemon *d, const char *id)
{
    section("PUT /v1/scenes/{id}/volumes/{name}");
    float v[24];
    for (int i = 0; i < 24; i++)
        v[i] = 1.25f;
    const size_t one = 8 * sizeof(float); /* dims 2,2,2 with 1 component */
    char p[300];
    EXPECT_RAW_ERROR(d, "PUT", "/v1/scenes/nope/volumes/v?dims=2,2,2", v, one, octet, 404,
                     "scene_not_found", "\"nope\"");
    /* the query */
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v"), v, one, octet, 400,
                     "missing_field", "dims", "?dims=");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=8,8"), v, one, octet, 400,
                     "invalid_field", "query parameter dims", "\"8,8\"");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=8,8,x"), v, one, octet,
                     400, "invalid_field", "query parameter dims", "\"8,8,x\"");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=0,8,8"), v, one, octet,
                     400, "invalid_field", "query parameter dims", "\"0,8,8\"");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=-2,2,2"), v, one, octet,
                     400, "invalid_field", "query parameter dims", "\"-2,2,2\"");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,2,2"), v, one, octet,
                     400, "invalid_field", "query parameter dims", "\"2,2,2,2\"");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims="), v, one, octet, 400,
                     "invalid_field", "query parameter dims", "\"\"");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,2&components=2"), v,
                     one, octet, 400, "invalid_field", "query parameter components", "\"2\"");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,2&components=rgb"), v,
                     one, octet, 400, "invalid_field", "query parameter components", "\"rgb\"");
    /* A misspelt parameter is not ignored: "component=3" must not store 1 component. */
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/typo?dims=2,2,2&component=3"), v,
                     one, octet, 400, "unknown_field", "component", "dims, components");
    /* the body against the dimensions */
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,2"), v, one - 1, octet,
                     400, "invalid_volume", "31 bytes", "need 32");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,2&components=3"), v,
                     one, octet, 400, "invalid_volume", "32 bytes", "need 96");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,2"), NULL, 0, octet,
                     400, "invalid_volume", "0 bytes", "need 32");
    /* non-finite values, located by voxel (x fastest) */
    float bad[24];
    memcpy(bad, v, sizeof bad);
    bad[5] = NAN;
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,2"), bad, one, octet,
                     400, "invalid_volume", "voxel x=1 y=0 z=1", "finite");
    memcpy(bad, v, sizeof bad);
    bad[0] = -INFINITY;
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,2"), bad, one, octet,
                     400, "invalid_volume", "voxel x=0 y=0 z=0");
    memcpy(bad, v, sizeof bad);
    bad[23] = INFINITY; /* voxel 7, component 2 */
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,2&components=3"), bad,
                     sizeof bad, octet, 400, "invalid_volume", "voxel x=1 y=1 z=1");
    /* limits */
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=65,2,2"), v, one, octet,
                     422, "limit_exceeded", "65 voxels along x", "--max-resolution");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,100"), v, one, octet,
                     422, "limit_exceeded", "along z", "--max-resolution");
    size_t big_len = 30 * 30 * 30 * sizeof(float); /* 108000 > --max-upload-bytes 100000 */
    char *big = calloc(1, big_len);
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=30,30,30"), big, big_len,
                     octet, 413, "body_too_large", "exceeds the limit of 100000 bytes",
                     "--max-upload-bytes");
    free(big);
    /* media type */
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,2"), v, one,
                     "application/json", 415, "unsupported_media_type", "\"application/json\"",
                     "application/octet-stream");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,2"), v, one,
                     "text/plain", 415, "unsupported_media_type", "\"text/plain\"");
    /* names: 1..63 characters of A-Z a-z 0-9 _ - */
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/a%20b?dims=2,2,2"), v, one, octet,
                     400, "invalid_field", "volume name \"a b\"", "1..63");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/a.b?dims=2,2,2"), v, one, octet,
                     400, "invalid_field", "volume name \"a.b\"");
    /* %00 decodes to a NUL byte, which must not cut the name ("a") or the query short. */
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/a%00b?dims=2,2,2"), v, one, octet,
                     400, "invalid_field", "volume name");
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/v?dims=2,2,2%00junk"), v, one,
                     octet, 400, "invalid_field", "query parameter dims");
    char name64[65], name70[71], rest[128];
    memset(name64, 'n', 64);
    name64[64] = '\0';
    memset(name70, 'n', 70);
    name70[70] = '\0';
    snprintf(rest, sizeof rest, "/volumes/%s?dims=2,2,2", name64);
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, rest), v, one, octet, 400, "invalid_field",
                     "volume name", "1..63");
    snprintf(rest, sizeof rest, "/volumes/%s?dims=2,2,2", name70);
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, rest), v, one, octet, 400, "invalid_field",
                     "volume name", "1..63");
}

static void a_good_volume_is_stored_and_a_bad_one_replaces_nothing(struct test_daemon *d,
                                                                   const char *id)
{
    float v[8] = {1.0f, 1.25f, 1.5f, 1.75f, 2.0f, 1.1f, 1.2f, 1.3f};
    char p[300], sum[20];
    cJSON *ans = EXPECT_UPLOAD(d, path_of(p, sizeof p, id, "/volumes/good_vol?dims=2,2,2"), v,
                               sizeof v, 201);
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(ans, "name");
    const cJSON *dims = cJSON_GetObjectItemCaseSensitive(ans, "dims");
    const cJSON *check = cJSON_GetObjectItemCaseSensitive(ans, "checksum_fnv1a64");
    CHECK_STR(cJSON_IsString(name) ? name->valuestring : NULL, "good_vol");
    CHECK(cJSON_GetArraySize(dims) == 3 && cJSON_GetArrayItem(dims, 0)->valueint == 2 &&
          cJSON_GetArrayItem(dims, 1)->valueint == 2 && cJSON_GetArrayItem(dims, 2)->valueint == 2);
    CHECK_NEAR(number_at(ans, "components"), 1, 0);
    CHECK_NEAR(number_at(ans, "bytes"), 32, 0);
    CHECK_NEAR(number_at(ans, "min"), 1.0, 1e-6);
    CHECK_NEAR(number_at(ans, "max"), 2.0, 1e-6);
    snprintf(sum, sizeof sum, "%016llx", (unsigned long long)fnv1a64(v, sizeof v));
    CHECK_STR(cJSON_IsString(check) ? check->valuestring : NULL, sum);
    cJSON_Delete(ans);

    /* A rejected upload under the same name leaves the stored volume as it was. */
    float bad[8];
    memcpy(bad, v, sizeof bad);
    bad[3] = NAN;
    EXPECT_RAW_ERROR(d, "PUT", path_of(p, sizeof p, id, "/volumes/good_vol?dims=8,1,1"), bad,
                     sizeof bad, octet, 400, "invalid_volume", "voxel x=3 y=0 z=0");
    cJSON *scene = scene_details(d, id);
    const cJSON *entry = volume_entry(scene, "good_vol");
    const cJSON *kept = cJSON_GetObjectItemCaseSensitive(entry, "dims");
    CHECK_MSG(cJSON_GetArraySize(kept) == 3 && cJSON_GetArrayItem(kept, 0)->valueint == 2,
              "good_vol should keep dims [2, 2, 2] after a rejected upload");
    CHECK(volume_entry(scene, "typo") == NULL); /* the misspelt upload stored nothing */
    CHECK(volume_entry(scene, "a") == NULL);    /* nor did "a%00b" */
    cJSON_Delete(scene);
}

/* ---- PUT /v1/scenes/{id}/environment ------------------------------------------------------ */

static void undecodable_environments_get_invalid_image(struct test_daemon *d, const char *id,
                                                       const struct refract_image *png)
{
    section("PUT /v1/scenes/{id}/environment");
    char p[300];
    unsigned char noise[1000];
    fill_random(noise, sizeof noise, 0x5eed);
    noise[0] = 0x00; /* no image format starts with a NUL byte */
    EXPECT_RAW_ERROR(d, "PUT", "/v1/scenes/nope/environment", png->bytes, png->len, octet, 404,
                     "scene_not_found", "\"nope\"");
    const char *env = path_of(p, sizeof p, id, "/environment");
    EXPECT_RAW_ERROR(d, "PUT", env, noise, sizeof noise, octet, 400, "invalid_image",
                     "1000 bytes that are not OpenEXR, Radiance .hdr, PNG or JPEG");
    EXPECT_RAW_ERROR(d, "PUT", env, NULL, 0, octet, 400, "invalid_image", "0 bytes");
    EXPECT_RAW_ERROR(d, "PUT", env, png->bytes, png->len / 2, octet, 400, "invalid_image",
                     "image:", "PNG");
    memcpy(noise, png->bytes, 16); /* a PNG signature and IHDR start, then noise */
    EXPECT_RAW_ERROR(d, "PUT", env, noise, sizeof noise, octet, 400, "invalid_image",
                     "image:", "PNG");
    EXPECT_RAW_ERROR(d, "PUT", env, png->bytes, png->len, "application/json", 415,
                     "unsupported_media_type", "\"application/json\"");
    EXPECT_RAW_ERROR(d, "PUT", env, png->bytes, png->len, "image/png", 415,
                     "unsupported_media_type", "\"image/png\"", "application/octet-stream");
    size_t big_len = 100001;
    char *big = calloc(1, big_len);
    EXPECT_RAW_ERROR(d, "PUT", env, big, big_len, octet, 413, "body_too_large", "100000",
                     "--max-upload-bytes");
    free(big);

    /* A good image is stored; a bad one after it replaces nothing. */
    cJSON *ans = EXPECT_UPLOAD(d, env, png->bytes, png->len, 201);
    CHECK_NEAR(number_at(ans, "width"), 16, 0);
    CHECK_NEAR(number_at(ans, "height"), 8, 0);
    cJSON_Delete(ans);
    EXPECT_RAW_ERROR(d, "PUT", env, png->bytes, png->len - 20, octet, 400, "invalid_image", "PNG");
    cJSON *scene = scene_details(d, id);
    const cJSON *e = cJSON_GetObjectItemCaseSensitive(scene, "environment");
    CHECK(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(e, "image_uploaded")));
    CHECK_NEAR(number_at(e, "width"), 16, 0);
    cJSON_Delete(scene);
}

/* ---- POST /v1/scenes/{id}/render ----------------------------------------------------------- */

/* Render requests against VALID_SCENE and the error each must get. */
/* clang-format off */
static const struct json_error_case render_cases[] = {
    {__LINE__, "{\"format\": ", 400, "invalid_json", {"invalid JSON at byte 10", "truncated"}},
    {__LINE__, "{\"format\": \"png\"} {}", 400, "invalid_json",
     {"unexpected text after the JSON document"}},
    {__LINE__, "[]", 400, "invalid_field", {"(root): expected an object"}},
    {__LINE__, "{\"colour\": 1}", 400, "unknown_field",
     {"(root): unknown field \"colour\"",
      "allowed: camera, width, height, format, exposure, tonemap, stepper, step, tolerance, "
      "max_steps"}},
    {__LINE__, "{\"camera\": {\"fov\": 30}}", 400, "unknown_field",
     {"camera: unknown field \"fov\"", "allowed: eye, look_at, up, fov_y_deg"}},
    {__LINE__, "{\"format\": \"gif\"}", 400, "invalid_field",
     {"format: expected one of \"png\", \"jpeg\", \"exr\"", "got \"gif\""}},
    {__LINE__, "{\"format\": 1}", 400, "invalid_field", {"format: expected one of", "got 1"}},
    {__LINE__, "{\"tonemap\": \"aces\"}", 400, "invalid_field",
     {"tonemap: expected one of \"clamp\", \"filmic\"", "got \"aces\""}},
    {__LINE__, "{\"width\": 0}", 400, "invalid_field", {"width: expected an integer", "got 0"}},
    {__LINE__, "{\"height\": -5}", 400, "invalid_field", {"height: expected an integer", "got -5"}},
    {__LINE__, "{\"width\": \"64\"}", 400, "invalid_field", {"width:", "got \"64\""}},
    {__LINE__, "{\"width\": 16.5}", 400, "invalid_field", {"width:", "got 16.5"}},
    /* proto/openapi.yaml: over --max-image-dim or --max-steps is 422 limit_exceeded, in a
     * render request as in a scene document, and "an error caused by a limit names the
     * flag that raises it". */
    {__LINE__, "{\"width\": 257}", 422, "limit_exceeded", {"width:", "257", "--max-image-dim"}},
    {__LINE__, "{\"max_steps\": 5001}", 422, "limit_exceeded", {"max_steps:", "--max-steps"}},
    {__LINE__, "{\"max_steps\": 0}", 400, "invalid_field", {"max_steps: expected an integer"}},
    {__LINE__, "{\"camera\": {\"eye\": [1, 2, 3], \"look_at\": [1, 2, 3]}}", 400, "invalid_field",
     {"camera", "look_at"}},
    {__LINE__, "{\"camera\": {\"eye\": [0, 0, 4], \"look_at\": [0, 0, 0], \"up\": [0, 0, 1]}}",
     400, "invalid_field", {"camera.up", "parallel"}},
    {__LINE__, "{\"camera\": {\"eye\": [0, 0]}}", 400, "invalid_field",
     {"camera.eye: expected an array of 3 numbers", "got an array of 2 values"}},
    {__LINE__, "{\"camera\": {\"eye\": [1e999, 0, 4]}}", 400, "invalid_field",
     {"camera.eye[0]", "got inf"}},
    {__LINE__, "{\"camera\": {\"fov_y_deg\": 180}}", 400, "invalid_field",
     {"camera.fov_y_deg: expected a finite number", "got 180"}},
    {__LINE__, "{\"camera\": null}", 400, "invalid_field",
     {"camera: expected an object, got null"}},
    {__LINE__, "{\"step\": 0}", 400, "invalid_field",
     {"step: expected a finite number in 0.01..8, got 0"}},
    {__LINE__, "{\"step\": 100}", 400, "invalid_field",
     {"step: expected a finite number in 0.01..8, got 100"}},
    {__LINE__, "{\"stepper\": \"verlet\"}", 400, "invalid_field",
     {"stepper: expected one of \"euler\", \"rk4\", \"rk2\", \"adaptive\", got \"verlet\""}},
    {__LINE__, "{\"stepper\": \"rk4\", \"integrator\": \"euler\"}", 400, "invalid_field", /* renamed: */
     {"integrator: \"integrator\" is the old name of \"stepper\"; give only \"stepper\""}}, /* renamed: */
    {__LINE__, "{\"ior_filter\": \"bicubic\"}", 400, "invalid_field",
     {"ior_filter: expected one of \"trilinear\", \"tricubic\", got \"bicubic\""}},
    {__LINE__, "{\"exposure\": 1e999}", 400, "invalid_field",
     {"exposure: expected a finite number in -20..20", "got inf"}},
    {__LINE__, "{\"exposure\": -1e999}", 400, "invalid_field", {"exposure:", "got -inf"}},
    {__LINE__, "{\"jpeg_quality\": 101}", 400, "invalid_field",
     {"jpeg_quality: expected an integer in 1..100, got 101"}},
    {__LINE__, "{\"boundary_threshold\": 0}", 400, "invalid_field", {"boundary_threshold:"}},
    {__LINE__, "{\"step\": 0.5, \"step\": 0.5}", 400, "invalid_field", {"step: duplicate field"}},
};
/* clang-format on */

static void bad_render_requests_get_their_errors(struct test_daemon *d, const char *id)
{
    section("POST /v1/scenes/{id}/render");
    char p[300];
    EXPECT_ERROR(d, "POST", "/v1/scenes/nope/render", "{}", 404, "scene_not_found", "\"nope\"");
    const char *render = path_of(p, sizeof p, id, "/render");
    size_t n = 70000; /* valid JSON over --max-json-bytes (65536) */
    char *big = malloc(n + 1);
    memset(big, ' ', n);
    memcpy(big, "{}", 2);
    big[n] = '\0';
    EXPECT_ERROR(d, "POST", render, big, 413, "body_too_large", "exceeds the limit of 65536 bytes",
                 "--max-json-bytes");
    free(big);
    EXPECT_JSON_ERROR_CASES(d, "POST", render, render_cases);
}

/* A scene that needs an upload it does not have renders as 409 conflict, saying what to
 * upload where; once uploaded, the same request renders. */
static void missing_uploads_are_conflicts_until_uploaded(struct test_daemon *d)
{
    char vol[REFRACT_ID_SIZE] = "", img[REFRACT_ID_SIZE] = "", p[300], want[200];
    CHECK(test_create_scene(d,
                            "{\"camera\": {\"width\": 32, \"height\": 24}, \"objects\": [{" BOUNDS
                            ", \"resolution\": 8, \"ior\": {\"volume\": \"ghost_vol\"}}]}",
                            vol));
    CHECK(test_create_scene(d,
                            "{\"environment\": {\"type\": \"image\"}, \"camera\": {\"width\": 32, "
                            "\"height\": 24}, \"objects\": [{" BOUNDS
                            ", \"resolution\": 8, \"ior\": 1.2}]}",
                            img));
    snprintf(want, sizeof want, "PUT /v1/scenes/%s/volumes/", vol);
    EXPECT_ERROR(d, "POST", path_of(p, sizeof p, vol, "/render"), "{}", 409, "conflict",
                 "ghost_vol", want);
    EXPECT_ERROR(d, "POST", path_of(p, sizeof p, vol, "/trace"), "{\"rays\": [" ONE_RAY "]}", 409,
                 "conflict", "ghost_vol", want);
    snprintf(want, sizeof want, "PUT /v1/scenes/%s/environment", img);
    EXPECT_ERROR(d, "POST", path_of(p, sizeof p, img, "/render"), "{}", 409, "conflict",
                 "environment", want);

    /* Fix each scene; the same requests now succeed. */
    float ior[8] = {1.3f, 1.3f, 1.3f, 1.3f, 1.3f, 1.3f, 1.3f, 1.3f};
    cJSON_Delete(EXPECT_UPLOAD(d, path_of(p, sizeof p, vol, "/volumes/ghost_vol?dims=2,2,2"), ior,
                               sizeof ior, 201));
    struct refract_image out = {0};
    int rc = refract_render(d->client, vol, "{}", &out);
    CHECK_MSG(rc == REFRACT_E_OK, "render once the volume is uploaded: %s",
              refract_errmsg(d->client));
    refract_image_free(&out);
    struct refract_image png = {0};
    CHECK(refract_render(d->client, vol, "{\"width\": 16, \"height\": 8}", &png) == REFRACT_E_OK);
    cJSON_Delete(
        EXPECT_UPLOAD(d, path_of(p, sizeof p, img, "/environment"), png.bytes, png.len, 201));
    rc = refract_render(d->client, img, "{}", &out);
    CHECK_MSG(rc == REFRACT_E_OK, "render once the environment is uploaded: %s",
              refract_errmsg(d->client));
    refract_image_free(&out);
    refract_image_free(&png);
}

/* ---- POST /v1/scenes/{id}/trace ------------------------------------------------------------- */

/* clang-format off */
static const struct json_error_case trace_cases[] = {
    {__LINE__, "", 400, "invalid_json", {"empty"}},
    {__LINE__, "{\"rays\": [", 400, "invalid_json", {"invalid JSON at byte 9", "truncated"}},
    {__LINE__, "{}", 400, "missing_field", {"rays: missing required field"}},
    {__LINE__, "{\"rays\": {}}", 400, "invalid_field", {"rays: expected an array"}},
    {__LINE__, "{\"rays\": \"many\"}", 400, "invalid_field", {"rays: expected an array"}},
    {__LINE__, "{\"rays\": []}", 400, "invalid_field", {"rays: expected at least one ray"}},
    {__LINE__, "{\"rays\": [1]}", 400, "invalid_field", {"rays[0]: expected an object", "got 1"}},
    {__LINE__, "{\"rays\": [" ONE_RAY ", {\"origin\": [0, 0, 4], \"direction\": [0, 0, 0]}]}", 400,
     "invalid_field", {"rays[1].direction: expected a non-zero direction", "[0, 0, 0]"}},
    {__LINE__, "{\"rays\": [{\"origin\": [0, 0, 4], \"direction\": [1e-300, 0, 0]}]}", 400,
     "invalid_field", {"rays[0].direction: expected a non-zero direction"}},
    {__LINE__, "{\"rays\": [{\"origin\": [1e999, 0, 4], \"direction\": [0, 0, -1]}]}", 400,
     "invalid_field", {"rays[0].origin[0]: expected a finite number", "got inf"}},
    {__LINE__, "{\"rays\": [{\"origin\": [0, 0, 4], \"direction\": [0, -1e999, -1]}]}", 400,
     "invalid_field", {"rays[0].direction[1]", "got -inf"}},
    {__LINE__, "{\"rays\": [{\"origin\": [0, 0], \"direction\": [0, 0, -1]}]}", 400,
     "invalid_field", {"rays[0].origin: expected an array of 3 numbers"}},
    {__LINE__, "{\"rays\": [" ONE_RAY ", {\"origin\": [0, 0, 4], \"direction\": [0, 0, -1], "
               "\"color\": 1}]}",
     400, "unknown_field", {"rays[1]: unknown field \"color\"", "allowed: origin, direction"}},
    {__LINE__, "{\"rays\": [{\"origin\": [0, 0, 4]}]}", 400, "missing_field",
     {"rays[0]: missing required field \"direction\""}},
    {__LINE__, "{\"rays\": [{\"direction\": [0, 0, -1]}]}", 400, "missing_field",
     {"rays[0]: missing required field \"origin\""}},
    {__LINE__, "{\"ray\": [" ONE_RAY "]}", 400, "unknown_field",
     {"(root): unknown field \"ray\"", "allowed: rays, step, tolerance, stepper, max_steps"}},
    {__LINE__, "{\"rays\": [" ONE_RAY "], \"max_steps\": 5001}", 422, "limit_exceeded",
     {"max_steps:", "--max-steps"}},
    {__LINE__, "{\"rays\": [" ONE_RAY "], \"ior_filter\": true}", 400, "invalid_field",
     {"ior_filter: expected one of \"trilinear\", \"tricubic\"", "got true"}},
    {__LINE__, "{\"rays\": [" ONE_RAY "], \"step\": 0}", 400, "invalid_field",
     {"step: expected a finite number in 0.01..8, got 0"}},
    {__LINE__, "{\"rays\": [" ONE_RAY ", " ONE_RAY ", " ONE_RAY ", " ONE_RAY ", " ONE_RAY "]}", 422,
     "limit_exceeded", {"rays: 5 rays exceed the limit of 4", "--max-rays"}},
};
/* clang-format on */

static void bad_trace_requests_get_their_errors(struct test_daemon *d, const char *id)
{
    section("POST /v1/scenes/{id}/trace");
    char p[300];
    EXPECT_ERROR(d, "POST", "/v1/scenes/nope/trace", "{\"rays\": [" ONE_RAY "]}", 404,
                 "scene_not_found", "\"nope\"");
    const char *trace = path_of(p, sizeof p, id, "/trace");
    EXPECT_JSON_ERROR_CASES(d, "POST", trace, trace_cases);
    /* --max-rays rays are fine. */
    char *body = EXPECT_STATUS(
        d, "POST", trace, "{\"rays\": [" ONE_RAY ", " ONE_RAY ", " ONE_RAY ", " ONE_RAY "]}", 200);
    cJSON *json = cJSON_Parse(body);
    CHECK_INT(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(json, "rays")), 4);
    cJSON_Delete(json);
    free(body);
}

/* ---- after all of it ------------------------------------------------------------------------- */

#define LIGHT_BODY(x) "{\"lights\": [" x "]}"
static const struct json_error_case lights_cases[] = {
    {__LINE__, "", 400, "invalid_json", {"empty", "\"lights\""}},
    {__LINE__, "{\"lights\": [", 400, "invalid_json", {"invalid JSON at byte 11", "truncated"}},
    {__LINE__, "{\"lights\": []} []", 400, "invalid_json", {"unexpected text after"}},
    {__LINE__, "[]", 400, "invalid_field", {"(root): expected an object"}},
    {__LINE__, "{}", 400, "missing_field", {"lights: required"}},
    {__LINE__,
     "{\"light\": []}",
     400,
     "unknown_field",
     {"unknown field \"light\"", "allowed: lights"}},
    {__LINE__, "{\"lights\": {}}", 400, "invalid_field", {"lights: must be an array"}},
    {__LINE__, LIGHT_BODY("1"), 400, "invalid_field", {"lights[0]"}},
    {__LINE__,
     LIGHT_BODY("{\"type\": \"laser\"}"),
     400,
     "invalid_field",
     {"lights[0].type", "\"laser\""}},
    {__LINE__,
     LIGHT_BODY("{\"type\": \"directional\", \"direction\": [0, 0, 0]}"),
     400,
     "invalid_field",
     {"lights[0].direction", "non-zero"}},
    {__LINE__,
     LIGHT_BODY("{\"type\": \"point\", \"position\": [0, 1, 1e999]}"),
     400,
     "invalid_field",
     {"lights[0].position[2]", "finite"}},
    {__LINE__,
     LIGHT_BODY("{\"type\": \"point\", \"position\": [0, 1]}"),
     400,
     "invalid_field",
     {"lights[0].position"}},
    {__LINE__,
     LIGHT_BODY("{\"type\": \"spot\", \"position\": [0, 1, 0], \"direction\": [0, -1, 0], "
                "\"angle_deg\": 95}"),
     400,
     "invalid_field",
     {"lights[0].angle_deg", "1..89"}},
    {__LINE__,
     LIGHT_BODY("{\"type\": \"point\", \"position\": [0, 1, 0], \"intensity\": -1}"),
     400,
     "invalid_field",
     {"lights[0].intensity", "-1"}},
    {__LINE__,
     LIGHT_BODY("{\"type\": \"point\", \"position\": [0, 1, 0], \"colour\": [1, 1, 1]}"),
     400,
     "unknown_field",
     {"lights[0]", "\"colour\""}},
    {__LINE__,
     LIGHT_BODY(
         "{\"name\": \"a\", \"type\": \"point\", \"position\": [0, 1, 0]}, {\"name\": \"a\", "
         "\"type\": \"point\", \"position\": [0, 2, 0]}"),
     400,
     "invalid_field",
     {"lights[1].name", "unique"}},
    {__LINE__,
     LIGHT_BODY(
         "{\"type\": \"point\", \"position\": [0, 1, 0]}, {\"type\": \"point\", \"position\": "
         "[0, 1, 0]}, {\"type\": \"point\", \"position\": [0, 1, 0]}, {\"type\": \"point\", "
         "\"position\": [0, 1, 0]}, {\"type\": \"point\", \"position\": [0, 1, 0]}"),
     400,
     "invalid_field",
     {"lights", "0..4"}},
};

static const struct json_error_case light_cases[] = {
    {__LINE__, "", 400, "invalid_json", {"empty", "one light object"}},
    {__LINE__, "{\"type\": ", 400, "invalid_json", {"truncated"}},
    {__LINE__, "[]", 400, "invalid_field", {"(root): expected an object"}},
    {__LINE__,
     "{\"name\": \"moon\", \"type\": \"point\", \"position\": [0, 1, 0]}",
     400,
     "invalid_field",
     {"name: must be the light's name in the URL (\"sun\")"}},
    {__LINE__,
     "{\"name\": 3, \"type\": \"point\", \"position\": [0, 1, 0]}",
     400,
     "invalid_field",
     {"name: must be"}},
    {__LINE__, "{\"type\": \"point\"}", 400, "missing_field", {"position"}},
    {__LINE__,
     "{\"type\": \"point\", \"position\": [0, 1e400, 0]}",
     400,
     "invalid_field",
     {"position[1]", "finite"}},
};

static void bad_lights_requests_get_their_errors(struct test_daemon *d, const char *id)
{
    section("PUT /v1/scenes/{id}/lights");
    char p[300];
    EXPECT_ERROR(d, "PUT", "/v1/scenes/nope/lights", "{\"lights\": []}", 404, "scene_not_found",
                 "\"nope\"");
    EXPECT_JSON_ERROR_CASES(d, "PUT", path_of(p, sizeof p, id, "/lights"), lights_cases);
    section("PUT /v1/scenes/{id}/lights/{name}");
    EXPECT_ERROR(d, "PUT", "/v1/scenes/nope/lights/sun", "{}", 404, "scene_not_found", "\"nope\"");
    EXPECT_JSON_ERROR_CASES(d, "PUT", path_of(p, sizeof p, id, "/lights/sun"), light_cases);
    EXPECT_ERROR(d, "PUT", path_of(p, sizeof p, id, "/lights/Sun"),
                 "{\"type\": \"point\", \"position\": [0, 1, 0]}", 400, "invalid_field", "name",
                 "\"Sun\"");
    /* Nothing above changed the lights: the scene still has none. */
    char *body = EXPECT_STATUS(d, "GET", path_of(p, sizeof p, id, "/lights"), NULL, 200);
    CHECK(body && strstr(body, "\"lights\":[]") != NULL);
    free(body);
}

static void daemon_still_answers_and_renders(struct test_daemon *d, const char *id)
{
    section("");
    free(EXPECT_STATUS(d, "GET", "/v1/health", NULL, 200));
    struct refract_image img = {0};
    int rc = refract_render(d->client, id, "{\"format\": \"jpeg\"}", &img);
    CHECK_MSG(rc == REFRACT_E_OK, "render after bad input: %s", refract_errmsg(d->client));
    CHECK_STR(img.content_type, "image/jpeg");
    refract_image_free(&img);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, daemon_args))
        test_setup_failed("test_bad_input_requests", d.why);
    char id[REFRACT_ID_SIZE] = "";
    CHECK(test_create_scene(&d, VALID_SCENE, id));
    struct refract_image png = {0};
    CHECK(refract_render(d.client, id, "{\"width\": 16, \"height\": 8}", &png) == REFRACT_E_OK);
    CHECK(png.len > 32);
    printf("cases per endpoint:\n");
    bad_volume_uploads_get_their_errors(&d, id);
    a_good_volume_is_stored_and_a_bad_one_replaces_nothing(&d, id);
    if (png.len > 32)
        undecodable_environments_get_invalid_image(&d, id, &png);
    bad_render_requests_get_their_errors(&d, id);
    missing_uploads_are_conflicts_until_uploaded(&d);
    bad_trace_requests_get_their_errors(&d, id);
    bad_lights_requests_get_their_errors(&d, id);
    daemon_still_answers_and_renders(&d, id);
    refract_image_free(&png);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_bad_input_requests");
}
