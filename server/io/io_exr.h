/*
 * io_exr.h - multi-channel float OpenEXR files in memory, with OpenEXR's C API: any set of
 * named 32-bit float channels, interleaved per pixel, plus string header attributes. The
 * irradiance cache stores and serves its volumes this way (docs/api.md, "Irradiance
 * volumes as EXR": slices stacked vertically, channels R, G, B, dir.X, dir.Y, dir.Z,
 * dir.W); io_encode_exr (io_image.h) is the RGBA case.
 *
 * Conventions: row 0 of the buffer is the top row of the image (EXR's y points down).
 * Ownership: encoders and decoders return new malloc'd buffers the caller frees.
 * Thread: any; no GL. Errors: REFRACT_E_INVALID_IMAGE for input that is not such a file
 * (not EXR, a channel missing, not FLOAT), REFRACT_E_LIMIT_EXCEEDED past max_pixels,
 * REFRACT_E_OUT_OF_MEMORY, REFRACT_E_INTERNAL with the library's message.
 */
#ifndef REFRACT_IO_EXR_H
#define REFRACT_IO_EXR_H

#include <stddef.h>

#include "../core/err.h"

/* pixels: width * height * nch floats; names: nch channel names; attrs: name, value, ...,
 * NULL (may be NULL) written as string attributes of the header. */
enum refract_code io_encode_exr_channels(const float *pixels, int width, int height, int nch,
                                         const char *const *names, const char *const *attrs,
                                         void **out_bytes, size_t *out_len, struct err *e);

/* The same as `parts` parts ("slice0", "slice1", ...) of width x height pixels each;
 * pixels holds the parts one after another. */
enum refract_code io_encode_exr_parts(const float *pixels, int width, int height, int parts,
                                      int nch, const char *const *names, const char *const *attrs,
                                      void **out_bytes, size_t *out_len, struct err *e);

/* Reads the channels `names` (nch of them, each must exist) of the file's first part into
 * *out_pixels (width * height * nch floats, interleaved in the order of names). When
 * attr_name is not NULL, the string attribute of that name is copied into attr_value
 * (empty when absent). */
enum refract_code io_decode_exr_channels(const void *bytes, size_t len, int nch,
                                         const char *const *names, long long max_pixels,
                                         float **out_pixels, int *width, int *height,
                                         const char *attr_name, char *attr_value, size_t attr_size,
                                         struct err *e);

#endif
