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
 *     and the same traces;
 *   - a mesh is a content-addressed blob with an uploads row: the 201's sha256 names the
 *     file <data>/blobs/<aa>/<sha256> of the uploaded size, GET /v1/storage counts it, and
 *     after kill -9 right after its 201 the mesh is back (same sha256 and checksum) with
 *     the storage figures of before the kill; replacing it removes the old blob.
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include "daemon.h"
#include "test.h"
#include "upload_util.h"
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

static double storage_number(struct test_daemon *d, const char *key)
{
    char *body = NULL;
    CHECK_INT(test_request(d, "GET", "/v1/storage", NULL, &body), 200);
    double x = upload_json_number(body, key);
    free(body);
    return x;
}

/* The size of blob `sha` in data_dir, or -1 when there is no such file. */
static long long blob_size(const char *data_dir, const char *sha)
{
    char path[512];
    snprintf(path, sizeof path, "%s/blobs/%.2s/%s", data_dir, sha, sha);
    struct stat st;
    return stat(path, &st) == 0 ? (long long)st.st_size : -1;
}

/* The "meshes" entry named `name` of the scene's GET answer, as "sha256 checksum". */
static void listed_mesh(struct test_daemon *d, const char *id, const char *name, char *out,
                        size_t size)
{
    out[0] = '\0';
    char *json = scene_json(d, id);
    cJSON *root = cJSON_Parse(json ? json : "");
    const cJSON *m = NULL;
    cJSON_ArrayForEach(m, cJSON_GetObjectItemCaseSensitive(root, "meshes"))
    {
        const cJSON *n = cJSON_GetObjectItemCaseSensitive(m, "name");
        const cJSON *sha = cJSON_GetObjectItemCaseSensitive(m, "sha256");
        const cJSON *sum = cJSON_GetObjectItemCaseSensitive(m, "checksum");
        if (cJSON_IsString(n) && strcmp(n->valuestring, name) == 0 && cJSON_IsString(sha) &&
            cJSON_IsString(sum))
            snprintf(out, size, "%s %s", sha->valuestring, sum->valuestring);
    }
    cJSON_Delete(root);
    refract_free(json);
}

static void kill9(struct test_daemon *d)
{
    refract_client_destroy(d->client);
    d->client = NULL;
    kill(d->pid, SIGKILL);
    int status;
    waitpid(d->pid, &status, 0);
    d->pid = 0;
}

static void mesh_survives_kill9_after_its_201(const char *data_dir, const char *id,
                                              const struct test_mesh *tm)
{
    const char *args[] = {"--max-mesh-triangles", "6000", NULL};
    struct test_daemon a, b;
    if (!test_daemon_start_in(&a, data_dir, args))
        test_setup_failed("test_mesh_upload (kill -9 start)", a.why);
    double used0 = storage_number(&a, "used_bytes"), blobs0 = storage_number(&a, "blobs");
    double uploads0 = storage_number(&a, "uploads");
    /* New content (an OBJ file), so a new blob; kill -9 as soon as the 201 is in (the row
     * is committed by then), no shutdown. */
    struct test_buf obj = test_write_obj(tm);
    char *body = NULL;
    CHECK_INT(post_mesh(&a, id, "?name=ball2", obj.p, obj.len, NULL, &body), 201);
    kill9(&a);
    char sha[80] = "", sum[40] = "";
    upload_json_string(body, "sha256", sha, sizeof sha);
    upload_json_string(body, "checksum", sum, sizeof sum);
    free(body);
    CHECK_INT((int)strlen(sha), 64);

    if (!test_daemon_start_in(&b, data_dir, args))
        test_setup_failed("test_mesh_upload (kill -9 restart)", b.why);
    char want[160], got[160];
    snprintf(want, sizeof want, "%s %s", sha, sum);
    listed_mesh(&b, id, "ball2", got, sizeof got);
    CHECK_STR(got, want);
    CHECK(blob_size(data_dir, sha) == (long long)obj.len);
    CHECK(storage_number(&b, "used_bytes") == used0 + (double)obj.len);
    CHECK(storage_number(&b, "blobs") == blobs0 + 1);
    CHECK(storage_number(&b, "uploads") == uploads0 + 1);
    /* The same content under another name: one blob, two rows. */
    CHECK_INT(post_mesh(&b, id, "?name=ball3", obj.p, obj.len, NULL, &body), 201);
    free(body);
    listed_mesh(&b, id, "ball3", got, sizeof got);
    CHECK_STR(got, want);
    CHECK(storage_number(&b, "used_bytes") == used0 + (double)obj.len);
    CHECK(storage_number(&b, "blobs") == blobs0 + 1);
    CHECK(storage_number(&b, "uploads") == uploads0 + 2);

    /* Replacing both with the PLY content frees the OBJ blob. */
    struct test_buf ply = test_write_ply(tm, TEST_PLY_ASCII);
    CHECK_INT(post_mesh(&b, id, "?name=ball2", ply.p, ply.len, NULL, &body), 201);
    free(body);
    CHECK(blob_size(data_dir, sha) == (long long)obj.len); /* ball3 still names it */
    CHECK_INT(post_mesh(&b, id, "?name=ball3", ply.p, ply.len, NULL, &body), 201);
    free(body);
    CHECK(blob_size(data_dir, sha) == -1);
    CHECK(storage_number(&b, "used_bytes") == used0 + (double)ply.len);
    CHECK_INT(test_daemon_stop(&b), 0);
    test_daemon_cleanup(&a);
    test_daemon_cleanup(&b);
    free(obj.p);
    free(ply.p);
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
    mesh_survives_kill9_after_its_201(d.data_dir, id, &tm);
    test_daemon_cleanup(&d);
    free(ply.p);
    test_mesh_free(&tm);
    return test_summary("test_mesh_upload");
}
