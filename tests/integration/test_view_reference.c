/*
 * test_view_reference.c - a view session in reference mode through a real refractd
 * (docs/views.md "Reference mode"):
 *
 *   - "mode": "reference" refines while the view is open: several frames, each with more
 *     paths per pixel ("samples_done" grows), until the target; then the session is idle;
 *   - the last frame is byte for byte the JPEG of POST .../render with "mode": "reference",
 *     the same samples and the same tone mapping and quality (the path tracer's streams do
 *     not depend on how the samples were sliced into frames);
 *   - a camera change starts a new image (samples_done falls back, then reaches the target
 *     again); "samples" past --max-reference-samples and an unknown mode are 400s.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon.h"
#include "test.h"
#include "view_util.h"

static const char *const scene_doc =
    "{\"name\": \"reference view\", \"camera\": {\"eye\": [0, 1.5, 4], \"look_at\": [0, -0.4, "
    "0], \"fov_y_deg\": 45, \"width\": 64, \"height\": 48}, \"environment\": {\"intensity\": "
    "0.2}, \"lights\": [{\"type\": \"point\", \"position\": [1, 4, 1], \"intensity\": 30, "
    "\"radius\": 0.1}], \"receiver\": {\"height\": -1, \"half_size\": \"infinite\"}, "
    "\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 0.6, \"medium\": {\"ior\": 1.5}}]}";

static double samples_done(struct test_daemon *d, const char *vid)
{
    cJSON *st = view_status(d, vid);
    const cJSON *n = cJSON_GetObjectItemCaseSensitive(st, "samples_done");
    double v = cJSON_IsNumber(n) ? n->valuedouble : -1;
    cJSON_Delete(st);
    return v;
}

int main(void)
{
    const char *args[] = {"--max-reference-samples", "4096", NULL};
    struct test_daemon d;
    if (!test_daemon_start(&d, args))
        test_setup_failed("test_view_reference", d.why);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, scene_doc, id));
    char vid[32];
    CHECK_INT(view_open(&d, id, "{\"mode\": \"reference\", \"samples\": 384, \"max_fps\": 60}", vid,
                        NULL),
              201);
    struct mjpeg_stream ms;
    CHECK_INT(mjpeg_open(&d, vid, 0, &ms), 200);
    /* Frames until the target: each with more paths per pixel. */
    struct mjpeg_frame f = {0}, last = {0};
    int frames = 0;
    double done = 0;
    for (int i = 0; i < 400 && done < 384; i++) {
        if (mjpeg_next(&ms, &f, 30000) != 1)
            break;
        frames++;
        free(last.jpeg);
        last = f;
        double now = samples_done(&d, vid);
        CHECK_MSG(now >= done, "samples_done went from %.0f to %.0f", done, now);
        done = now;
    }
    double seq = view_wait_seq(&d, vid, (double)last.seq, 60000); /* idle at the target */
    cJSON *st = view_status(&d, vid);
    CHECK_STR(cJSON_GetObjectItemCaseSensitive(st, "state")->valuestring, "idle");
    CHECK_STR(cJSON_GetObjectItemCaseSensitive(st, "mode")->valuestring, "reference");
    cJSON_Delete(st);
    printf("reference view: %d frames to 384 paths per pixel (newest seq %.0f)\n", frames, seq);
    CHECK_MSG(frames >= 2, "only %d frame(s): nothing was refined", frames);
    CHECK_NEAR(samples_done(&d, vid), 384, 0);
    /* Frames after the target repeat it (keep-alives); read any to get the newest. */
    struct mjpeg_frame more;
    while (mjpeg_next(&ms, &more, 500) == 1) {
        free(last.jpeg);
        last = more;
    }

    /* The same picture as a reference render request: byte for byte. */
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    struct refract_response r;
    const char body[] = "{\"mode\": \"reference\", \"samples\": 384, \"format\": \"jpeg\", "
                        "\"jpeg_quality\": 80}";
    CHECK_INT(refract_request(d.client, "POST", path, body, strlen(body), "application/json", &r),
              0);
    CHECK_INT((int)r.status, 200);
    CHECK_MSG(r.body_len == last.len && last.jpeg && memcmp(r.body, last.jpeg, last.len) == 0,
              "the view's last frame (%zu bytes) is not the render's JPEG (%zu bytes)", last.len,
              r.body_len);
    refract_response_free(&r);
    free(last.jpeg);

    /* A new camera: a new image, refined again. */
    CHECK_INT(view_patch(&d, vid, "{\"camera\": {\"eye\": [2, 2, 3]}}"), 200);
    bool restarted = false;
    for (int i = 0; i < 2000 && !restarted; i++) {
        double n = samples_done(&d, vid);
        restarted = n >= 0 && n < 384;
        view_sleep_ms(2);
    }
    double now = view_now_ms();
    while (samples_done(&d, vid) < 384 && view_now_ms() < now + 60000)
        view_sleep_ms(20);
    CHECK_NEAR(samples_done(&d, vid), 384, 0);
    printf("after a camera change: restarted %s, back at 384\n", restarted ? "seen" : "not seen");
    mjpeg_close(&ms);

    /* Refusals. */
    char *reply = NULL;
    char vpath[96];
    snprintf(vpath, sizeof vpath, "/v1/views/%s", vid);
    long status = test_request(&d, "PATCH", vpath, "{\"samples\": 5000}", &reply);
    CHECK_MSG(status == 400 && reply && strstr(reply, "samples"), "%ld %s", status,
              reply ? reply : "");
    free(reply);
    reply = NULL;
    status = test_request(&d, "PATCH", vpath, "{\"mode\": \"slow\"}", &reply);
    CHECK_MSG(status == 400 && reply && strstr(reply, "mode"), "%ld %s", status,
              reply ? reply : "");
    free(reply);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_view_reference");
}
