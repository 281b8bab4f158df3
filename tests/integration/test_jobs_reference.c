/*
 * test_jobs_reference.c - batch jobs in reference mode through a real refractd
 * (docs/api.md "Batch jobs", "mode": "reference"; docs/pathtracer.md "In jobs"):
 *
 *   - a job with "mode": "reference", "samples" and "seed" renders each frame with the path
 *     tracer: frame 0, at the scene's camera, is bit for bit the image of POST .../render
 *     with "mode": "reference" and the same samples and seed (the path tracer's streams do
 *     not depend on threads or on who runs it); frame 1, another camera, differs;
 *   - `refractd --batch` with the same specification (the scene inline) writes frame 0 byte
 *     for byte as the daemon's job did;
 *   - "samples" or "seed" without "mode": "reference", an unknown mode and samples past
 *     --max-reference-samples are 400s naming the field.
 */
#include <math.h>
#include <stdio.h>
#include <unistd.h>
#include <stdlib.h>
#include <string.h>

#include "daemon.h"
#include "expect.h"
#include "io/io_image.h"
#include "jobs_util.h"
#include "test.h"

#define W 32
#define H 24

/* A glass ball over a floor under a small lamp: caustic, shadow and the floor seen through
 * the glass, all of which the path tracer renders. */
static const char *const scene_doc =
    "{\"name\": \"reference job\", \"camera\": {\"eye\": [0, 1.5, 4], \"look_at\": [0, -0.4, 0], "
    "\"fov_y_deg\": 45, \"width\": 32, \"height\": 24}, \"environment\": {\"intensity\": 0.2}, "
    "\"lights\": [{\"type\": \"point\", \"position\": [1, 4, 1], \"intensity\": 30, "
    "\"radius\": 0.1}], \"receiver\": {\"height\": -1, \"half_size\": \"infinite\"}, "
    "\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 0.6, \"medium\": {\"ior\": 1.5}}]}";

static char *read_whole(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    char *buf = malloc(1 << 22);
    *len = buf ? fread(buf, 1, 1 << 22, f) : 0;
    fclose(f);
    return buf;
}

static bool decode(const void *bytes, size_t len, struct io_image *out)
{
    struct err e = {0};
    if (io_image_decode(bytes, len, 1 << 24, out, &e) != REFRACT_E_OK) {
        fprintf(stderr, "decode: %s\n", e.msg);
        return false;
    }
    return out->width == W && out->height == H;
}

int main(void)
{
    const char *args[] = {"--max-reference-samples", "512", NULL};
    struct test_daemon d;
    if (!test_daemon_start(&d, args))
        test_setup_failed("test_jobs_reference", d.why);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, scene_doc, id));

    char spec[512], job[64];
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"mode\": \"reference\", \"samples\": 16, \"seed\": 7, "
             "\"format\": \"exr\", \"frames\": [{}, {\"camera\": {\"eye\": [2, 2, 3]}}]}",
             id);
    CHECK(job_submit_json(&d, spec, job));
    cJSON *st = job_wait(&d, job, 120);
    CHECK_STR(job_str(st, "state"), "done");
    cJSON_Delete(st);

    /* The same picture through POST .../render. */
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    struct refract_response r;
    const char body[] = "{\"mode\": \"reference\", \"samples\": 16, \"seed\": 7, \"format\": \"exr\"}";
    CHECK_INT(refract_request(d.client, "POST", path, body, strlen(body), "application/json", &r),
              0);
    CHECK_INT((int)r.status, 200);
    struct io_image direct = {0}, f0 = {0}, f1 = {0};
    CHECK(decode(r.body, r.body_len, &direct));
    refract_response_free(&r);
    CHECK(job_frame_image(&d, job, 0, W, H, &f0));
    CHECK(job_frame_image(&d, job, 1, W, H, &f1));
    int same = 0, lit = 0;
    double diff01 = 0.0;
    for (int i = 0; i < W * H && f0.rgba && f1.rgba && direct.rgba; i++) {
        bool eq = true;
        for (int c = 0; c < 3; c++) {
            eq = eq && f0.rgba[4 * i + c] == direct.rgba[4 * i + c];
            diff01 += fabs(f0.rgba[4 * i + c] - f1.rgba[4 * i + c]);
        }
        same += eq;
        lit += f0.rgba[4 * i + 1] > 0.0f;
    }
    printf("frame 0 against the direct reference render: %d of %d pixels equal; %d lit; frame 1 "
           "differs by %.3f in all\n",
           same, W * H, lit, diff01);
    CHECK_INT(same, W * H);
    CHECK(lit > W * H / 2);
    CHECK(diff01 > 1.0);

    /* refractd --batch with the same job, the scene inline: the same frame 0, byte for byte. */
    char dir[256], spec_path[320], out[320];
    test_temp_template(dir, sizeof dir, "refract-reference-batch");
    if (mkdtemp(dir) == NULL)
        test_setup_failed("test_jobs_reference", "mkdtemp failed");
    snprintf(spec_path, sizeof spec_path, "%s/job.json", dir);
    snprintf(out, sizeof out, "%s/out", dir);
    FILE *fs = fopen(spec_path, "w");
    if (fs) {
        fprintf(fs,
                "{\"scene\": %s, \"mode\": \"reference\", \"samples\": 16, \"seed\": 7, "
                "\"format\": \"exr\", \"frames\": [{}]}",
                scene_doc);
        fclose(fs);
    }
    const char *bargs[] = {"--batch", spec_path, "--frames", "0-0", "--out", out, NULL};
    char *log = NULL;
    CHECK_INT(test_run_refractd(bargs, &log), 0);
    size_t daemon_len = 0;
    void *daemon_frame = job_frame_bytes(&d, job, 0, &daemon_len, NULL, 0);
    char frame_path[400];
    snprintf(frame_path, sizeof frame_path, "%s/frame_00000.exr", out);
    size_t batch_len = 0;
    char *batch_frame = read_whole(frame_path, &batch_len);
    CHECK_MSG(daemon_frame && batch_frame && batch_len == daemon_len &&
                  memcmp(daemon_frame, batch_frame, batch_len) == 0,
              "--batch frame 0 (%zu bytes) differs from the daemon's (%zu bytes); log: %s",
              batch_len, daemon_len, log ? log : "");
    free(daemon_frame);
    free(batch_frame);
    free(log);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    io_image_free(&direct);
    io_image_free(&f0);
    io_image_free(&f1);

    /* Refusals, each naming its field. */
    static const struct {
        const char *extra, *needle;
    } bad[] = {
        {"\"samples\": 16", "samples, seed: only with"},
        {"\"mode\": \"slow\"", "mode"},
        {"\"mode\": \"reference\", \"samples\": 100000", "samples"},
        {"\"mode\": \"reference\", \"seed\": 1.5", "seed"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        snprintf(spec, sizeof spec, "{\"scene\": \"%s\", %s, \"frames\": [{}]}", id, bad[i].extra);
        char *reply = NULL;
        long status = test_request(&d, "POST", "/v1/jobs", spec, &reply);
        CHECK_MSG(status == 400 && reply && strstr(reply, bad[i].needle) != NULL,
                  "case %zu: %ld %s", i, status, reply ? reply : "(none)");
        free(reply);
    }
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_jobs_reference");
}
