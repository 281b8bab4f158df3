/*
 * test_cli_view.c - `refract view` and `refract events` ($REFRACT_CLI, the real binary)
 * against a real refractd:
 *   - view --frames 3 --orbit saves frame_0001.jpg .. frame_0003.jpg, each a JPEG of the
 *     asked size, prints a line per frame with growing seqs, and leaves no session behind;
 *   - view --print-url prints <url>/viewer/<scene>; a scene that does not exist is exit 6
 *     with refractd's message, for both forms; --frames 0 is a usage error (24);
 *   - events --since 0 --type scene.updated --count 1 prints the lights change from the
 *     history; a live `refract events` started before the change sees it; a missing
 *     scene is exit 6.
 */
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "daemon.h"
#include "io/io_image.h"
#include "support_cli.h"
#include "test.h"

static const char scene_json[] =
    "{\"name\": \"cli view ball\", \"camera\": {\"eye\": [0, 0.5, 4], \"look_at\": [0, 0, 0],"
    " \"width\": 32, \"height\": 24},"
    " \"objects\": [{\"bounds\": {\"min\": [-0.5, -0.5, -0.5], \"max\": [0.5, 0.5, 0.5]},"
    "   \"resolution\": 16, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.45, \"inside\": 1.5},"
    "   \"attenuation\": {\"shape\": \"sphere\", \"radius\": 0.45, \"inside\": [0.5, 1.5, 3]}}]}";

static struct cli_run run_cli(const struct test_daemon *d, const char *const *args)
{
    return cli_run(d, NULL, NULL, args);
}

static void check_frame_file(const char *path, int width, int height)
{
    char *bytes = cli_slurp(path);
    struct stat st;
    struct io_image img = {0};
    struct err e = {0};

    CHECK_MSG(stat(path, &st) == 0 && st.st_size > 4, "%s missing or empty", path);
    if (stat(path, &st) == 0 && st.st_size > 4) {
        CHECK_INT(io_image_decode(bytes, (size_t)st.st_size, 1 << 24, &img, &e), REFRACT_E_OK);
        CHECK_INT(img.width, width);
        CHECK_INT(img.height, height);
        CHECK((unsigned char)bytes[0] == 0xFF && (unsigned char)bytes[1] == 0xD8);
    }
    io_image_free(&img);
    free(bytes);
}

static void view_saves_three_frames_and_ends_its_session(struct test_daemon *d, const char *scene)
{
    char dir[400];
    char path[460];
    char *views = NULL;
    struct cli_run r;

    snprintf(dir, sizeof(dir), "%s/frames", d->dir);
    r = run_cli(d, (const char *[]){"view", scene, "--frames", "3", "--orbit", "30", "--out", dir,
                                    "--width", "72", "--height", "40", NULL});
    CHECK_MSG(r.status == 0, "exit %d: %s", r.status, r.err);
    CHECK_CONTAINS(r.out, "frame 1: seq ");
    CHECK_CONTAINS(r.out, "frame 3: seq ");
    CHECK_CONTAINS(r.out, "72x40, full, ");
    CHECK_CONTAINS(r.out, "irradiance not-needed -> ");
    CHECK(strstr(r.out, "frame 4:") == NULL);
    {
        long long seq[3] = {-1, -1, -1};
        const char *p = r.out;

        for (int i = 0; i < 3 && p != NULL; i++) {
            p = strstr(p, ": seq ");
            if (p != NULL) {
                seq[i] = atoll(p + 6);
                p += 6;
            }
        }
        CHECK(seq[0] >= 1 && seq[1] > seq[0] && seq[2] > seq[1]);
    }
    for (int i = 1; i <= 3; i++) {
        snprintf(path, sizeof(path), "%s/frame_%04d.jpg", dir, i);
        CHECK_CONTAINS(r.out, path);
        check_frame_file(path, 72, 40);
    }
    snprintf(path, sizeof(path), "%s/frame_0004.jpg", dir);
    CHECK(access(path, F_OK) != 0);
    cli_run_free(&r);
    CHECK_INT(refract_view_list(d->client, &views), REFRACT_E_OK);
    CHECK_CONTAINS(views, "{\"views\":[]}");
    refract_free(views);
}

static void print_url_and_bad_scenes(struct test_daemon *d, const char *scene)
{
    char want[256];
    struct cli_run r;

    snprintf(want, sizeof(want), "%s/viewer/%s\n", d->url, scene);
    r = run_cli(d, (const char *[]){"view", scene, "--print-url", NULL});
    CHECK_INT(r.status, 0);
    CHECK_STR(r.out, want);
    cli_run_free(&r);

    r = run_cli(d, (const char *[]){"view", "no_such_scene", "--print-url", NULL});
    CHECK_INT(r.status, REFRACT_E_SCENE_NOT_FOUND);
    CHECK_STR(r.out, "");
    CHECK_CONTAINS(r.err, "refract: ");
    CHECK_CONTAINS(r.err, "no_such_scene");
    cli_run_free(&r);

    r = run_cli(d, (const char *[]){"view", "no_such_scene", "--frames", "2", NULL});
    CHECK_INT(r.status, REFRACT_E_SCENE_NOT_FOUND);
    CHECK_CONTAINS(r.err, "no_such_scene");
    cli_run_free(&r);

    r = run_cli(d, (const char *[]){"view", scene, "--frames", "0", NULL});
    CHECK_INT(r.status, REFRACT_E_USAGE);
    CHECK_CONTAINS(r.err, "refract: view: --frames: ");
    cli_run_free(&r);

    r = run_cli(d, (const char *[]){"view", scene, "--quality", "superb", NULL});
    CHECK_INT(r.status, REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(r.err, "quality");
    cli_run_free(&r);
}

static void set_sun(struct test_daemon *d, const char *scene, int i)
{
    char light[128];

    snprintf(light, sizeof(light),
             "{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0.%d, -1, 0]}",
             i % 10);
    CHECK_INT(refract_light_put(d->client, scene, "sun", light, NULL), REFRACT_E_OK);
}

static void events_print_scene_updates(struct test_daemon *d, const char *scene)
{
    char out_path[400];
    struct cli_run r;
    pid_t pid;
    int status = -1;
    char *out;

    set_sun(d, scene, 1);
    r = run_cli(d, (const char *[]){"events", scene, "--since", "0", "--type", "scene.updated",
                                    "--count", "1", NULL});
    CHECK_MSG(r.status == 0, "exit %d: %s", r.status, r.err);
    CHECK_CONTAINS(r.out, " scene.updated {");
    CHECK_CONTAINS(r.out, "\"what\":\"lights\"");
    CHECK(strchr(r.out, '\n') == r.out + strlen(r.out) - 1); /* one line */
    cli_run_free(&r);

    /* Live: started first, it must see a change made after it connected; changes go on
     * until it exits, since it may connect after any of them. */
    snprintf(out_path, sizeof(out_path), "%s/events.out", d->dir);
    pid = fork();
    if (pid == 0) {
        int fd = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
        int null = open("/dev/null", O_RDWR);

        dup2(fd, 1);
        dup2(null, 0);
        execl(getenv("REFRACT_CLI"), "refract", "--url", d->url, "events", scene, "--type",
              "scene.updated", "--count", "1", (char *)NULL);
        _exit(127);
    }
    for (int i = 0; i < 100; i++) {
        struct timespec ts = {0, 200 * 1000000L};

        if (waitpid(pid, &status, WNOHANG) == pid)
            break;
        set_sun(d, scene, i + 2);
        nanosleep(&ts, NULL);
        status = -1;
    }
    if (status == -1) {
        kill(pid, SIGTERM);
        waitpid(pid, &status, 0);
        CHECK_MSG(0, "refract events saw no scene.updated within 20 s");
    } else {
        CHECK(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    }
    out = cli_slurp(out_path);
    CHECK_CONTAINS(out, " scene.updated {");
    free(out);

    r = run_cli(d, (const char *[]){"events", "no_such_scene", "--count", "1", NULL});
    CHECK_INT(r.status, REFRACT_E_SCENE_NOT_FOUND);
    CHECK_CONTAINS(r.err, "no_such_scene");
    cli_run_free(&r);
}

int main(void)
{
    struct test_daemon d;
    char scene[REFRACT_ID_SIZE];

    if (getenv("REFRACTD") == NULL || getenv("REFRACT_CLI") == NULL)
        test_skip("test_cli_view", "REFRACTD or REFRACT_CLI is not set (run it through ctest)");
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_cli_view", d.why);
    CHECK(test_create_scene(&d, scene_json, scene));
    view_saves_three_frames_and_ends_its_session(&d, scene);
    print_url_and_bad_scenes(&d, scene);
    events_print_scene_updates(&d, scene);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_cli_view");
}
