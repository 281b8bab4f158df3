/*
 * test_view_events.c - view sessions follow what the event hub says changed (docs/views.md
 * "Frames: when and how"), with no PATCH:
 *   - a lights change (scene.updated, what = lights) renders a new frame of that scene's
 *     sessions, and none of another scene's;
 *   - a scene that needs light simulation: the first frame is rendered before its
 *     irradiance volume exists ("missing"); when the volume is ready (irradiance.ready) a
 *     new frame follows, rendered with it ("ready"), and it is brighter where the beam
 *     lands;
 *   - deleting the scene (scene.deleted) ends its sessions: their streams end and their
 *     ids answer 404.
 */
#include "io/io_image.h"
#include "irradiance_util.h"
#include "view_util.h"

static void lights_change_renders_only_that_scene(struct test_daemon *d, const char *lit,
                                                  const char *other)
{
    char vid_lit[32], vid_other[32];
    CHECK_INT(view_open(d, lit, "{\"progressive\": false}", vid_lit, NULL), 201);
    CHECK_INT(view_open(d, other, "{\"progressive\": false}", vid_other, NULL), 201);
    double seq_lit = view_wait_seq(d, vid_lit, 1, 30000);
    double seq_other = view_wait_seq(d, vid_other, 1, 30000);
    CHECK(seq_lit >= 1 && seq_other >= 1);
    char path[128], *body = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s/lights/sun", other);
    long st = test_request(d, "PUT", path,
                           "{\"type\": \"directional\", \"direction\": [0.3, -1, 0], "
                           "\"intensity\": 2}",
                           &body);
    CHECK_MSG(st == 200 || st == 202, "PUT %s: %ld %s", path, st, body ? body : "");
    free(body);
    CHECK(view_wait_seq(d, vid_other, seq_other + 1, 30000) > seq_other);
    view_sleep_ms(500);
    cJSON *s = view_status(d, vid_lit);
    CHECK_MSG(view_status_seq(s) == seq_lit, "the other scene's session rendered (seq %g -> %g)",
              seq_lit, view_status_seq(s));
    cJSON_Delete(s);
}

static double mean(const struct mjpeg_frame *f)
{
    struct io_image img = {0};
    struct err e = {0};
    if (io_image_decode(f->jpeg, f->len, 1 << 24, &img, &e) != REFRACT_E_OK)
        return -1;
    double sum = 0;
    size_t n = (size_t)img.width * (size_t)img.height;
    for (size_t i = 0; i < n * 4; i++)
        sum += (i % 4 == 3) ? 0 : img.rgba[i];
    io_image_free(&img);
    return sum / (3.0 * (double)n);
}

static void irradiance_ready_renders_again(struct test_daemon *d)
{
    char *doc = beam_scene("[{\"name\": \"sun\", \"type\": \"directional\", \"direction\": "
                           "[0, -1, 0], \"intensity\": 1}]");
    char beam[REFRACT_ID_SIZE], vid[32];
    CHECK(test_create_scene(d, doc, beam));
    free(doc);
    CHECK_INT(view_open(d, beam, "{\"progressive\": false}", vid, NULL), 201);
    struct mjpeg_stream s;
    CHECK_INT(mjpeg_open(d, vid, 0, &s), 200);
    /* Frames until one made with the volume: the first may already have it when the
     * simulation beat the first render; then the check below is about that one. */
    struct mjpeg_frame f;
    char first_irr[16] = "";
    double first_mean = -1, ready_mean = -1;
    for (int i = 0; i < 10; i++) {
        if (mjpeg_next(&s, &f, 60000) != 1)
            break;
        if (first_irr[0] == '\0') {
            snprintf(first_irr, sizeof first_irr, "%s", f.irradiance);
            first_mean = mean(&f);
        }
        bool ready = strcmp(f.irradiance, "ready") == 0;
        if (ready)
            ready_mean = mean(&f);
        free(f.jpeg);
        if (ready)
            break;
    }
    CHECK_MSG(ready_mean >= 0, "no frame rendered with a ready volume (first: %s)", first_irr);
    if (strcmp(first_irr, "ready") != 0) {
        CHECK(strcmp(first_irr, "missing") == 0 || strcmp(first_irr, "stale") == 0);
        CHECK_MSG(ready_mean > first_mean, "mean %g with the volume, %g without", ready_mean,
                  first_mean);
    } else {
        printf("  the volume was ready before the first frame: the event path is not shown\n");
    }
    mjpeg_close(&s);
}

static void scene_delete_ends_sessions(struct test_daemon *d, const char *scene)
{
    char vid[32];
    CHECK_INT(view_open(d, scene, "{}", vid, NULL), 201);
    struct mjpeg_stream s;
    CHECK_INT(mjpeg_open(d, vid, 0, &s), 200);
    struct mjpeg_frame f;
    CHECK_INT(mjpeg_next(&s, &f, 30000), 1);
    free(f.jpeg);
    char path[128], *body = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s", scene);
    CHECK_INT(test_request(d, "DELETE", path, NULL, &body), 204);
    free(body);
    int rc = 1;
    for (int i = 0; i < 3 && rc == 1; i++) {
        rc = mjpeg_next(&s, &f, 10000);
        if (rc == 1)
            free(f.jpeg);
    }
    CHECK_INT(rc, -1);
    mjpeg_close(&s);
    snprintf(path, sizeof path, "/v1/views/%s", vid);
    CHECK_INT(test_request(d, "GET", path, NULL, &body), 404);
    CHECK(test_error_is(body, "not_found", vid));
    free(body);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_view_events", d.why);
    char a[REFRACT_ID_SIZE], b[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, view_sphere_scene, a));
    CHECK(test_create_scene(&d, view_sphere_scene, b));
    lights_change_renders_only_that_scene(&d, a, b);
    irradiance_ready_renders_again(&d);
    scene_delete_ends_sessions(&d, a);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_view_events");
}
