/*
 * test_upload_bombs.c - with refractd's DEFAULT limits, small uploads that decode to huge
 * volumes or images are refused, each with 422 limit_exceeded naming the limit and its
 * flag, and the data directory is finite by default (issue 13, part 3):
 *   - nrrd_bomb_is_refused_naming_max_upload_voxels: 62 KB of gzip that a NRRD header
 *     says is 512 x 512 x 256 uint8 (64M voxels, a 256 MB float32 blob);
 *   - nrrd_whose_gzip_outgrows_its_header_is_stopped: a header of 64^3 over a gzip stream
 *     of 64 MB is stopped while it inflates (400 invalid_volume), nothing stored;
 *   - png_bomb_is_refused_naming_max_env_pixels: a 49 KB PNG of 4096 x 4096 pixels
 *     (256 MiB of float RGBA once decoded);
 *   - storage_is_finite_by_default: GET /v1/storage reports max_storage_bytes = 10 GiB;
 *   - a volume and an image just under the limits still upload (the limits are not off
 *     by one the wrong way, and the daemon is alive after the bombs).
 * The bombs are built here with zlib, so no file is committed.
 */
#include <cjson/cJSON.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <zlib.h>

#include "daemon.h"
#include "test.h"
#include "upload_util.h"

#define BOMB_SCENE                                                                                 \
    "{\"name\": \"bombs\", \"environment\": {\"type\": \"image\"}, \"objects\": [{\"bounds\": "    \
    "{\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, \"ior\": {\"shape\": "       \
    "\"sphere\", \"radius\": 0.8, \"inside\": 1.5}}]}"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* A NRRD file: header for sizes x y z uint8, gzip data of `zeros` zero bytes. */
static unsigned char *nrrd_gzip_zeros(int x, int y, int z, size_t zeros, size_t *len)
{
    char header[256];
    int hn = snprintf(header, sizeof header,
                      "NRRD0004\ntype: uint8\ndimension: 3\nsizes: %d %d %d\nencoding: gzip\n\n", x,
                      y, z);
    unsigned char *raw = calloc(zeros, 1);
    size_t gz_len = 0;
    unsigned char *gz = raw ? upload_gzip(raw, zeros, &gz_len) : NULL;
    free(raw);
    unsigned char *file = gz ? malloc((size_t)hn + gz_len) : NULL;
    if (file) {
        memcpy(file, header, (size_t)hn);
        memcpy(file + hn, gz, gz_len);
        *len = (size_t)hn + gz_len;
    }
    free(gz);
    return file;
}

static void put_be32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)(v >> 24);
    p[1] = (unsigned char)(v >> 16);
    p[2] = (unsigned char)(v >> 8);
    p[3] = (unsigned char)v;
}

/* Appends a PNG chunk (length, type, data, CRC over type and data). */
static size_t png_chunk(unsigned char *out, const char *type, const unsigned char *data, size_t len)
{
    put_be32(out, (uint32_t)len);
    memcpy(out + 4, type, 4);
    if (len)
        memcpy(out + 8, data, len);
    uLong crc = crc32(0L, out + 4, (uInt)(4 + len));
    put_be32(out + 8 + len, (uint32_t)crc);
    return 12 + len;
}

/* A black 8-bit RGB PNG of w x h pixels (every row: filter 0 and zeros), deflated at
 * level 9 as a bomb would be. */
static unsigned char *png_black(int w, int h, size_t *len)
{
    size_t row = 1 + (size_t)w * 3, raw_len = row * (size_t)h;
    unsigned char *raw = calloc(raw_len, 1);
    uLongf z_len = compressBound((uLong)raw_len);
    unsigned char *z = malloc(z_len);
    if (raw == NULL || z == NULL || compress2(z, &z_len, raw, (uLong)raw_len, 9) != Z_OK) {
        free(raw);
        free(z);
        return NULL;
    }
    free(raw);
    unsigned char *png = malloc(8 + 25 + 12 + z_len + 12);
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    memcpy(png, sig, 8);
    unsigned char ihdr[13] = {0};
    put_be32(ihdr, (uint32_t)w);
    put_be32(ihdr + 4, (uint32_t)h);
    ihdr[8] = 8; /* bit depth */
    ihdr[9] = 2; /* RGB */
    size_t n = 8;
    n += png_chunk(png + n, "IHDR", ihdr, sizeof ihdr);
    n += png_chunk(png + n, "IDAT", z, z_len);
    n += png_chunk(png + n, "IEND", NULL, 0);
    free(z);
    *len = n;
    return png;
}

static void nrrd_bomb_is_refused_naming_max_upload_voxels(struct test_daemon *d, const char *id)
{
    size_t len = 0;
    unsigned char *bomb = nrrd_gzip_zeros(512, 512, 256, (size_t)512 * 512 * 256, &len);
    CHECK(bomb != NULL);
    if (bomb == NULL)
        return;
    printf("  NRRD bomb: %zu bytes of body for 512 x 512 x 256 voxels\n", len);
    CHECK(len < 100 * 1024);
    char path[256], *body = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s/volumes/bomb", id);
    double t0 = now_s();
    long status = upload_put(d, path, bomb, len, &body);
    printf("  refused in %.0f ms: %s\n", (now_s() - t0) * 1e3, body ? body : "(no body)");
    CHECK_INT(status, 422);
    CHECK(test_error_is(body, "limit_exceeded", "--max-upload-voxels"));
    CHECK(test_error_is(body, "limit_exceeded", "max_upload_voxels"));
    CHECK(test_error_is(body, "limit_exceeded", "67108864 voxels"));
    free(body);
    free(bomb);
}

static void nrrd_whose_gzip_outgrows_its_header_is_stopped(struct test_daemon *d, const char *id)
{
    size_t len = 0;
    unsigned char *liar = nrrd_gzip_zeros(64, 64, 64, (size_t)64 << 20, &len);
    CHECK(liar != NULL);
    if (liar == NULL)
        return;
    char path[256], *body = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s/volumes/liar", id);
    long status = upload_put(d, path, liar, len, &body);
    CHECK_INT(status, 400);
    CHECK(test_error_is(body, "invalid_volume", "holds more than the 262144 bytes"));
    free(body);
    body = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s", id);
    CHECK_INT(test_request(d, "GET", path, NULL, &body), 200);
    CHECK(body != NULL && strstr(body, "\"liar\"") == NULL);
    free(body);
    free(liar);
}

static void png_bomb_is_refused_naming_max_env_pixels(struct test_daemon *d, const char *id)
{
    size_t len = 0;
    unsigned char *bomb = png_black(4096, 4096, &len);
    CHECK(bomb != NULL);
    if (bomb == NULL)
        return;
    printf("  PNG bomb: %zu bytes of body for 4096 x 4096 pixels\n", len);
    CHECK(len < 100 * 1024);
    char path[256], *body = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s/environment", id);
    long status = upload_put(d, path, bomb, len, &body);
    CHECK_INT(status, 422);
    CHECK(test_error_is(body, "limit_exceeded", "--max-env-pixels"));
    CHECK(test_error_is(body, "limit_exceeded", "16777216 pixels"));
    free(body);
    free(bomb);
}

static void storage_is_finite_by_default(struct test_daemon *d)
{
    char *body = NULL;
    CHECK_INT(test_request(d, "GET", "/v1/storage", NULL, &body), 200);
    CHECK_NEAR(upload_json_number(body, "max_storage_bytes"), 10737418240.0, 0.5);
    free(body);
}

static void uploads_under_the_limits_still_work(struct test_daemon *d, const char *id)
{
    size_t len = 0;
    unsigned char *ok = nrrd_gzip_zeros(32, 32, 32, 32 * 32 * 32, &len);
    char path[256], *body = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s/volumes/small", id);
    CHECK_INT(upload_put(d, path, ok, len, &body), 201);
    free(body);
    free(ok);
    unsigned char *png = png_black(64, 32, &len);
    snprintf(path, sizeof path, "/v1/scenes/%s/environment", id);
    body = NULL;
    CHECK_INT(upload_put(d, path, png, len, &body), 201);
    free(body);
    free(png);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL)) /* the defaults are what is tested */
        test_setup_failed("test_upload_bombs", d.why);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, BOMB_SCENE, id));
    nrrd_bomb_is_refused_naming_max_upload_voxels(&d, id);
    nrrd_whose_gzip_outgrows_its_header_is_stopped(&d, id);
    png_bomb_is_refused_naming_max_env_pixels(&d, id);
    storage_is_finite_by_default(&d);
    uploads_under_the_limits_still_work(&d, id);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_upload_bombs");
}
