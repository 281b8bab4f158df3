/*
 * test_uploads.c - uploaded volumes and environment maps do what docs/scenes.md says,
 * through a real refractd and librefract, and survive a restart:
 *   - an uploaded ior volume holding the linear field n = 1.3 + 0.2 y traces exactly like
 *     the procedural "linear" profile on the same voxels (the rays bend, and lose light
 *     only at the bounds faces: a steep smooth ramp is not an interface);
 *   - an uploaded RGB attenuation volume gives Beer-Lambert transmittance exp(-sigma L);
 *   - an uploaded equirectangular EXR is the background: pixels looking up show the
 *     upper half's radiance, pixels looking down the lower half's, times the intensity;
 *   - after a restart on the same data directory, the scenes and their uploads are
 *     back and give byte-identical renders and identical traces.
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/env.h"
#include "daemon.h"
#include "io/io_image.h"
#include "test.h"

#define RES 16

static const char *const volume_scene =
    "{\"name\": \"uploaded ramp\", \"render\": {\"stepper\": \"rk4\", \"step\": 0.5},"
    " \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16,"
    " \"smoothing_sigma\": 0, \"ior\": {\"volume\": \"ramp\"}}]}";
static const char *const profile_scene =
    "{\"name\": \"profile ramp\", \"render\": {\"stepper\": \"rk4\", \"step\": 0.5},"
    " \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16,"
    " \"smoothing_sigma\": 0,"
    " \"ior\": {\"profile\": \"linear\", \"n0\": 1.3, \"gradient\": [0, 0.2, 0]}}]}";
static const char *const absorber_scene =
    "{\"name\": \"uploaded absorber\", \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1],"
    " \"max\": [1, 1, 1]}, \"resolution\": 8, \"ior\": 1.0,"
    " \"attenuation\": {\"volume\": \"sigma\", \"scale\": 2.0}}]}";
static const char *const env_scene =
    "{\"name\": \"uploaded sky\", \"environment\": {\"type\": \"image\", \"intensity\": 2},"
    " \"camera\": {\"eye\": [0, 0, 4], \"look_at\": [0, 0, 0], \"up\": [0, 1, 0],"
    " \"fov_y_deg\": 60, \"width\": 48, \"height\": 36},"
    " \"objects\": [{\"bounds\": {\"min\": [-0.2, -0.2, -0.2], \"max\": [0.2, 0.2, 0.2]},"
    " \"resolution\": 4, \"ior\": 1.0}]}";

static const char *const rays_request =
    "{\"rays\": [{\"origin\": [0, -0.5, -3], \"direction\": [0, 0, 1]},"
    " {\"origin\": [0.2, 0.1, -3], \"direction\": [0, 0.1, 1]},"
    " {\"origin\": [-0.3, 0.4, -3], \"direction\": [0.05, -0.1, 1]}]}";

static const float top_rgb[3] = {2.0f, 0.5f, 0.25f}, bottom_rgb[3] = {0.1f, 0.2f, 0.3f};

/* Traces rays_request; returns the parsed "rays" array's parent (caller deletes). */
static cJSON *trace(struct test_daemon *d, const char *id, const char *request)
{
    char *json = NULL;
    int rc = refract_trace(d->client, id, request, &json);
    CHECK_INT(rc, REFRACT_E_OK);
    if (rc != REFRACT_E_OK) {
        fprintf(stderr, "trace: %s\n", refract_errmsg(d->client));
        return NULL;
    }
    cJSON *root = cJSON_Parse(json);
    refract_free(json);
    return root;
}

static double number_at(const cJSON *ray, const char *key, int index)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(ray, key);
    if (index >= 0)
        item = cJSON_GetArrayItem(item, index);
    return cJSON_IsNumber(item) ? item->valuedouble : NAN;
}

static bool upload_ramp(struct test_daemon *d, const char *id)
{
    static float ramp[RES * RES * RES];
    for (int z = 0; z < RES; z++)
        for (int y = 0; y < RES; y++)
            for (int x = 0; x < RES; x++) {
                double py = -1.0 + (y + 0.5) * 2.0 / RES; /* the voxel centre */
                ramp[(z * RES + y) * RES + x] = (float)(1.3 + 0.2 * py);
            }
    char *answer = NULL;
    int rc = refract_volume_upload(d->client, id, "ramp", (const int[]){RES, RES, RES}, 1, ramp,
                                   &answer);
    CHECK_INT(rc, REFRACT_E_OK);
    if (answer)
        CHECK_CONTAINS(answer, "\"dims\":[16,16,16]");
    refract_free(answer);
    return rc == REFRACT_E_OK;
}

/* The uploaded ramp and the procedural profile build the same voxels, so the same rays
 * leave the same way (float32 rounding of the upload aside). */
static void uploaded_ior_traces_like_the_profile(struct test_daemon *d, char *vol_id)
{
    char prof_id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(d, volume_scene, vol_id));
    CHECK(test_create_scene(d, profile_scene, prof_id));
    char *body = NULL;
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/trace", vol_id);
    CHECK_INT(test_request(d, "POST", path, rays_request, &body), 409); /* not uploaded yet */
    CHECK(test_error_is(body, "conflict", "ramp"));
    free(body);
    if (!upload_ramp(d, vol_id))
        return;
    cJSON *a = trace(d, vol_id, rays_request), *b = trace(d, prof_id, rays_request);
    const cJSON *ra = cJSON_GetObjectItemCaseSensitive(a, "rays");
    const cJSON *rb = cJSON_GetObjectItemCaseSensitive(b, "rays");
    CHECK_INT(cJSON_GetArraySize(ra), 3);
    double worst = 0.0;
    for (int i = 0; i < cJSON_GetArraySize(ra) && i < cJSON_GetArraySize(rb); i++) {
        const cJSON *x = cJSON_GetArrayItem(ra, i), *y = cJSON_GetArrayItem(rb, i);
        CHECK_STR(cJSON_GetObjectItemCaseSensitive(x, "status")->valuestring, "exited");
        for (int k = 0; k < 3; k++) {
            worst = fmax(
                worst, fabs(number_at(x, "exit_direction", k) - number_at(y, "exit_direction", k)));
            worst =
                fmax(worst, fabs(number_at(x, "exit_origin", k) - number_at(y, "exit_origin", k)));
        }
        worst = fmax(worst, fabs(number_at(x, "optical_path_length", -1) -
                                 number_at(y, "optical_path_length", -1)) /
                                number_at(y, "optical_path_length", -1));
    }
    printf("uploaded ior volume vs linear profile: worst difference %.2e\n", worst);
    CHECK_MSG(worst < 1e-5, "uploaded volume and profile differ by %g", worst);
    /* The field bends the first ray (launched along +z) towards +y, higher n. */
    double dy = number_at(cJSON_GetArrayItem(ra, 0), "exit_direction", 1);
    CHECK_MSG(dy > 0.05, "the ramp did not bend the ray (exit d.y %g)", dy);
    /* A smooth ramp reflects only at the two bounds faces (1-4% each here), although
     * its slope, 0.025 per voxel, is above the 0.02 boundary threshold. */
    for (int i = 0; i < cJSON_GetArraySize(ra); i++) {
        double t = number_at(cJSON_GetArrayItem(ra, i), "transmittance", 0);
        CHECK_MSG(t > 0.9, "ray %d lost light inside a smooth ramp: T = %g", i, t);
    }
    cJSON_Delete(a);
    cJSON_Delete(b);
}

/* An RGB attenuation volume sigma = (0.1, 0.2, 0.4), scaled by 2, over the cube's 2
 * units of length: T = exp(-2 * 2 * sigma). n = 1: no Fresnel, no bending. */
static void uploaded_attenuation_follows_beer_lambert(struct test_daemon *d, char *abs_id)
{
    CHECK(test_create_scene(d, absorber_scene, abs_id));
    static float sigma[4 * 4 * 4 * 3];
    for (int i = 0; i < 4 * 4 * 4; i++) {
        sigma[3 * i] = 0.1f;
        sigma[3 * i + 1] = 0.2f;
        sigma[3 * i + 2] = 0.4f;
    }
    CHECK_INT(
        refract_volume_upload(d->client, abs_id, "sigma", (const int[]){4, 4, 4}, 3, sigma, NULL),
        REFRACT_E_OK);
    cJSON *root =
        trace(d, abs_id, "{\"rays\": [{\"origin\": [0.1, 0.2, -3], \"direction\": [0, 0, 1]}]}");
    const cJSON *ray = cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "rays"), 0);
    const double s[3] = {0.1, 0.2, 0.4};
    for (int k = 0; k < 3; k++) {
        double expected = exp(-2.0 * 2.0 * s[k]);
        CHECK_NEAR(number_at(ray, "transmittance", k), expected, 1e-4);
    }
    cJSON_Delete(root);
}

/* A 64 x 32 equirectangular EXR: upper half (v < 0.5: above the horizon) top_rgb, lower
 * half bottom_rgb. */
static bool upload_sky(struct test_daemon *d, const char *id)
{
    enum { W = 64, H = 32 };
    static float px[W * H * 4];
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            const float *c = j < H / 2 ? top_rgb : bottom_rgb;
            float *p = &px[(j * W + i) * 4];
            p[0] = c[0];
            p[1] = c[1];
            p[2] = c[2];
            p[3] = 1.0f;
        }
    void *exr = NULL;
    size_t len = 0;
    struct err e = {0};
    CHECK_INT(io_encode_exr(px, W, H, &exr, &len, &e), REFRACT_E_OK);
    char *answer = NULL;
    int rc = refract_environment_upload(d->client, id, exr, len, &answer);
    CHECK_INT(rc, REFRACT_E_OK);
    if (answer)
        CHECK_CONTAINS(answer, "64");
    refract_free(answer);
    free(exr);
    return rc == REFRACT_E_OK;
}

/* Renders the scene's default view as EXR; returns the encoded bytes in *img. */
static bool render_exr(struct test_daemon *d, const char *id, struct refract_image *img)
{
    int rc = refract_render(d->client, id, "{\"format\": \"exr\"}", img);
    CHECK_INT(rc, REFRACT_E_OK);
    if (rc != REFRACT_E_OK)
        fprintf(stderr, "render: %s\n", refract_errmsg(d->client));
    return rc == REFRACT_E_OK;
}

static void uploaded_environment_is_the_background(struct test_daemon *d, char *env_id)
{
    CHECK(test_create_scene(d, env_scene, env_id));
    if (!upload_sky(d, env_id))
        return;
    struct refract_image img;
    if (!render_exr(d, env_id, &img))
        return;
    struct io_image pic = {0};
    struct err e = {0};
    CHECK_INT(io_image_decode(img.bytes, img.len, 1 << 20, &pic, &e), REFRACT_E_OK);
    int up = 0, down = 0, wrong = 0;
    for (int row = 0; row < pic.height; row++)
        for (int col = 0; col < pic.width; col++) {
            vec3 o, dir;
            camera_ray((vec3){0, 0, 4}, (vec3){0, 0, 0}, (vec3){0, 1, 0}, 60, pic.width, pic.height,
                       col, row, &o, &dir);
            double elevation = asin(dir.y) * 180.0 / M_PI;
            if (fabs(elevation) < 8.0) /* texels are 5.6 degrees tall: the seam filters */
                continue;
            const float *want = elevation > 0 ? top_rgb : bottom_rgb;
            const float *got = &pic.rgba[(row * pic.width + col) * 4];
            bool ok = true;
            for (int k = 0; k < 3; k++)
                ok = ok && fabs(got[k] - 2.0 * want[k]) < 1e-3 * 2.0 * want[k] + 1e-6;
            if (!ok && wrong++ < 3)
                fprintf(stderr,
                        "  pixel (%d, %d), elevation %.1f: got (%g %g %g), want 2 x "
                        "(%g %g %g)\n",
                        col, row, elevation, got[0], got[1], got[2], want[0], want[1], want[2]);
            *(elevation > 0 ? &up : &down) += 1;
        }
    printf("uploaded environment: %d pixels above the horizon, %d below, %d wrong\n", up, down,
           wrong);
    CHECK(up > 200 && down > 200);
    CHECK_INT(wrong, 0);
    io_image_free(&pic);
    refract_image_free(&img);
}

static void everything_is_back_after_a_restart(struct test_daemon *d, const char *vol_id,
                                               const char *abs_id, const char *env_id)
{
    struct refract_image before;
    cJSON *trace_before = trace(d, vol_id, rays_request);
    bool rendered = render_exr(d, env_id, &before);
    CHECK_INT(test_daemon_stop(d), 0);
    if (!rendered) {
        cJSON_Delete(trace_before);
        return;
    }
    char data_dir[sizeof d->data_dir];
    snprintf(data_dir, sizeof data_dir, "%s", d->data_dir);
    struct test_daemon again;
    if (!test_daemon_start_in(&again, data_dir, NULL)) {
        fprintf(stderr, "restart failed: %s\n", again.why);
        CHECK(false);
        refract_image_free(&before);
        cJSON_Delete(trace_before);
        return;
    }
    char *list = NULL;
    CHECK_INT(refract_scene_list(again.client, &list), REFRACT_E_OK);
    CHECK_CONTAINS(list, vol_id);
    CHECK_CONTAINS(list, abs_id);
    CHECK_CONTAINS(list, env_id);
    refract_free(list);
    struct refract_image after;
    if (render_exr(&again, env_id, &after)) {
        CHECK(after.len == before.len && memcmp(after.bytes, before.bytes, before.len) == 0);
        refract_image_free(&after);
    }
    cJSON *trace_after = trace(&again, vol_id, rays_request);
    cJSON_DeleteItemFromObjectCaseSensitive(trace_before, "gpu_ms"); /* timing differs */
    cJSON_DeleteItemFromObjectCaseSensitive(trace_after, "gpu_ms");
    char *x = cJSON_PrintUnformatted(trace_before), *y = cJSON_PrintUnformatted(trace_after);
    CHECK_STR(y ? y : "", x ? x : "(none)");
    free(x);
    free(y);
    cJSON_Delete(trace_before);
    cJSON_Delete(trace_after);
    refract_image_free(&before);
    CHECK_INT(test_daemon_stop(&again), 0);
    test_daemon_cleanup(&again);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_uploads", d.why);
    char vol_id[REFRACT_ID_SIZE] = "", abs_id[REFRACT_ID_SIZE] = "", env_id[REFRACT_ID_SIZE] = "";
    uploaded_ior_traces_like_the_profile(&d, vol_id);
    uploaded_attenuation_follows_beer_lambert(&d, abs_id);
    uploaded_environment_is_the_background(&d, env_id);
    everything_is_back_after_a_restart(&d, vol_id, abs_id, env_id); /* stops d */
    test_daemon_cleanup(&d);
    return test_summary("test_uploads");
}
