/*
 * test_volume_formats.c - PUT /v1/scenes/{id}/volumes/{name} stores what each format
 * holds, and answers each bad file with its precise 4xx (docs/api.md, "Volume uploads"):
 *   - every format round-trips: raw float32, float16, uint8 and uint16 (with scale and
 *     offset), NRRD raw and gzip (little- and big-endian, scalar and RGB), OpenEXR one
 *     slice per part and slice atlas; the 201's checksum equals the FNV-1a 64 the test
 *     computes itself over the values it meant to send, and so do dims, components,
 *     min and max, and GET /v1/scenes/{id} lists the same checksum;
 *   - truncated, oversized, mis-typed, NaN-filled and lying-header files, detached and
 *     corrupt NRRDs, unknown query parameters and unphysical values each get their own
 *     status, error code and a message naming the problem.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon.h"
#include "io/io_exr.h"
#include "test.h"
#include "upload_util.h"

#define NX 5
#define NY 4
#define NZ 3
#define NV (NX * NY * NZ)

/* A scene whose object uses volume "n" for its ior (scale 1, offset 0) and "a" for its
 * attenuation; other names are free. */
static const char *const scene_json =
    "{\"name\": \"formats\", \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1],"
    " \"max\": [1, 1, 1]}, \"resolution\": 4, \"ior\": {\"volume\": \"n\"},"
    " \"attenuation\": {\"volume\": \"a\", \"scale\": 2.0}}]}";

static char scene_id[REFRACT_ID_SIZE];

/* Checks a 201 against the floats the upload meant to store. */
static void check_stored(const char *what, long status, const char *body, const float *want,
                         size_t count, int components)
{
    CHECK_MSG(status == 201, "%s: status %ld, body %s", what, status, body ? body : "");
    if (status != 201)
        return;
    char want_sum[17], got_sum[32];
    upload_fnv_hex(want, count, want_sum);
    upload_json_string(body, "checksum_fnv1a64", got_sum, sizeof got_sum);
    CHECK_MSG(strcmp(want_sum, got_sum) == 0, "%s: checksum %s, expected %s", what, got_sum,
              want_sum);
    double lo = want[0], hi = want[0];
    for (size_t i = 0; i < count; i++) {
        lo = fmin(lo, want[i]);
        hi = fmax(hi, want[i]);
    }
    CHECK_NEAR(upload_json_number(body, "min"), lo, 0.0);
    CHECK_NEAR(upload_json_number(body, "max"), hi, 0.0);
    CHECK_NEAR(upload_json_number(body, "components"), components, 0.0);
    CHECK_NEAR(upload_json_number(body, "bytes"), (double)(count * sizeof(float)), 0.0);
    CHECK_CONTAINS(body, "\"dims\":[5,4,3]");
    char sha[80];
    upload_json_string(body, "sha256", sha, sizeof sha);
    CHECK_INT((long long)strlen(sha), 64);
}

static long put(struct test_daemon *d, const char *name, const char *query, const void *bytes,
                size_t len, char **body)
{
    char path[512];
    snprintf(path, sizeof path, "/v1/scenes/%s/volumes/%s%s%s", scene_id, name, query[0] ? "?" : "",
             query);
    return upload_put(d, path, bytes, len, body);
}

static void raw_float32_round_trips(struct test_daemon *d)
{
    float v[NV];
    for (int i = 0; i < NV; i++)
        v[i] = 1.0f + 0.01f * (float)i;
    char *body = NULL;
    long st = put(d, "n", "dims=5,4,3&type=float32", v, sizeof v, &body);
    check_stored("raw float32", st, body, v, NV, 1);
    CHECK_CONTAINS(body, "\"format\":\"raw\"");
    free(body);
    /* The scene lists the stored volume with the same checksum. */
    char path[128], want[17];
    snprintf(path, sizeof path, "/v1/scenes/%s", scene_id);
    CHECK_INT(test_request(d, "GET", path, NULL, &body), 200);
    upload_fnv_hex(v, NV, want);
    CHECK_CONTAINS(body, want);
    free(body);
}

static void raw_float16_rgb_round_trips(struct test_daemon *d)
{
    /* Halves and the floats they are exactly. */
    static const uint16_t halves[] = {0x3C00, 0x3800, 0x4000, 0x3E00, 0x3400, 0x4200, 0x0000};
    static const float floats[] = {1.0f, 0.5f, 2.0f, 1.5f, 0.25f, 3.0f, 0.0f};
    uint16_t h[NV * 3];
    float want[NV * 3];
    for (int i = 0; i < NV * 3; i++) {
        h[i] = halves[i % 7];
        want[i] = floats[i % 7];
    }
    char *body = NULL;
    long st = put(d, "a", "dims=5,4,3&type=float16&components=3", h, sizeof h, &body);
    check_stored("raw float16 rgb", st, body, want, NV * 3, 3);
    CHECK_CONTAINS(body, "\"type\":\"float16\"");
    free(body);
}

static void raw_integers_scale_and_offset(struct test_daemon *d)
{
    unsigned char u8[NV];
    uint16_t u16[NV];
    float want8[NV], want16[NV];
    for (int i = 0; i < NV; i++) {
        u8[i] = (unsigned char)(i * 4);
        u16[i] = (uint16_t)(i * 1000);
        want8[i] = (float)(1.0 + 0.01 * u8[i]);
        want16[i] = (float)(1.0 + 1e-5 * u16[i]);
    }
    char *body = NULL;
    long st = put(d, "n", "dims=5,4,3&type=uint8&scale=0.01&offset=1", u8, sizeof u8, &body);
    check_stored("raw uint8", st, body, want8, NV, 1);
    free(body);
    st = put(d, "n", "dims=5,4,3&type=uint16&scale=1e-5&offset=1", u16, sizeof u16, &body);
    check_stored("raw uint16", st, body, want16, NV, 1);
    free(body);
}

/* A NRRD file: header lines + data. */
static unsigned char *nrrd(const char *header, const void *data, size_t len, size_t *out_len)
{
    size_t h = strlen(header);
    unsigned char *f = malloc(h + len);
    memcpy(f, header, h);
    memcpy(f + h, data, len);
    *out_len = h + len;
    return f;
}

static void nrrd_round_trips(struct test_daemon *d)
{
    float v[NV], big[NV];
    for (int i = 0; i < NV; i++) {
        v[i] = 1.2f + 0.005f * (float)i;
        uint32_t u;
        memcpy(&u, &v[i], 4);
        u = __builtin_bswap32(u);
        memcpy(&big[i], &u, 4);
    }
    size_t len = 0;
    unsigned char *f = nrrd("NRRD0004\n# made by the test\ntype: float\ndimension: 3\n"
                            "space: left-posterior-superior\nsizes: 5 4 3\nendian: little\n"
                            "encoding: raw\nspacings: 1 1 1\nkey:=value\n\n",
                            v, sizeof v, &len);
    char *body = NULL;
    long st = put(d, "n", "", f, len, &body); /* the format is detected */
    check_stored("nrrd raw little", st, body, v, NV, 1);
    CHECK_CONTAINS(body, "\"format\":\"nrrd\"");
    free(body);
    free(f);
    size_t zlen = 0;
    unsigned char *z = upload_gzip(big, sizeof big, &zlen);
    f = nrrd("NRRD0005\ntype: float\ndimension: 3\nsizes: 5 4 3\nendian: big\nencoding: gzip\n\n",
             z, zlen, &len);
    st = put(d, "n", "format=nrrd", f, len, &body);
    check_stored("nrrd gzip big", st, body, v, NV, 1);
    free(body);
    free(f);
    free(z);
    /* RGB uchar, the components axis first, with scale. */
    unsigned char rgb[NV * 3];
    float want[NV * 3];
    for (int i = 0; i < NV * 3; i++) {
        rgb[i] = (unsigned char)(i % 200);
        want[i] = (float)(0.5 * rgb[i]);
    }
    z = upload_gzip(rgb, sizeof rgb, &zlen);
    f = nrrd("NRRD0004\ntype: uchar\ndimension: 4\nsizes: 3 5 4 3\nkinds: RGB-color domain domain "
             "domain\nencoding: gz\n\n",
             z, zlen, &len);
    st = put(d, "a", "scale=0.5", f, len, &body);
    check_stored("nrrd gzip rgb uchar", st, body, want, NV * 3, 3);
    free(body);
    free(f);
    free(z);
}

static void exr_round_trips(struct test_daemon *d)
{
    float v[NV], rgb[NV * 3];
    for (int i = 0; i < NV; i++)
        v[i] = 1.0f + 0.25f * (float)(i % 9);
    for (int i = 0; i < NV * 3; i++)
        rgb[i] = 0.125f * (float)(i % 17);
    void *bytes = NULL;
    size_t len = 0;
    struct err e;
    static const char *const y[] = {"Y"}, *const rgbn[] = {"R", "G", "B"};
    /* Atlas: width X, height Y*Z; slice z in rows z*Y.. is the volume's own order. */
    CHECK_INT(io_encode_exr_channels(v, NX, NY * NZ, 1, y, NULL, &bytes, &len, &e), REFRACT_E_OK);
    char *body = NULL;
    long st = put(d, "n", "dims=5,4,3", bytes, len, &body);
    check_stored("exr atlas", st, body, v, NV, 1);
    CHECK_CONTAINS(body, "\"format\":\"exr\"");
    free(body);
    /* The atlas needs dims; the same file without them is refused. */
    st = put(d, "n", "format=exr", bytes, len, &body);
    CHECK_INT(st, 400);
    CHECK(test_error_is(body, "missing_field", "dims=X,Y,Z"));
    free(body);
    st = put(d, "n", "dims=5,4,2", bytes, len, &body);
    CHECK_INT(st, 400);
    CHECK(test_error_is(body, "invalid_volume", "slice atlas must be"));
    free(body);
    free(bytes);
    /* One slice per part, RGB. */
    CHECK_INT(io_encode_exr_parts(rgb, NX, NY, NZ, 3, rgbn, NULL, &bytes, &len, &e), REFRACT_E_OK);
    st = put(d, "a", "", bytes, len, &body);
    check_stored("exr parts rgb", st, body, rgb, NV * 3, 3);
    free(body);
    free(bytes);
}

/* ---- bad files ---- */

static void expect_error(struct test_daemon *d, const char *what, const char *name,
                         const char *query, const void *bytes, size_t len, long status,
                         const char *code, const char *needle)
{
    char *body = NULL;
    long st = put(d, name, query, bytes, len, &body);
    CHECK_MSG(st == status, "%s: status %ld, expected %ld (%s)", what, st, status,
              body ? body : "");
    CHECK_MSG(test_error_is(body, code, needle), "%s", what);
    free(body);
}

static void bad_files_get_precise_errors(struct test_daemon *d)
{
    float v[NV];
    for (int i = 0; i < NV; i++)
        v[i] = 1.5f;
    expect_error(d, "truncated raw", "n", "dims=5,4,3", v, sizeof v - 4, 400, "invalid_volume",
                 "the body has 236 bytes but dims=5,4,3");
    expect_error(d, "mis-typed raw", "n", "dims=5,4,3&type=float64", v, sizeof v, 400,
                 "invalid_field", "type");
    expect_error(d, "unknown query", "n", "dims=5,4,3&component=3", v, sizeof v, 400,
                 "unknown_field", "component");
    expect_error(d, "rgb for ior", "n", "dims=5,4,1&components=3", v, sizeof v, 400,
                 "invalid_volume", "scalar channel");
    float nan[NV];
    memcpy(nan, v, sizeof v);
    nan[NX * NY + NX + 2] = NAN; /* voxel x=2 y=1 z=1 */
    expect_error(d, "NaN", "n", "dims=5,4,3", nan, sizeof nan, 400, "invalid_volume",
                 "voxel x=2 y=1 z=1, component 0) is NaN");
    float low[NV];
    for (int i = 0; i < NV; i++)
        low[i] = 0.5f;
    expect_error(d, "ior below 1", "n", "dims=5,4,3", low, sizeof low, 400, "invalid_volume",
                 "outside the physical range of ior");
    for (int i = 0; i < NV; i++)
        low[i] = -0.25f; /* attenuation = 2 * sample < 0 */
    expect_error(d, "negative attenuation", "a", "dims=5,4,3", low, sizeof low, 400,
                 "invalid_volume", "objects[0].attenuation[0] uses volume \"a\"");
    static unsigned char big[70000];
    expect_error(d, "oversized", "x", "dims=70000,1,1&type=uint8", big, sizeof big, 413,
                 "body_too_large", "--max-upload-bytes");
    size_t len = 0;
    unsigned char *f = nrrd("NRRD0004\ntype: float\ndimension: 3\nsizes: 5 4 2\nendian: little\n"
                            "encoding: raw\n\n",
                            v, sizeof v, &len);
    expect_error(d, "lying nrrd header", "n", "", f, len, 400, "invalid_volume",
                 "the header does not describe the data");
    free(f);
    f = nrrd("NRRD0004\ntype: float\ndimension: 3\nsizes: 5 4 3\nendian: little\n"
             "encoding: raw\n\n",
             v, sizeof v - 40, &len);
    expect_error(d, "truncated nrrd", "n", "", f, len, 400, "invalid_volume", "truncated");
    free(f);
    f = nrrd("NRRD0004\ntype: int\ndimension: 3\nsizes: 5 4 3\nendian: little\nencoding: raw\n\n",
             v, sizeof v, &len);
    expect_error(d, "nrrd int", "n", "", f, len, 400, "invalid_volume", "NRRD type \"int\"");
    free(f);
    f = nrrd("NRRD0004\ntype: float\ndimension: 3\nsizes: 5 4 3\nendian: little\nencoding: raw\n"
             "data file: vol.raw\n\n",
             "", 0, &len);
    expect_error(d, "detached nrrd", "n", "", f, len, 400, "invalid_volume", "detached");
    free(f);
    f = nrrd("NRRD0004\ntype: float\ndimension: 3\nsizes: 5 4 3\nendain: little\nencoding: raw\n\n",
             v, sizeof v, &len);
    expect_error(d, "nrrd typo", "n", "", f, len, 400, "invalid_volume",
                 "\"endain\" is not a field");
    free(f);
    size_t zlen = 0;
    unsigned char *z = upload_gzip(v, sizeof v, &zlen);
    f = nrrd(
        "NRRD0004\ntype: float\ndimension: 3\nsizes: 5 4 3\nendian: little\nencoding: gzip\n\n", z,
        zlen / 2, &len);
    expect_error(d, "truncated gzip", "n", "", f, len, 400, "invalid_volume", "truncated");
    free(f);
    f = nrrd(
        "NRRD0004\ntype: float\ndimension: 3\nsizes: 5 4 1\nendian: little\nencoding: gzip\n\n", z,
        zlen, &len);
    expect_error(d, "lying gzip header", "n", "", f, len, 400, "invalid_volume", "more than");
    free(f);
    z[zlen / 2] ^= 0x5a;
    z[zlen / 2 + 1] ^= 0xa5;
    f = nrrd(
        "NRRD0004\ntype: float\ndimension: 3\nsizes: 5 4 3\nendian: little\nencoding: gzip\n\n", z,
        zlen, &len);
    char *body = NULL;
    long st = put(d, "n", "", f, len, &body);
    CHECK_INT(st, 400); /* corrupt deflate data, or a wrong CRC: either is invalid_volume */
    CHECK(test_error_is(body, "invalid_volume", "NRRD gzip"));
    free(body);
    free(f);
    free(z);
    expect_error(d, "not exr", "n", "format=exr&dims=5,4,3", v, sizeof v, 400, "invalid_volume",
                 "not an OpenEXR file");
    expect_error(d, "bad format", "n", "format=tiff", v, sizeof v, 400, "invalid_field",
                 "raw, nrrd or exr");
}

int main(void)
{
    struct test_daemon d;
    const char *const args[] = {"--max-upload-bytes", "65536", NULL};
    if (!test_daemon_start(&d, args))
        test_setup_failed("test_volume_formats", d.why);
    if (test_create_scene(&d, scene_json, scene_id)) {
        raw_float32_round_trips(&d);
        raw_float16_rgb_round_trips(&d);
        raw_integers_scale_and_offset(&d);
        nrrd_round_trips(&d);
        exr_round_trips(&d);
        bad_files_get_precise_errors(&d);
    }
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_volume_formats");
}
