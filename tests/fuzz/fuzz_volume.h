/*
 * fuzz_volume.h - what the volume harnesses (fuzz_nrrd.c, fuzz_raw.c, fuzz_exr.c) share:
 * the decoder of one format called on a private heap copy of the bytes, its output
 * written to /dev/null through the real sink (checks, hashes, writes).
 *
 * WHY the format decoders (volume_internal.h) and not io_volume_decode: that one maps
 * the upload file with mmap, and a read past the end of a mapping that stays inside its
 * last page is invisible to ASan; a heap copy of exactly `size` bytes makes every such
 * read a reported overflow. io_volume_decode adds nothing else (the map, the choice of
 * decoder, the canonical-source flag).
 *
 * Limits are smaller than refractd's (64 voxels per axis, 2^18 voxels) so that one input
 * stays fast; the limit checks themselves run as in refractd.
 */
#ifndef REFRACT_FUZZ_VOLUME_H
#define REFRACT_FUZZ_VOLUME_H

#include <fcntl.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "io/volume_internal.h"

typedef enum refract_code (*fuzz_volume_decoder)(const unsigned char *src, size_t len,
                                                 const struct io_volume_desc *d,
                                                 struct volume_sink *sink,
                                                 struct io_volume_info *info, struct err *e);

static inline struct io_volume_desc fuzz_volume_desc(enum io_volume_format format)
{
    return (struct io_volume_desc){.format = format,
                                   .scale = 1.0,
                                   .offset = 0.0,
                                   .max_resolution = 64,
                                   .max_voxels = 1 << 18,
                                   .max_upload_voxels = 1 << 18};
}

static inline void fuzz_volume_one(fuzz_volume_decoder decode, const struct io_volume_desc *d,
                                   const uint8_t *data, size_t size)
{
    /* The sink holds 1 MiB of output buffer: made once, like the /dev/null it writes to. */
    static struct volume_sink *sink;
    static int devnull = -1;
    if (sink == NULL) {
        sink = malloc(sizeof *sink);
        devnull = open("/dev/null", O_WRONLY | O_CLOEXEC);
        if (sink == NULL || devnull < 0)
            abort();
    }
    unsigned char *copy = malloc(size ? size : 1);
    if (copy == NULL)
        return;
    memcpy(copy, data, size);
    sink->fd = devnull;
    struct io_volume_info info;
    memset(&info, 0, sizeof info);
    struct err e = {0};
    enum refract_code rc = decode(copy, size, d, sink, &info, &e);
    if (rc == REFRACT_E_OK) {
        /* What was stored must be what the limits allow, with a consistent size. */
        long long voxels = (long long)info.dims[0] * info.dims[1] * info.dims[2];
        if (info.components != 1 && info.components != 3)
            abort();
        if (voxels < 1 || voxels > d->max_voxels)
            abort();
        if (info.bytes != (size_t)voxels * (size_t)info.components * sizeof(float))
            abort();
    } else if (e.msg[0] == '\0') {
        abort(); /* an error must say what was wrong */
    }
    free(copy);
}

#endif
