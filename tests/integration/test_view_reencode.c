/*
 * test_view_reencode.c - exposure, tonemap and jpeg_quality changes of a view session are
 * encoded again from the newest full frame's linear image, not rendered (docs/views.md
 * "Frames: when and how"):
 *   - PATCH exposure: the next frame is "reencoded" (frames.rendered unchanged,
 *     frames.reencoded + 1), different from before, and byte-equal to the full frame a
 *     fresh session rendered with that exposure;
 *   - PATCH tonemap, then jpeg_quality: reencoded again, each different from the last;
 *   - PATCH camera, and PATCH camera + exposure together: rendered (reencoded false);
 *   - a frame drawn in tiles (a daemon with --render-tile-pixels 200: 16 tiles of 3 rows,
 *     other work free to run between them) is byte-equal to the frame drawn at once.
 */
#include "view_util.h"

static const char *const sized = "{\"width\": 64, \"height\": 48, \"progressive\": false";

static double counter(const cJSON *st, const char *name)
{
    const cJSON *frames = cJSON_GetObjectItemCaseSensitive(st, "frames");
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(frames, name);
    return cJSON_IsNumber(v) ? v->valuedouble : -1;
}

static bool frame_reencoded(const cJSON *st)
{
    const cJSON *frame = cJSON_GetObjectItemCaseSensitive(st, "frame");
    return cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(frame, "reencoded"));
}

/* Waits for seq >= at_least, then checks the counters and the newest frame's flag. */
static void expect_frame(struct test_daemon *d, const char *vid, double at_least, double rendered,
                         double reencoded, bool is_reencoded)
{
    CHECK(view_wait_seq(d, vid, at_least, 20000) >= at_least);
    cJSON *st = view_status(d, vid);
    CHECK_NEAR(counter(st, "rendered"), rendered, 0);
    CHECK_NEAR(counter(st, "reencoded"), reencoded, 0);
    CHECK(frame_reencoded(st) == is_reencoded);
    cJSON_Delete(st);
}

/* The next full frame after seq `after` from the stream. */
static struct mjpeg_frame next_full(struct mjpeg_stream *s, long long after)
{
    struct mjpeg_frame f = {0};
    CHECK_INT(mjpeg_next_full(s, &f, after, 20000), 1);
    return f;
}

static bool same_bytes(const struct mjpeg_frame *a, const struct mjpeg_frame *b)
{
    return a->jpeg && b->jpeg && a->len == b->len && memcmp(a->jpeg, b->jpeg, a->len) == 0;
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_view_reencode", d.why);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, view_sphere_scene, id));
    char body[256], va[32] = "", vb[32] = "";
    snprintf(body, sizeof body, "%s, \"exposure\": 0}", sized);
    CHECK_INT(view_open(&d, id, body, va, NULL), 201);
    expect_frame(&d, va, 1, 1, 0, false);
    struct mjpeg_stream sa;
    CHECK_INT(mjpeg_open(&d, va, 0, &sa), 200);
    struct mjpeg_frame f1 = next_full(&sa, 0);

    /* Exposure: encoded again, not rendered. */
    CHECK_INT(view_patch(&d, va, "{\"exposure\": 1.5}"), 200);
    struct mjpeg_frame f2 = next_full(&sa, f1.seq);
    expect_frame(&d, va, 2, 1, 1, true);
    CHECK(!same_bytes(&f1, &f2));

    /* The same frame rendered from scratch by a session that starts at +1.5 EV. */
    snprintf(body, sizeof body, "%s, \"exposure\": 1.5}", sized);
    CHECK_INT(view_open(&d, id, body, vb, NULL), 201);
    expect_frame(&d, vb, 1, 1, 0, false);
    struct mjpeg_stream sb;
    CHECK_INT(mjpeg_open(&d, vb, 0, &sb), 200);
    struct mjpeg_frame fresh = next_full(&sb, 0);
    CHECK_MSG(same_bytes(&f2, &fresh), "re-encoded %zu bytes, rendered %zu bytes", f2.len,
              fresh.len);
    mjpeg_close(&sb);

    /* Tonemap, then JPEG quality: each encoded again from the same image. */
    CHECK_INT(view_patch(&d, va, "{\"tonemap\": \"filmic\"}"), 200);
    struct mjpeg_frame f3 = next_full(&sa, f2.seq);
    expect_frame(&d, va, 3, 1, 2, true);
    CHECK(!same_bytes(&f2, &f3));
    CHECK_INT(view_patch(&d, va, "{\"jpeg_quality\": 30}"), 200);
    struct mjpeg_frame f4 = next_full(&sa, f3.seq);
    expect_frame(&d, va, 4, 1, 3, true);
    CHECK(f4.len < f3.len); /* quality 30 of the same image is smaller than 80 */

    /* Anything that changes the image is rendered, alone or with an exposure change. */
    CHECK_INT(view_patch(&d, va, "{\"camera\": {\"eye\": [0.3, 0, 4]}}"), 200);
    struct mjpeg_frame f5 = next_full(&sa, f4.seq);
    expect_frame(&d, va, 5, 2, 3, false);
    CHECK_INT(view_patch(&d, va, "{\"camera\": {\"eye\": [0, 0.3, 4]}, \"exposure\": 0.5}"), 200);
    struct mjpeg_frame f6 = next_full(&sa, f5.seq);
    expect_frame(&d, va, 6, 3, 3, false);
    printf("frames: %zu bytes; +1.5 EV re-encoded %zu = rendered %zu; filmic %zu; q30 %zu\n",
           f1.len, f2.len, fresh.len, f3.len, f4.len);
    mjpeg_close(&sa);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);

    /* The first frame again, from a daemon that draws it in 16 tiles. */
    struct test_daemon t;
    const char *const tiled[] = {"--render-tile-pixels", "200", NULL};
    if (!test_daemon_start(&t, tiled))
        test_setup_failed("test_view_reencode", t.why);
    char tid[REFRACT_ID_SIZE], vt[32] = "";
    CHECK(test_create_scene(&t, view_sphere_scene, tid));
    snprintf(body, sizeof body, "%s, \"exposure\": 0}", sized);
    CHECK_INT(view_open(&t, tid, body, vt, NULL), 201);
    struct mjpeg_stream st;
    CHECK_INT(mjpeg_open(&t, vt, 0, &st), 200);
    struct mjpeg_frame ft = next_full(&st, 0);
    CHECK_MSG(same_bytes(&f1, &ft), "at once %zu bytes, in tiles %zu bytes", f1.len, ft.len);
    mjpeg_close(&st);
    free(ft.jpeg);
    CHECK_INT(test_daemon_stop(&t), 0);
    test_daemon_cleanup(&t);

    free(f1.jpeg);
    free(f2.jpeg);
    free(f3.jpeg);
    free(f4.jpeg);
    free(f5.jpeg);
    free(f6.jpeg);
    free(fresh.jpeg);
    return test_summary("test_view_reencode");
}
