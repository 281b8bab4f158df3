/*
 * test_cli_job.c - `refract job` against a real refractd: submit from stdin prints only
 * the id; wait reports progress lines with an ETA and exits 0 when done; get saves every
 * frame as a PNG of the asked size; status and list print JSON; cancel of a finished job
 * deletes it (status then exits 5, not_found); a bad spec exits with refractd's code and
 * message; a missing --out is a usage error; submit --scene-file sends the file's document
 * as the job's inline scene.
 */
#include <sys/stat.h>

#include "jobs_util.h"
#include "support_cli.h"

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_cli_job", d.why);
    size_t len = 0;
    char *doc = test_read_source_file("proto/examples/glass_sphere.json", &len);
    char scene[REFRACT_ID_SIZE] = "";
    if (!doc || !test_create_scene(&d, doc, scene))
        test_setup_failed("test_cli_job", "could not create the scene");
    free(doc);
    char spec_path[400], out_dir[400];
    snprintf(spec_path, sizeof spec_path, "%s/job.json", d.dir);
    snprintf(out_dir, sizeof out_dir, "%s/frames", d.dir);
    FILE *f = fopen(spec_path, "w");
    CHECK(f != NULL);
    if (f) {
        fprintf(
            f, "{\"scene\": \"%s\", \"width\": 40, \"height\": 30, \"turntable\": {\"frames\": 4}}",
            scene);
        fclose(f);
    }
    struct cli_run r = cli_run(&d, NULL, spec_path, (const char *[]){"job", "submit", "-", NULL});
    CHECK_INT(r.status, 0);
    char id[64] = "";
    sscanf(r.out, "%63s", id);
    CHECK(id[0] == 'j' && strlen(id) == 17);
    cli_run_free(&r);

    r = cli_run(&d, NULL, NULL, (const char *[]){"job", "wait", id, NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.err, "4/4 frames");
    CHECK_CONTAINS(r.err, "ETA");
    cli_run_free(&r);

    r = cli_run(&d, NULL, NULL, (const char *[]){"job", "get", id, "--out", out_dir, NULL});
    CHECK_INT(r.status, 0);
    cli_run_free(&r);
    for (int n = 0; n < 4; n++) {
        char path[512];
        snprintf(path, sizeof path, "%s/frame_%05d.png", out_dir, n);
        FILE *png = fopen(path, "rb");
        CHECK_MSG(png != NULL, "%s was not saved", path);
        if (png == NULL)
            continue;
        unsigned char buf[1 << 16];
        size_t got = fread(buf, 1, sizeof buf, png);
        fclose(png);
        struct io_image img = {0};
        struct err e = {0};
        CHECK(io_image_decode(buf, got, 1 << 20, &img, &e) == REFRACT_E_OK);
        CHECK(img.width == 40 && img.height == 30);
        io_image_free(&img);
    }

    r = cli_run(&d, NULL, NULL, (const char *[]){"job", "status", id, NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, "\"state\":\"done\"");
    cli_run_free(&r);
    r = cli_run(&d, NULL, NULL, (const char *[]){"job", "list", "--state", "done", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, id);
    cli_run_free(&r);
    r = cli_run(&d, NULL, NULL, (const char *[]){"job", "list", "--state", "running", NULL});
    CHECK_INT(r.status, 0);
    CHECK(strstr(r.out, id) == NULL);
    cli_run_free(&r);

    r = cli_run(&d, NULL, NULL, (const char *[]){"job", "get", id, NULL});
    CHECK_INT(r.status, REFRACT_E_USAGE);
    CHECK_CONTAINS(r.err, "--out");
    cli_run_free(&r);

    r = cli_run(&d, NULL, NULL, (const char *[]){"job", "cancel", id, NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.err, "deleted job");
    cli_run_free(&r);
    r = cli_run(&d, NULL, NULL, (const char *[]){"job", "status", id, NULL});
    CHECK_INT(r.status, REFRACT_E_NOT_FOUND);
    cli_run_free(&r);

    f = fopen(spec_path, "w");
    if (f) {
        fprintf(f, "{\"scene\": \"%s\", \"turntable\": {\"frames\": 0}}", scene);
        fclose(f);
    }
    r = cli_run(&d, NULL, NULL, (const char *[]){"job", "submit", spec_path, NULL});
    CHECK_INT(r.status, REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(r.err, "turntable.frames");
    cli_run_free(&r);

    /* --scene-file: the job's scene is the document in the file (an inline scene). */
    char scene_path[400];
    snprintf(scene_path, sizeof scene_path, "%s/scene.json", d.dir);
    f = fopen(scene_path, "w");
    char *scene_doc = test_read_source_file("proto/examples/glass_sphere.json", &len);
    if (f && scene_doc)
        fputs(scene_doc, f);
    if (f)
        fclose(f);
    free(scene_doc);
    f = fopen(spec_path, "w");
    if (f) {
        fputs("{\"width\": 24, \"height\": 18, \"turntable\": {\"frames\": 2}}", f);
        fclose(f);
    }
    r = cli_run(&d, NULL, spec_path,
                (const char *[]){"job", "submit", "-", "--scene-file", scene_path, NULL});
    CHECK_INT(r.status, 0);
    char inline_id[64] = "";
    sscanf(r.out, "%63s", inline_id);
    cli_run_free(&r);
    r = cli_run(&d, NULL, NULL, (const char *[]){"job", "wait", inline_id, NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.err, "2/2 frames");
    cli_run_free(&r);
    r = cli_run(&d, NULL, NULL, (const char *[]){"job", "status", inline_id, NULL});
    CHECK_CONTAINS(r.out, "\"scene\":null");
    CHECK_CONTAINS(r.out, "\"inline_scene\":true");
    cli_run_free(&r);
    r = cli_run(&d, NULL, spec_path,
                (const char *[]){"job", "submit", "-", "--scene-file", spec_path, NULL});
    CHECK_INT(r.status, REFRACT_E_UNKNOWN_FIELD); /* a job spec is no scene document */
    CHECK_CONTAINS(r.err, "scene: unknown field \"width\"");
    cli_run_free(&r);
    r = cli_run(&d, NULL, NULL,
                (const char *[]){"job", "submit", spec_path, "--scene-file", out_dir, NULL});
    CHECK(r.status != 0); /* a directory is not a scene file */
    cli_run_free(&r);

    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_cli_job");
}
