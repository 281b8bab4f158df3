/*
 * io_volume.h - uploaded volume files decoded, validated and written out as the data
 * directory's canonical volume blob: little-endian float32, x fastest, then y, then z,
 * `components` floats per voxel (docs/api.md, "Volume uploads").
 *
 * Formats (the body of PUT /v1/scenes/{id}/volumes/{name}):
 *   raw   dims, type (float32, float16, uint8, uint16; little-endian), components from
 *         the query;
 *   NRRD  "NRRD000N" magic, a header of "field: value" lines, a blank line, then the
 *         data: type, dimension (3, or 4 with the components axis first), sizes, endian,
 *         encoding raw or gzip (volume_nrrd.c says which fields are read and which are
 *         refused);
 *   EXR   OpenEXR, HALF/FLOAT/UINT channels: one slice per part (part z is slice z,
 *         each X x Y), or a single-part slice atlas of width X and height Y*Z where
 *         slice z is rows z*Y .. z*Y+Y-1 (volume_exr.c).
 * Every sample becomes value = offset + scale * sample (scale 1, offset 0 by default).
 *
 * DESIGN: the source is a file (the request body as it was streamed to disk) read
 * through mmap, and the output goes to a file descriptor in chunks of 1 MiB, so no
 * step holds the whole volume in heap memory. The output is hashed (SHA-256, its
 * content address; FNV-1a 64, the checksum the API reports) and scanned (finite values,
 * per-component min and max) as it is written.
 *
 * Errors: REFRACT_E_INVALID_VOLUME for a file that is not what it says (the message
 * names the field or the byte offset and what was expected), REFRACT_E_INVALID_FIELD for
 * a bad query value, REFRACT_E_LIMIT_EXCEEDED past the voxel limits, REFRACT_E_STORAGE
 * when the output cannot be written. Thread: any.
 */
#ifndef REFRACT_IO_VOLUME_H
#define REFRACT_IO_VOLUME_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"
#include "../core/sha256.h"

enum io_volume_format { IO_VOLUME_RAW = 0, IO_VOLUME_NRRD = 1, IO_VOLUME_EXR = 2 };

enum io_sample_type {
    IO_SAMPLE_FLOAT32 = 0,
    IO_SAMPLE_FLOAT16 = 1,
    IO_SAMPLE_UINT8 = 2,
    IO_SAMPLE_UINT16 = 3,
    IO_SAMPLE_FLOAT64 = 4, /* NRRD "double" only */
    IO_SAMPLE_UINT32 = 5,  /* EXR UINT only */
};

/* What the request says about the file. Zero dims or components mean "from the file"
 * (required for raw). */
struct io_volume_desc {
    enum io_volume_format format;
    int dims[3];
    int components;           /* 1 or 3; 0 = from the file (raw: 1) */
    enum io_sample_type type; /* raw only */
    double scale, offset;     /* value = offset + scale * sample */
    int max_resolution;       /* voxels per axis */
    long long max_voxels;
    long long max_upload_voxels; /* decoded voxels of this upload; 0 = no limit */
};

/* What was stored. */
struct io_volume_info {
    int dims[3];
    int components;
    enum io_sample_type source_type;
    double min[3], max[3]; /* per component, after scale and offset */
    double min_all, max_all;
    uint64_t fnv1a64;             /* of the canonical bytes */
    char sha256[SHA256_HEX_SIZE]; /* of the canonical bytes */
    size_t bytes;                 /* canonical bytes: voxels * components * 4 */
};

/* Decodes the file src_path (src_bytes long) described by d, writing the canonical blob
 * to dst_fd. When the source already is the canonical blob (raw float32, scale 1, offset
 * 0), nothing is written and *source_is_canonical is set: the caller keeps the source
 * file (and its own hash of it) instead; info->sha256 is then empty. Borrows everything
 * until return. */
enum refract_code io_volume_decode(const char *src_path, const struct io_volume_desc *d, int dst_fd,
                                   struct io_volume_info *info, bool *source_is_canonical,
                                   struct err *e);

/* "float32", "float16", ... ; and the reverse (false when unknown). */
const char *io_sample_type_name(enum io_sample_type t);
bool io_sample_type_parse(const char *text, enum io_sample_type *out);
/* "raw", "nrrd", "exr" and the reverse. */
const char *io_volume_format_name(enum io_volume_format f);
bool io_volume_format_parse(const char *text, enum io_volume_format *out);

/* FNV-1a 64 offset basis and step, for checksums computed in pieces. */
#define IO_FNV1A64_INIT 14695981039346656037ull
uint64_t io_fnv1a64_update(uint64_t h, const void *data, size_t len);

#endif
