/*
 * volume_internal.h - what the volume decoders (volume_raw.c, volume_nrrd.c,
 * volume_exr.c) share: the sink that validates, hashes and writes canonical float32
 * samples, and the sample converters. Not used outside server/io/.
 */
#ifndef REFRACT_IO_VOLUME_INTERNAL_H
#define REFRACT_IO_VOLUME_INTERNAL_H

#include "io_volume.h"

#define VOLUME_SINK_FLOATS (256 * 1024) /* 1 MiB of output per write */

/* INVARIANT: `written` samples have been checked, hashed and either written to fd or
 * (verify-only, fd < 0) only checked; buf holds `used` of them not yet written. */
struct volume_sink {
    int fd; /* -1: verify only */
    double scale, offset;
    int components;
    size_t expected; /* samples (voxels * components) */
    size_t written;
    float buf[VOLUME_SINK_FLOATS];
    size_t used;
    int comp; /* component of the next sample */
    struct sha256 sha;
    uint64_t fnv;
    double min[3], max[3];
    int dims[3];
};

void volume_sink_init(struct volume_sink *s, int fd, const int dims[3], int components,
                      double scale, double offset);
/* Adds one sample (before scale and offset). INVALID_VOLUME for a non-finite value
 * (naming its voxel) or too many samples; STORAGE when writing fails. */
enum refract_code volume_sink_put(struct volume_sink *s, double sample, struct err *e);
/* Flushes and checks that exactly `expected` samples arrived; fills info. */
enum refract_code volume_sink_finish(struct volume_sink *s, struct io_volume_info *info,
                                     struct err *e);

/* Converts n samples of type t from little- or big-endian bytes into the sink. */
enum refract_code volume_sink_put_bytes(struct volume_sink *s, enum io_sample_type t,
                                        bool big_endian, const unsigned char *bytes, size_t n,
                                        struct err *e);
size_t volume_sample_size(enum io_sample_type t);
float volume_half_to_float(uint16_t h);

/* Shared checks of dims and components against the limits. */
enum refract_code volume_check_dims(const struct io_volume_desc *d, const int dims[3],
                                    int components, const char *where, struct err *e);

enum refract_code volume_decode_raw(const unsigned char *src, size_t len,
                                    const struct io_volume_desc *d, struct volume_sink *sink,
                                    struct io_volume_info *info, struct err *e);
enum refract_code volume_decode_nrrd(const unsigned char *src, size_t len,
                                     const struct io_volume_desc *d, struct volume_sink *sink,
                                     struct io_volume_info *info, struct err *e);
enum refract_code volume_decode_exr(const unsigned char *src, size_t len,
                                    const struct io_volume_desc *d, struct volume_sink *sink,
                                    struct io_volume_info *info, struct err *e);

#endif
