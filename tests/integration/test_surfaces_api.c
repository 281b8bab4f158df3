/*
 * test_surfaces_api.c - exact surfaces through the HTTP API of a real refractd
 * (docs/scenes.md "Surfaces", docs/api.md "Trace"):
 *   - a glass sphere scene of surfaces only is created, rendered (PNG and EXR) and traced;
 *     the trace's exit direction against Snell at both surfaces (closed form);
 *   - "events": true lists each surface event: surface and media names, n on both sides,
 *     the normal, the Fresnel reflectance (closed form at normal incidence), and a ray that
 *     meets the glass-wine interface of nested media with 1.33 -> 1.5;
 *   - a scene of voxel objects only traces exactly as before (no "events" key without
 *     the option; an empty events list with it);
 *   - bad input gets a 400/422 naming the JSON path: voxel-only shapes, a missing
 *     medium, an out-of-range ior, equal priorities of overlapping solids, a voxel object
 *     overlapping a surface, a receiver with surfaces, too many surfaces, unknown keys,
 *     a plane without a normal.
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon.h"
#include "expect.h"
#include "test.h"

#define SPHERE_SCENE                                                                               \
    "{\"name\": \"ball\", \"camera\": {\"eye\": [0, 0, 4], \"look_at\": [0, 0, 0], "               \
    "\"width\": 64, \"height\": 48}, \"surfaces\": [{\"name\": \"ball\", \"shape\": \"sphere\", "  \
    "\"radius\": 0.8, \"medium\": {\"ior\": 1.5, \"attenuation\": [0.02, 0.01, 0.02]}}]}"

static const cJSON *get(const cJSON *o, const char *k)
{
    return cJSON_GetObjectItemCaseSensitive(o, k);
}

static double num(const cJSON *o, const char *k)
{
    const cJSON *v = get(o, k);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

static void vec(const cJSON *o, const char *k, double out[3])
{
    const cJSON *a = get(o, k);
    for (int i = 0; i < 3; i++) {
        const cJSON *v = cJSON_GetArrayItem(a, i);
        out[i] = cJSON_IsNumber(v) ? v->valuedouble : NAN;
    }
}

static void sphere_scene(struct test_daemon *d)
{
    section("sphere");
    char id[128];
    CHECK(test_create_scene(d, SPHERE_SCENE, id));
    char path[256];
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    char *png = EXPECT_STATUS(d, "POST", path, "{\"format\": \"png\"}", 200);
    CHECK(png != NULL);
    free(png);
    /* A ray at height b: Snell in and out (closed form for a sphere of radius R, n):
     * deviation 2 (theta_i - theta_t). */
    snprintf(path, sizeof path, "/v1/scenes/%s/trace", id);
    const double b = 0.5, R = 0.8, n = 1.5;
    char req[512];
    snprintf(req, sizeof req,
             "{\"events\": true, \"rays\": [{\"origin\": [0, %g, -3], \"direction\": [0, 0, 1]},"
             " {\"origin\": [0, 0, -3], \"direction\": [0, 0, 1]},"
             " {\"origin\": [0, 0.9, -3], \"direction\": [0, 0, 1]}]}",
             b);
    char *body = EXPECT_STATUS(d, "POST", path, req, 200);
    cJSON *root = cJSON_Parse(body ? body : "{}");
    const cJSON *rays = get(root, "rays");
    CHECK_INT(cJSON_GetArraySize(rays), 3);
    const cJSON *r0 = cJSON_GetArrayItem(rays, 0);
    double dir[3];
    vec(r0, "exit_direction", dir);
    double ti = asin(b / R), tt = asin(b / (R * n));
    double dev = 2 * (ti - tt);
    CHECK_NEAR(dir[1], -sin(dev), 1e-5);
    CHECK_NEAR(dir[2], cos(dev), 1e-5);
    CHECK_INT((int)num(r0, "event_count"), 2);
    const cJSON *events = get(r0, "events");
    CHECK_INT(cJSON_GetArraySize(events), 2);
    const cJSON *e0 = cJSON_GetArrayItem(events, 0), *e1 = cJSON_GetArrayItem(events, 1);
    CHECK(cJSON_IsString(get(e0, "kind")) &&
          strcmp(get(e0, "kind")->valuestring, "refracted") == 0);
    CHECK(cJSON_IsString(get(e0, "surface")) &&
          strcmp(get(e0, "surface")->valuestring, "ball") == 0);
    CHECK(strcmp(get(e0, "medium_before")->valuestring, "ambient") == 0);
    CHECK(strcmp(get(e0, "medium_after")->valuestring, "ball") == 0);
    CHECK(strcmp(get(e1, "medium_after")->valuestring, "ambient") == 0);
    CHECK_NEAR(num(e0, "n_before"), 1.0, 1e-6);
    CHECK_NEAR(num(e0, "n_after"), 1.5, 1e-6);
    double p[3], nrm[3];
    vec(e0, "point", p);
    vec(e0, "normal", nrm);
    CHECK_NEAR(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), R, 1e-5);
    CHECK_NEAR(nrm[2], -sqrt(1 - (b / R) * (b / R)), 1e-5); /* faces the incoming ray */
    /* The central ray: normal incidence, R = ((n - 1) / (n + 1))^2 = 0.04, no deviation. */
    const cJSON *r1 = cJSON_GetArrayItem(rays, 1);
    CHECK_NEAR(num(cJSON_GetArrayItem(get(r1, "events"), 0), "fresnel_reflectance"), 0.04, 1e-6);
    vec(r1, "transmittance", dir);
    CHECK_NEAR(dir[0], 0.96 * 0.96 * exp(-0.02 * 2 * R), 1e-5);
    /* The ray above the sphere passes by: no events, "missed". */
    const cJSON *r2 = cJSON_GetArrayItem(rays, 2);
    CHECK(strcmp(get(r2, "status")->valuestring, "missed") == 0);
    CHECK_INT(cJSON_GetArraySize(get(r2, "events")), 0);
    cJSON_Delete(root);
    free(body);
}

static void nested_media(struct test_daemon *d)
{
    section("nested");
    /* Wine (priority 1) overlapping the inside of a glass ball shell (priority 2): a
     * ray from the centre meets the glass at r = 0.9 with 1.33 -> 1.5. */
    const char *doc =
        "{\"name\": \"nested\", \"surfaces\": ["
        " {\"name\": \"wine\", \"shape\": \"sphere\", \"radius\": 0.92, \"priority\": 1,"
        "  \"medium\": {\"ior\": 1.33}},"
        " {\"name\": \"glass\", \"shape\": \"sphere\", \"radius\": 1.0, \"priority\": 2,"
        "  \"medium\": {\"ior\": 1.5}},"
        " {\"name\": \"inner\", \"shape\": \"sphere\", \"radius\": 0.9, \"priority\": 3,"
        "  \"medium\": {\"ior\": 1.33}}]}";
    char id[128], path[256];
    CHECK(test_create_scene(d, doc, id));
    snprintf(path, sizeof path, "/v1/scenes/%s/trace", id);
    char *body = EXPECT_STATUS(d, "POST", path,
                               "{\"events\": true, \"rays\": [{\"origin\": [0.1, 0, 0], "
                               "\"direction\": [0, 0.6, 0.8]}]}",
                               200);
    cJSON *root = cJSON_Parse(body ? body : "{}");
    const cJSON *r0 = cJSON_GetArrayItem(get(root, "rays"), 0);
    const cJSON *events = get(r0, "events");
    CHECK_INT(cJSON_GetArraySize(events), 2); /* wine -> glass, glass -> air */
    const cJSON *e0 = cJSON_GetArrayItem(events, 0);
    CHECK(cJSON_IsString(get(e0, "medium_before")) &&
          strcmp(get(e0, "medium_before")->valuestring, "inner") == 0);
    CHECK(cJSON_IsString(get(e0, "medium_after")) &&
          strcmp(get(e0, "medium_after")->valuestring, "glass") == 0);
    CHECK_NEAR(num(e0, "n_before"), 1.33, 1e-6);
    CHECK_NEAR(num(e0, "n_after"), 1.5, 1e-6);
    double p[3];
    vec(e0, "point", p);
    CHECK_NEAR(sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]), 0.9, 1e-5);
    cJSON_Delete(root);
    free(body);
}

static void voxel_scene_unchanged(struct test_daemon *d)
{
    section("voxels");
    const char *doc = "{\"name\": \"vox\", \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], "
                      "\"max\": [1, 1, 1]}, \"resolution\": 16, \"ior\": 1.2}]}";
    char id[128], path[256];
    CHECK(test_create_scene(d, doc, id));
    snprintf(path, sizeof path, "/v1/scenes/%s/trace", id);
    const char *ray = "\"rays\": [{\"origin\": [0, 0.3, -3], \"direction\": [0, 0, 1]}]}";
    char req[256];
    snprintf(req, sizeof req, "{%s", ray);
    char *plain = EXPECT_STATUS(d, "POST", path, req, 200);
    CHECK(plain != NULL && strstr(plain, "\"events\"") == NULL);
    snprintf(req, sizeof req, "{\"events\": true, %s", ray);
    char *with = EXPECT_STATUS(d, "POST", path, req, 200);
    CHECK(with != NULL && strstr(with, "\"events\":[]") != NULL);
    free(plain);
    free(with);
}

/* A unit cube as OBJ, wound outward; OPEN_CUBE lacks its top face (two triangles). */
#define CUBE_VERTS                                                                                 \
    "v -0.5 -0.5 -0.5\nv 0.5 -0.5 -0.5\nv 0.5 0.5 -0.5\nv -0.5 0.5 -0.5\n"                         \
    "v -0.5 -0.5 0.5\nv 0.5 -0.5 0.5\nv 0.5 0.5 0.5\nv -0.5 0.5 0.5\n"
#define CUBE_SIDES                                                                                 \
    "f 1 4 3\nf 1 3 2\nf 5 6 7\nf 5 7 8\nf 1 2 6\nf 1 6 5\nf 2 3 7\nf 2 7 6\nf 4 1 5\nf 4 5 8\n"
static const char closed_cube[] = CUBE_VERTS CUBE_SIDES "f 3 4 8\nf 3 8 7\n";
static const char open_cube[] = CUBE_VERTS CUBE_SIDES;

static long post_mesh(struct test_daemon *d, const char *id, const char *name, const char *obj,
                      char **body)
{
    char path[256];
    snprintf(path, sizeof path, "/v1/scenes/%s/meshes?name=%s", id, name);
    struct refract_response r;
    *body = NULL;
    if (refract_request(d->client, "POST", path, obj, strlen(obj), "application/octet-stream",
                        &r) != REFRACT_E_OK)
        return -1;
    *body = r.body;
    r.body = NULL;
    long status = r.status;
    refract_response_free(&r);
    return status;
}

/* A mesh surface: missing (listed, 409 on render), a closed cube (traced like the box it
 * is), an open one (400 invalid_mesh naming the edge). */
static void mesh_surfaces(struct test_daemon *d)
{
    section("mesh surfaces");
    const char *doc = "{\"name\": \"gem\", \"camera\": {\"width\": 32, \"height\": 24},"
                      " \"surfaces\": [{\"name\": \"gem\", \"shape\": \"mesh\", \"mesh\": \"cube\","
                      " \"scale\": 1.0, \"medium\": {\"ior\": 1.5}}]}";
    char id[128], path[256], *body = NULL;
    CHECK(test_create_scene(d, doc, id));
    snprintf(path, sizeof path, "/v1/scenes/%s", id);
    body = EXPECT_STATUS(d, "GET", path, NULL, 200);
    CHECK(body != NULL && strstr(body, "\"missing_meshes\":\"cube\"") != NULL);
    free(body);
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    EXPECT_ERROR(d, "POST", path, "{\"format\": \"png\"}", 409, "conflict", "mesh \"cube\"",
                 "not uploaded");
    CHECK_INT(post_mesh(d, id, "cube", closed_cube, &body), 201);
    free(body);
    free(EXPECT_STATUS(d, "POST", path, "{\"format\": \"png\"}", 200));
    /* A ray through the cube's centre, tilted: Snell at two parallel faces gives back the
     * direction, displaced; both events name the gem. */
    snprintf(path, sizeof path, "/v1/scenes/%s/trace", id);
    body = EXPECT_STATUS(d, "POST", path,
                         "{\"events\": true, \"rays\": [{\"origin\": [0.1, 0.05, -3], "
                         "\"direction\": [0.1, 0, 1]}]}",
                         200);
    cJSON *root = cJSON_Parse(body ? body : "{}");
    const cJSON *r0 = cJSON_GetArrayItem(get(root, "rays"), 0);
    CHECK_INT((int)num(r0, "event_count"), 2);
    double dir[3];
    vec(r0, "exit_direction", dir);
    double len = sqrt(1.01);
    CHECK_NEAR(dir[0], 0.1 / len, 1e-5);
    CHECK_NEAR(dir[2], 1.0 / len, 1e-5);
    const cJSON *e0 = cJSON_GetArrayItem(get(r0, "events"), 0);
    CHECK_NEAR(num(e0, "n_after"), 1.5, 1e-6);
    double p[3];
    vec(e0, "point", p);
    CHECK_NEAR(p[2], -0.5, 1e-5);
    cJSON_Delete(root);
    free(body);
    /* The open cube cannot bound a medium: the error names the mesh and the open edge. */
    CHECK_INT(post_mesh(d, id, "cube", open_cube, &body), 201);
    free(body);
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    EXPECT_ERROR(d, "POST", path, "{\"format\": \"png\"}", 400, "invalid_mesh",
                 "surfaces[0] (\"gem\")", "cannot bound a medium", "edge");
    /* What else cannot bound a medium, each named with its first offender: one face wound
     * the other way, a zero-area triangle, an edge of three triangles (a fin). An
     * inside-out cube (every face reversed) is fine: it is flipped. */
    static const struct {
        const char *obj, *what;
    } bad[] = {
        {CUBE_VERTS CUBE_SIDES "f 3 8 4\nf 3 8 7\n", "winding is inconsistent"},
        {CUBE_VERTS CUBE_SIDES "f 3 4 8\nf 3 8 7\nf 1 2 2\n", "zero area"},
        {CUBE_VERTS "v 0 2 0\n" CUBE_SIDES "f 3 4 8\nf 3 8 7\nf 3 4 9\n", "non-manifold"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        CHECK_INT(post_mesh(d, id, "cube", bad[i].obj, &body), 201);
        free(body);
        EXPECT_ERROR(d, "POST", path, "{\"format\": \"png\"}", 400, "invalid_mesh",
                     "surfaces[0] (\"gem\")", "cannot bound a medium", bad[i].what);
    }
    const char *inside_out = CUBE_VERTS
        "f 1 3 4\nf 1 2 3\nf 5 7 6\nf 5 8 7\nf 1 6 2\nf 1 5 6\nf 2 7 3\nf 2 6 7\nf 4 5 1\n"
        "f 4 8 5\nf 3 8 4\nf 3 7 8\n";
    CHECK_INT(post_mesh(d, id, "cube", inside_out, &body), 201);
    free(body);
    free(EXPECT_STATUS(d, "POST", path, "{\"format\": \"png\"}", 200));
}

#define SURF(body) "{\"surfaces\": [" body "]}"
#define BALL "{\"shape\": \"sphere\", \"radius\": 0.5, \"medium\": {\"ior\": 1.5}}"

static void bad_input(struct test_daemon *d)
{
    section("bad input");
    char many[8192] = "{\"surfaces\": [";
    for (int i = 0; i < 33; i++) {
        char one[160];
        snprintf(one, sizeof one,
                 "%s{\"shape\": \"sphere\", \"center\": [%d, 0, 0], \"radius\": 0.4, "
                 "\"medium\": {\"ior\": 1.5}}",
                 i ? ", " : "", i);
        strcat(many, one);
    }
    strcat(many, "]}");
    const struct json_error_case cases[] = {
        {__LINE__,
         SURF("{\"shape\": \"text\", \"text\": \"A\", \"height\": 1, \"depth\": 0.2, "
              "\"medium\": {\"ior\": 1.5}}"),
         400,
         "invalid_field",
         {"surfaces[0].shape", "\"text\" has no exact surface", "mesh"}},
        {__LINE__,
         SURF("{\"shape\": \"rounded_box\", \"size\": [1, 1, 0.4], \"radius\": 0.3, "
              "\"medium\": {\"ior\": 1.5}}"),
         400,
         "invalid_field",
         {"surfaces[0].radius", "0.3", "0..0.2"}},
        {__LINE__,
         SURF("{\"shape\": \"sphere\", \"radius\": 0.5}"),
         400,
         "missing_field",
         {"surfaces[0]", "medium"}},
        {__LINE__,
         SURF("{\"shape\": \"sphere\", \"radius\": 0.5, \"medium\": {\"ior\": 7}}"),
         400,
         "invalid_field",
         {"surfaces[0].medium.ior"}},
        {__LINE__,
         SURF("{\"shape\": \"sphere\", \"radius\": 0.5, \"medium\": {\"n\": 1.5}}"),
         400,
         "unknown_field",
         {"surfaces[0].medium", "n"}},
        {__LINE__,
         SURF(BALL ", {\"shape\": \"box\", \"size\": [1, 1, 1], \"priority\": 0, "
                   "\"medium\": {\"ior\": 1.3}}"),
         400,
         "invalid_field",
         {"surfaces[1].priority", "different priorities"}},
        {__LINE__,
         "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
         "\"resolution\": 8, \"ior\": 1.2}], \"surfaces\": [" BALL "]}",
         400,
         "invalid_field",
         {"surfaces[0]", "objects[0]"}},
        {__LINE__,
         "{\"receiver\": {\"height\": -1, \"half_size\": 2}, \"surfaces\": [{\"shape\": "
         "\"mesh\", \"mesh\": \"gem\", \"medium\": {\"ior\": 1.5}}]}",
         400,
         "invalid_field",
         {"receiver", "mesh surfaces", "surfaces[0]"}},
        {__LINE__,
         "{\"receiver\": {\"height\": 0, \"half_size\": 2}, \"surfaces\": [" BALL "]}",
         400,
         "invalid_field",
         {"receiver.height", "surfaces[0]"}},
        {__LINE__, many, 422, "limit_exceeded", {"surfaces", "32"}},
        {__LINE__,
         SURF("{\"shape\": \"sphere\", \"radius\": 0.5, \"colour\": 1, "
              "\"medium\": {\"ior\": 1.5}}"),
         400,
         "unknown_field",
         {"surfaces[0]", "colour"}},
        {__LINE__,
         SURF("{\"shape\": \"plane\", \"point\": [0, 0, 0], \"medium\": {\"ior\": 1.33}}"),
         400,
         "missing_field",
         {"surfaces[0]", "normal"}},
        {__LINE__, "{\"surfaces\": []}", 400, "invalid_field", {"surfaces"}},
        {__LINE__, "{\"name\": \"x\"}", 400, "missing_field", {"objects", "surfaces"}},
    };
    EXPECT_JSON_ERROR_CASES(d, "POST", "/v1/scenes", cases);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_surfaces_api", d.why);
    sphere_scene(&d);
    nested_media(&d);
    voxel_scene_unchanged(&d);
    mesh_surfaces(&d);
    bad_input(&d);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_surfaces_api");
}
