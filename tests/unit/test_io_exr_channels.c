/*
 * test_io_exr_channels.c - multi-channel float EXR in memory (io_exr.h), the format of the
 * irradiance volumes:
 *   - a round trip of 7 named channels is bit-exact, in the order asked for (not the
 *     file's sorted order), over several scanline chunks, with a string attribute;
 *   - asking for a subset reads just those channels;
 *   - a missing channel, bytes that are not EXR, a truncated file and an image over
 *     max_pixels are refused with INVALID_IMAGE / LIMIT_EXCEEDED, never a crash;
 *   - io_encode_exr (RGBA frames) still decodes through the same reader.
 */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/io_exr.h"
#include "io/io_image.h"
#include "test.h"

static const char *const names[] = {"R", "G", "B", "dir.X", "dir.Y", "dir.Z", "dir.W"};

int main(void)
{
    const int w = 5, h = 37, n = 7; /* 37 rows: three 16-line ZIP chunks, the last short */
    float *px = malloc(sizeof(float) * (size_t)(w * h * n));
    for (int i = 0; i < w * h * n; i++)
        px[i] = (float)(sin(0.37 * i) * pow(10.0, (i % 9) - 4)); /* signs and magnitudes */
    px[3] = 0.0f;
    px[4] = -0.0f;
    const char *attrs[] = {"refract.grid", "{\"dims\": [5, 37, 1]}", NULL};
    void *bytes = NULL;
    size_t len = 0;
    struct err e = {0};
    CHECK_INT(io_encode_exr_channels(px, w, h, n, names, attrs, &bytes, &len, &e), REFRACT_E_OK);

    float *back = NULL;
    int bw = 0, bh = 0;
    char attr[128];
    CHECK_INT(io_decode_exr_channels(bytes, len, n, names, 1 << 20, &back, &bw, &bh, "refract.grid",
                                     attr, sizeof attr, &e),
              REFRACT_E_OK);
    CHECK_INT(bw, w);
    CHECK_INT(bh, h);
    CHECK_STR(attr, "{\"dims\": [5, 37, 1]}");
    CHECK(back && memcmp(back, px, sizeof(float) * (size_t)(w * h * n)) == 0);
    free(back);

    /* A subset, in another order. */
    static const char *const two[] = {"dir.Y", "R"};
    CHECK_INT(
        io_decode_exr_channels(bytes, len, 2, two, 1 << 20, &back, &bw, &bh, NULL, NULL, 0, &e),
        REFRACT_E_OK);
    bool same = back != NULL;
    for (int i = 0; same && i < w * h; i++)
        same = back[i * 2] == px[i * n + 4] && back[i * 2 + 1] == px[i * n];
    CHECK(same);
    free(back);

    /* Refusals. */
    static const char *const missing[] = {"R", "dir.Q"};
    CHECK_INT(
        io_decode_exr_channels(bytes, len, 2, missing, 1 << 20, &back, &bw, &bh, NULL, NULL, 0, &e),
        REFRACT_E_INVALID_IMAGE);
    CHECK(strstr(e.msg, "dir.Q") != NULL);
    CHECK(back == NULL);
    CHECK_INT(io_decode_exr_channels("not an exr", 10, n, names, 1 << 20, &back, &bw, &bh, NULL,
                                     NULL, 0, &e),
              REFRACT_E_INVALID_IMAGE);
    CHECK_INT(io_decode_exr_channels(bytes, len / 2, n, names, 1 << 20, &back, &bw, &bh, NULL, NULL,
                                     0, &e),
              REFRACT_E_INVALID_IMAGE);
    CHECK(back == NULL);
    CHECK_INT(io_decode_exr_channels(bytes, len, n, names, 100, &back, &bw, &bh, NULL, NULL, 0, &e),
              REFRACT_E_LIMIT_EXCEEDED);
    free(bytes);

    /* A frame from io_encode_exr reads back through the same reader. */
    float rgba[4 * 6] = {0.5f, 1.5f, 2.5f, 1.0f, 3.0f, 4.0f, 5.0f, 1.0f};
    CHECK_INT(io_encode_exr(rgba, 3, 2, &bytes, &len, &e), REFRACT_E_OK);
    static const char *const rgba_names[] = {"R", "G", "B", "A"};
    CHECK_INT(io_decode_exr_channels(bytes, len, 4, rgba_names, 1 << 20, &back, &bw, &bh, NULL,
                                     NULL, 0, &e),
              REFRACT_E_OK);
    CHECK(back && memcmp(back, rgba, sizeof rgba) == 0);
    free(back);
    free(bytes);
    free(px);
    return test_summary("test_io_exr_channels");
}
