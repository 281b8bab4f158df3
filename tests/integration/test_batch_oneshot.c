/*
 * test_batch_oneshot.c - `refractd --batch` without a scheduler (docs/slurm.md): two tasks
 * (--task 0/2, 1/2) together write every frame of a turntable once, byte-identical to
 * the same job run by a refractd daemon (POST /v1/jobs); progress.json then says done; a rerun
 * removes its range's leftover temporary file, skips the frames present and renders only
 * the one that is missing, byte-identical again; SIGTERM stops a task after the frame in
 * flight with exit status 143 and its record "stopped", leaving only complete frames; a
 * missing --out and an unknown field of the specification (not in the sanitizer build) are
 * refused with the documented exit code and a message that names the problem.
 *
 * The Slurm test (tests/slurm/test_slurm_array.sh) runs the same binary under a real
 * scheduler; this one runs everywhere, root or not.
 */
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "jobs_util.h"

#define FRAMES 8
#define LONG_FRAMES 400

static char dir[256], spec_path[320], long_spec_path[320], out[320];

static char *read_all(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    char *buf = malloc(1 << 20);
    size_t n = buf ? fread(buf, 1, (1 << 20) - 1, f) : 0;
    fclose(f);
    if (buf)
        buf[n] = '\0';
    *len = n;
    return buf;
}

static bool write_text(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    if (f == NULL)
        return false;
    bool ok = fputs(text, f) >= 0;
    return fclose(f) == 0 && ok;
}

/* {"width":..., "turntable": {"frames": n}, "scene": <glass_sphere.json>} */
static char *job_spec(int frames)
{
    char *scene = test_read_source_file("proto/examples/glass_sphere.json", NULL);
    if (scene == NULL)
        return NULL;
    size_t size = strlen(scene) + 256;
    char *spec = malloc(size);
    if (spec)
        snprintf(spec, size,
                 "{\"width\": 64, \"height\": 48, \"turntable\": {\"frames\": %d, \"axis\": [0, 1, "
                 "0]}, \"scene\": %s}",
                 frames, scene);
    free(scene);
    return spec;
}

static int batch(const char *spec, const char *range_flag, const char *range, char **log)
{
    const char *args[] = {"--batch", spec, range_flag, range, "--out", out, NULL};
    return test_run_refractd(args, log);
}

static bool frame_equals(int n, const void *bytes, size_t len)
{
    char path[400];
    snprintf(path, sizeof path, "%s/frame_%05d.png", out, n);
    size_t got = 0;
    char *file = read_all(path, &got);
    bool same = file && got == len && memcmp(file, bytes, len) == 0;
    free(file);
    return same;
}

/* Starts refractd --batch SPEC --task TASK --out OUT with its output in log_path. */
static pid_t spawn_task(const char *task, const char *log_path)
{
    pid_t pid = fork();
    if (pid == 0) {
        int fd = open(log_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(fd, STDOUT_FILENO);
        dup2(fd, STDERR_FILENO);
        const char *argv[] = {
            getenv("REFRACTD"), "--batch", spec_path, "--task", task, "--out", out, NULL};
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    return pid;
}

/* The two tasks one after the other (at once they only compete for 2 cores here; the
 * Slurm test runs four at once). */
static void tasks_equal_the_daemon(void *ref[FRAMES], const size_t ref_len[FRAMES])
{
    for (int t = 0; t < 2; t++) {
        char task[8], log_path[400];
        snprintf(task, sizeof task, "%d/2", t);
        snprintf(log_path, sizeof log_path, "%s/task%d.log", dir, t);
        pid_t pid = spawn_task(task, log_path);
        int st = 0;
        CHECK(pid > 0 && waitpid(pid, &st, 0) == pid);
        CHECK(WIFEXITED(st) && WEXITSTATUS(st) == 0);
        size_t len = 0;
        char *log = read_all(log_path, &len);
        CHECK_CONTAINS(log, t == 0 ? "frames 0-3 of 8: 4 rendered, 0 already there"
                                   : "frames 4-7 of 8: 4 rendered, 0 already there");
        free(log);
    }
    for (int n = 0; n < FRAMES; n++)
        CHECK_MSG(ref[n] && frame_equals(n, ref[n], ref_len[n]), "frame %d differs", n);
    char path[400];
    snprintf(path, sizeof path, "%s/progress.json", out);
    size_t len = 0;
    char *progress = read_all(path, &len);
    CHECK_CONTAINS(progress, "\"frames_done\":\t8");
    CHECK_CONTAINS(progress, "\"state\":\t\"done\"");
    CHECK_CONTAINS(progress, "\"frames\":\t[0, 3]");
    CHECK_CONTAINS(progress, "\"frames\":\t[4, 7]");
    free(progress);
}

static void rerun_renders_only_what_is_missing(void *ref[FRAMES], const size_t ref_len[FRAMES])
{
    char path[400], tmp[400];
    snprintf(path, sizeof path, "%s/frame_00005.png", out);
    CHECK_INT(unlink(path), 0);
    snprintf(tmp, sizeof tmp, "%s/.frame_00006.png.deadhost.1.tmp", out);
    CHECK(write_text(tmp, "half a frame"));
    struct stat before4, after4;
    snprintf(path, sizeof path, "%s/frame_00004.png", out);
    CHECK_INT(stat(path, &before4), 0);
    char *log = NULL;
    CHECK_INT(batch(spec_path, "--task", "1/2", &log), 0);
    CHECK_CONTAINS(log, "(1 partial files of an earlier run removed)");
    CHECK_CONTAINS(log, "frames 4-7 of 8: 1 rendered, 3 already there");
    free(log);
    CHECK(access(tmp, F_OK) != 0);
    CHECK(ref[5] && frame_equals(5, ref[5], ref_len[5]));
    CHECK_INT(stat(path, &after4), 0);
    CHECK_MSG(before4.st_ino == after4.st_ino, "frame 4 was written again");
}

/* Starts a long task, waits for its first frame, sends SIGTERM. */
static void sigterm_stops_after_the_frame_in_flight(void)
{
    char long_out[400], record[480];
    snprintf(long_out, sizeof long_out, "%s/long", dir);
    snprintf(record, sizeof record, "%s/progress.d/frames_00000-00399.json", long_out);
    pid_t pid = fork();
    if (pid == 0) {
        int fd = open("/dev/null", O_WRONLY);
        dup2(fd, STDOUT_FILENO);
        dup2(fd, STDERR_FILENO);
        const char *argv[] = {getenv("REFRACTD"), "--batch", long_spec_path,
                              "--frames",         "0-399",   "--out",
                              long_out,           NULL};
        execv(argv[0], (char *const *)argv);
        _exit(127);
    }
    CHECK(pid > 0);
    bool started = false;
    for (int i = 0; i < 3000 && !started; i++) { /* 30 s */
        size_t len = 0;
        char *text = read_all(record, &len);
        started = text && strstr(text, "\"frames_done\":\t0,") == NULL &&
                  strstr(text, "\"frames_done\"") != NULL;
        free(text);
        if (!started)
            job_sleep_ms(10);
    }
    CHECK(started);
    kill(pid, SIGTERM);
    int st = 0;
    CHECK_INT(waitpid(pid, &st, 0), pid);
    CHECK(WIFEXITED(st));
    CHECK_INT(WEXITSTATUS(st), 128 + SIGTERM);
    size_t len = 0;
    char *text = read_all(record, &len);
    CHECK_CONTAINS(text, "\"state\":\t\"stopped\"");
    free(text);
    int present = 0;
    for (int n = 0; n < LONG_FRAMES; n++) {
        char path[480];
        snprintf(path, sizeof path, "%s/frame_%05d.png", long_out, n);
        struct stat st_frame;
        if (stat(path, &st_frame) == 0) {
            present++;
            CHECK_MSG(st_frame.st_size > 8, "frame %d is empty", n); /* complete: renamed */
        }
    }
    CHECK_MSG(present >= 1 && present < LONG_FRAMES, "%d frames present", present);
}

static void bad_invocations_say_what_is_wrong(void)
{
    /* (a bad range's messages: tests/unit/test_job_batch_dir.c) */
    char *log = NULL;
    const char *no_out[] = {"--batch", spec_path, "--task", "0/2", NULL};
    CHECK_INT(test_run_refractd(no_out, &log), REFRACT_E_USAGE);
    CHECK_CONTAINS(log, "--batch needs --out DIR");
    free(log);
    /* The specification's errors are job_spec's, which test_jobs_api checks in full; the
     * sanitizer build leaves out this run (another GPU start-up) to stay short. */
    if (test_sanitized())
        return;
    char bad_path[320];
    snprintf(bad_path, sizeof bad_path, "%s/bad.json", dir);
    CHECK(write_text(bad_path, "{\"turntable\": {\"frames\": 2}, \"scene\": {\"colour\": 1}}"));
    CHECK_INT(batch(bad_path, "--task", "0/1", &log), REFRACT_E_UNKNOWN_FIELD);
    CHECK_CONTAINS(log, "scene: unknown field \"colour\"");
    free(log);
}

int main(void)
{
    test_temp_template(dir, sizeof dir, "refract-batch-test");
    if (mkdtemp(dir) == NULL)
        test_setup_failed("test_batch_oneshot", "mkdtemp failed");
    snprintf(spec_path, sizeof spec_path, "%s/job.json", dir);
    snprintf(long_spec_path, sizeof long_spec_path, "%s/long.json", dir);
    snprintf(out, sizeof out, "%s/out", dir);
    char *spec = job_spec(FRAMES), *long_spec = job_spec(LONG_FRAMES);
    if (spec == NULL || long_spec == NULL || !write_text(spec_path, spec) ||
        !write_text(long_spec_path, long_spec))
        test_setup_failed("test_batch_oneshot", "cannot write the job specifications");

    /* The reference: the same job run by one daemon. */
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_batch_oneshot", d.why);
    char id[64] = "";
    void *ref[FRAMES] = {0};
    size_t ref_len[FRAMES] = {0};
    CHECK(job_submit_json(&d, spec, id));
    cJSON *st = job_wait(&d, id, 120);
    CHECK_STR(job_str(st, "state"), "done");
    cJSON_Delete(st);
    for (int n = 0; n < FRAMES; n++)
        ref[n] = job_frame_bytes(&d, id, n, &ref_len[n], NULL, 0);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);

    tasks_equal_the_daemon(ref, ref_len);
    rerun_renders_only_what_is_missing(ref, ref_len);
    sigterm_stops_after_the_frame_in_flight();
    bad_invocations_say_what_is_wrong();

    for (int n = 0; n < FRAMES; n++)
        free(ref[n]);
    free(spec);
    free(long_spec);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    return test_summary("test_batch_oneshot");
}
