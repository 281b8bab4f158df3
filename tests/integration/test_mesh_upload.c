/*
 * test_mesh_upload.c - uploaded meshes through a real refractd (POST
 * /v1/scenes/{id}/meshes, docs/api.md), referenced by a mesh shape (docs/scenes.md):
 *   - a scene whose mesh is not uploaded lists it in missing_meshes, and rendering it is
 *     a 409 conflict that names the mesh and the upload to make;
 *   - the upload answers 201 with what was stored (triangles, vertices, bounds, checksum,
 *     bytes), and the scene lists the mesh;
 *   - a glass sphere made of the uploaded icosphere traces like the procedural sphere of
 *     the same radius (same exit points and directions to 0.02: the same voxels up to
 *     the polyhedron's sag), and renders;
 *   - every bad file and bad query gets its own precise 4xx: out-of-range index, NaN,
 *     truncated binary PLY, a lying header, too many triangles, empty body, unknown
 *     format, missing or bad name, unknown parameter, bad format, unknown scene, wrong
 *     Content-Type;
 *   - after a restart on the same data directory the mesh is back, with the same checksum
 *     and the same traces.
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon.h"
#include "test.h"
#include "unit/mesh_test_util.h"

#define GLASS(shape)                                                                               \
    "{\"name\": \"mesh ball\", \"camera\": {\"eye\": [0, 0, 4], \"look_at\": [0, 0, 0], \"up\": "  \
    "[0, 1, 0], \"fov_y_deg\": 40, \"width\": 32, \"height\": 24}, \"objects\": [{\"bounds\": "    \
    "{\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 24, \"ior\": [1.0, {" shape      \
    ", \"inside\": 1.5}]}]}"

static const char *const mesh_scene =
    GLASS("\"shape\": \"mesh\", \"mesh\": \"ball\", \"center\": [0.05, 0, 0], \"scale\": 0.7");
static const char *const sphere_scene =
    GLASS("\"shape\": \"sphere\", \"center\": [0.05, 0, 0], \"radius\": 0.7");

static const char *const rays_request =
    "{\"rays\": [{\"origin\": [0, 0, -3], \"direction\": [0, 0, 1]},"
    " {\"origin\": [0.3, 0.1, -3], \"direction\": [0, 0, 1]},"
    " {\"origin\": [-0.2, -0.4, -3], \"direction\": [0.02, 0.05, 1]}]}";

/* POST the bytes to /v1/scenes/<id>/meshes<query>; returns the status, *body the reply. */
static long post_mesh(struct test_daemon *d, const char *id, const char *query, const void *bytes,
                      size_t len, const char *content_type, char **body)
{
    char path[256];
    snprintf(path, sizeof path, "/v1/scenes/%s/meshes%s", id, query);
    struct refract_response r;
    *body = NULL;
    if (refract_request(d->client, "POST", path, bytes, len, content_type, &r) != REFRACT_E_OK)
        return -1;
    *body = r.body;
    r.body = NULL;
    long status = r.status;
    refract_response_free(&r);
    return status;
}

static cJSON *trace(struct test_daemon *d, const char *id)
{
    char *json = NULL;
    int rc = refract_trace(d->client, id, rays_request, &json);
    CHECK_MSG(rc == REFRACT_E_OK, "trace: %s", refract_errmsg(d->client));
    cJSON *root = rc == REFRACT_E_OK ? cJSON_Parse(json) : NULL;
    refract_free(json);
    return root;
}

static double at(const cJSON *rays, int ray, const char *key, int k)
{
    const cJSON *v =
        cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(cJSON_GetArrayItem(rays, ray), key), k);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* The two traces' exits agree to tol in position and direction. */
static void check_same_exits(const cJSON *a, const cJSON *b, double tol)
{
    const cJSON *ra = cJSON_GetObjectItemCaseSensitive(a, "rays");
    const cJSON *rb = cJSON_GetObjectItemCaseSensitive(b, "rays");
    CHECK_INT(cJSON_GetArraySize(ra), 3);
    for (int i = 0; i < 3; i++) {
        for (int k = 0; k < 3; k++) {
            CHECK_NEAR(at(ra, i, "exit_origin", k), at(rb, i, "exit_origin", k), tol);
            CHECK_NEAR(at(ra, i, "exit_direction", k), at(rb, i, "exit_direction", k), tol);
        }
    }
}

static char *scene_json(struct test_daemon *d, const char *id)
{
    char *json = NULL;
    CHECK_INT(refract_scene_get(d->client, id, &json), REFRACT_E_OK);
    return json;
}

static void missing_mesh_is_listed_and_refused(struct test_daemon *d, const char *id)
{
    char *json = scene_json(d, id);
    CHECK_CONTAINS(json, "\"missing_meshes\":\"ball\"");
    refract_free(json);
    char *body = NULL;
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    CHECK_INT(test_request(d, "POST", path, "{}", &body), 409);
    CHECK(test_error_is(body, "conflict",
                        "objects[0].ior[1]: mesh \"ball\" has not been uploaded; upload it with "
                        "POST /v1/scenes/{id}/meshes?name=ball"));
    free(body);
}

static void uploaded_mesh_traces_like_the_sphere(struct test_daemon *d, const char *id,
                                                 const struct test_buf *ply, size_t triangles,
                                                 size_t vertices)
{
    char *body = NULL;
    CHECK_INT(post_mesh(d, id, "?name=ball", ply->p, ply->len, "application/octet-stream", &body),
              201);
    cJSON *root = cJSON_Parse(body);
    CHECK_STR(cJSON_GetStringValue(cJSON_GetObjectItem(root, "name")), "ball");
    CHECK_NEAR(cJSON_GetNumberValue(cJSON_GetObjectItem(root, "triangles")), triangles, 0);
    CHECK_NEAR(cJSON_GetNumberValue(cJSON_GetObjectItem(root, "vertices")), vertices, 0);
    CHECK_NEAR(cJSON_GetNumberValue(cJSON_GetObjectItem(root, "bytes")), ply->len, 0);
    const cJSON *bmax = cJSON_GetObjectItem(cJSON_GetObjectItem(root, "bounds"), "max");
    CHECK_NEAR(cJSON_GetNumberValue(cJSON_GetArrayItem(bmax, 2)), 1.0, 1e-9);
    CHECK(strlen(cJSON_GetStringValue(cJSON_GetObjectItem(root, "checksum"))) == 16);
    cJSON_Delete(root);
    free(body);
    char *json = scene_json(d, id);
    CHECK_CONTAINS(json, "\"meshes\":[{\"name\":\"ball\"");
    CHECK(json != NULL && strstr(json, "missing_meshes") == NULL);
    refract_free(json);
    char sphere_id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(d, sphere_scene, sphere_id));
    cJSON *a = trace(d, id), *b = trace(d, sphere_id);
    if (a && b)
        check_same_exits(a, b, 0.02);
    cJSON_Delete(a);
    cJSON_Delete(b);
    struct refract_image img;
    int rc = refract_render(d->client, id, "{\"format\": \"png\"}", &img);
    CHECK_MSG(rc == REFRACT_E_OK, "render: %s", refract_errmsg(d->client));
    if (rc == REFRACT_E_OK) {
        CHECK_STR(img.content_type, "image/png");
        CHECK(img.len > 100);
        refract_image_free(&img);
    }
}

struct bad_upload {
    const char *query;
    const char *content_type;
    const char *body; /* NULL: use `bytes` */
    long status;
    const char *code;
    const char *message;
};

static void each_bad_upload_gets_a_precise_4xx(struct test_daemon *d, const char *id,
                                               const struct test_buf *ply)
{
    const struct bad_upload cases[] = {
        {"?name=b", NULL, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", 400, "invalid_mesh",
         "line 4: face vertex 3 refers to vertex 4, but only 3 vertices are defined"},
        {"?name=b", NULL, "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", 400, "invalid_mesh",
         "line 2: vertex coordinate y is \"nan\", not a finite number"},
        {"?name=b", NULL,
         "ply\nformat ascii 1.0\nelement vertex 300\nproperty float x\nproperty float y\n"
         "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
         "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
         400, "invalid_mesh", "the header declares 300 \"vertex\" records of at least 6 bytes"},
        {"?name=b", NULL, "hello\n", 400, "invalid_mesh", "the file is neither PLY"},
        {"?name=b", NULL, "", 400, "invalid_mesh", "the request body is empty"},
        {"", NULL, "v 0 0 0\n", 400, "missing_field", "query parameter name is required"},
        {"?name=a.b", NULL, "v 0 0 0\n", 400, "invalid_field", "\"a.b\" is not a mesh name"},
        {"?name=b&scale=2", NULL, "v 0 0 0\n", 400, "unknown_field",
         "query parameter \"scale\" is not known here; allowed: name, format"},
        {"?name=b&format=stl", NULL, "v 0 0 0\n", 400, "invalid_field",
         "query parameter format: expected obj or ply, got \"stl\""},
        {"?name=b&format=obj", NULL, "ply\nformat ascii 1.0\n", 400, "invalid_mesh",
         "line 1: unknown statement \"ply\""},
        {"?name=b", "image/png", "v 0 0 0\n", 415, "unsupported_media_type",
         "Content-Type \"image/png\" is not accepted here"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char *body = NULL;
        const struct bad_upload *c = &cases[i];
        long status = post_mesh(d, id, c->query, c->body, strlen(c->body), c->content_type, &body);
        CHECK_MSG(status == c->status, "case %zu: status %ld, expected %ld", i, status, c->status);
        CHECK_MSG(test_error_is(body, c->code, c->message), "case %zu", i);
        free(body);
    }
    /* The binary icosphere cut short, and one too big for --max-mesh-triangles 6000. */
    char *body = NULL;
    CHECK_INT(post_mesh(d, id, "?name=b", ply->p, ply->len - 7, NULL, &body), 400);
    CHECK(test_error_is(body, "invalid_mesh", "the file ends at byte"));
    free(body);
    struct test_mesh big = test_icosphere(5, 1.0);
    struct test_buf big_ply = test_write_ply(&big, TEST_PLY_BE);
    CHECK_INT(post_mesh(d, id, "?name=b", big_ply.p, big_ply.len, NULL, &body), 422);
    CHECK(test_error_is(body, "limit_exceeded",
                        "the header declares 20480 faces, more than the limit "
                        "max_mesh_triangles = 6000; simplify the mesh or start refractd with "
                        "--max-mesh-triangles"));
    free(body);
    free(big_ply.p);
    test_mesh_free(&big);
    CHECK_INT(post_mesh(d, "nosuchscene", "?name=b", "v 0 0 0\n", 8, NULL, &body), 404);
    CHECK(test_error_is(body, "scene_not_found", "nosuchscene"));
    free(body);
}

static void mesh_is_back_after_a_restart(struct test_daemon *d, const char *id)
{
    cJSON *before = trace(d, id);
    char *json = scene_json(d, id);
    const char *sum = json ? strstr(json, "\"checksum\":\"") : NULL;
    char checksum[40] = "";
    if (sum)
        snprintf(checksum, sizeof checksum, "%.29s", sum);
    refract_free(json);
    CHECK_INT(test_daemon_stop(d), 0);
    struct test_daemon again;
    const char *args[] = {"--max-mesh-triangles", "6000", NULL};
    if (!test_daemon_start_in(&again, d->data_dir, args)) {
        fprintf(stderr, "restart failed: %s\n", again.why);
        CHECK(false);
        cJSON_Delete(before);
        return;
    }
    json = scene_json(&again, id);
    CHECK(checksum[0] != '\0');
    CHECK_CONTAINS(json, checksum);
    refract_free(json);
    cJSON *after = trace(&again, id);
    if (before && after)
        check_same_exits(before, after, 1e-6);
    cJSON_Delete(before);
    cJSON_Delete(after);
    CHECK_INT(test_daemon_stop(&again), 0);
    test_daemon_cleanup(&again);
}

int main(void)
{
    struct test_daemon d;
    const char *args[] = {"--max-mesh-triangles", "6000", NULL};
    if (!test_daemon_start(&d, args))
        test_setup_failed("test_mesh_upload", d.why);
    struct test_mesh tm = test_icosphere(4, 1.0); /* 5120 triangles */
    struct test_buf ply = test_write_ply(&tm, TEST_PLY_LE);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, mesh_scene, id));
    missing_mesh_is_listed_and_refused(&d, id);
    uploaded_mesh_traces_like_the_sphere(&d, id, &ply, tm.nt, tm.nv);
    each_bad_upload_gets_a_precise_4xx(&d, id, &ply);
    mesh_is_back_after_a_restart(&d, id);
    test_daemon_cleanup(&d);
    free(ply.p);
    test_mesh_free(&tm);
    return test_summary("test_mesh_upload");
}
