/*
 * test_job_batch_dir.c - the pieces of `refractd --batch` that need no GPU
 * (server/jobs/job_batch.c, job_batch_dir.c): N tasks' shares cover every frame exactly
 * once for any total and N; bad --frames / --task values are usage errors that name the
 * flag; a frame is written under its final name with its bytes and no temporary file; the
 * temporary files of a killed run (frames and progress files) are removed for the task's
 * own range only; progress.json
 * counts the frames present and lists every task's record.
 */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "jobs/jobs.h"
#include "test.h"

static void shares_cover_every_frame_once(void)
{
    const int totals[] = {1, 5, 24, 25, 97};
    for (size_t t = 0; t < sizeof totals / sizeof totals[0]; t++) {
        for (int tasks = 1; tasks <= 9; tasks++) {
            int total = totals[t], seen[97] = {0};
            for (int i = 0; i < tasks; i++) {
                char task[32];
                snprintf(task, sizeof task, "%d/%d", i, tasks);
                int first = 0, last = 0;
                struct err e = {0};
                CHECK_INT(job_batch_range(NULL, task, total, &first, &last, &e), REFRACT_E_OK);
                /* shares differ by at most one frame */
                int size = last - first + 1;
                CHECK_MSG(size == total / tasks || size == total / tasks + 1,
                          "task %s of %d frames: %d frames", task, total, size);
                for (int n = first; n <= last; n++)
                    seen[n]++;
            }
            for (int n = 0; n < total; n++)
                CHECK_MSG(seen[n] == 1, "%d tasks, %d frames: frame %d rendered %d times", tasks,
                          total, n, seen[n]);
        }
    }
    int first = 0, last = 0;
    struct err e = {0};
    CHECK_INT(job_batch_range("3-7", NULL, 24, &first, &last, &e), REFRACT_E_OK);
    CHECK_INT(first, 3);
    CHECK_INT(last, 7);
    CHECK_INT(job_batch_range(NULL, "1/4", 24, &first, &last, &e), REFRACT_E_OK);
    CHECK_INT(first, 6);
    CHECK_INT(last, 11);
}

static void bad_ranges_name_the_flag(void)
{
    struct {
        const char *frames, *task, *needle;
    } cases[] = {
        {"3-1", NULL, "--frames 3-1"}, {"0-24", NULL, "the job has 24 frames"},
        {"x", NULL, "--frames x"},     {"-1-3", NULL, "--frames -1-3"},
        {"2-", NULL, "--frames 2-"},   {NULL, "4/4", "--task 4/4"},
        {NULL, "1/0", "--task 1/0"},   {NULL, "1", "--task 1"},
        {NULL, NULL, "exactly one"},   {"0-1", "0/2", "exactly one"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int first = 0, last = 0;
        struct err e = {0};
        CHECK_INT(job_batch_range(cases[i].frames, cases[i].task, 24, &first, &last, &e),
                  REFRACT_E_USAGE);
        CHECK_CONTAINS(e.msg, cases[i].needle);
    }
}

static int count_entries(const char *dir, const char *suffix)
{
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *ent;
    while (d && (ent = readdir(d)) != NULL) {
        size_t len = strlen(ent->d_name), sl = strlen(suffix);
        if (len >= sl && strcmp(ent->d_name + len - sl, suffix) == 0)
            n++;
    }
    if (d)
        closedir(d);
    return n;
}

static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    char *buf = calloc(1, 65536);
    size_t got = buf ? fread(buf, 1, 65535, f) : 0;
    (void)got; /* calloc'd: the text ends at the first zero either way */
    fclose(f);
    return buf;
}

static void frames_appear_whole_and_temps_are_cleaned(const char *dir)
{
    struct err e = {0};
    CHECK_INT(job_batch_dir_prepare(dir, &e), REFRACT_E_OK);
    CHECK(!job_batch_frame_exists(dir, 2, JOB_FORMAT_PNG));
    const char bytes[] = "not really a PNG, but bytes";
    CHECK_INT(job_batch_frame_write(dir, 2, JOB_FORMAT_PNG, bytes, sizeof bytes, &e), REFRACT_E_OK);
    CHECK(job_batch_frame_exists(dir, 2, JOB_FORMAT_PNG));
    CHECK(!job_batch_frame_exists(dir, 2, JOB_FORMAT_EXR));
    char path[1024];
    job_batch_frame_path(dir, 2, JOB_FORMAT_PNG, path, sizeof path);
    CHECK_CONTAINS(path, "/frame_00002.png");
    char *back = read_file(path);
    CHECK(back && memcmp(back, bytes, sizeof bytes) == 0);
    free(back);
    CHECK_INT(count_entries(dir, ".tmp"), 0);

    /* What killed runs leave: partial files of frames 1, 4 and 9, of range 3-5's progress
     * files and of range 0-2's progress.json (and an empty frame file, which does not count
     * as done). Range 3-5 removes only its own. */
    const char *partial[] = {".frame_00001.png.h.1.tmp",
                             ".frame_00004.png.h.2.tmp",
                             ".frame_00009.exr.h.3.tmp",
                             "progress.json.frames_00003-00005.h.4.tmp",
                             "progress.d/frames_00003-00005.json.frames_00003-00005.h.4.tmp",
                             "progress.json.frames_00000-00002.h.5.tmp"};
    for (size_t i = 0; i < sizeof partial / sizeof partial[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, partial[i]);
        FILE *f = fopen(path, "w");
        CHECK(f != NULL);
        if (f)
            fclose(f);
    }
    char sub[1024];
    snprintf(sub, sizeof sub, "%s/progress.d", dir);
    snprintf(path, sizeof path, "%s/frame_00005.png", dir);
    FILE *empty = fopen(path, "w");
    if (empty)
        fclose(empty);
    CHECK(!job_batch_frame_exists(dir, 5, JOB_FORMAT_PNG));
    CHECK_INT(job_batch_clean_temps(dir, 3, 5), 3);
    CHECK_INT(count_entries(dir, ".tmp"), 3);
    CHECK_INT(count_entries(sub, ".tmp"), 0);
    CHECK_INT(job_batch_clean_temps(dir, 0, 10), 2); /* frames 1 and 9; not 0-2's progress */
    CHECK_INT(job_batch_clean_temps(dir, 0, 2), 1);
    CHECK_INT(count_entries(dir, ".tmp"), 0);
    unlink(path);
}

static void progress_counts_frames_and_tasks(const char *dir)
{
    struct job_frame frames[6];
    memset(frames, 0, sizeof frames);
    struct err e = {0};
    /* frame 2 is there from the test above; two tasks of 3 frames */
    struct job_batch_task a = {.first = 0, .last = 2, .done = 1, .state = "running"};
    CHECK_INT(job_batch_progress_write(dir, &a, frames, 6, &e), REFRACT_E_OK);
    char path[1024];
    snprintf(path, sizeof path, "%s/progress.json", dir);
    char *text = read_file(path);
    CHECK_CONTAINS(text, "\"frames_total\":\t6");
    CHECK_CONTAINS(text, "\"frames_done\":\t1");
    CHECK_CONTAINS(text, "\"state\":\t\"running\"");
    free(text);
    for (int n = 3; n < 6; n++)
        CHECK_INT(job_batch_frame_write(dir, n, JOB_FORMAT_PNG, "x", 1, &e), REFRACT_E_OK);
    struct job_batch_task b = {.first = 3, .last = 5, .done = 3, .state = "done"};
    CHECK_INT(job_batch_progress_write(dir, &b, frames, 6, &e), REFRACT_E_OK);
    text = read_file(path);
    CHECK_CONTAINS(text, "\"frames_done\":\t4");
    CHECK_CONTAINS(text, "\"frames\":\t[0, 2]");
    CHECK_CONTAINS(text, "\"frames\":\t[3, 5]");
    free(text);
    for (int n = 0; n < 2; n++)
        CHECK_INT(job_batch_frame_write(dir, n, JOB_FORMAT_PNG, "x", 1, &e), REFRACT_E_OK);
    a.done = 3;
    a.state = "done";
    CHECK_INT(job_batch_progress_write(dir, &a, frames, 6, &e), REFRACT_E_OK);
    text = read_file(path);
    CHECK_CONTAINS(text, "\"frames_done\":\t6");
    CHECK_CONTAINS(text, "\"state\":\t\"done\"");
    free(text);
    CHECK_INT(count_entries(dir, ".tmp"), 0);
    snprintf(path, sizeof path, "%s/progress.d", dir);
    CHECK_INT(count_entries(path, ".json"), 2);
}

int main(void)
{
    char dir[] = "/tmp/refract-test-batch-XXXXXX";
    if (mkdtemp(dir) == NULL)
        test_setup_failed("test_job_batch_dir", "mkdtemp failed");
    char out[600];
    snprintf(out, sizeof out, "%s/out/nested", dir); /* created with its parents */
    shares_cover_every_frame_once();
    bad_ranges_name_the_flag();
    frames_appear_whole_and_temps_are_cleaned(out);
    progress_counts_frames_and_tasks(out);
    char cmd[700];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    return test_summary("test_job_batch_dir");
}
