/*
 * test_jobs_restart.c - a batch job survives a kill -9: refractd is killed with SIGKILL
 * while a turntable renders, restarted on the same data directory, and the job resumes at
 * its first unfinished frame (no committed frame is lost: frames_done never goes back) and
 * finishes with every frame exactly once and in its place: each frame equals the same
 * frame of an uninterrupted run of the same specification (renders are deterministic).
 */
#include <signal.h>
#include <sys/wait.h>

#include "jobs_util.h"

#define W 48
#define H 36
#define FRAMES 24

static void kill9(struct test_daemon *d)
{
    refract_client_destroy(d->client);
    d->client = NULL;
    kill(d->pid, SIGKILL);
    int status;
    waitpid(d->pid, &status, 0);
    d->pid = 0;
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_jobs_restart", d.why);
    size_t len = 0;
    char *doc = test_read_source_file("proto/examples/glass_sphere.json", &len);
    char scene[REFRACT_ID_SIZE] = "", spec[256], id[64] = "";
    if (!doc || !test_create_scene(&d, doc, scene))
        test_setup_failed("test_jobs_restart", "could not create the scene");
    free(doc);
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"width\": %d, \"height\": %d, \"turntable\": {\"frames\": %d}}",
             scene, W, H, FRAMES);
    if (!job_submit_json(&d, spec, id))
        test_setup_failed("test_jobs_restart", "could not submit the job");

    /* Kill it once a few frames are committed and before the last. */
    int before = -1;
    for (int i = 0; i < 6000 && before < 3; i++) {
        cJSON *st = job_status_get(&d, id);
        before = st ? job_int(st, "frames_done") : -1;
        cJSON_Delete(st);
        if (before < 3)
            job_sleep_ms(10);
    }
    CHECK_MSG(before >= 3 && before < FRAMES, "frames_done %d when killed", before);
    kill9(&d);

    struct test_daemon d2;
    if (!test_daemon_start_in(&d2, d.data_dir, NULL))
        test_setup_failed("test_jobs_restart (restart)", d2.why);
    cJSON *st = job_status_get(&d2, id);
    CHECK(st != NULL);
    int after = st ? job_int(st, "frames_done") : -1;
    CHECK_MSG(after >= before, "frames_done went back from %d to %d", before, after);
    CHECK_INT(job_int(st, "frames_total"), FRAMES);
    cJSON_Delete(st);

    st = job_wait(&d2, id, 180);
    CHECK_STR(job_str(st, "state"), "done");
    CHECK_INT(job_int(st, "frames_done"), FRAMES);
    cJSON_Delete(st);
    /* The log says where it resumed. */
    FILE *log = fopen(d2.log_path, "r");
    char line[1024];
    bool resumed = false;
    while (log && fgets(line, sizeof line, log))
        resumed |= strstr(line, id) && strstr(line, "resumes at frame");
    if (log)
        fclose(log);
    CHECK(resumed);

    /* Every frame in its place: the same frames as an uninterrupted run. */
    char ref[64] = "";
    CHECK(job_submit_json(&d2, spec, ref));
    st = job_wait(&d2, ref, 180);
    CHECK_STR(job_str(st, "state"), "done");
    cJSON_Delete(st);
    for (int n = 0; n < FRAMES; n++) {
        size_t la = 0, lb = 0;
        void *a = job_frame_bytes(&d2, id, n, &la, NULL, 0);
        void *b = job_frame_bytes(&d2, ref, n, &lb, NULL, 0);
        CHECK_MSG(a && b && la == lb && memcmp(a, b, la) == 0,
                  "frame %d of the resumed job differs from the uninterrupted run's", n);
        free(a);
        free(b);
    }
    /* No frame beyond the last. */
    char path[128], *body = NULL;
    snprintf(path, sizeof path, "/v1/jobs/%s/frames/%d", id, FRAMES);
    CHECK_INT(test_request(&d2, "GET", path, NULL, &body), 404);
    free(body);
    CHECK_INT(test_daemon_stop(&d2), 0);
    test_daemon_cleanup(&d2);
    test_daemon_cleanup(&d);
    return test_summary("test_jobs_restart");
}
