/*
 * test_cli_upload.c - `refract upload` ($REFRACT_CLI, the real binary) against a real
 * refractd (docs/cli.md "upload"):
 *   - a raw float32 volume, a gzip NRRD volume, an OBJ mesh and a PNG environment
 *     image, each told apart by its extension, are stored; the answer on stdout carries
 *     the sha256 refractd documents (docs/api.md: a volume's stored float32 data, a
 *     mesh's and an image's file as sent), which equals the one sha256sum computes
 *     over the bytes the test wrote, and the volume's FNV-1a 64 equals the test's own;
 *   - the progress on stderr (not a terminal) is a line per 10 %, percentages never
 *     going back, the last one 100 %; --quiet prints none;
 *   - a raw file whose size is not --dims times --type is refused here with exit 17
 *     (invalid_volume) and nothing is sent: against an address where nothing listens the
 *     exit is still 17, not 21 (connect_failed), and the real daemon has no such volume;
 *     so is a detached NRRD header;
 *   - refractd's 4xx come back with their code and message: a NaN-filled volume (17,
 *     the voxel named) and an OBJ with a bad index (26, the line named);
 *   - a name that does not say the kind (.exr, no extension) is a usage error (24).
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon.h"
#include "io/io_image.h"
#include "support_cli.h"
#include "test.h"
#include "upload_util.h"

#define N 48 /* voxels per axis of the raw volume: 48^3 float32 = 432 KiB */

static const char *const scene_json =
    "{\"name\": \"cli uploads\", \"environment\": {\"type\": \"image\"},"
    " \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]},"
    " \"resolution\": 8, \"ior\": 1.2}]}";

static struct test_daemon d;
static char scene[REFRACT_ID_SIZE];

static void write_file(const char *path, const void *bytes, size_t len)
{
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL);
    if (f == NULL)
        return;
    CHECK(fwrite(bytes, 1, len, f) == len);
    fclose(f);
}

static void temp_path(char *out, size_t size, const char *name)
{
    snprintf(out, size, "%s/%s", d.dir, name);
}

static struct cli_run upload(const char *const *args)
{
    const char *argv[24] = {"upload", scene};
    int n = 2;
    for (int i = 0; args[i] != NULL && n < 23; i++)
        argv[n++] = args[i];
    argv[n] = NULL;
    return cli_run(&d, NULL, NULL, argv);
}

/* The "upload: P%" lines of stderr: at least two (0 % and 100 %), P never decreasing,
 * the last 100. */
static void check_progress_lines(const char *what, const char *err)
{
    int lines = 0, last = -1;
    bool monotone = true;
    for (const char *p = strstr(err, "upload: "); p != NULL; p = strstr(p + 1, "upload: ")) {
        int pct = -1;
        if (sscanf(p, "upload: %d%%", &pct) != 1)
            continue;
        monotone = monotone && pct >= last;
        last = pct;
        lines++;
    }
    CHECK_MSG(lines >= 2 && monotone && last == 100, "%s: %d progress lines, last %d%%: %s", what,
              lines, last, err);
}

static void check_sha(const char *what, const char *reply, const char *file_with_the_bytes)
{
    char want[65], got[80];
    upload_sha256sum(file_with_the_bytes, want);
    upload_json_string(reply, "sha256", got, sizeof got);
    CHECK_MSG(strlen(want) == 64 && strcmp(want, got) == 0, "%s: sha256 %s, sha256sum says %s",
              what, got, want);
}

static float *ramp(size_t count)
{
    float *v = malloc(count * sizeof *v);
    for (size_t i = 0; i < count; i++)
        v[i] = 1.0f + 0.5f * (float)i / (float)count;
    return v;
}

static void raw_volume(void)
{
    size_t count = (size_t)N * N * N;
    float *v = ramp(count);
    char path[400];
    temp_path(path, sizeof path, "ior.raw");
    write_file(path, v, count * sizeof *v);
    struct cli_run r = upload((const char *[]){path, "--dims", "48,48,48", NULL});
    CHECK_MSG(r.status == 0, "raw: exit %d: %s", r.status, r.err);
    CHECK_CONTAINS(r.out, "\"name\":\"ior\"");
    CHECK_CONTAINS(r.out, "\"format\":\"raw\"");
    CHECK_CONTAINS(r.out, "\"dims\":[48,48,48]");
    check_sha("raw", r.out, path); /* float32 as sent is what is stored */
    char want[17], got[32];
    upload_fnv_hex(v, count, want);
    upload_json_string(r.out, "checksum_fnv1a64", got, sizeof got);
    CHECK_STR(got, want);
    check_progress_lines("raw", r.err);
    CHECK_CONTAINS(r.err, "MB/s");
    cli_run_free(&r);

    /* --quiet: the same answer, no progress */
    r = upload((const char *[]){path, "--volume", "quiet", "--dims", "48,48,48", "-q", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, "\"name\":\"quiet\"");
    CHECK_STR(r.err, "");
    cli_run_free(&r);
    free(v);
}

static void nrrd_gzip_volume(void)
{
    size_t count = 6 * 5 * 4;
    float *v = ramp(count);
    size_t zlen = 0;
    unsigned char *z = upload_gzip(v, count * sizeof *v, &zlen);
    static const char header[] = "NRRD0004\ntype: float\ndimension: 3\nsizes: 6 5 4\n"
                                 "endian: little\nencoding: gzip\n\n";
    size_t len = strlen(header) + zlen;
    unsigned char *file = malloc(len);
    memcpy(file, header, strlen(header));
    memcpy(file + strlen(header), z, zlen);
    char path[400], floats[400];
    temp_path(path, sizeof path, "density.nrrd");
    temp_path(floats, sizeof floats, "density.f32");
    write_file(path, file, len);
    write_file(floats, v, count * sizeof *v); /* what refractd stores and hashes */
    struct cli_run r = upload((const char *[]){path, NULL});
    CHECK_MSG(r.status == 0, "nrrd: exit %d: %s", r.status, r.err);
    CHECK_CONTAINS(r.out, "\"name\":\"density\"");
    CHECK_CONTAINS(r.out, "\"format\":\"nrrd\"");
    CHECK_CONTAINS(r.out, "\"dims\":[6,5,4]");
    check_sha("nrrd", r.out, floats);
    check_progress_lines("nrrd", r.err);
    cli_run_free(&r);

    /* a detached header is refused here */
    char nhdr[400];
    temp_path(nhdr, sizeof nhdr, "detached.nhdr");
    static const char detached[] = "NRRD0004\ntype: float\ndimension: 3\nsizes: 6 5 4\n"
                                   "encoding: raw\ndata file: detached.raw\n\n";
    write_file(nhdr, detached, strlen(detached));
    r = cli_run(&d, "http://127.0.0.1:1", NULL, (const char *[]){"upload", scene, nhdr, NULL});
    CHECK_INT(r.status, REFRACT_E_INVALID_VOLUME);
    CHECK_CONTAINS(r.err, "detached NRRD header");
    cli_run_free(&r);
    free(file);
    free(z);
    free(v);
}

static void obj_mesh(void)
{
    static const char obj[] = "# a tetrahedron\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                              "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    char path[400];
    temp_path(path, sizeof path, "tet.obj");
    write_file(path, obj, strlen(obj));
    struct cli_run r = upload((const char *[]){path, "--mesh", "gem", NULL});
    CHECK_MSG(r.status == 0, "obj: exit %d: %s", r.status, r.err);
    CHECK_CONTAINS(r.out, "\"name\":\"gem\"");
    CHECK_CONTAINS(r.out, "\"format\":\"obj\"");
    CHECK_CONTAINS(r.out, "\"triangles\":4");
    check_sha("obj", r.out, path);
    check_progress_lines("obj", r.err);
    cli_run_free(&r);

    /* refractd's 400 invalid_mesh, with the line it names */
    static const char bad[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n";
    temp_path(path, sizeof path, "bad.obj");
    write_file(path, bad, strlen(bad));
    r = upload((const char *[]){path, NULL});
    CHECK_INT(r.status, REFRACT_E_INVALID_MESH);
    CHECK_CONTAINS(r.err, "refract: line 4");
    CHECK_CONTAINS(r.err, "refers to vertex 9");
    cli_run_free(&r);

    /* volume flags make no sense for a mesh */
    r = upload((const char *[]){path, "--type", "uint8", NULL});
    CHECK_INT(r.status, REFRACT_E_USAGE);
    CHECK_CONTAINS(r.err, "--type applies to volumes only");
    cli_run_free(&r);
}

static void png_environment(void)
{
    enum { W = 16, H = 8 };
    uint8_t rgba[W * H * 4];
    for (int i = 0; i < W * H; i++) {
        rgba[4 * i + 0] = (uint8_t)(i * 2);
        rgba[4 * i + 1] = (uint8_t)(255 - i);
        rgba[4 * i + 2] = 90;
        rgba[4 * i + 3] = 255;
    }
    void *png = NULL;
    size_t len = 0;
    struct err e = {0};
    CHECK_INT(io_encode_png(rgba, W, H, &png, &len, &e), REFRACT_E_OK);
    char path[400];
    temp_path(path, sizeof path, "sky.png");
    write_file(path, png, len);
    free(png);
    struct cli_run r = upload((const char *[]){path, NULL});
    CHECK_MSG(r.status == 0, "png: exit %d: %s", r.status, r.err);
    CHECK_CONTAINS(r.out, "\"width\":16");
    CHECK_CONTAINS(r.out, "\"height\":8");
    check_sha("png", r.out, path);
    check_progress_lines("png", r.err);
    cli_run_free(&r);

    /* .exr could be either: the command line must say */
    temp_path(path, sizeof path, "sky.exr");
    write_file(path, "v/1\1", 4);
    r = upload((const char *[]){path, NULL});
    CHECK_INT(r.status, REFRACT_E_USAGE);
    CHECK_CONTAINS(r.err, "--environment");
    cli_run_free(&r);
}

static void wrong_raw_size_is_refused_before_sending(void)
{
    float v[2 * 2 * 3] = {0};
    char path[400];
    temp_path(path, sizeof path, "short.raw");
    write_file(path, v, sizeof v);
    /* nothing listens on port 1: had it connected, the exit would be 21 */
    struct cli_run r = cli_run(&d, "http://127.0.0.1:1", NULL,
                               (const char *[]){"upload", scene, path, "--dims", "2,2,4", NULL});
    CHECK_INT(r.status, REFRACT_E_INVALID_VOLUME);
    CHECK_CONTAINS(r.err, "has 48 bytes");
    CHECK_CONTAINS(r.err, "2*2*4*1*4 = 64 bytes of float32");
    CHECK_CONTAINS(r.err, "nothing was sent");
    cli_run_free(&r);
    /* the size of uint16 samples counts: 2*2*3*2 = 24 bytes, not 48 */
    r = upload((const char *[]){path, "--dims", "2,2,3", "--type", "uint16", NULL});
    CHECK_INT(r.status, REFRACT_E_INVALID_VOLUME);
    CHECK_CONTAINS(r.err, "= 24 bytes of uint16");
    cli_run_free(&r);
    /* and the daemon never heard of it */
    char *body = NULL, route[128];
    snprintf(route, sizeof route, "/v1/scenes/%s", scene);
    CHECK_INT(test_request(&d, "GET", route, NULL, &body), 200);
    CHECK(body != NULL && strstr(body, "\"short\"") == NULL);
    free(body);
    /* a raw file without --dims is a usage error */
    r = upload((const char *[]){path, NULL});
    CHECK_INT(r.status, REFRACT_E_USAGE);
    CHECK_CONTAINS(r.err, "needs --dims");
    cli_run_free(&r);
}

static void nan_volume_gets_refractds_error(void)
{
    float v[8] = {1, 1, 1, 1, 1, 1, 1, 1};
    v[5] = NAN;
    char path[400];
    temp_path(path, sizeof path, "nan.raw");
    write_file(path, v, sizeof v);
    struct cli_run r = upload((const char *[]){path, "--dims", "2,2,2", NULL});
    CHECK_INT(r.status, REFRACT_E_INVALID_VOLUME);
    CHECK_CONTAINS(r.err, "refract: value 5 (voxel x=1 y=0 z=1, component 0) is NaN");
    CHECK_STR(r.out, "");
    cli_run_free(&r);
}

int main(void)
{
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_cli_upload", d.why);
    if (!test_create_scene(&d, scene_json, scene))
        test_setup_failed("test_cli_upload", "could not create the scene");
    raw_volume();
    nrrd_gzip_volume();
    obj_mesh();
    png_environment();
    wrong_raw_size_is_refused_before_sending();
    nan_volume_gets_refractds_error();
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_cli_upload");
}
