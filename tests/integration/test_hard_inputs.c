/*
 * test_hard_inputs.c - degenerate inputs through the HTTP API of a real refractd
 * (docs/tracing.md "Hard cases"): zero-size and sub-precision bounds, vanishing and huge
 * scales, non-finite numbers (overflowing literals, NaN/Infinity tokens), cameras whose
 * eye meets look_at or whose up is parallel (or anti-parallel, or nearly) to the view, and
 * zero-length or underflowing ray directions. Each must get a clear 4xx JSON error that
 * names the field and says what to do, never a crash or a 500.
 *
 * The inputs just inside each rule are accepted, and what they produce is checked: every
 * number of every trace is finite (a NaN would print as JSON null), statuses are the
 * documented ones, steps stay within the budget, and every pixel of an EXR render is finite
 * and no brighter than the environment. The daemon must still be healthy at the end and
 * stop cleanly. Found by this test and fixed in the scene parser: bounds 1e-300 thin and
 * transform.scale 1e-300 or 1e-30 gave NaN traces; a scene whose eye lay within 1e-9 of
 * look_at was created and then refused by every render; a zero camera.up in a render
 * request was called "parallel to the view direction".
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon.h"
#include "expect.h"
#include "io/io_image.h"
#include "irradiance_util.h"
#include "test.h"

static const char *const daemon_args[] = {"--max-steps", "5000", "--max-rays", "16", NULL};

#define OBJ_B(min, max) "{\"bounds\": {\"min\": " min ", \"max\": " max "}, \"ior\": 1.5}"
#define SCENE_OBJ(obj) "{\"camera\": {\"width\": 16, \"height\": 12}, \"objects\": [" obj "]}"
#define UNIT_OBJ OBJ_B("[-1, -1, -1]", "[1, 1, 1]")
#define SCENE_CAM(cam) "{\"camera\": " cam ", \"objects\": [" UNIT_OBJ "]}"
#define SCALED(scale)                                                                              \
    SCENE_OBJ("{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "      \
              "\"transform\": {\"scale\": " scale "}, \"ior\": 1.5}")

/* clang-format off */
static const struct json_error_case scene_cases[] = {
    /* zero-size and inverted bounds, on each axis */
    {__LINE__, SCENE_OBJ(OBJ_B("[0, 0, 0]", "[1, 0, 1]")), 400, "invalid_field",
     {"objects[0].bounds: max must be greater than min", "on y, min = 0 and max = 0"}},
    {__LINE__, SCENE_OBJ(OBJ_B("[0, 0, 2]", "[1, 1, 2]")), 400, "invalid_field",
     {"objects[0].bounds: max must be greater than min", "on z"}},
    {__LINE__, SCENE_OBJ(OBJ_B("[1, 0, 0]", "[-1, 1, 1]")), 400, "invalid_field",
     {"objects[0].bounds: max must be greater than min", "on x, min = 1 and max = -1"}},
    /* thinner than single precision can march */
    {__LINE__, SCENE_OBJ(OBJ_B("[0, 0, 0]", "[1e-300, 1, 1]")), 400, "invalid_field",
     {"objects[0].bounds: too thin on x", "transform.scale"}},
    {__LINE__, SCENE_OBJ(OBJ_B("[0, 0, 0]", "[1, 1e-30, 1]")), 400, "invalid_field",
     {"objects[0].bounds: too thin on y", "at least 1e-06"}},
    {__LINE__, SCENE_OBJ(OBJ_B("[0, 0, 1000]", "[1, 1, 1000.01]")), 400, "invalid_field",
     {"objects[0].bounds: too thin on z", "max - min = 0.01", "at least 0.1"}},
    /* vanishing, zero and negative scales */
    {__LINE__, SCALED("1e-300"), 400, "invalid_field",
     {"objects[0].transform.scale: expected a finite number in 1e-06..1000000", "got 1e-300"}},
    {__LINE__, SCALED("1e-7"), 400, "invalid_field", {"objects[0].transform.scale:", "1e-07"}},
    {__LINE__, SCALED("0"), 400, "invalid_field", {"objects[0].transform.scale:", "got 0"}},
    {__LINE__, SCALED("-1"), 400, "invalid_field", {"objects[0].transform.scale:", "got -1"}},
    /* non-finite numbers: overflowing literals and tokens JSON does not have */
    {__LINE__, SCENE_CAM("{\"eye\": [0, 1e999, 4]}"), 400, "invalid_field",
     {"camera.eye[1]: expected a finite number", "got inf"}},
    {__LINE__, SCENE_CAM("{\"look_at\": [-1e999, 0, 0]}"), 400, "invalid_field",
     {"camera.look_at[0]", "got -inf"}},
    {__LINE__, SCENE_CAM("{\"up\": [0, 1e999, 0]}"), 400, "invalid_field",
     {"camera.up[1]", "got inf"}},
    {__LINE__, SCENE_CAM("{\"fov_y_deg\": 1e999}"), 400, "invalid_field",
     {"camera.fov_y_deg", "got inf"}},
    {__LINE__, SCENE_CAM("{\"eye\": [NaN, 0, 4]}"), 400, "invalid_json", {"invalid JSON at byte"}},
    {__LINE__, SCENE_CAM("{\"eye\": [0, Infinity, 4]}"), 400, "invalid_json", {"invalid JSON"}},
    {__LINE__, SCENE_CAM("{\"eye\": [0, 0, -Infinity]}"), 400, "invalid_json", {"invalid JSON"}},
    {__LINE__, SCENE_CAM("{\"fov_y_deg\": nan}"), 400, "invalid_json", {"invalid JSON"}},
    /* the camera's up: zero, underflowing, parallel, anti-parallel, nearly parallel */
    {__LINE__, SCENE_CAM("{\"up\": [0, 0, 0]}"), 400, "invalid_field",
     {"camera.up: expected a non-zero direction", "[0, 0, 0]"}},
    {__LINE__, SCENE_CAM("{\"up\": [0, 1e-300, 0]}"), 400, "invalid_field",
     {"camera.up: expected a non-zero direction"}},
    {__LINE__, SCENE_CAM("{\"up\": [0, 0, -1]}"), 400, "invalid_field",
     {"camera.up:", "is parallel to the viewing direction", "choose an up vector"}},
    {__LINE__, SCENE_CAM("{\"up\": [0, 0, 5]}"), 400, "invalid_field",
     {"camera.up:", "is parallel to the viewing direction"}},
    {__LINE__, SCENE_CAM("{\"up\": [0, 1e-11, 1]}"), 400, "invalid_field",
     {"camera.up:", "is parallel to the viewing direction"}},
    /* eye on look_at, exactly or within 1e-9 */
    {__LINE__, SCENE_CAM("{\"eye\": [0, 0, 0]}"), 400, "invalid_field",
     {"camera.look_at: equals camera.eye", "differs from where it stands"}},
    {__LINE__, SCENE_CAM("{\"eye\": [1, 2, 3], \"look_at\": [1, 2, 3.0000000000001]}"), 400,
     "invalid_field", {"camera.look_at:", "within 1e-9"}},
    /* zero-length light directions */
    {__LINE__, "{\"lights\": [{\"type\": \"directional\", \"direction\": [0, 0, 0]}], "
               "\"objects\": [" UNIT_OBJ "]}", 400, "invalid_field",
     {"lights[0].direction: expected a non-zero direction"}},
    {__LINE__, "{\"lights\": [{\"type\": \"spot\", \"position\": [0, 2, 0], \"direction\": "
               "[1e-200, -1e-200, 0]}], \"objects\": [" UNIT_OBJ "]}", 400, "invalid_field",
     {"lights[0].direction: expected a non-zero direction"}},
};

static const struct json_error_case render_cases[] = {
    {__LINE__, "{\"camera\": {\"up\": [0, 0, 0]}}", 400, "invalid_field",
     {"camera.up: expected a non-zero direction"}},
    {__LINE__, "{\"camera\": {\"up\": [0, 0, -1e-300]}}", 400, "invalid_field",
     {"camera.up: expected a non-zero direction"}},
    {__LINE__, "{\"camera\": {\"up\": [0, 0, 1]}}", 400, "invalid_field",
     {"camera.up: parallel to the view direction", "choose an up vector"}},
    {__LINE__, "{\"camera\": {\"eye\": [0, 0, 4], \"look_at\": [0, 0, 4.0000000001]}}", 400,
     "invalid_field", {"camera: eye and look_at are the same point"}},
    {__LINE__, "{\"camera\": {\"eye\": [0, NaN, 4]}}", 400, "invalid_json", {"invalid JSON"}},
    {__LINE__, "{\"camera\": {\"look_at\": [0, 0, 1e999]}}", 400, "invalid_field",
     {"camera.look_at[2]", "got inf"}},
    {__LINE__, "{\"camera\": {\"fov_y_deg\": -1e999}}", 400, "invalid_field",
     {"camera.fov_y_deg", "got -inf"}},
};

#define RAY(o, d) "{\"origin\": " o ", \"direction\": " d "}"
static const struct json_error_case trace_cases[] = {
    {__LINE__, "{\"rays\": [" RAY("[0, 0, 4]", "[0, 0, 0]") "]}", 400, "invalid_field",
     {"rays[0].direction: expected a non-zero direction", "[0, 0, 0]"}},
    {__LINE__, "{\"rays\": [" RAY("[0, 0, 4]", "[-0.0, -0.0, -0.0]") "]}", 400, "invalid_field",
     {"rays[0].direction: expected a non-zero direction"}},
    {__LINE__, "{\"rays\": [" RAY("[0, 0, 4]", "[1e-13, 0, 0]") "]}", 400, "invalid_field",
     {"rays[0].direction: expected a non-zero direction (length > 1e-12)"}},
    /* squares underflow to zero: the length must not be computed naively */
    {__LINE__, "{\"rays\": [" RAY("[0, 0, 4]", "[1e-200, 1e-200, 1e-200]") "]}", 400,
     "invalid_field", {"rays[0].direction: expected a non-zero direction"}},
    {__LINE__, "{\"rays\": [" RAY("[0, 0, 4]", "[0, 0, -1]") ", " RAY("[0, 0, 4]", "[0, 0, NaN]")
     "]}", 400, "invalid_json", {"invalid JSON"}},
    {__LINE__, "{\"rays\": [" RAY("[0, 0, 1e999]", "[0, 0, -1]") "]}", 400, "invalid_field",
     {"rays[0].origin[2]: expected a finite number", "got inf"}},
    {__LINE__, "{\"rays\": [" RAY("[1e300, 0, 4]", "[0, 0, -1]") "]}", 400, "invalid_field",
     {"rays[0].origin[0]: expected a finite number in -1000000..1000000"}},
};
/* clang-format on */

/* ---- what accepted extremes produce ----------------------------------------------------- */

static bool finite_number(const cJSON *n)
{
    return cJSON_IsNumber(n) && isfinite(n->valuedouble);
}

static bool finite_triple(const cJSON *a)
{
    if (!cJSON_IsArray(a) || cJSON_GetArraySize(a) != 3)
        return false;
    for (int i = 0; i < 3; i++)
        if (!finite_number(cJSON_GetArrayItem(a, i)))
            return false;
    return true;
}

/* Traces `rays` (a JSON array text) and checks every hit: finite numbers (NaN would be
 * null), a documented status, steps within max_steps, 0 <= T <= 1, a unit exit direction.
 * Returns the parsed answer (caller deletes) or NULL. */
static cJSON *trace_ok(struct test_daemon *d, const char *id, const char *request, int max_steps,
                       const char *what)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/trace", id);
    char *body = EXPECT_STATUS(d, "POST", path, request, 200);
    cJSON *root = body ? cJSON_Parse(body) : NULL;
    free(body);
    const cJSON *rays = cJSON_GetObjectItemCaseSensitive(root, "rays");
    CHECK_MSG(cJSON_IsArray(rays), "%s: no rays in the answer", what);
    int i = 0;
    const cJSON *hit;
    cJSON_ArrayForEach(hit, rays)
    {
        const cJSON *st = cJSON_GetObjectItemCaseSensitive(hit, "status");
        const char *s = cJSON_IsString(st) ? st->valuestring : "";
        CHECK_MSG(strcmp(s, "exited") == 0 || strcmp(s, "missed") == 0 ||
                      strcmp(s, "absorbed") == 0 || strcmp(s, "max_steps") == 0,
                  "%s ray %d: status \"%s\"", what, i, s);
        const cJSON *dir = cJSON_GetObjectItemCaseSensitive(hit, "exit_direction");
        const cJSON *T = cJSON_GetObjectItemCaseSensitive(hit, "transmittance");
        const cJSON *steps = cJSON_GetObjectItemCaseSensitive(hit, "steps");
        bool finite = finite_triple(cJSON_GetObjectItemCaseSensitive(hit, "exit_origin")) &&
                      finite_triple(dir) && finite_triple(T) &&
                      finite_number(cJSON_GetObjectItemCaseSensitive(hit, "optical_path_length")) &&
                      finite_number(steps);
        CHECK_MSG(finite, "%s ray %d: a non-finite value: %s", what, i,
                  cJSON_PrintUnformatted(hit));
        if (finite) {
            double len = 0.0;
            for (int k = 0; k < 3; k++) {
                double t = cJSON_GetArrayItem(T, k)->valuedouble;
                double c = cJSON_GetArrayItem(dir, k)->valuedouble;
                len += c * c;
                CHECK_MSG(t >= 0.0 && t <= 1.0 + 1e-5, "%s ray %d: T = %g", what, i, t);
            }
            CHECK_MSG(fabs(sqrt(len) - 1.0) < 1e-4, "%s ray %d: |direction| = %g", what, i,
                      sqrt(len));
            CHECK_MSG(steps->valueint >= 0 && steps->valueint <= max_steps,
                      "%s ray %d: %d steps, budget %d", what, i, steps->valueint, max_steps);
        }
        i++;
    }
    return root;
}

/* Renders EXR and checks every pixel: finite and within [0, bound]. */
static void render_bounded(struct test_daemon *d, const char *id, const char *request,
                           const char *what, float bound)
{
    struct refract_image img = {0};
    int rc = refract_render(d->client, id, request, &img);
    CHECK_MSG(rc == REFRACT_E_OK, "%s: render: %s", what, refract_errmsg(d->client));
    if (rc != REFRACT_E_OK)
        return;
    struct io_image px = {0};
    struct err e = {0};
    CHECK_INT(io_image_decode(img.bytes, img.len, 1 << 20, &px, &e), REFRACT_E_OK);
    size_t bad = 0, bright = 0, n = (size_t)px.width * px.height;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) {
            float v = px.rgba[4 * i + c];
            bad += !isfinite(v);
            bright += isfinite(v) && (v < -1e-6f || v > bound);
        }
    CHECK_MSG(n > 0 && bad == 0, "%s: %zu non-finite pixel values of %zu", what, bad, 3 * n);
    CHECK_MSG(bright == 0, "%s: %zu pixel values outside [0, %g]", what, bright, bound);
    io_image_free(&px);
    refract_image_free(&img);
}

/* Without lights or emission no pixel is brighter than the environment's maximum, 1. */
static void render_ok(struct test_daemon *d, const char *id, const char *request, const char *what)
{
    render_bounded(d, id, request, what, 1.0f + 1e-4f);
}

static int count_status(const cJSON *root, const char *status)
{
    int n = 0;
    const cJSON *hit;
    cJSON_ArrayForEach(hit, cJSON_GetObjectItemCaseSensitive(root, "rays"))
    {
        const cJSON *st = cJSON_GetObjectItemCaseSensitive(hit, "status");
        n += cJSON_IsString(st) && strcmp(st->valuestring, status) == 0;
    }
    return n;
}

#define FAN                                                                                        \
    "{\"rays\": [" RAY("[0, 0.1, -3]", "[0, 0, 1]") ", " RAY("[0, 0, 0]", "[1, 0.1, 0]") ", " RAY( \
        "[0.3, -0.2, 0.1]",                                                                        \
        "[-0.2, 1, 0.3]") ", " RAY("[1e5, 0, 0]",                                                  \
                                   "[-1, 1e-6, 0]") ", " RAY("[0, 0, 4]",                          \
                                                             "[1e300, 1e300, "                     \
                                                             "-1e308]") ", " RAY("[0"              \
                                                                                 ", "              \
                                                                                 "0."              \
                                                                                 "2,"              \
                                                                                 " 4"              \
                                                                                 "]",              \
                                                                                 "[1"              \
                                                                                 "e-"              \
                                                                                 "11"              \
                                                                                 ", "              \
                                                                                 "0,"              \
                                                                                 " -"              \
                                                                                 "1e"              \
                                                                                 "-1"              \
                                                                                 "1"               \
                                                                                 "]") "]}"

/* Scenes just inside each rule: accepted, and every output finite. */
static void accepted_extremes_give_finite_output(struct test_daemon *d)
{
    section("accepted extremes");
    struct {
        const char *what, *json;
    } scenes[] = {
        {"bounds 1e-6 thin at the origin",
         SCENE_OBJ("{\"bounds\": {\"min\": [-6e-7, -1, -1], \"max\": [6e-7, 1, 1]}, "
                   "\"resolution\": 8, \"ior\": 1.5}")},
        {"bounds 0.2 thin at 1000",
         SCENE_OBJ("{\"bounds\": {\"min\": [-1, -1, 1000], \"max\": [1, 1, 1000.2]}, "
                   "\"resolution\": 8, \"ior\": 1.5}")},
        {"scale 1e-6", SCALED("1e-6")},
        {"scale 1e6 (camera inside)", SCALED("1e6")},
        {"up nearly parallel, allowed",
         "{\"camera\": {\"up\": [0, 1e-6, 1], \"width\": 16, \"height\": 12}, \"objects\": "
         "[" UNIT_OBJ "]}"},
        {"eye 2e-9 from look_at",
         "{\"camera\": {\"eye\": [0, 0, 4], \"look_at\": [0, 0, 3.999999998], \"width\": 16, "
         "\"height\": 12}, \"objects\": [" UNIT_OBJ "]}"},
        {"huge up vector",
         "{\"camera\": {\"up\": [1e300, 1e300, 0], \"width\": 16, \"height\": 12}, \"objects\": "
         "[" UNIT_OBJ "]}"},
    };
    for (size_t i = 0; i < sizeof scenes / sizeof scenes[0]; i++) {
        char id[REFRACT_ID_SIZE] = "";
        section_cases++;
        if (!test_create_scene(d, scenes[i].json, id)) {
            CHECK_MSG(false, "%s: not accepted", scenes[i].what);
            continue;
        }
        cJSON_Delete(trace_ok(d, id, FAN, 5000, scenes[i].what));
        render_ok(d, id, "{\"format\": \"exr\"}", scenes[i].what);
        char del[128];
        snprintf(del, sizeof del, "/v1/scenes/%s", id);
        char *gone = NULL;
        CHECK_INT(test_request(d, "DELETE", del, NULL, &gone), 204);
        free(gone);
    }
}

/* Budgets: a ray trapped by total internal reflection in a glass block ends with status
 * max_steps after exactly the requested budget; one step, or the whole --max-steps. */
static void trapped_rays_end_on_their_budget(struct test_daemon *d)
{
    section("step budgets");
    char id[REFRACT_ID_SIZE] = "";
    CHECK(test_create_scene(d,
                            SCENE_OBJ("{\"bounds\": {\"min\": [-0.5, -0.5, -0.5], \"max\": [0.5, "
                                      "0.5, 0.5]}, \"resolution\": 8, \"ior\": 1.5}"),
                            id));
    const int budgets[3] = {1, 37, 5000};
    for (int b = 0; b < 3; b++) {
        char req[512];
        snprintf(
            req, sizeof req,
            "{\"max_steps\": %d, \"rays\": [" RAY("[0.1, 0.2, -0.05]", "[1, 1.1, 0.9]") ", " RAY(
                "[-0.3, 0.1, 0.2]", "[-0.9, 1, -1.1]") "]}",
            budgets[b]);
        section_cases++;
        cJSON *root = trace_ok(d, id, req, budgets[b], "trapped");
        CHECK_INT(count_status(root, "max_steps"), 2);
        const cJSON *hit;
        cJSON_ArrayForEach(hit, cJSON_GetObjectItemCaseSensitive(root, "rays"))
        {
            CHECK_INT(cJSON_GetObjectItemCaseSensitive(hit, "steps")->valueint, budgets[b]);
            /* lossless: total internal reflection only */
            CHECK_NEAR(cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(hit, "transmittance"), 0)
                           ->valuedouble,
                       1.0, 1e-6);
        }
        cJSON_Delete(root);
    }
    /* The camera inside that block: every pixel finite and bounded. */
    render_ok(
        d, id,
        "{\"format\": \"exr\", \"camera\": {\"eye\": [0.1, 0, 0.2], \"look_at\": [0, 0, -1]}}",
        "camera inside the block");
}

/* Lights inside the volume, through the daemon's light simulation and irradiance cache: a
 * point light at the centre of a scattering box (seen from outside and from inside), one at
 * the centre of a glass ball over a receiver, and a direct light (a scene that needs no
 * simulation) placed exactly at the camera inside a glass block. The irradiance becomes
 * ready, and every pixel is finite and >= 0 (the lights make them brighter than the
 * environment, so the upper bound is only a sanity bound). */
static void lights_inside_the_volume_render_finite(struct test_daemon *d)
{
    section("lights inside the volume");
    static const char *const scenes[3] = {
        "{\"camera\": {\"width\": 16, \"height\": 12}, \"objects\": [{\"bounds\": {\"min\": "
        "[-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, \"attenuation\": 0.2, "
        "\"scattering\": 1.0}], \"lights\": [{\"type\": \"point\", \"position\": [0, 0, 0], "
        "\"intensity\": 2}], \"lightsim\": {\"resolution\": 16, \"initial_patches\": 8}}",
        "{\"camera\": {\"width\": 16, \"height\": 12, \"eye\": [0, 1.5, 3.5]}, \"objects\": "
        "[{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, "
        "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.7, \"inside\": 1.5}}], \"receiver\": "
        "{\"height\": -1}, \"lights\": [{\"type\": \"point\", \"position\": [0, 0, 0]}], "
        "\"lightsim\": {\"resolution\": 16, \"initial_patches\": 8}}",
        "{\"camera\": {\"width\": 16, \"height\": 12, \"eye\": [0.1, 0, 0.2]}, \"objects\": "
        "[{\"bounds\": {\"min\": [-0.5, -0.5, -0.5], \"max\": [0.5, 0.5, 0.5]}, "
        "\"resolution\": 8, \"ior\": 1.5, \"brdf\": {\"type\": \"lambert\"}}], \"lights\": "
        "[{\"type\": \"point\", \"position\": [0.1, 0, 0.2], \"intensity\": 5}]}",
    };
    static const char *const names[3] = {"point light in smoke", "point light in a glass ball",
                                         "direct light at the camera"};
    for (int i = 0; i < 3; i++) {
        char id[REFRACT_ID_SIZE] = "";
        section_cases++;
        if (!test_create_scene(d, scenes[i], id)) {
            CHECK_MSG(false, "%s: not accepted", names[i]);
            continue;
        }
        if (i < 2)
            cJSON_Delete(irr_wait_ready(d, id, 60.0));
        render_bounded(d, id, "{\"format\": \"exr\"}", names[i], 1e6f);
        if (i == 0)
            render_bounded(d, id,
                           "{\"format\": \"exr\", \"camera\": {\"eye\": [0.3, 0.2, 0.5], "
                           "\"look_at\": [0, 0, 0]}}",
                           "camera and light in smoke", 1e6f);
    }
}

static void degenerate_requests_get_clear_errors(struct test_daemon *d)
{
    section("POST /v1/scenes, degenerate");
    EXPECT_JSON_ERROR_CASES(d, "POST", "/v1/scenes", scene_cases);
    char id[REFRACT_ID_SIZE] = "", path[128];
    CHECK(test_create_scene(d, SCENE_OBJ(UNIT_OBJ), id));
    section("POST /v1/scenes/{id}/render, degenerate");
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    EXPECT_JSON_ERROR_CASES(d, "POST", path, render_cases);
    section("POST /v1/scenes/{id}/trace, degenerate");
    snprintf(path, sizeof path, "/v1/scenes/%s/trace", id);
    EXPECT_JSON_ERROR_CASES(d, "POST", path, trace_cases);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, daemon_args))
        test_setup_failed("test_hard_inputs", d.why);
    printf("cases per section:\n");
    degenerate_requests_get_clear_errors(&d);
    accepted_extremes_give_finite_output(&d);
    trapped_rays_end_on_their_budget(&d);
    lights_inside_the_volume_render_finite(&d);
    section("");
    /* still healthy, and a clean stop: nothing above crashed it */
    free(EXPECT_STATUS(&d, "GET", "/v1/health", NULL, 200));
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_hard_inputs");
}
