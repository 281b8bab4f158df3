/*
 * test_io_image.c - the sRGB transfer function, tone mapping, and image decoding and
 * encoding (server/io) against closed forms and exact round trips.
 *
 * Every image here is made by the test itself (our encoders, or a few bytes written
 * out below), so the test needs no files and no network. Temporary files from the
 * forced fallback path go to a private directory that must be empty afterwards.
 */
#include "io/io_image.h"
#include "test.h"

#include <dirent.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define NO_LIMIT (1LL << 40)

/* memmem, which glibc declares only under _GNU_SOURCE */
static const char *find_bytes(const char *hay, size_t len, const char *needle, size_t n)
{
    for (size_t i = 0; n <= len && i <= len - n; i++) {
        if (memcmp(hay + i, needle, n) == 0)
            return hay + i;
    }
    return NULL;
}

/* sRGB 8-bit code of a linear value, computed directly (the tonemapper's reference). */
static int srgb8_of(double linear)
{
    return (int)lrint(255.0 * io_srgb_encode(linear));
}

/* ---- sRGB transfer function (IEC 61966-2-1) ---------------------------------------- */

static void srgb_known_points_match_the_standard(void)
{
    CHECK(io_srgb_encode(0.0) == 0.0);
    CHECK(io_srgb_encode(1.0) == 1.0);
    CHECK(io_srgb_decode(0.0) == 0.0);
    CHECK(io_srgb_decode(1.0) == 1.0);
    /* The break point: 12.92 * 0.0031308 = 0.040449936 on the linear side; the power
     * side meets it to within 3e-8 (the standard's constants are rounded). */
    CHECK_NEAR(io_srgb_encode(0.0031308), 0.040449936, 1e-9);
    CHECK_NEAR(io_srgb_encode(0.0031308 + 1e-12), 0.040449936, 1e-6);
    CHECK_NEAR(io_srgb_decode(0.04045), 0.04045 / 12.92, 1e-12);
    CHECK_NEAR(io_srgb_decode(0.04045 + 1e-12), 0.0031308, 1e-7);
    /* Mid grey: 1.055 * 0.5^(1/2.4) - 0.055 = 0.735356983 */
    CHECK_NEAR(io_srgb_encode(0.5), 0.735356983, 1e-8);
    CHECK_NEAR(io_srgb_decode(0.735356983), 0.5, 1e-8);
    /* Linear segment slope */
    CHECK_NEAR(io_srgb_encode(0.001), 0.01292, 1e-12);
}

static void srgb_decode_inverts_encode_on_0_1(void)
{
    double worst = 0.0;
    for (int i = 0; i <= 100000; i++) {
        double x = i / 100000.0;
        double back = io_srgb_decode(io_srgb_encode(x));
        double err = fabs(back - x);
        if (err > worst)
            worst = err;
    }
    CHECK_MSG(worst < 1e-12, "worst round-trip error %.3g", worst);
    /* and encoded -> linear -> encoded */
    worst = 0.0;
    for (int k = 0; k <= 255; k++) {
        double err = fabs(io_srgb_encode(io_srgb_decode(k / 255.0)) - k / 255.0);
        if (err > worst)
            worst = err;
    }
    CHECK_MSG(worst < 1e-12, "worst 8-bit round-trip error %.3g", worst);
}

static void srgb_clamps_outside_0_1_and_nan(void)
{
    CHECK(io_srgb_encode(-0.5) == 0.0);
    CHECK(io_srgb_encode(2.0) == 1.0);
    CHECK(io_srgb_encode(NAN) == 0.0);
    CHECK(io_srgb_decode(-0.5) == 0.0);
    CHECK(io_srgb_decode(7.0) == 1.0);
}

/* ---- tone mapping ------------------------------------------------------------------ */

/* Tone maps one grey pixel and returns its R code (all three are checked equal). */
static int tonemap_one(float linear, double ev, enum io_tonemap tm)
{
    float px[4] = {linear, linear, linear, 0.25f};
    uint8_t out[4] = {1, 2, 3, 4};
    io_tonemap_srgb8(px, 1, 1, ev, tm, out);
    CHECK(out[0] == out[1] && out[1] == out[2]);
    CHECK_INT(out[3], 255);
    return out[0];
}

static void tonemap_clamp_maps_known_values(void)
{
    CHECK_INT(tonemap_one(1.0f, 0.0, IO_TONEMAP_CLAMP), 255);
    CHECK_INT(tonemap_one(0.0f, 0.0, IO_TONEMAP_CLAMP), 0);
    /* 255 * 0.735357 = 187.516 -> 188 */
    CHECK_INT(tonemap_one(0.5f, 0.0, IO_TONEMAP_CLAMP), 188);
    CHECK_INT(tonemap_one(0.5f, 0.0, IO_TONEMAP_CLAMP), srgb8_of(0.5));
    CHECK_INT(tonemap_one(7.5f, 0.0, IO_TONEMAP_CLAMP), 255);
    CHECK_INT(tonemap_one(3e38f, 0.0, IO_TONEMAP_CLAMP), 255);
}

static void tonemap_exposure_plus_one_doubles_linear_value(void)
{
    for (int i = 1; i <= 200; i++) {
        float l = i / 400.0f; /* 0.0025 .. 0.5: 2l stays below clipping */
        CHECK_INT(tonemap_one(l, 1.0, IO_TONEMAP_CLAMP), tonemap_one(2 * l, 0.0, IO_TONEMAP_CLAMP));
        CHECK_INT(tonemap_one(2 * l, -1.0, IO_TONEMAP_CLAMP),
                  tonemap_one(l, 0.0, IO_TONEMAP_CLAMP));
    }
    CHECK_INT(tonemap_one(0.25f, 1.0, IO_TONEMAP_CLAMP), 188);
    CHECK_INT(tonemap_one(0.5f, 1.0, IO_TONEMAP_CLAMP), 255);
}

static void tonemap_rounds_like_the_direct_formula(void)
{
    /* The tonemapper quantizes by threshold search; it must agree with
     * round(255 * encode(v)) everywhere (ties have measure zero). */
    int mismatches = 0;
    for (int i = 0; i <= 20000; i++) {
        float l = (float)i / 20000.0f;
        if (tonemap_one(l, 0.0, IO_TONEMAP_CLAMP) != srgb8_of(l))
            mismatches++;
    }
    /* and finely where codes are densest (the linear segment: 3295 codes per unit) */
    for (int i = 0; i <= 20000; i++) {
        float l = (float)i * 1e-6f;
        if (tonemap_one(l, 0.0, IO_TONEMAP_CLAMP) != srgb8_of(l))
            mismatches++;
    }
    CHECK_INT(mismatches, 0);
}

static void tonemap_turns_negative_and_non_finite_into_zero(void)
{
    enum io_tonemap modes[2] = {IO_TONEMAP_CLAMP, IO_TONEMAP_FILMIC};
    for (int m = 0; m < 2; m++) {
        CHECK_INT(tonemap_one(-1.0f, 0.0, modes[m]), 0);
        CHECK_INT(tonemap_one(-INFINITY, 0.0, modes[m]), 0);
        CHECK_INT(tonemap_one(NAN, 0.0, modes[m]), 0);
        CHECK_INT(tonemap_one(INFINITY, 0.0, modes[m]), 0);
        CHECK_INT(tonemap_one(-0.0f, 3.0, modes[m]), 0);
    }
    /* Channels are independent: a NaN in G does not disturb R and B. */
    float px[4] = {1.0f, NAN, 0.5f, NAN};
    uint8_t out[4];
    io_tonemap_srgb8(px, 1, 1, 0.0, IO_TONEMAP_CLAMP, out);
    CHECK_INT(out[0], 255);
    CHECK_INT(out[1], 0);
    CHECK_INT(out[2], 188);
    CHECK_INT(out[3], 255);
}

static void tonemap_filmic_is_monotonic_and_below_white_for_moderate_values(void)
{
    CHECK_INT(tonemap_one(0.0f, 0.0, IO_TONEMAP_FILMIC), 0);
    int prev = 0;
    int non_monotonic = 0;
    for (int i = 0; i <= 4000; i++) {
        float l = i / 1000.0f; /* 0 .. 4 */
        int v = tonemap_one(l, 0.0, IO_TONEMAP_FILMIC);
        if (v < prev)
            non_monotonic++;
        prev = v;
        if (l <= 2.0f)
            CHECK_MSG(v < 255, "filmic(%g) = %d", l, v);
    }
    CHECK_INT(non_monotonic, 0);
    /* f(1) = 2.54 / 3.16 = 0.80380 -> sRGB 0.90767 -> 231 */
    CHECK_INT(tonemap_one(1.0f, 0.0, IO_TONEMAP_FILMIC), srgb8_of(2.54 / 3.16));
    /* Filmic compresses highlights that clamp would clip. */
    CHECK(tonemap_one(1.5f, 0.0, IO_TONEMAP_FILMIC) < 255);
    CHECK_INT(tonemap_one(1e30f, 0.0, IO_TONEMAP_FILMIC), 255);
}

/* ---- EXR --------------------------------------------------------------------------- */

/* Distinct values per pixel and channel: > 1, tiny, negative, a denormal. */
static float *make_float_image(int w, int h)
{
    float *px = malloc((size_t)w * h * 4 * sizeof(float));
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            float *p = px + 4 * ((size_t)y * w + x);
            float i = (float)(y * w + x);
            p[0] = 1000.0f + i * 3.25f;   /* R: large */
            p[1] = 1e-30f * (i + 1.0f);   /* G: tiny */
            p[2] = -0.125f * i + 0.0625f; /* B: crosses zero */
            p[3] = 1.0f / (i + 3.0f);     /* A: inexact in binary */
        }
    }
    px[1] = 1e-42f; /* G at (0,0): a denormal */
    return px;
}

static void *encode_exr_or_fail(const float *rgba, int w, int h, size_t *len)
{
    struct err e = {0};
    void *bytes = NULL;
    enum refract_code rc = io_encode_exr(rgba, w, h, &bytes, len, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "io_encode_exr: %d %s", rc, e.msg);
    return bytes;
}

static void exr_round_trip_is_bit_exact_with_row_0_at_top(int w, int h)
{
    float *src = make_float_image(w, h);
    size_t len = 0;
    unsigned char *bytes = encode_exr_or_fail(src, w, h, &len);
    CHECK(bytes != NULL && len > 4);
    if (bytes == NULL) {
        free(src);
        return;
    }
    CHECK(memcmp(bytes, "\x76\x2f\x31\x01", 4) == 0);

    struct io_image img;
    struct err e = {0};
    enum refract_code rc = io_image_decode(bytes, len, NO_LIMIT, &img, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "decode %dx%d EXR: %s", w, h, e.msg);
    CHECK_INT(img.width, w);
    CHECK_INT(img.height, h);
    if (rc == REFRACT_E_OK) {
        CHECK(memcmp(img.rgba, src, (size_t)w * h * 4 * sizeof(float)) == 0);
        /* Orientation spelled out: the first pixel in memory is (0,0) = top left, the
         * next row starts at index w. */
        CHECK(img.rgba[0] == 1000.0f);
        if (h > 1)
            CHECK(img.rgba[4 * w] == 1000.0f + 3.25f * (float)w);
        CHECK(img.rgba[4 * ((size_t)w * h - 1)] == 1000.0f + 3.25f * (w * h - 1));
    }
    io_image_free(&img);
    CHECK(img.rgba == NULL);
    free(bytes);
    free(src);
}

static void exr_encode_writes_float_abgr_zip_scanlines(void)
{
    float *src = make_float_image(7, 5);
    size_t len = 0;
    char *bytes = encode_exr_or_fail(src, 7, 5, &len);
    if (bytes != NULL) {
        /* The header is plain text attributes: look for the names and the channel list
         * in the order EXR requires (sorted: A, B, G, R), type 2 = FLOAT. */
        const char chlist[] = "A\0\2\0\0\0";
        CHECK(find_bytes(bytes, len, "channels\0chlist", 15) != NULL);
        CHECK(find_bytes(bytes, len, chlist, sizeof chlist - 1) != NULL);
        const char *a = find_bytes(bytes, len, "A\0\2\0\0\0", 6);
        const char *r = find_bytes(bytes, len, "R\0\2\0\0\0", 6);
        CHECK(a != NULL && r != NULL && a < r);
        /* compression attribute = 3 (ZIP_COMPRESSION, 16 scanlines per chunk) */
        CHECK(find_bytes(bytes, len, "compression\0compression\0\1\0\0\0\3", 29) != NULL);
    }
    free(bytes);
    free(src);
}

static void exr_encode_rejects_empty_size(void)
{
    float px[4] = {0};
    void *bytes = (void *)1;
    size_t len = 99;
    struct err e = {0};
    CHECK_INT(io_encode_exr(px, 0, 5, &bytes, &len, &e), REFRACT_E_INVALID_FIELD);
    CHECK(bytes == NULL && len == 0);
    CHECK_CONTAINS(e.msg, "0 x 5");
}

/* ---- PNG / JPEG -------------------------------------------------------------------- */

static uint8_t *make_rgba8(int w, int h)
{
    uint8_t *px = malloc((size_t)w * h * 4);
    for (int i = 0; i < w * h; i++) {
        px[4 * i + 0] = (uint8_t)(i * 7);
        px[4 * i + 1] = (uint8_t)(255 - i * 3);
        px[4 * i + 2] = (uint8_t)(i * i);
        px[4 * i + 3] = (uint8_t)(i * 13); /* dropped by the PNG encoder */
    }
    return px;
}

/* PNG bytes -> decode -> re-encode to sRGB 8-bit: every code must come back. */
static void check_png_round_trip(const uint8_t *src, int w, int h, const void *png, size_t len)
{
    struct io_image img;
    struct err e = {0};
    enum refract_code rc = io_image_decode(png, len, NO_LIMIT, &img, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "decode PNG: %s", e.msg);
    if (rc != REFRACT_E_OK)
        return;
    CHECK_INT(img.width, w);
    CHECK_INT(img.height, h);
    int wrong = 0;
    for (int i = 0; i < w * h; i++) {
        for (int c = 0; c < 3; c++) {
            if (srgb8_of(img.rgba[4 * i + c]) != src[4 * i + c])
                wrong++;
        }
        if (img.rgba[4 * i + 3] != 1.0f)
            wrong++;
    }
    CHECK_INT(wrong, 0);
    /* Decoded values are linear: code 188 would be ~0.5, not 0.737. */
    io_image_free(&img);
}

static void png_round_trip_returns_the_same_8bit_codes(void)
{
    int w = 13, h = 9;
    uint8_t *src = make_rgba8(w, h);
    src[0] = 188; /* pixel (0,0) R: linear 0.5 */
    void *png = NULL;
    size_t len = 0;
    struct err e = {0};
    enum refract_code rc = io_encode_png(src, w, h, &png, &len, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "io_encode_png: %s", e.msg);
    CHECK(len > 8 && memcmp(png, "\x89PNG", 4) == 0);
    if (rc == REFRACT_E_OK) {
        check_png_round_trip(src, w, h, png, len);
        struct io_image img;
        if (io_image_decode(png, len, NO_LIMIT, &img, &e) == REFRACT_E_OK) {
            /* linear, not the 0.737 code value; one code step here is 0.0047 linear */
            CHECK_NEAR(img.rgba[0], 0.5, 0.004);
            io_image_free(&img);
        }
    }
    free(png);
    free(src);
}

/* A 2x2 8-bit greyscale PNG (0, 64 / 128, 255) and a 2x1 grey+alpha PNG
 * ((200, a 51), (30, a 255)), written by hand (zlib + CRC) for the expansion rules. */
static const unsigned char grey_png[] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48, 0x44,
    0x52, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x02, 0x08, 0x00, 0x00, 0x00, 0x00, 0x57,
    0xdd, 0x52, 0xf8, 0x00, 0x00, 0x00, 0x0e, 0x49, 0x44, 0x41, 0x54, 0x78, 0xda, 0x63, 0x60,
    0x70, 0x60, 0x68, 0xf8, 0x0f, 0x00, 0x03, 0x05, 0x01, 0xc0, 0x53, 0x5b, 0x15, 0x9f, 0x00,
    0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
static const unsigned char grey_alpha_png[] = {
    0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x48,
    0x44, 0x52, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0x01, 0x08, 0x04, 0x00, 0x00,
    0x00, 0x5e, 0x2b, 0xb7, 0x01, 0x00, 0x00, 0x00, 0x0d, 0x49, 0x44, 0x41, 0x54, 0x78,
    0xda, 0x63, 0x38, 0x61, 0x2c, 0xf7, 0x1f, 0x00, 0x04, 0xf9, 0x02, 0x19, 0x73, 0x2b,
    0x4d, 0xc6, 0x00, 0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};

static void grey_png_expands_to_rgb_with_linear_alpha(void)
{
    struct io_image img;
    struct err e = {0};
    enum refract_code rc = io_image_decode(grey_png, sizeof grey_png, NO_LIMIT, &img, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "grey PNG: %s", e.msg);
    if (rc == REFRACT_E_OK) {
        static const int codes[4] = {0, 64, 128, 255};
        for (int i = 0; i < 4; i++) {
            double want = io_srgb_decode(codes[i] / 255.0);
            for (int c = 0; c < 3; c++)
                CHECK_NEAR(img.rgba[4 * i + c], want, 1e-7);
            CHECK(img.rgba[4 * i + 3] == 1.0f);
        }
        io_image_free(&img);
    }
    rc = io_image_decode(grey_alpha_png, sizeof grey_alpha_png, NO_LIMIT, &img, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "grey+alpha PNG: %s", e.msg);
    if (rc == REFRACT_E_OK) {
        CHECK_INT(img.width, 2);
        CHECK_INT(img.height, 1);
        CHECK_NEAR(img.rgba[0], io_srgb_decode(200 / 255.0), 1e-7);
        CHECK(img.rgba[1] == img.rgba[0] && img.rgba[2] == img.rgba[0]);
        CHECK_NEAR(img.rgba[3], 51 / 255.0, 1e-7); /* alpha is not sRGB-decoded */
        CHECK_NEAR(img.rgba[4], io_srgb_decode(30 / 255.0), 1e-7);
        CHECK_NEAR(img.rgba[7], 1.0, 1e-7);
        io_image_free(&img);
    }
}

/* JPEG at quality 90 of a smooth gradient: the size is exact, every re-encoded code is
 * within 6 of the input and the mean error is under 1.5 codes (measured with
 * libjpeg-turbo 2.1 and 4:2:0 chroma: max 5, mean 0.72). */
static void jpeg_decodes_a_smooth_gradient_near_its_input(void)
{
    int w = 64, h = 48;
    uint8_t *src = malloc((size_t)w * h * 4);
    for (int y = 0; y < h; y++) {
        for (int x = 0; x < w; x++) {
            uint8_t *p = src + 4 * (y * w + x);
            p[0] = (uint8_t)(40 + 2 * x);
            p[1] = (uint8_t)(60 + 3 * y);
            p[2] = (uint8_t)(100 + x + y);
            p[3] = 255;
        }
    }
    void *jpg = NULL;
    size_t len = 0;
    struct err e = {0};
    enum refract_code rc = io_encode_jpeg(src, w, h, 90, &jpg, &len, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "io_encode_jpeg: %s", e.msg);
    CHECK(len > 3 && memcmp(jpg, "\xff\xd8\xff", 3) == 0);
    struct io_image img;
    rc = io_image_decode(jpg, len, NO_LIMIT, &img, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "decode JPEG: %s", e.msg);
    if (rc == REFRACT_E_OK) {
        CHECK_INT(img.width, w);
        CHECK_INT(img.height, h);
        int worst = 0;
        long total = 0;
        for (int i = 0; i < w * h; i++) {
            for (int c = 0; c < 3; c++) {
                int d = abs(srgb8_of(img.rgba[4 * i + c]) - src[4 * i + c]);
                worst = d > worst ? d : worst;
                total += d;
            }
        }
        CHECK_MSG(worst <= 6, "worst JPEG error %d codes", worst);
        CHECK_MSG(total <= 1.5 * w * h * 3, "mean JPEG error %.3f codes",
                  (double)total / (w * h * 3));
        io_image_free(&img);
    }
    free(jpg);
    free(src);
}

static void encoders_reject_bad_arguments(void)
{
    uint8_t px[4] = {0};
    void *bytes = NULL;
    size_t len = 0;
    struct err e = {0};
    CHECK_INT(io_encode_jpeg(px, 1, 1, 0, &bytes, &len, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "1..100");
    CHECK_INT(io_encode_jpeg(px, 1, 1, 101, &bytes, &len, &e), REFRACT_E_INVALID_FIELD);
    CHECK_INT(io_encode_png(px, 1, 0, &bytes, &len, &e), REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "1 x 0");
    CHECK(bytes == NULL);
}

/* ---- Radiance RGBE ----------------------------------------------------------------- */

/* A 2x2 flat (not run-length encoded: width < 8) RGBE file. Value = mantissa *
 * 2^(exponent - 136) (Walter's rgbe.c; Radiance proper adds 0.5 to the mantissa, a
 * 0.4% difference at mantissa 128, inside the tolerance). */
static void radiance_hdr_decodes_rgbe_pixels_top_row_first(const char *magic)
{
    static const unsigned char pixels[16] = {
        128, 64,  32,  129, /* (0,0): 1, 0.5, 0.25 */
        128, 128, 128, 128, /* (1,0): 0.5 */
        128, 0,   0,   132, /* (0,1): 8, 0, 0 */
        0,   0,   0,   0,   /* (1,1): black */
    };
    static const float want[16] = {1, 0.5f, 0.25f, 1, 0.5f, 0.5f, 0.5f, 1, 8, 0, 0, 1, 0, 0, 0, 1};
    char file[128];
    int n = snprintf(file, sizeof file, "%s\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 2\n", magic);
    memcpy(file + n, pixels, sizeof pixels);

    struct io_image img;
    struct err e = {0};
    enum refract_code rc = io_image_decode(file, (size_t)n + sizeof pixels, NO_LIMIT, &img, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "decode %s: %s", magic, e.msg);
    if (rc != REFRACT_E_OK)
        return;
    CHECK_INT(img.width, 2);
    CHECK_INT(img.height, 2);
    for (int i = 0; i < 16; i++)
        CHECK_MSG(fabs(img.rgba[i] - want[i]) <= 0.005 * want[i] + 1e-6,
                  "%s sample %d: got %g, want %g", magic, i, img.rgba[i], want[i]);
    io_image_free(&img);
}

/* ---- rejections -------------------------------------------------------------------- */

static void check_rejected(const void *bytes, size_t len, long long max_pixels,
                           enum refract_code want, const char *what)
{
    struct io_image img = {.width = 5, .height = 5, .rgba = NULL};
    struct err e = {0};
    enum refract_code rc = io_image_decode(bytes, len, max_pixels, &img, &e);
    CHECK_MSG(rc == want, "%s: code %d, want %d (%s)", what, rc, want, e.msg);
    CHECK_MSG(e.code == want, "%s: e.code %d", what, e.code);
    CHECK_MSG(e.msg[0] != '\0', "%s: empty message", what);
    CHECK(img.rgba == NULL && img.width == 0 && img.height == 0);
}

static void decode_rejects_empty_random_and_truncated_input(void)
{
    check_rejected("", 0, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "empty");
    check_rejected(NULL, 0, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "NULL");

    unsigned char noise[1024];
    uint32_t s = 12345;
    for (size_t i = 0; i < sizeof noise; i++) {
        s = s * 1664525u + 1013904223u;
        noise[i] = (unsigned char)(s >> 24);
    }
    noise[0] = 0x42; /* no format begins with 'B' */
    check_rejected(noise, sizeof noise, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "random bytes");
    struct io_image img;
    struct err e = {0};
    io_image_decode(noise, sizeof noise, NO_LIMIT, &img, &e);
    CHECK_CONTAINS(e.msg, "first bytes: 42 ");

    /* A valid magic number followed by garbage */
    memcpy(noise, "\x89PNG\r\n\x1a\n", 8);
    check_rejected(noise, sizeof noise, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "PNG magic + noise");
    memcpy(noise, "\x76\x2f\x31\x01", 4);
    check_rejected(noise, sizeof noise, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "EXR magic + noise");

    int w = 40, h = 30;
    uint8_t *rgba8 = make_rgba8(w, h);
    void *png = NULL;
    size_t png_len = 0;
    if (io_encode_png(rgba8, w, h, &png, &png_len, &e) == REFRACT_E_OK) {
        check_rejected(png, png_len / 2, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "half a PNG");
        check_rejected(png, 40, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "PNG header only");
        check_rejected(png, png_len - 1, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "PNG less 1 byte");
        struct io_image img2;
        io_image_decode(png, png_len / 2, NO_LIMIT, &img2, &e);
        CHECK_CONTAINS(e.msg, "PNG is truncated");
    }
    free(png);

    /* libjpeg decodes a cut JPEG as grey with only a warning; we refuse it. */
    void *jpg = NULL;
    size_t jpg_len = 0;
    if (io_encode_jpeg(rgba8, w, h, 90, &jpg, &jpg_len, &e) == REFRACT_E_OK) {
        check_rejected(jpg, jpg_len / 2, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "half a JPEG");
        check_rejected(jpg, jpg_len - 2, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "JPEG less EOI");
    }
    free(jpg);
    free(rgba8);

    float *rgba = make_float_image(w, h);
    size_t exr_len = 0;
    void *exr = encode_exr_or_fail(rgba, w, h, &exr_len);
    if (exr != NULL) {
        check_rejected(exr, exr_len / 2, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "half an EXR");
        check_rejected(exr, exr_len - 8, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "EXR less 8 bytes");
        check_rejected(exr, 100, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "EXR header cut");
    }
    free(exr);
    free(rgba);
}

static void decode_rejects_images_over_max_pixels(void)
{
    float *rgba = make_float_image(7, 5);
    size_t len = 0;
    void *exr = encode_exr_or_fail(rgba, 7, 5, &len);
    if (exr != NULL) {
        check_rejected(exr, len, 34, REFRACT_E_LIMIT_EXCEEDED, "EXR of 35 pixels, limit 34");
        struct io_image img;
        struct err e = {0};
        io_image_decode(exr, len, 34, &img, &e);
        CHECK_CONTAINS(e.msg, "7 x 5 = 35 pixels");
        CHECK_CONTAINS(e.msg, "34");
        CHECK_INT(io_image_decode(exr, len, 35, &img, &e), REFRACT_E_OK);
        io_image_free(&img);
    }
    free(exr);
    free(rgba);

    uint8_t px[4 * 6] = {0};
    void *png = NULL;
    struct err e = {0};
    if (io_encode_png(px, 3, 2, &png, &len, &e) == REFRACT_E_OK)
        check_rejected(png, len, 5, REFRACT_E_LIMIT_EXCEEDED, "PNG of 6 pixels, limit 5");
    free(png);
}

static void decode_rejects_non_finite_exr_naming_the_pixel(void)
{
    int w = 7, h = 5;
    float *rgba = make_float_image(w, h);
    rgba[4 * (2 * w + 3) + 1] = NAN; /* (x=3, y=2) G */
    size_t len = 0;
    void *exr = encode_exr_or_fail(rgba, w, h, &len);
    if (exr != NULL) {
        check_rejected(exr, len, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "EXR with NaN");
        struct io_image img;
        struct err e = {0};
        io_image_decode(exr, len, NO_LIMIT, &img, &e);
        CHECK_CONTAINS(e.msg, "x=3, y=2");
        CHECK_CONTAINS(e.msg, "NaN");
    }
    free(exr);

    rgba[4 * (2 * w + 3) + 1] = 0.0f;
    rgba[4 * (4 * w + 6) + 3] = -INFINITY; /* (x=6, y=4) A, the last pixel */
    exr = encode_exr_or_fail(rgba, w, h, &len);
    if (exr != NULL) {
        struct io_image img;
        struct err e = {0};
        CHECK_INT(io_image_decode(exr, len, NO_LIMIT, &img, &e), REFRACT_E_INVALID_IMAGE);
        CHECK_CONTAINS(e.msg, "x=6, y=4");
        CHECK_CONTAINS(e.msg, "channel A");
    }
    free(exr);
    free(rgba);
}

/* ---- the temporary-file fallback --------------------------------------------------- */

static int dir_entry_count(const char *path)
{
    DIR *d = opendir(path);
    if (d == NULL)
        return -1;
    int n = 0;
    const struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        if (strcmp(ent->d_name, ".") != 0 && strcmp(ent->d_name, "..") != 0)
            n++;
    }
    closedir(d);
    return n;
}

static void tempfile_fallback_round_trips_and_cleans_up(void)
{
    char dir[] = "/tmp/refract-test-io-XXXXXX";
    if (mkdtemp(dir) == NULL) {
        CHECK_MSG(0, "mkdtemp failed");
        return;
    }
    const char *old = getenv("TMPDIR");
    char *saved = old ? strdup(old) : NULL;
    setenv("TMPDIR", dir, 1);
    io_image_test_force_tempfile(1);

    int w = 11, h = 6;
    uint8_t *src = make_rgba8(w, h);
    void *png = NULL;
    size_t len = 0;
    struct err e = {0};
    enum refract_code rc = io_encode_png(src, w, h, &png, &len, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "PNG via temp file: %s", e.msg);
    if (rc == REFRACT_E_OK)
        check_png_round_trip(src, w, h, png, len); /* decodes via a temp file too */
    if (rc == REFRACT_E_OK)
        check_rejected(png, len / 2, NO_LIMIT, REFRACT_E_INVALID_IMAGE, "half PNG, temp file");
    void *jpg = NULL;
    CHECK_INT(io_encode_jpeg(src, w, h, 75, &jpg, &len, &e), REFRACT_E_OK);
    free(jpg);
    free(png);
    free(src);
    io_image_test_force_tempfile(0);
    exr_round_trip_is_bit_exact_with_row_0_at_top(7, 5); /* and memory again */

    CHECK_INT(dir_entry_count(dir), 0);
    rmdir(dir);
    if (saved) {
        setenv("TMPDIR", saved, 1);
        free(saved);
    } else {
        unsetenv("TMPDIR");
    }
}

int main(void)
{
    srgb_known_points_match_the_standard();
    srgb_decode_inverts_encode_on_0_1();
    srgb_clamps_outside_0_1_and_nan();

    tonemap_clamp_maps_known_values();
    tonemap_exposure_plus_one_doubles_linear_value();
    tonemap_rounds_like_the_direct_formula();
    tonemap_turns_negative_and_non_finite_into_zero();
    tonemap_filmic_is_monotonic_and_below_white_for_moderate_values();

    exr_round_trip_is_bit_exact_with_row_0_at_top(7, 5);
    exr_round_trip_is_bit_exact_with_row_0_at_top(1, 1);
    exr_round_trip_is_bit_exact_with_row_0_at_top(33, 40); /* 3 ZIP chunks, last partial */
    exr_encode_writes_float_abgr_zip_scanlines();
    exr_encode_rejects_empty_size();

    png_round_trip_returns_the_same_8bit_codes();
    grey_png_expands_to_rgb_with_linear_alpha();
    jpeg_decodes_a_smooth_gradient_near_its_input();
    encoders_reject_bad_arguments();

    radiance_hdr_decodes_rgbe_pixels_top_row_first("#?RADIANCE");
    radiance_hdr_decodes_rgbe_pixels_top_row_first("#?RGBE");

    decode_rejects_empty_random_and_truncated_input();
    decode_rejects_images_over_max_pixels();
    decode_rejects_non_finite_exr_naming_the_pixel();

    tempfile_fallback_round_trips_and_cleans_up();
    return test_summary("test_io_image");
}
