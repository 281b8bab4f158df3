/*
 * test_jobs_light_sweep.c - a light_path job on smoke_spot (its spot light needs the light
 * simulation): the job moves the spot's direction from [0,-1,0] to [0.3,-1,0] in 3 frames
 * (directions slerped). Every frame is lit: frame i equals, within 8-bit rounding, a single
 * render of the scene with the spot set to that direction once that pose's volume is ready
 * (the middle one is the closed form normalize(a + b), independent of the job's slerp).
 * The frames differ (the light moved), and the scene's own light is unchanged by the job.
 * A frame list's per-frame "lights" change to the last pose gives the sweep's last frame.
 */
#include <math.h>

#include "jobs_util.h"

#define W 48
#define H 36

static void render_with_direction(struct test_daemon *d, const char *scene, const double dir[3],
                                  struct io_image *out)
{
    char path[128], body[256], *answer = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s/lights/spot", scene);
    snprintf(body, sizeof body,
             "{\"type\": \"spot\", \"position\": [0, 3, 0], \"direction\": [%.17g, %.17g, %.17g],"
             " \"angle_deg\": 12, \"intensity\": 40}",
             dir[0], dir[1], dir[2]);
    long status = test_request(d, "PUT", path, body, &answer);
    CHECK_MSG(status == 200 || status == 202, "PUT light: %ld %s", status, answer ? answer : "");
    free(answer);
    char req[64];
    snprintf(req, sizeof req, "{\"width\": %d, \"height\": %d}", W, H);
    struct refract_image img = {0};
    for (int i = 0; i < 600; i++) {
        refract_image_free(&img);
        if (refract_render(d->client, scene, req, &img) != 0 || !strcmp(img.irradiance, "ready"))
            break;
        job_sleep_ms(100);
    }
    CHECK_STR(img.irradiance, "ready");
    struct err e = {0};
    CHECK(io_image_decode(img.bytes, img.len, 1 << 20, out, &e) == REFRACT_E_OK);
    refract_image_free(&img);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_jobs_light_sweep", d.why);
    size_t len = 0;
    char *doc = test_read_source_file("proto/examples/smoke_spot.json", &len);
    char scene[REFRACT_ID_SIZE] = "", spec[512], id[64] = "";
    if (!doc || !test_create_scene(&d, doc, scene))
        test_setup_failed("test_jobs_light_sweep", "could not create the scene");
    free(doc);
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"width\": %d, \"height\": %d, \"light_path\": {\"light\": "
             "\"spot\", \"frames\": 3, \"keyframes\": [{\"direction\": [0, -1, 0]}, "
             "{\"direction\": [0.3, -1, 0]}]}}",
             scene, W, H);
    CHECK(job_submit_json(&d, spec, id));
    cJSON *st = job_wait(&d, id, 240);
    CHECK_STR(job_str(st, "state"), "done");
    CHECK_INT(job_int(st, "frames_done"), 3);
    cJSON_Delete(st);

    /* The scene's own light did not move. */
    char path[128], *body = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s/lights", scene);
    CHECK_INT(test_request(&d, "GET", path, NULL, &body), 200);
    CHECK_CONTAINS(body, "\"direction\":[0,-1,0]");
    free(body);

    double b_len = sqrt(0.3 * 0.3 + 1.0);
    double a[3] = {0, -1, 0}, b[3] = {0.3 / b_len, -1 / b_len, 0};
    double mid[3] = {a[0] + b[0], a[1] + b[1], 0};
    double m_len = sqrt(mid[0] * mid[0] + mid[1] * mid[1]);
    mid[0] /= m_len;
    mid[1] /= m_len;
    const double *dirs[3] = {a, mid, b};
    struct io_image frames[3] = {0};
    for (int n = 0; n < 3; n++) {
        CHECK_MSG(job_frame_image(&d, id, n, W, H, &frames[n]), "frame %d", n);
        struct io_image ref = {0};
        render_with_direction(&d, scene, dirs[n], &ref);
        if (frames[n].rgba && ref.rgba && ref.width == W && ref.height == H) {
            double diff = job_image_max_diff(&frames[n], &ref);
            /* One 8-bit step of sRGB near white is < 0.01 in linear. */
            CHECK_MSG(diff < 0.01, "frame %d differs from the lit render by %g", n, diff);
        }
        io_image_free(&ref);
    }
    /* A frame list's per-frame light change to the last pose renders that pose (a cache hit
     * now): the same image as the sweep's last frame. */
    char list_id[64] = "";
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"width\": %d, \"height\": %d, \"frames\": [{\"lights\": "
             "[{\"name\": \"spot\", \"direction\": [0.3, -1, 0]}]}]}",
             scene, W, H);
    CHECK(job_submit_json(&d, spec, list_id));
    st = job_wait(&d, list_id, 120);
    CHECK_STR(job_str(st, "state"), "done");
    cJSON_Delete(st);
    struct io_image moved = {0};
    CHECK(job_frame_image(&d, list_id, 0, W, H, &moved));
    if (moved.rgba && frames[2].rgba)
        CHECK_MSG(job_image_max_diff(&moved, &frames[2]) < 1e-6,
                  "a frame's light change differs from the light path's same pose");
    io_image_free(&moved);
    if (frames[0].rgba && frames[2].rgba)
        CHECK_MSG(job_image_max_diff(&frames[0], &frames[2]) > 0.02,
                  "the first and last frames are alike: the light did not move");
    for (int n = 0; n < 3; n++)
        io_image_free(&frames[n]);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_jobs_light_sweep");
}
