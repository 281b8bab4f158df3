/*
 * test_lightsim_mesh_api.c - a mesh surface in a scene that needs the light simulator,
 * through a real refractd (docs/lightsim.md "Surfaces", docs/scenes.md "Surfaces"):
 *   - a scene with a mesh surface (a glass ball: an icosphere uploaded as OBJ) and a
 *     receiver is accepted (201; it used to be refused with 400);
 *   - once the mesh is uploaded, its irradiance volume becomes ready, and the EXR download
 *     shows the ball's caustic: on the receiver layer below the ball the irradiance peaks
 *     at several times the unit beam's E = 1 that the receiver gets beside the ball;
 *   - the render of the view answers 200 with the volume "ready";
 *   - a receiver above the mesh's bottom, which only the upload can show, fails the
 *     volume with the receiver.height message (irradiance state "failed").
 * The light grid is coarse (16 voxels, N0 8): the mesh path is the slow one on llvmpipe.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/io_exr.h"
#include "irradiance_util.h"
#include "mesh/mesh.h"
#include "mesh/mesh_rt.h"

/* The unit icosphere of `sub` subdivisions as OBJ text (caller frees). */
static char *icosphere_obj(int sub)
{
    struct mesh *m = NULL;
    struct err e = {0};
    if (mesh_make_icosphere(sub, 1.0, &m, &e) != REFRACT_E_OK)
        test_setup_failed("test_lightsim_mesh_api", e.msg);
    size_t cap = 64 * (m->vertex_count + m->triangle_count) + 1, len = 0;
    char *obj = malloc(cap);
    for (size_t i = 0; i < m->vertex_count; i++)
        len += (size_t)snprintf(obj + len, cap - len, "v %.9f %.9f %.9f\n", m->vertices[i][0],
                                m->vertices[i][1], m->vertices[i][2]);
    for (size_t i = 0; i < m->triangle_count; i++)
        len += (size_t)snprintf(obj + len, cap - len, "f %u %u %u\n", m->triangles[i][0] + 1,
                                m->triangles[i][1] + 1, m->triangles[i][2] + 1);
    mesh_destroy(m);
    return obj;
}

static long post_mesh(struct test_daemon *d, const char *id, const char *name, const char *obj)
{
    char path[256];
    snprintf(path, sizeof path, "/v1/scenes/%s/meshes?name=%s", id, name);
    struct refract_response r;
    if (refract_request(d->client, "POST", path, obj, strlen(obj), "application/octet-stream",
                        &r) != REFRACT_E_OK)
        return -1;
    long status = r.status;
    refract_response_free(&r);
    return status;
}

#define BALL_SCENE(height)                                                                         \
    "{\"name\": \"mesh lens\", \"camera\": {\"eye\": [0, 1.5, 3], \"look_at\": [0, -0.8, 0],"      \
    " \"width\": 32, \"height\": 24}, \"environment\": {\"intensity\": 0},"                        \
    " \"surfaces\": [{\"name\": \"ball\", \"shape\": \"mesh\", \"mesh\": \"ico\", \"scale\": 0.5," \
    " \"medium\": {\"ior\": 1.5}}],"                                                               \
    " \"receiver\": {\"height\": " height ", \"half_size\": 0.9, \"albedo\": 0.8,"          \
    " \"caustics\": \"volume\"},"                \
    " \"lights\": [{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0, -1, 0]}],"    \
    " \"lightsim\": {\"resolution\": 16, \"initial_patches\": 8}}"

/* The caustic on the receiver layer of the downloaded volume. */
static void caustic(struct test_daemon *d, const char *id)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/irradiance/sun.exr", id);
    struct irr_answer a = irr_http(d, "GET", path, NULL);
    CHECK_INT(a.status, 200);
    static const char *const names[] = {"R", "G", "B", "dir.X", "dir.Y", "dir.Z", "dir.W"};
    float *px = NULL;
    int w = 0, h = 0;
    char grid_text[512];
    struct err e = {0};
    if (a.status != 200 || !IRR_CHECK(io_decode_exr_channels(a.body, a.len, 7, names, 1 << 24, &px,
                                                             &w, &h, "refract.grid", grid_text,
                                                             sizeof grid_text, &e) == REFRACT_E_OK,
                                      e.msg)) {
        free(a.body);
        return;
    }
    cJSON *grid = cJSON_Parse(grid_text);
    const cJSON *dims = cJSON_GetObjectItemCaseSensitive(grid, "dims");
    int nx = (int)cJSON_GetArrayItem(dims, 0)->valuedouble;
    int ny = (int)cJSON_GetArrayItem(dims, 1)->valuedouble;
    double voxel = irr_num(grid, "voxel");
    const cJSON *bmin = cJSON_GetObjectItemCaseSensitive(grid, "bmin");
    double x0 = cJSON_GetArrayItem(bmin, 0)->valuedouble;
    double z0 = cJSON_GetArrayItem(bmin, 2)->valuedouble;
    /* The receiver plane lies between layers 1 and 2: the grid reaches two voxels below it
     * (docs/lightsim.md "Domain"), and the receiver reads E on the plane, their mean. */
    double y0 = cJSON_GetArrayItem(bmin, 1)->valuedouble;
    CHECK_NEAR(y0 + 2.0 * voxel, -0.8, 1e-9);
    double peak = 0, beside = 0;
    int n_beside = 0;
    for (int k = 0; k < h / ny; k++)
        for (int i = 0; i < nx; i++) {
            double x = x0 + (i + 0.5) * voxel, z = z0 + (k + 0.5) * voxel;
            double r = sqrt(x * x + z * z);
            float E = 0.5f * (px[((size_t)(k * ny + 1) * nx + i) * 7] +
                              px[((size_t)(k * ny + 2) * nx + i) * 7]);
            if (r < 0.2)
                peak = fmax(peak, E);
            else if (r > 0.6 && fabs(x) < 0.75 && fabs(z) < 0.75) {
                beside += E;
                n_beside++;
            }
        }
    beside = n_beside ? beside / n_beside : 0;
    printf("receiver layer (%d x %d voxels of %.4f): peak E %.3f below the ball, mean %.3f "
           "beside it (%d voxels)\n",
           nx, h / ny, voxel, peak, beside, n_beside);
    CHECK(n_beside > 10);
    CHECK_NEAR(beside, 1.0, 0.25);
    CHECK(peak > 3.0 * beside);
    cJSON_Delete(grid);
    free(px);
    free(a.body);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_lightsim_mesh_api", d.why);
    char *obj = icosphere_obj(3);
    char id[REFRACT_ID_SIZE] = "";
    CHECK(test_create_scene(&d, BALL_SCENE("-0.8"), id));
    if (id[0]) {
        CHECK_INT(post_mesh(&d, id, "ico", obj), 201);
        /* seconds alone on llvmpipe; minutes on a machine loaded with other llvmpipe runs */
        cJSON_Delete(irr_wait_ready(&d, id, 240));
        caustic(&d, id);
        char path[128];
        snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
        struct irr_answer a = irr_http(&d, "POST", path, "{\"format\": \"png\"}");
        CHECK_INT(a.status, 200);
        CHECK_STR(a.irradiance, "ready");
        free(a.body);
    }
    /* The receiver cuts the ball (its bottom is at y = -0.5): the volume fails, saying so. */
    char id2[REFRACT_ID_SIZE] = "";
    CHECK(test_create_scene(&d, BALL_SCENE("-0.3"), id2));
    if (id2[0]) {
        CHECK_INT(post_mesh(&d, id2, "ico", obj), 201);
        cJSON *st = NULL;
        for (int i = 0; i < 500; i++) {
            cJSON_Delete(st);
            st = irr_status(&d, id2);
            const cJSON *l = irr_light(st, "sun");
            if (strcmp(irr_str(l, "state"), "failed") == 0)
                break;
            nanosleep(&(struct timespec){0, 20 * 1000 * 1000}, NULL);
        }
        char *text = st ? cJSON_PrintUnformatted(st) : NULL;
        printf("receiver above the mesh's bottom: %s\n", text ? text : "(no status)");
        CHECK(text != NULL && strstr(text, "\"failed\"") != NULL);
        CHECK(text != NULL && strstr(text, "receiver.height") != NULL);
        free(text);
        cJSON_Delete(st);
    }
    free(obj);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_lightsim_mesh_api");
}
