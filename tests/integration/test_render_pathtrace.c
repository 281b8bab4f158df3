/*
 * test_render_pathtrace.c - "mode": "reference" renders through a real refractd: the CPU
 * path tracer (docs/pathtracer.md) answers linear EXR with variance channels and reads the
 * closed-form check value of scene A's floor (/work/shared/peer-scenes SCENES.md: 0.264553
 * at pixel (32.6, 199.5) with the ball removed, +-1 %), and so does the fast renderer once
 * the light simulation is done (issue 14 item 4: the infinite floor, lit by the light's
 * closed form beyond the ball's footprint); a time budget ends a render early;
 * PNG comes back tone-mapped; bad requests get the exact error (the limit flag named,
 * unknown keys, what the path tracer cannot render yet).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "daemon.h"
#include "io/io_exr.h"
#include "irradiance_util.h"
#include "test.h"

/* Scene A's camera, light and infinite floor; a small glass ball far from the check
 * point's view and shadow rays (the scene format needs no ball, it keeps a surface in the
 * path). A receiver makes refractd compute the fast renderer's light simulation in the
 * background; its grid covers the ball's footprint on the floor (docs/lightsim.md
 * "Domain"), at a coarse resolution so that it takes seconds on llvmpipe. */
static const char *const floor_scene =
    "{\"name\": \"peer floor\", \"camera\": {\"eye\": [0, 2.5, 7], \"look_at\": [0, -0.5, 0], "
    "\"up\": [0, 1, 0], \"fov_y_deg\": 35, \"width\": 320, \"height\": 240}, "
    "\"environment\": {\"type\": \"procedural\", \"intensity\": 0}, "
    "\"lights\": [{\"type\": \"point\", \"position\": [2, 6, 1], \"intensity\": 79.5775}], "
    "\"receiver\": {\"height\": -1, \"half_size\": \"infinite\", \"albedo\": 0.8}, "
    "\"lightsim\": {\"resolution\": 16, \"initial_patches\": 8}, "
    "\"surfaces\": [{\"name\": \"ball\", \"shape\": \"sphere\", \"center\": [2, -0.5, -2], "
    "\"radius\": 0.5, \"medium\": {\"ior\": 1.5}}]}";

static const char *const voxel_scene =
    "{\"name\": \"voxels\", \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, "
    "1]}, \"resolution\": 8, \"ior\": 1.2}]}";

static void floor_reads_the_scene_a_check_value(struct test_daemon *d, const char *id)
{
    struct refract_image img = {0};
    int rc = refract_render(d->client, id,
                            "{\"mode\": \"reference\", \"samples\": 8, \"format\": \"exr\"}", &img);
    CHECK_MSG(rc == REFRACT_E_OK, "%s", refract_errmsg(d->client));
    if (rc != REFRACT_E_OK)
        return;
    CHECK_STR(img.content_type, "image/x-exr");
    static const char *const names[] = {"R", "G", "B", "variance.G"};
    float *px = NULL;
    int w = 0, h = 0;
    struct err e = {0};
    CHECK(io_decode_exr_channels(img.bytes, img.len, 4, names, 1 << 20, &px, &w, &h, NULL, NULL, 0,
                                 &e) == REFRACT_E_OK);
    refract_image_free(&img);
    if (px == NULL)
        return;
    CHECK_INT(w, 320);
    CHECK_INT(h, 240);
    /* The 3 x 3 pixels about (32.6, 199.5), as the peers measured. */
    double sum = 0.0, var = 0.0;
    for (int y = 198; y <= 200; y++)
        for (int x = 31; x <= 33; x++) {
            sum += px[4 * (y * w + x) + 1];
            var += px[4 * (y * w + x) + 3];
            CHECK(px[4 * (y * w + x) + 3] >= 0.0f);
        }
    CHECK_NEAR(sum / 9.0, 0.264553, 0.01 * 0.264553);
    /* the noise estimate: the footprint's spread over 8 samples, well under 1 % here */
    CHECK(sqrt(var) / 9.0 < 0.01 * 0.264553);
    CHECK(var > 0.0);
    free(px);
}

/* The fast renderer (GLSL light_receiver, light_direct beyond the ball's footprint) reads
 * the same check value once the irradiance volume is ready. */
static void fast_renderer_reads_the_check_value(struct test_daemon *d, const char *id)
{
    cJSON *st = irr_wait_ready(d, id, 300.0);
    cJSON_Delete(st);
    struct refract_image img = {0};
    int rc = refract_render(d->client, id, "{\"format\": \"exr\"}", &img);
    CHECK_MSG(rc == REFRACT_E_OK, "%s", refract_errmsg(d->client));
    if (rc != REFRACT_E_OK)
        return;
    static const char *const names[] = {"R", "G", "B"};
    float *px = NULL;
    int w = 0, h = 0;
    struct err e = {0};
    CHECK(io_decode_exr_channels(img.bytes, img.len, 3, names, 1 << 20, &px, &w, &h, NULL, NULL, 0,
                                 &e) == REFRACT_E_OK);
    refract_image_free(&img);
    if (px == NULL)
        return;
    double sum = 0.0;
    for (int y = 198; y <= 200; y++)
        for (int x = 31; x <= 33; x++)
            sum += px[3 * (y * w + x) + 1];
    printf("fast renderer: the floor's 3 x 3 pixels about (32.6, 199.5) read %.6f (0.264553)\n",
           sum / 9.0);
    CHECK_NEAR(sum / 9.0, 0.264553, 0.01 * 0.264553);
    free(px);
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void time_budget_ends_the_render(struct test_daemon *d, const char *id)
{
    struct refract_image img = {0};
    double t0 = now_s();
    int rc = refract_render(d->client, id,
                            "{\"mode\": \"reference\", \"time_budget_ms\": 300, \"width\": 64, "
                            "\"height\": 48}",
                            &img);
    double dt = now_s() - t0;
    CHECK_MSG(rc == REFRACT_E_OK, "%s", refract_errmsg(d->client));
    CHECK_MSG(dt < 5.0, "took %.1f s with a budget of 0.3 s", dt);
    CHECK_STR(img.content_type, "image/png");
    CHECK(img.len > 8 && memcmp(img.bytes, "\x89PNG", 4) == 0);
    refract_image_free(&img);
}

static void bad_requests_get_exact_errors(struct test_daemon *d, const char *id)
{
    char path[128], *body = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    long st = test_request(d, "POST", path, "{\"mode\": \"reference\", \"samples\": 0}", &body);
    CHECK(st == 400 && test_error_is(body, "invalid_field", "samples"));
    free(body);
    st = test_request(d, "POST", path, "{\"mode\": \"reference\", \"samples\": 5000}", &body);
    CHECK_MSG(st == 400 && test_error_is(body, "invalid_field", "--max-reference-samples"), "%s",
              body ? body : "");
    free(body);
    st = test_request(d, "POST", path, "{\"mode\": \"reference\", \"stepper\": \"rk4\"}", &body);
    CHECK(st == 400 && test_error_is(body, "unknown_field", "stepper"));
    free(body);
    st = test_request(d, "POST", path, "{\"mode\": \"reference\", \"seed\": 1.5}", &body);
    CHECK(st == 400 && test_error_is(body, "invalid_field", "seed"));
    free(body);
    st = test_request(d, "POST", path, "{\"mode\": \"bogus\"}", &body);
    CHECK(st == 400 && test_error_is(body, "invalid_field", "mode"));
    free(body);
    char vid[REFRACT_ID_SIZE];
    CHECK(test_create_scene(d, voxel_scene, vid));
    snprintf(path, sizeof path, "/v1/scenes/%s/render", vid);
    st = test_request(d, "POST", path, "{\"mode\": \"reference\"}", &body);
    CHECK(st == 409 && test_error_is(body, "conflict", "volume object"));
    free(body);
    /* "fast", the default, goes on to the fast renderer's parser (which rejects the width
     * here, so no GPU render is waited for) */
    st = test_request(d, "POST", path, "{\"mode\": \"fast\", \"width\": 0}", &body);
    CHECK(st == 400 && test_error_is(body, "invalid_field", "width"));
    free(body);
}

int main(void)
{
    struct test_daemon d;
    const char *args[] = {"--max-reference-samples", "1000", NULL};
    if (!test_daemon_start(&d, args))
        test_setup_failed("test_render_pathtrace", d.why);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, floor_scene, id));
    floor_reads_the_scene_a_check_value(&d, id);
    fast_renderer_reads_the_check_value(&d, id);
    time_budget_ends_the_render(&d, id);
    bad_requests_get_exact_errors(&d, id);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_render_pathtrace");
}
