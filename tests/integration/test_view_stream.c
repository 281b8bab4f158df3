/*
 * test_view_stream.c - view sessions and their MJPEG frame streams through a real refractd
 * (docs/views.md), read from a raw socket:
 *   - a stream is multipart/x-mixed-replace; every part is a JPEG that decodes to the
 *     session's size, with X-Frame-Seq growing;
 *   - a PATCH of the camera makes a next frame whose pixels differ; of the exposure, a
 *     brighter one;
 *   - progressive: the first frame after a change is a half-size preview when full frames
 *     take over 20 ms, and the full frame follows; without progressive, no previews;
 *   - nothing changes (a PATCH to the values it has included) -> no new frame within 2 s,
 *     and the status' seq stays;
 *   - 8 viewers of one scene (two sessions) plus viewers of another scene all get frames;
 *   - ?frames=2 ends the stream after two frames;
 *   - DELETE ends the open streams, and the session answers 404 afterwards.
 */
#include <math.h>

#include "io/io_image.h"
#include "view_util.h"

#define W 64
#define H 48

static bool decode(const struct mjpeg_frame *f, struct io_image *out)
{
    struct err e = {0};
    if (io_image_decode(f->jpeg, f->len, 1 << 24, out, &e) != REFRACT_E_OK) {
        fprintf(stderr, "frame %lld: %s\n", f->seq, e.msg);
        return false;
    }
    return true;
}

static double mean_abs_difference(const struct io_image *a, const struct io_image *b)
{
    double sum = 0;
    size_t n = (size_t)a->width * (size_t)a->height * 4;
    for (size_t i = 0; i < n; i++)
        sum += fabs(a->rgba[i] - b->rgba[i]);
    return sum / (double)n;
}

static double mean_value(const struct io_image *a)
{
    double sum = 0;
    size_t n = (size_t)a->width * (size_t)a->height;
    for (size_t i = 0; i < n; i++)
        sum += a->rgba[i * 4] + a->rgba[i * 4 + 1] + a->rgba[i * 4 + 2];
    return sum / (3.0 * (double)n);
}

static void frames_follow_patches(struct test_daemon *d, const char *scene)
{
    char vid[32];
    CHECK_INT(
        view_open(d, scene, "{\"width\": 64, \"height\": 48, \"progressive\": false}", vid, NULL),
        201);
    CHECK_INT(strlen(vid), 17);
    CHECK(vid[0] == 'v' && strspn(vid + 1, "0123456789abcdef") == 16);
    struct mjpeg_stream s;
    CHECK_INT(mjpeg_open(d, vid, 0, &s), 200);
    CHECK(strcmp(s.content_type, "multipart/x-mixed-replace; boundary=refract-frame") == 0);

    struct mjpeg_frame f1, f2, f3;
    struct io_image i1 = {0}, i2 = {0}, i3 = {0};
    CHECK_INT(mjpeg_next(&s, &f1, 30000), 1);
    CHECK(decode(&f1, &i1));
    CHECK_INT(i1.width, W);
    CHECK_INT(i1.height, H);
    CHECK(strcmp(f1.kind, "full") == 0);
    CHECK(strcmp(f1.irradiance, "not-needed") == 0);

    /* Orbit: the sphere moves in the picture. */
    CHECK_INT(view_patch(d, vid, "{\"camera\": {\"eye\": [0.6, 0.3, 3.9]}}"), 200);
    CHECK_INT(mjpeg_next_full(&s, &f2, f1.seq, 30000), 1);
    CHECK(decode(&f2, &i2) && i2.width == W);
    CHECK(f2.seq > f1.seq);
    double diff = i2.rgba ? mean_abs_difference(&i1, &i2) : 0;
    CHECK_MSG(diff > 1e-3, "mean |frame 2 - frame 1| = %g: the camera PATCH changed nothing", diff);

    /* One stop brighter: mean value grows (clamped pixels aside). */
    CHECK_INT(view_patch(d, vid, "{\"exposure\": 1.0}"), 200);
    CHECK_INT(mjpeg_next_full(&s, &f3, f2.seq, 30000), 1);
    CHECK(decode(&f3, &i3) && i3.width == W);
    double m2 = i2.rgba ? mean_value(&i2) : 0, m3 = i3.rgba ? mean_value(&i3) : 0;
    CHECK_MSG(m3 > m2 * 1.2, "mean %g after +1 EV, %g before", m3, m2);

    /* Once the stream is quiet, the newest frame comes once more (marked as a repeat) so
     * that a browser's plain <img> shows it; then nothing. */
    struct mjpeg_frame extra;
    CHECK_INT(mjpeg_next_part(&s, &extra, 3000), 1);
    CHECK(extra.repeat);
    CHECK(extra.seq == f3.seq);
    CHECK(extra.len == f3.len && extra.jpeg && memcmp(extra.jpeg, f3.jpeg, f3.len) == 0);
    free(extra.jpeg);

    /* Nothing changes: nothing is sent (not even a repeat), and the seq stays. */
    double seq_before = view_wait_seq(d, vid, (double)f3.seq, 10000);
    CHECK_INT(view_patch(d, vid, "{\"exposure\": 1.0}"), 200); /* the value it has */
    CHECK_INT(mjpeg_next_part(&s, &extra, 2500), 0);
    cJSON *st = view_status(d, vid);
    CHECK(view_status_seq(st) == seq_before);
    const cJSON *streams = cJSON_GetObjectItemCaseSensitive(st, "streams");
    CHECK(cJSON_IsNumber(streams) && streams->valueint == 1);
    cJSON_Delete(st);

    /* ?frames=2: two frames (the newest, then the next), then the body ends. */
    char snap[128];
    snprintf(snap, sizeof snap, "/v1/views/%s/stream?frames=2", vid);
    struct mjpeg_stream two;
    CHECK(mjpeg_connect(d, snap, 0, &two) && mjpeg_read_head(&two, 10000) == 200);
    CHECK_INT(mjpeg_next(&two, &extra, 10000), 1);
    free(extra.jpeg);
    CHECK_INT(view_patch(d, vid, "{\"exposure\": 0.5}"), 200);
    CHECK_INT(mjpeg_next(&two, &extra, 30000), 1);
    free(extra.jpeg);
    CHECK_INT(mjpeg_next(&two, &extra, 10000), -1);
    CHECK(two.eof);
    mjpeg_close(&two);

    /* DELETE ends the stream; the session is gone. */
    char path[96], *body = NULL;
    snprintf(path, sizeof path, "/v1/views/%s", vid);
    CHECK_INT(test_request(d, "DELETE", path, NULL, &body), 204);
    free(body);
    int rc_end = 1; /* a frame made before the DELETE may still come first */
    for (int i = 0; i < 3 && rc_end == 1; i++) {
        rc_end = mjpeg_next(&s, &extra, 5000);
        if (rc_end == 1)
            free(extra.jpeg);
    }
    CHECK_INT(rc_end, -1);
    CHECK(s.eof);
    CHECK_INT(test_request(d, "GET", path, NULL, &body), 404);
    CHECK(test_error_is(body, "not_found", vid));
    free(body);
    mjpeg_close(&s);
    free(f1.jpeg);
    free(f2.jpeg);
    free(f3.jpeg);
    io_image_free(&i1);
    io_image_free(&i2);
    io_image_free(&i3);
}

/* Counts the preview and full frames that follow one PATCH, until the full one. */
static void frames_after_patch(struct test_daemon *d, const char *vid, struct mjpeg_stream *s,
                               const char *patch, long long after, int *previews, int *fulls,
                               int *preview_width)
{
    *previews = *fulls = 0;
    CHECK_INT(view_patch(d, vid, patch), 200);
    for (int guard = 0; guard < 20 && *fulls == 0; guard++) {
        struct mjpeg_frame f;
        if (mjpeg_next(s, &f, 30000) != 1)
            break;
        struct io_image img = {0};
        if (f.seq > after && decode(&f, &img)) {
            if (strcmp(f.kind, "preview") == 0) {
                (*previews)++;
                *preview_width = img.width;
            } else {
                (*fulls)++;
            }
        }
        io_image_free(&img);
        free(f.jpeg);
    }
}

static void progressive_previews(struct test_daemon *d, const char *scene)
{
    /* 256x192 full frames take longer than 20 ms on llvmpipe and on most GPUs' first
     * frames; the preview rule is checked against the render time the status reports. */
    char vid[32];
    CHECK_INT(view_open(d, scene, "{\"width\": 256, \"height\": 192, \"max_fps\": 120}", vid, NULL),
              201);
    struct mjpeg_stream s;
    CHECK_INT(mjpeg_open(d, vid, 0, &s), 200);
    struct mjpeg_frame first;
    CHECK_INT(mjpeg_next_full(&s, &first, 0, 30000), 1);
    free(first.jpeg);
    double seq = view_wait_seq(d, vid, (double)first.seq, 10000);
    cJSON *st = view_status(d, vid);
    const cJSON *ms =
        cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItem(st, "frame"), "render_ms");
    double render_ms = cJSON_IsNumber(ms) ? ms->valuedouble : 0;
    cJSON_Delete(st);
    int previews = 0, fulls = 0, width = 0;
    frames_after_patch(d, vid, &s, "{\"camera\": {\"fov_y_deg\": 35}}", (long long)seq, &previews,
                       &fulls, &width);
    CHECK_INT(fulls, 1);
    if (render_ms > 20.0) {
        CHECK_INT(previews, 1);
        CHECK_INT(width, 128);
    } else {
        printf("  full frames took %.1f ms (<= 20): no preview expected\n", render_ms);
        CHECK_INT(previews, 0);
    }
    seq = view_wait_seq(d, vid, seq + 1, 10000);
    frames_after_patch(d, vid, &s, "{\"progressive\": false, \"camera\": {\"fov_y_deg\": 38}}",
                       (long long)seq, &previews, &fulls, &width);
    CHECK_INT(fulls, 1);
    CHECK_INT(previews, 0);
    mjpeg_close(&s);
}

static void many_viewers(struct test_daemon *d, const char *scene_a, const char *scene_b)
{
    enum { SESSIONS = 3, STREAMS = 10 };
    char vids[SESSIONS][32];
    /* Two sessions of scene A (4 streams each: 8 viewers), one of scene B (2 streams). */
    const char *scenes[SESSIONS] = {scene_a, scene_a, scene_b};
    const int owner[STREAMS] = {0, 0, 0, 0, 1, 1, 1, 1, 2, 2};
    for (int i = 0; i < SESSIONS; i++)
        CHECK_INT(view_open(d, scenes[i], "{\"width\": 64, \"height\": 48}", vids[i], NULL), 201);
    struct mjpeg_stream s[STREAMS];
    long long seen[STREAMS] = {0};
    for (int i = 0; i < STREAMS; i++)
        CHECK_INT(mjpeg_open(d, vids[owner[i]], 0, &s[i]), 200);
    for (int i = 0; i < STREAMS; i++) {
        struct mjpeg_frame f;
        CHECK_INT(mjpeg_next_full(&s[i], &f, 0, 30000), 1);
        seen[i] = f.seq;
        free(f.jpeg);
    }
    for (int i = 0; i < SESSIONS; i++) {
        cJSON *st = view_status(d, vids[i]);
        const cJSON *n = cJSON_GetObjectItemCaseSensitive(st, "streams");
        CHECK(cJSON_IsNumber(n) && n->valueint == (i < 2 ? 4 : 2));
        cJSON_Delete(st);
        CHECK_INT(view_patch(d, vids[i], "{\"camera\": {\"eye\": [0.5, 0.5, 3.9]}}"), 200);
    }
    int got = 0;
    for (int i = 0; i < STREAMS; i++) {
        struct mjpeg_frame f;
        int rc = mjpeg_next_full(&s[i], &f, seen[i], 30000);
        CHECK_MSG(rc == 1, "stream %d (session %d) got no frame after the PATCH", i, owner[i]);
        got += rc == 1;
        if (rc == 1)
            free(f.jpeg);
        mjpeg_close(&s[i]);
    }
    CHECK_INT(got, STREAMS);
    for (int i = 0; i < SESSIONS; i++) {
        char path[128], *body = NULL;
        snprintf(path, sizeof path, "/v1/views/%s", vids[i]);
        CHECK_INT(test_request(d, "DELETE", path, NULL, &body), 204);
        free(body);
    }
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_view_stream", d.why);
    char scene_a[REFRACT_ID_SIZE], scene_b[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, view_sphere_scene, scene_a));
    CHECK(test_create_scene(&d, view_sphere_scene, scene_b));
    frames_follow_patches(&d, scene_a);
    progressive_previews(&d, scene_a);
    many_viewers(&d, scene_a, scene_b);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_view_stream");
}
