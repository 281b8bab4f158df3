/*
 * test_cli.c - the refract CLI ($REFRACT_CLI, the real binary) against a real refractd:
 * every command once on the happy path, and the failures a script must be able to tell
 * apart by exit status (proto/refract_errors.h numbers, docs/cli.md):
 *   - health, scene create (file and stdin) / list / show / delete, volume upload,
 *     render -o (PNG and EXR, decoded and sized), trace;
 *   - a missing scene (6), a volume file of the wrong size (17, before sending), a
 *     daemon that is not there (21), a wrong command line (24), a bad scene (2);
 *   - the light and irradiance commands' command-line mistakes, refused before anything
 *     is sent, and `light list` of a scene without lights (test_cli_lights.c drives
 *     them against lights with irradiance volumes).
 */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "daemon.h"
#include "io/io_image.h"
#include "support_cli.h"
#include "test.h"

/* The shared runner, plus the failing command's stderr on the test's log. */
static struct cli_run run_cli(const struct test_daemon *d, const char *url, const char *stdin_path,
                              const char *const *args)
{
    struct cli_run r = cli_run(d, url, stdin_path, args);
    if (r.status != 0)
        fprintf(stderr, "  refract %s ...: exit %d, stderr: %s", args[0], r.status, r.err);
    return r;
}

static bool file_starts_with(const char *path, const void *magic, size_t n)
{
    unsigned char buf[16] = {0};
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return false;
    size_t got = fread(buf, 1, n, f);
    fclose(f);
    return got == n && memcmp(buf, magic, n) == 0;
}

static void check_image_file(const char *path, int w, int h)
{
    char *bytes = NULL;
    FILE *f = fopen(path, "rb");
    CHECK(f != NULL);
    if (f == NULL)
        return;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    bytes = malloc((size_t)n);
    CHECK(fread(bytes, 1, (size_t)n, f) == (size_t)n);
    fclose(f);
    struct io_image img = {0};
    struct err e = {0};
    CHECK_INT(io_image_decode(bytes, (size_t)n, 1 << 24, &img, &e), REFRACT_E_OK);
    CHECK_INT(img.width, w);
    CHECK_INT(img.height, h);
    io_image_free(&img);
    free(bytes);
}

/* Strips the trailing newline of a one-line output. */
static void chomp(char *s)
{
    size_t n = strlen(s);
    while (n > 0 && (s[n - 1] == '\n' || s[n - 1] == '\r'))
        s[--n] = '\0';
}

int main(void)
{
    if (getenv("REFRACT_CLI") == NULL || access(getenv("REFRACT_CLI"), X_OK) != 0)
        test_skip("test_cli", "REFRACT_CLI is not set to the refract binary (ctest sets it)");
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL)) {
        fprintf(stderr, "cannot start refractd: %s\n", d.why);
        return 1;
    }
    char path[512];

    /* health */
    struct cli_run r = run_cli(&d, NULL, NULL, (const char *[]){"health", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, "\"renderer\"");
    CHECK_CONTAINS(r.out, "\"status\":\"ok\"");
    cli_run_free(&r);

    /* scene create from a file prints only the id */
    snprintf(path, sizeof path, "%s/proto/examples/glass_sphere.json",
             getenv("REFRACT_SOURCE_DIR"));
    r = run_cli(&d, NULL, NULL, (const char *[]){"scene", "create", path, NULL});
    CHECK_INT(r.status, 0);
    chomp(r.out);
    char id[64];
    snprintf(id, sizeof id, "%s", r.out);
    CHECK(strlen(id) > 0 && strchr(id, ' ') == NULL);
    cli_run_free(&r);

    /* ... and from stdin */
    char stdin_path[400];
    snprintf(stdin_path, sizeof stdin_path, "%s/small.json", d.dir);
    FILE *f = fopen(stdin_path, "w");
    fputs("{\"name\": \"small box\", \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], "
          "\"max\": [1, 1, 1]}, \"resolution\": 16, \"ior\": 1.33}]}",
          f);
    fclose(f);
    r = run_cli(&d, NULL, stdin_path, (const char *[]){"scene", "create", "-", NULL});
    CHECK_INT(r.status, 0);
    chomp(r.out);
    char small_id[64];
    snprintf(small_id, sizeof small_id, "%s", r.out);
    cli_run_free(&r);

    r = run_cli(&d, NULL, NULL, (const char *[]){"scene", "list", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, id);
    CHECK_CONTAINS(r.out, small_id);
    cli_run_free(&r);

    r = run_cli(&d, NULL, NULL, (const char *[]){"scene", "show", small_id, NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, "\"small box\"");
    cli_run_free(&r);

    /* render -o: PNG and EXR, format from the extension, size from the flags */
    char png[400], exr[400];
    snprintf(png, sizeof png, "%s/view.png", d.dir);
    snprintf(exr, sizeof exr, "%s/view.exr", d.dir);
    r = run_cli(&d, NULL, NULL,
                (const char *[]){"render", id, "-o", png, "--width", "64", "--height", "48",
                                 "--stepper", "euler", "--step", "1", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.err, "64x48");
    cli_run_free(&r);
    CHECK(file_starts_with(png, "\x89PNG", 4));
    check_image_file(png, 64, 48);
    r = run_cli(&d, NULL, NULL,
                (const char *[]){"render", id, "-o", exr, "--width", "40", "--height", "30",
                                 "--eye", "0,0,5", NULL});
    CHECK_INT(r.status, 0);
    cli_run_free(&r);
    CHECK(file_starts_with(exr, "\x76\x2f\x31\x01", 4)); /* OpenEXR magic 20000630 */
    check_image_file(exr, 40, 30);

    /* trace: a ray along the axis of the glass sphere exits straight on */
    r = run_cli(&d, NULL, NULL,
                (const char *[]){"trace", id, "--origin", "0,0,-3", "--direction", "0,0,1", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, "\"status\":\"exited\"");
    CHECK_CONTAINS(r.out, "\"optical_path_length\"");
    cli_run_free(&r);
    /* ... and with --events, where it crosses the sphere's exact surface */
    r = run_cli(&d, NULL, NULL,
                (const char *[]){"trace", id, "--origin", "0,0,-3", "--direction", "0,0,1",
                                 "--events", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, "\"event_count\":2");
    CHECK_CONTAINS(r.out, "\"medium_after\":\"sphere\"");
    cli_run_free(&r);

    /* volume upload: a 2x2x2 float32 file; then one of the wrong size is refused before
     * anything is sent (exit 17, invalid_volume) */
    char vol[400];
    snprintf(vol, sizeof vol, "%s/v.f32", d.dir);
    float values[8] = {1.1f, 1.2f, 1.3f, 1.4f, 1.5f, 1.6f, 1.7f, 1.8f};
    f = fopen(vol, "wb");
    fwrite(values, sizeof values[0], 8, f);
    fclose(f);
    r = run_cli(
        &d, NULL, NULL,
        (const char *[]){"volume", "upload", small_id, "density", vol, "--dims", "2,2,2", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, "\"name\":\"density\"");
    CHECK_CONTAINS(r.out, "\"min\":1.1");
    cli_run_free(&r);
    r = run_cli(
        &d, NULL, NULL,
        (const char *[]){"volume", "upload", small_id, "density", vol, "--dims", "2,2,3", NULL});
    CHECK_INT(r.status, REFRACT_E_INVALID_VOLUME);
    CHECK_CONTAINS(r.err, "refract: ");
    CHECK_CONTAINS(r.err, "48");
    cli_run_free(&r);

    /* failures a script can tell apart */
    r = run_cli(&d, NULL, NULL, (const char *[]){"scene", "show", "no_such_scene", NULL});
    CHECK_INT(r.status, REFRACT_E_SCENE_NOT_FOUND);
    CHECK_CONTAINS(r.err, "no_such_scene");
    cli_run_free(&r);

    snprintf(stdin_path, sizeof stdin_path, "%s/bad.json", d.dir);
    f = fopen(stdin_path, "w");
    fputs("{\"objects\": [{\"bounds\": {\"min\": [0, 0, 0], \"max\": [1, 1, 1]}, "
          "\"resolution\": 16, \"ior\": -2}]}",
          f);
    fclose(f);
    r = run_cli(&d, NULL, NULL, (const char *[]){"scene", "create", stdin_path, NULL});
    CHECK_INT(r.status, REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(r.err, "objects[0].ior");
    cli_run_free(&r);

    r = run_cli(&d, NULL, NULL, (const char *[]){"render", id, NULL}); /* no -o */
    CHECK_INT(r.status, REFRACT_E_USAGE);
    CHECK_CONTAINS(r.err, "-o");
    cli_run_free(&r);

    r = run_cli(&d, NULL, NULL, (const char *[]){"rendr", id, NULL});
    CHECK_INT(r.status, REFRACT_E_USAGE);
    cli_run_free(&r);

    /* a port nothing listens on: port 1 is privileged and unused on a test machine */
    r = run_cli(&d, "http://127.0.0.1:1", NULL, (const char *[]){"health", NULL});
    CHECK_INT(r.status, REFRACT_E_CONNECT_FAILED);
    CHECK_CONTAINS(r.err, "127.0.0.1:1");
    cli_run_free(&r);

    /* light and irradiance: mistakes on the command line are usage errors (24) that name
     * what is wrong, found before anything is sent */
    static const struct {
        const char *args[10];
        const char *says;
    } usage_cases[] = {
        {{"light", NULL}, "missing the command (set or list)"},
        {{"light", "move", NULL}, "unknown light command 'move'"},
        {{"light", "set", "s", NULL}, "missing the light NAME"},
        {{"light", "set", "s", "sun", "--type", "lamp", NULL}, "got 'lamp'"},
        {{"light", "set", "s", "sun", "--type", "directional", "--position", "0,2,0", NULL},
         "--position does not apply to a directional light"},
        {{"light", "set", "s", "sun", "--wait", "--no-wait", NULL}, "contradict"},
        {{"light", "set", "s", "sun", "--color", "1,1", NULL}, "--color: "},
        {{"light", "set", "s", "sun", "--intensty", "2", NULL}, "did you mean '--intensity'?"},
        {{"light", "list", NULL}, "missing the scene ID"},
        {{"irradiance", "status", NULL}, "missing the scene ID"},
        {{"irradiance", "get", "s", "sun", NULL}, "missing -o FILE"},
        {{"irradiance", "get", "s", "sun", "-o", "sun.png", NULL}, "name it .exr"},
    };
    for (size_t i = 0; i < sizeof usage_cases / sizeof usage_cases[0]; i++) {
        r = run_cli(&d, "http://127.0.0.1:1", NULL, usage_cases[i].args);
        CHECK_MSG(r.status == REFRACT_E_USAGE, "refract %s %s: exit %d", usage_cases[i].args[0],
                  usage_cases[i].args[1] ? usage_cases[i].args[1] : "", r.status);
        CHECK_CONTAINS(r.err, usage_cases[i].says);
        CHECK_CONTAINS(r.err, "Run 'refract help ");
        cli_run_free(&r);
    }
    r = run_cli(&d, NULL, NULL, (const char *[]){"help", "light", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, "--no-wait");
    cli_run_free(&r);
    r = run_cli(&d, NULL, NULL, (const char *[]){"light", "list", small_id, NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, "\"lights\":[]");
    cli_run_free(&r);
    r = run_cli(&d, NULL, NULL, (const char *[]){"light", "list", "no_such_scene", NULL});
    CHECK_INT(r.status, REFRACT_E_SCENE_NOT_FOUND);
    cli_run_free(&r);

    /* delete, then it is gone */
    r = run_cli(&d, NULL, NULL, (const char *[]){"scene", "delete", small_id, NULL});
    CHECK_INT(r.status, 0);
    cli_run_free(&r);
    r = run_cli(&d, NULL, NULL, (const char *[]){"scene", "show", small_id, NULL});
    CHECK_INT(r.status, REFRACT_E_SCENE_NOT_FOUND);
    cli_run_free(&r);

    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_cli");
}
