/*
 * test_job_tiles.c - batch-job frames are drawn a tile of --render-tile-pixels per GPU turn,
 * like renders and view frames (issue 13, "Fair sharing"; docs/api.md "Fair sharing"),
 * against real daemons:
 *   - a small render asked for while a job's large frame is being drawn is answered while
 *     that frame is still in progress, after about one tile of it, not after the whole
 *     frame (the tile time is measured here, from a render of the frame's size, so a loaded
 *     machine moves the bound with it);
 *   - a job cancelled while its large frame is drawn stops drawing it within a few tiles,
 *     and a daemon stopped meanwhile (SIGTERM) exits after about one tile of it, not after
 *     the whole frame (the log says the frame was dropped);
 *   - the job's frame drawn in tiles is byte-equal (linear EXR) to the same job's frame
 *     from a daemon that draws it at once, and to the frame `refractd --batch` draws in
 *     tiles (the one-shot mode of Slurm array tasks, whose frames must equal a daemon's).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "jobs_util.h"

/* 384 x 288 in tiles of 4096 pixels: 29 tiles of 10 rows (the last of 8). */
#define TILE_PIXELS "4096"
#define WIDTH 384
#define HEIGHT 288
#define TILES 29

static const char scene_json[] =
    "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 32, "
    "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}}]}";

/* POST .../render with body json: the status; *gpu_ms gets X-Render-Time-Ms. */
static long render(struct test_daemon *d, const char *id, const char *json, double *gpu_ms)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    struct refract_response r;
    if (refract_request(d->client, "POST", path, json, strlen(json), "application/json", &r) != 0)
        return -1;
    long status = r.status;
    *gpu_ms = r.render_ms;
    refract_response_free(&r);
    return status;
}

/* The job: one frame of the scene, sent inline so that `refractd --batch` can run it too. */
static void job_spec(char *out, size_t size)
{
    snprintf(out, size,
             "{\"scene\": %s, \"width\": %d, \"height\": %d, \"format\": \"exr\", "
             "\"frames\": [{}]}",
             scene_json, WIDTH, HEIGHT);
}

static void *read_file(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    void *buf = n > 0 ? malloc((size_t)n) : NULL;
    *len = buf && fread(buf, 1, (size_t)n, f) == (size_t)n ? (size_t)n : 0;
    fclose(f);
    return buf;
}

/* The frame `refractd --batch` draws in tiles of TILE_PIXELS (new bytes) or NULL. */
static void *batch_frame(const char *spec, size_t *len)
{
    char dir[256], spec_path[300], out[300], frame[340];
    test_temp_template(dir, sizeof dir, "refract-job-tiles");
    if (mkdtemp(dir) == NULL)
        return NULL;
    snprintf(spec_path, sizeof spec_path, "%s/job.json", dir);
    snprintf(out, sizeof out, "%s/out", dir);
    snprintf(frame, sizeof frame, "%s/frame_00000.exr", out);
    FILE *f = fopen(spec_path, "w");
    if (f == NULL)
        return NULL;
    fputs(spec, f);
    fclose(f);
    char *log = NULL;
    const char *args[] = {
        "--batch",   spec_path, "--frames", "0-0", "--out", out, "--render-tile-pixels",
        TILE_PIXELS, NULL};
    int rc = test_run_refractd(args, &log);
    if (rc != 0)
        fprintf(stderr, "refractd --batch: exit %d\n%s\n", rc, log ? log : "");
    free(log);
    void *bytes = rc == 0 ? read_file(frame, len) : NULL;
    char cmd[400];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    return bytes;
}

/* A large frame: 1024 x 768 in tiles of 4 rows, 192 tiles. */
#define LARGE_TILES 192
static const char large_spec[] =
    "{\"scene\": {\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
    "\"resolution\": 32, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}}]}, "
    "\"width\": 1024, \"height\": 768, \"frames\": [{}]}";

/* Polls until job is running (5 s at most). */
static void wait_running(struct test_daemon *d, const char *job)
{
    for (int i = 0; i < 1000; i++) {
        cJSON *st = job_status_get(d, job);
        bool running = st && !strcmp(job_str(st, "state"), "running");
        cJSON_Delete(st);
        if (running)
            return;
        job_sleep_ms(5);
    }
}

/* Lines of the daemon's log that contain needle. */
static int log_count(const struct test_daemon *d, const char *needle)
{
    FILE *f = fopen(d->log_path, "r");
    if (f == NULL)
        return -1;
    char line[4096];
    int n = 0;
    while (fgets(line, sizeof line, f))
        n += strstr(line, needle) != NULL;
    fclose(f);
    return n;
}

static const char dropped[] = "job frame dropped: its job was cancelled, or refractd is stopping";

/* A job cancelled mid-frame stops drawing within a few tiles; then a daemon stopped
 * mid-frame exits after about a tile. Stops d. */
static void cancel_and_stop_mid_frame(struct test_daemon *d, double tile_ms)
{
    double frame_ms = LARGE_TILES * tile_ms; /* about: the tiles are 4096 pixels, not 3840 */
    char job[64], path[128];
    CHECK(job_submit_json(d, large_spec, job));
    wait_running(d, job);
    job_sleep_ms((int)(5.0 * tile_ms) + 50);
    snprintf(path, sizeof path, "/v1/jobs/%s", job);
    double t0 = test_now_ms();
    CHECK_INT(test_request(d, "DELETE", path, NULL, NULL), 200);
    while (log_count(d, dropped) < 1 && test_now_ms() - t0 < frame_ms)
        job_sleep_ms(5);
    double cancel_ms = test_now_ms() - t0;
    printf("a job cancelled during its %d-tile frame (about %.0f ms): the frame dropped after "
           "%.0f ms\n",
           LARGE_TILES, frame_ms, cancel_ms);
    CHECK_INT(log_count(d, dropped), 1);
    CHECK_MSG(cancel_ms < 5.0 * tile_ms + 200.0, "dropped after %.0f ms; a tile takes %.1f ms",
              cancel_ms, tile_ms);

    CHECK(job_submit_json(d, large_spec, job));
    wait_running(d, job);
    job_sleep_ms((int)(5.0 * tile_ms) + 50);
    t0 = test_now_ms();
    CHECK_INT(test_daemon_stop(d), 0);
    double stop_ms = test_now_ms() - t0;
    printf("a daemon stopped during a job's %d-tile frame (about %.0f ms): exited after %.0f ms\n",
           LARGE_TILES, frame_ms, stop_ms);
    CHECK_INT(log_count(d, dropped), 2);
    CHECK_MSG(stop_ms < frame_ms / 2.0, "stopping took %.0f ms; the frame takes about %.0f ms",
              stop_ms, frame_ms);
}

/* Runs the one-frame job to its end on d: frame 0's bytes (new) or NULL. */
static void *job_frame(struct test_daemon *d, const char *job, size_t *len)
{
    cJSON *st = job_wait(d, job, 60.0);
    CHECK(st != NULL && !strcmp(job_str(st, "state"), "done"));
    cJSON_Delete(st);
    return job_frame_bytes(d, job, 0, len, NULL, 0);
}

int main(void)
{
    struct test_daemon d;
    const char *const tiled[] = {"--render-tile-pixels", TILE_PIXELS, NULL};
    if (!test_daemon_start(&d, tiled))
        test_setup_failed("test_job_tiles", d.why);
    char scene[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, scene_json, scene));
    double small_gpu = 0.0, big_gpu = 0.0;
    static const char small_json[] = "{\"width\": 32, \"height\": 24}";
    CHECK_INT(render(&d, scene, small_json, &small_gpu), 200); /* warm-up: kernel compiles */
    char big_json[96];
    snprintf(big_json, sizeof big_json, "{\"width\": %d, \"height\": %d}", WIDTH, HEIGHT);
    CHECK_INT(render(&d, scene, big_json, &big_gpu), 200);
    double tile_ms = big_gpu / TILES;

    /* The job's frame starts drawing; a small render asked for meanwhile. */
    char spec[1024], job[64];
    job_spec(spec, sizeof spec);
    CHECK(job_submit_json(&d, spec, job));
    double t_job = test_now_ms();
    wait_running(&d, job);
    job_sleep_ms((int)(3.0 * tile_ms) + 20); /* a few of its tiles are drawn */
    double t0 = test_now_ms();
    CHECK_INT(render(&d, scene, small_json, &small_gpu), 200);
    double small_ms = test_now_ms() - t0;
    cJSON *st = job_status_get(&d, job);
    int done_then = st ? job_int(st, "frames_done") : -1;
    cJSON_Delete(st);
    size_t tiled_len = 0;
    void *tiled_frame = job_frame(&d, job, &tiled_len);
    double job_ms = test_now_ms() - t_job;
    printf("small render during a job's %dx%d frame (%d tiles of about %.1f ms): answered after "
           "%.1f ms (%.1f ms its own), the frame still in progress (frames_done %d); the job took "
           "%.0f ms\n",
           WIDTH, HEIGHT, TILES, tile_ms, small_ms, small_gpu, done_then, job_ms);
    /* Answered before the frame was finished... */
    CHECK_INT(done_then, 0);
    /* ...after about one tile of it (and its own render), far less than the whole frame. */
    CHECK_MSG(small_ms - small_gpu < 3.0 * tile_ms + 50.0,
              "the small render waited %.1f ms; a tile takes %.1f ms", small_ms - small_gpu,
              tile_ms);
    CHECK_MSG(small_ms < big_gpu / 3.0, "the small render took %.1f ms; the whole frame %.1f ms",
              small_ms, big_gpu);
    CHECK(tiled_frame != NULL && tiled_len > 0);
    cancel_and_stop_mid_frame(&d, tile_ms);
    test_daemon_cleanup(&d);

    /* The same job from a daemon that draws the frame at once: the same bytes. */
    struct test_daemon a;
    const char *const at_once[] = {"--render-tile-pixels", "16777216", NULL};
    if (!test_daemon_start(&a, at_once))
        test_setup_failed("test_job_tiles", a.why);
    CHECK(job_submit_json(&a, spec, job));
    size_t once_len = 0;
    void *once_frame = job_frame(&a, job, &once_len);
    CHECK(once_frame != NULL);
    bool same = tiled_frame && once_frame && tiled_len == once_len &&
                memcmp(tiled_frame, once_frame, once_len) == 0;
    printf("the frame drawn in %d tiles and drawn at once: %s (%zu and %zu bytes of EXR)\n", TILES,
           same ? "byte-equal" : "DIFFERENT", tiled_len, once_len);
    CHECK(same);
    CHECK_INT(test_daemon_stop(&a), 0);
    test_daemon_cleanup(&a);

    /* The one-shot batch mode draws it in tiles too, and the same. */
    size_t batch_len = 0;
    void *batch = batch_frame(spec, &batch_len);
    same = batch && once_frame && batch_len == once_len && memcmp(batch, once_frame, once_len) == 0;
    printf("the frame refractd --batch drew in %d tiles and the frame drawn at once: %s\n", TILES,
           same ? "byte-equal" : "DIFFERENT");
    CHECK(same);
    free(batch);
    free(tiled_frame);
    free(once_frame);
    return test_summary("test_job_tiles");
}
