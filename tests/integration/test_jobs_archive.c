/*
 * test_jobs_archive.c - GET /v1/jobs/{id}/archive, which refractd streams frame by frame
 * from the blobs, is exactly the ustar file of the frames fetched one by one: for a job
 * of six frames of three formats and odd sizes (entries that are no multiple of 512 bytes
 * and that straddle the server's 64 KiB read blocks) every entry is a valid ustar header
 * (checksum computed here, name <job>/frame_NNNNN.<ext by format>, mode 0644, size, mtime
 * = the job's created) followed by the bytes GET .../frames/{n} gives and zero padding,
 * and the file ends with exactly two zero blocks; a job cancelled before its first frame
 * gives only those two blocks.
 */
#include "jobs_util.h"

#define FRAMES 6

struct frame {
    void *bytes;
    size_t len;
};

static bool all_zero(const char *p, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        if (p[i] != 0)
            return false;
    }
    return true;
}

/* Checks the 512-byte header h of entry n (the frame's bytes are f) of job id. */
static void check_header(const unsigned char *h, const char *id, int n, const struct frame *f,
                         const char *ext, long created)
{
    char name[128], field[16];
    snprintf(name, sizeof name, "%s/frame_%05d.%s", id, n, ext);
    CHECK_STR((const char *)h, name);
    memcpy(field, h + 100, 8);
    field[8] = '\0';
    CHECK_INT(strtol(field, NULL, 8), 0644);
    memcpy(field, h + 124, 12);
    field[12] = '\0';
    CHECK_INT((long)strtoull(field, NULL, 8), (long)f->len);
    memcpy(field, h + 136, 12);
    field[12] = '\0';
    CHECK_INT(strtol(field, NULL, 8), created);
    CHECK_INT(h[156], '0');
    CHECK(memcmp(h + 257,
                 "ustar\0"
                 "00",
                 8) == 0);
    /* The checksum: the header's bytes summed with its own 8-byte field as spaces. */
    unsigned sum = 0;
    for (int i = 0; i < 512; i++)
        sum += (i >= 148 && i < 156) ? ' ' : h[i];
    memcpy(field, h + 148, 8);
    field[8] = '\0';
    CHECK_INT((long)strtoul(field, NULL, 8), (long)sum);
}

static void check_archive(struct test_daemon *d, const char *id, const struct frame *frames,
                          const char *const *ext, int count, long created)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/jobs/%s/archive", id);
    struct refract_response r;
    CHECK_INT(refract_request(d->client, "GET", path, NULL, 0, NULL, &r), 0);
    CHECK_INT(r.status, 200);
    CHECK_STR(r.content_type, "application/x-tar");
    size_t expected = 1024;
    for (int n = 0; n < count; n++)
        expected += 512 + (frames[n].len + 511) / 512 * 512;
    CHECK_MSG(r.body_len == expected, "the archive has %zu bytes, expected %zu", r.body_len,
              expected);
    size_t off = 0;
    for (int n = 0; n < count && r.body && off + 512 <= r.body_len; n++) {
        check_header((const unsigned char *)r.body + off, id, n, &frames[n], ext[n], created);
        off += 512;
        size_t pad = (frames[n].len + 511) / 512 * 512;
        CHECK_MSG(off + pad <= r.body_len &&
                      memcmp(r.body + off, frames[n].bytes, frames[n].len) == 0,
                  "entry %d differs from GET .../frames/%d", n, n);
        if (off + pad <= r.body_len)
            CHECK(all_zero(r.body + off + frames[n].len, pad - frames[n].len));
        off += pad;
    }
    CHECK(off + 1024 == r.body_len && all_zero(r.body + off, 1024));
    refract_response_free(&r);
}

static void mixed_formats(struct test_daemon *d, const char *scene)
{
    char spec[1024], id[64] = "";
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"frames\": ["
             "{\"width\": 64, \"height\": 48},"
             "{\"width\": 64, \"height\": 48, \"format\": \"exr\"},"
             "{\"width\": 40, \"height\": 30, \"format\": \"jpeg\"},"
             "{\"width\": 33, \"height\": 17, \"camera\": {\"eye\": [0, 0.5, 3]}},"
             "{\"width\": 50, \"height\": 40, \"format\": \"exr\"},"
             "{\"width\": 64, \"height\": 48, \"exposure\": 1}]}",
             scene);
    CHECK(job_submit_json(d, spec, id));
    cJSON *st = job_wait(d, id, 120);
    CHECK_STR(job_str(st, "state"), "done");
    long created = job_int(st, "created");
    cJSON_Delete(st);
    const char *const ext[FRAMES] = {"png", "exr", "jpg", "png", "exr", "png"};
    struct frame frames[FRAMES] = {0};
    size_t total = 0;
    for (int n = 0; n < FRAMES; n++) {
        frames[n].bytes = job_frame_bytes(d, id, n, &frames[n].len, NULL, 0);
        CHECK_MSG(frames[n].bytes != NULL, "frame %d", n);
        total += frames[n].len;
    }
    CHECK_MSG(total > 64 * 1024, "the frames total %zu bytes: not enough to span read blocks",
              total);
    check_archive(d, id, frames, ext, FRAMES, created);
    for (int n = 0; n < FRAMES; n++)
        free(frames[n].bytes);
}

static void no_frames(struct test_daemon *d, const char *scene)
{
    char spec[256], id[64] = "", path[128];
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"width\": 320, \"height\": 240, \"turntable\": {\"frames\": 8}}",
             scene);
    CHECK(job_submit_json(d, spec, id));
    snprintf(path, sizeof path, "/v1/jobs/%s", id);
    CHECK_INT(test_request(d, "DELETE", path, NULL, NULL), 200);
    cJSON *st = job_status_get(d, id);
    int done = job_int(st, "frames_done");
    long created = job_int(st, "created");
    cJSON_Delete(st);
    struct frame frames[8] = {0};
    const char *const ext[8] = {"png", "png", "png", "png", "png", "png", "png", "png"};
    for (int n = 0; n < done && n < 8; n++)
        frames[n].bytes = job_frame_bytes(d, id, n, &frames[n].len, NULL, 0);
    check_archive(d, id, frames, ext, done, created); /* usually 0 frames: two zero blocks */
    for (int n = 0; n < 8; n++)
        free(frames[n].bytes);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_jobs_archive", d.why);
    size_t len = 0;
    char *doc = test_read_source_file("proto/examples/glass_sphere.json", &len);
    char scene[REFRACT_ID_SIZE] = "";
    if (!doc || !test_create_scene(&d, doc, scene))
        test_setup_failed("test_jobs_archive", "could not create the scene");
    free(doc);
    mixed_formats(&d, scene);
    no_frames(&d, scene);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_jobs_archive");
}
