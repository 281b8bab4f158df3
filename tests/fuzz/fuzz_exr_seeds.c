/*
 * fuzz_exr_seeds.c - writes the seed corpus of fuzz_exr (tests/fuzz/corpus/exr/) with the
 * server's own EXR encoder (server/io/exr_write.c): a single-part slice atlas of one
 * channel, the same with R, G, B, and a multi-part file (one part per slice). Each file
 * gets fuzz_exr.c's 4 bytes of query in front. Not a test and not run by CI: run it when
 * the formats change.
 *
 *     build-fuzz/tests/fuzz/fuzz_exr_seeds tests/fuzz/corpus/exr
 */
#include <stdio.h>
#include <stdlib.h>

#include "io/io_exr.h"

static int put(const char *dir, const char *name, const unsigned char query[4], void *bytes,
               size_t len)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    int ok = f != NULL && fwrite(query, 1, 4, f) == 4 && fwrite(bytes, 1, len, f) == len;
    if (f != NULL && fclose(f) != 0)
        ok = 0;
    free(bytes);
    if (!ok)
        fprintf(stderr, "fuzz_exr_seeds: cannot write %s\n", path);
    return ok ? 0 : 1;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: fuzz_exr_seeds CORPUS_DIR\n");
        return 2;
    }
    enum { X = 3, Y = 2, Z = 2 };
    float px[X * Y * Z * 3];
    for (int i = 0; i < X * Y * Z * 3; i++)
        px[i] = 0.25f * (float)i;
    const char *const y_name[] = {"Y"};
    const char *const rgb[] = {"R", "G", "B"};
    const char *const attrs[] = {"refract.seed", "1", NULL};
    struct err e = {0};
    void *bytes = NULL;
    size_t len = 0;
    int failed = 0;
    /* query byte 0: bit 2 = dims from bytes 1..3, low 2 bits = components (fuzz_exr.c) */
    if (io_encode_exr_channels(px, X, Y * Z, 1, y_name, attrs, &bytes, &len, &e) == REFRACT_E_OK)
        failed |= put(argv[1], "atlas_y", (const unsigned char[4]){4 | 1, X, Y, Z}, bytes, len);
    else
        failed = 1;
    if (io_encode_exr_channels(px, X, Y * Z, 3, rgb, NULL, &bytes, &len, &e) == REFRACT_E_OK)
        failed |= put(argv[1], "atlas_rgb", (const unsigned char[4]){4 | 0, X, Y, Z}, bytes, len);
    else
        failed = 1;
    if (io_encode_exr_parts(px, X, Y, Z, 3, rgb, NULL, &bytes, &len, &e) == REFRACT_E_OK)
        failed |= put(argv[1], "parts_rgb", (const unsigned char[4]){3, 0, 0, 0}, bytes, len);
    else
        failed = 1;
    if (io_encode_exr_parts(px, X, Y, Z, 1, y_name, NULL, &bytes, &len, &e) == REFRACT_E_OK)
        failed |= put(argv[1], "parts_y", (const unsigned char[4]){0, 0, 0, 0}, bytes, len);
    else
        failed = 1;
    if (failed)
        fprintf(stderr, "fuzz_exr_seeds: %s\n", e.msg[0] ? e.msg : "a write failed");
    return failed;
}
