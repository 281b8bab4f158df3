/*
 * test_jobs_turntable.c - batch jobs through a real refractd: a turntable completes with
 * every frame a valid image of the asked size that differs from its neighbour (the camera
 * moved), the archive holds every frame once, an explicit frame list keeps each frame's
 * format, and a job on a scene with a simulated light renders only lit frames: its frame 0
 * equals a single render of the same camera made once the light's volume is ready.
 */
#include "jobs_util.h"

#define W 48
#define H 36
#define FRAMES 6

static void turntable(struct test_daemon *d, const char *scene)
{
    char spec[256], id[64] = "";
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"width\": %d, \"height\": %d,"
             " \"turntable\": {\"frames\": %d, \"axis\": [0, 1, 0]}}",
             scene, W, H, FRAMES);
    CHECK(job_submit_json(d, spec, id));
    cJSON *st = job_wait(d, id, 120);
    CHECK_STR(job_str(st, "state"), "done");
    CHECK_INT(job_int(st, "frames_done"), FRAMES);
    CHECK_INT(job_int(st, "frames_total"), FRAMES);
    cJSON_Delete(st);
    struct io_image img[FRAMES] = {0};
    for (int n = 0; n < FRAMES; n++)
        CHECK_MSG(job_frame_image(d, id, n, W, H, &img[n]), "frame %d", n);
    for (int n = 0; n < FRAMES; n++) {
        const struct io_image *next = &img[(n + 1) % FRAMES];
        if (img[n].rgba && next->rgba)
            CHECK_MSG(job_image_max_diff(&img[n], next) > 1e-3, "frame %d equals frame %d", n,
                      (n + 1) % FRAMES);
    }
    for (int n = 0; n < FRAMES; n++)
        io_image_free(&img[n]);

    /* The archive: a ustar file with frame_00000.png .. frame_00005.png, once each. */
    char path[128];
    snprintf(path, sizeof path, "/v1/jobs/%s/archive", id);
    struct refract_response r;
    CHECK_INT(refract_request(d->client, "GET", path, NULL, 0, NULL, &r), 0);
    CHECK_INT(r.status, 200);
    CHECK_STR(r.content_type, "application/x-tar");
    int seen[FRAMES] = {0}, entries = 0;
    for (size_t off = 0; r.body && off + 512 <= r.body_len && r.body[off] != '\0';) {
        const char *h = r.body + off;
        size_t size = strtoull(h + 124, NULL, 8);
        int n = -1;
        const char *slash = strchr(h, '/');
        CHECK(slash && sscanf(slash, "/frame_%d.png", &n) == 1);
        if (n >= 0 && n < FRAMES)
            seen[n]++;
        CHECK_CONTAINS(h + 257, "ustar");
        entries++;
        off += 512 + (size + 511) / 512 * 512;
    }
    CHECK_INT(entries, FRAMES);
    for (int n = 0; n < FRAMES; n++)
        CHECK_MSG(seen[n] == 1, "frame %d is in the archive %d times", n, seen[n]);
    refract_response_free(&r);
}

static void frame_list(struct test_daemon *d, const char *scene)
{
    char spec[512], id[64] = "";
    snprintf(
        spec, sizeof spec,
        "{\"scene\": \"%s\", \"frames\": ["
        "{\"width\": 40, \"height\": 30, \"format\": \"jpeg\"},"
        "{\"width\": 32, \"height\": 24, \"format\": \"exr\", \"camera\": {\"eye\": [0, 0.5, 3]}},"
        "{\"width\": 20, \"height\": 16, \"exposure\": 1.5}]}",
        scene);
    CHECK(job_submit_json(d, spec, id));
    cJSON *st = job_wait(d, id, 120);
    CHECK_STR(job_str(st, "state"), "done");
    cJSON_Delete(st);
    const char *types[] = {"image/jpeg", "image/x-exr", "image/png"};
    const int sizes[][2] = {{40, 30}, {32, 24}, {20, 16}};
    for (int n = 0; n < 3; n++) {
        size_t len = 0;
        char ct[64] = "";
        void *bytes = job_frame_bytes(d, id, n, &len, ct, sizeof ct);
        CHECK_STR(ct, types[n]);
        free(bytes);
        struct io_image img = {0};
        CHECK_MSG(job_frame_image(d, id, n, sizes[n][0], sizes[n][1], &img), "frame %d", n);
        io_image_free(&img);
    }
}

/* smoke_spot's spot light needs the light simulation: the job starts before its volume
 * exists, so it must wait, and its frames must be the lit ones. */
static void lit(struct test_daemon *d)
{
    size_t len = 0;
    char *doc = test_read_source_file("proto/examples/smoke_spot.json", &len);
    char scene[REFRACT_ID_SIZE] = "", spec[256], id[64] = "";
    CHECK(doc && test_create_scene(d, doc, scene));
    free(doc);
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"width\": %d, \"height\": %d, \"turntable\": {\"frames\": 2}}",
             scene, W, H);
    CHECK(job_submit_json(d, spec, id));
    cJSON *st = job_wait(d, id, 120);
    CHECK_STR(job_str(st, "state"), "done");
    cJSON_Delete(st);
    /* The same camera (turntable angle 0 is the scene camera) rendered with the ready volume. */
    char req[64];
    snprintf(req, sizeof req, "{\"width\": %d, \"height\": %d}", W, H);
    struct refract_image ref = {0};
    for (int i = 0; i < 600; i++) {
        refract_image_free(&ref);
        if (refract_render(d->client, scene, req, &ref) != 0 || !strcmp(ref.irradiance, "ready"))
            break;
        job_sleep_ms(100);
    }
    CHECK_STR(ref.irradiance, "ready");
    size_t flen = 0;
    void *frame = job_frame_bytes(d, id, 0, &flen, NULL, 0);
    CHECK(frame != NULL);
    CHECK_INT((long long)flen, (long long)ref.len);
    CHECK_MSG(frame && flen == ref.len && memcmp(frame, ref.bytes, flen) == 0,
              "frame 0 of the job differs from the lit render of the same camera");
    free(frame);
    refract_image_free(&ref);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_jobs_turntable", d.why);
    size_t len = 0;
    char *doc = test_read_source_file("proto/examples/glass_sphere.json", &len);
    char scene[REFRACT_ID_SIZE] = "";
    CHECK(doc && test_create_scene(&d, doc, scene));
    free(doc);
    if (scene[0]) {
        turntable(&d, scene);
        frame_list(&d, scene);
    }
    lit(&d);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_jobs_turntable");
}
