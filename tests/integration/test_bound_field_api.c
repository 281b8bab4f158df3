/*
 * test_bound_field_api.c - a GRIN field inside an exact surface through the HTTP API of a
 * real refractd (docs/scenes.md "Surfaces", the medium "object" form; docs/tracing.md
 * "Fields inside surfaces"):
 *   - the Luneburg lens filling its exact sphere (object bounds touching the sphere) is
 *     created, rendered (PNG) and traced: parallel rays leave the sphere at the focus
 *     (0, 0, 1) within two voxels, each with two events on "ball" whose inside index is the
 *     field's (n = 1 at the rim of a Luneburg lens);
 *   - bad input gets a 400 invalid_field naming the JSON path: an unknown object, bounds
 *     that do not cover the sphere, constants together with "object", a receiver (the
 *     light simulator does not bend inside surfaces yet).
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon.h"
#include "expect.h"
#include "test.h"

#define RES 32
#define LENS(half)                                                                                 \
    "{\"name\": \"lens\", \"bounds\": {\"min\": [-" half ", -" half ", -" half                     \
    "], \"max\": [" half ", " half ", " half                                                       \
    "]}, \"resolution\": 32, \"smoothing_sigma\": 0, \"ior\": "                                    \
    "{\"profile\": \"luneburg\", \"center\": [0, 0, 0], \"radius\": 1.0}}"
#define BALL(medium)                                                                               \
    "{\"name\": \"ball\", \"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "           \
    "\"medium\": " medium "}"

static const cJSON *get(const cJSON *o, const char *k)
{
    return cJSON_GetObjectItemCaseSensitive(o, k);
}

static void vec(const cJSON *o, const char *k, double out[3])
{
    const cJSON *a = get(o, k);
    for (int i = 0; i < 3; i++) {
        const cJSON *v = cJSON_GetArrayItem(a, i);
        out[i] = cJSON_IsNumber(v) ? v->valuedouble : NAN;
    }
}

static void lens_scene(struct test_daemon *d)
{
    section("bounded lens");
    const char *doc = "{\"name\": \"lens\", \"camera\": {\"eye\": [0, 1.2, 4.5], \"look_at\": [0, "
                      "0, 0], \"width\": 48, \"height\": 36}, \"objects\": [" LENS(
                          "1") "], "
                               "\"surfaces\": [" BALL("{\"object\": \"lens\"}") "]}";
    char id[128], path[256];
    CHECK(test_create_scene(d, doc, id));
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    char *png = EXPECT_STATUS(d, "POST", path, "{\"format\": \"png\"}", 200);
    CHECK(png != NULL);
    free(png);
    snprintf(path, sizeof path, "/v1/scenes/%s/trace", id);
    char *body = EXPECT_STATUS(d, "POST", path,
                               "{\"events\": true, \"rays\": ["
                               "{\"origin\": [0.3, 0, -2], \"direction\": [0, 0, 1]},"
                               "{\"origin\": [0, -0.6, -2], \"direction\": [0, 0, 1]},"
                               "{\"origin\": [0.5, 0.5, -2], \"direction\": [0, 0, 1]}]}",
                               200);
    cJSON *root = cJSON_Parse(body ? body : "{}");
    const cJSON *rays = get(root, "rays");
    CHECK_INT(cJSON_GetArraySize(rays), 3);
    for (int k = 0; k < cJSON_GetArraySize(rays); k++) {
        const cJSON *r = cJSON_GetArrayItem(rays, k);
        CHECK(cJSON_IsString(get(r, "status")) &&
              strcmp(get(r, "status")->valuestring, "exited") == 0);
        double x[3];
        vec(r, "exit_origin", x);
        double miss = sqrt(x[0] * x[0] + x[1] * x[1] + (x[2] - 1) * (x[2] - 1));
        CHECK_MSG(miss < 2.0 * 2.0 / RES, "ray %d leaves at (%g, %g, %g)", k, x[0], x[1], x[2]);
        const cJSON *events = get(r, "events");
        CHECK_INT(cJSON_GetArraySize(events), 2);
        const cJSON *e1 = cJSON_GetArrayItem(events, 1);
        CHECK(cJSON_IsString(get(e1, "medium_before")) &&
              strcmp(get(e1, "medium_before")->valuestring, "ball") == 0);
        const cJSON *n = get(e1, "n_before");
        CHECK(cJSON_IsNumber(n) && fabs(n->valuedouble - 1.0) < 0.05);
    }
    cJSON_Delete(root);
    free(body);
}

static void bad_input(struct test_daemon *d)
{
    section("bad input");
    const struct json_error_case cases[] = {
        {__LINE__,
         "{\"objects\": [" LENS("1") "], \"surfaces\": [" BALL("{\"object\": \"lense\"}") "]}",
         400,
         "invalid_field",
         {"surfaces[0].medium.object", "lense"}},
        {__LINE__,
         "{\"objects\": [" LENS("0.8") "], \"surfaces\": [" BALL("{\"object\": \"lens\"}") "]}",
         400,
         "invalid_field",
         {"surfaces[0].medium.object", "cover"}},
        {__LINE__,
         "{\"objects\": [" LENS("1") "], \"surfaces\": [" BALL(
             "{\"object\": \"lens\", \"ior\": 1.5}") "]}",
         400,
         "invalid_field",
         {"surfaces[0].medium.ior", "object"}},
        {__LINE__, /* the light simulator asked for ("auto" gives direct light only) */
         "{\"receiver\": {\"height\": -1.5, \"caustics\": \"volume\"}, \"objects\": [" LENS(
             "1") "], \"surfaces\": [" BALL("{\"object\": \"lens\"}") "]}",
         400,
         "invalid_field",
         {"receiver", "light simulator"}},
    };
    EXPECT_JSON_ERROR_CASES(d, "POST", "/v1/scenes", cases);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_bound_field_api", d.why);
    lens_scene(&d);
    bad_input(&d);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_bound_field_api");
}
