/*
 * io_image.h - images in and out of refractd: decoding uploaded environment maps
 * (OpenImageIO, behind the project's one C++ file), encoding rendered frames to PNG
 * and JPEG (OpenImageIO) and to linear float EXR (OpenEXR's C API), and the tone
 * mapping that turns linear radiance into display pixels.
 *
 * Conventions: pixel buffers are row-major with row 0 at the TOP of the image,
 * 4 components per pixel (RGBA). Float images are linear radiance. 8-bit images are
 * sRGB-encoded.
 *
 * Ownership: every encoder returns a new malloc'd buffer in *out_bytes that the caller
 * frees with free(). io_image_free releases what io_image_decode made.
 * Thread: any; no GL. Errors: REFRACT_E_INVALID_IMAGE for undecodable input,
 * REFRACT_E_OUT_OF_MEMORY, REFRACT_E_INTERNAL for encoder failures (with the library's
 * message), REFRACT_E_INVALID_FIELD from an encoder given a side < 1 or a JPEG quality
 * outside 1..100.
 */
#ifndef REFRACT_IO_IMAGE_H
#define REFRACT_IO_IMAGE_H

#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"

struct io_image {
    int width, height;
    float *rgba; /* width * height * 4 linear floats, row 0 at the top; owned */
};

/* Decodes an image held in memory: OpenEXR, Radiance .hdr, PNG or JPEG, recognised by
 * their first bytes (formats other than these four are refused, so an upload reaches
 * only their parsers). 8-bit sRGB formats are converted to linear; 1-3 channel images
 * are expanded to RGBA (grey -> RGB, alpha = 1). Rejects images larger than max_pixels
 * (width * height) with REFRACT_E_LIMIT_EXCEEDED, and non-finite pixel values with
 * REFRACT_E_INVALID_IMAGE. */
enum refract_code io_image_decode(const void *bytes, size_t len, long long max_pixels,
                                  struct io_image *out, struct err *e);
void io_image_free(struct io_image *img);

/* Tests only: when on is non-zero, decoding and PNG/JPEG encoding on the calling thread
 * go through a temporary file even where OIIO could use memory, so the tests cover
 * that fallback. Per thread; default off. */
void io_image_test_force_tempfile(int on);

enum io_tonemap { IO_TONEMAP_CLAMP = 0, IO_TONEMAP_FILMIC = 1 };

/* Linear RGBA float -> sRGB RGBA8: v = tonemap(2^exposure_ev * L), then the sRGB
 * transfer function (IEC 61966-2-1), rounded to nearest. CLAMP clamps v to [0, 1];
 * FILMIC applies Narkowicz's ACES fit (x(2.51x+0.03))/(x(2.43x+0.59)+0.14).
 * Alpha is written as 255. Non-finite inputs become 0. */
void io_tonemap_srgb8(const float *rgba, int width, int height, double exposure_ev,
                      enum io_tonemap tonemap, uint8_t *out_rgba8);

/* Exact inverse pieces, exposed for tests: sRGB transfer of a linear value in [0,1]
 * and its inverse. */
double io_srgb_encode(double linear);
double io_srgb_decode(double encoded);

/* RGBA8 -> PNG bytes (8-bit RGB, alpha dropped). */
enum refract_code io_encode_png(const uint8_t *rgba8, int width, int height, void **out_bytes,
                                size_t *out_len, struct err *e);
/* RGBA8 -> baseline JPEG bytes, quality 1..100. */
enum refract_code io_encode_jpeg(const uint8_t *rgba8, int width, int height, int quality,
                                 void **out_bytes, size_t *out_len, struct err *e);
enum io_frame_format { IO_FRAME_PNG = 0, IO_FRAME_JPEG = 1, IO_FRAME_EXR = 2 };

/* A rendered frame (linear RGBA float) in one of the output formats: EXR as linear
 * floats; PNG and JPEG tone-mapped first (io_tonemap_srgb8 with exposure_ev and tonemap;
 * jpeg_quality for JPEG). The one path POST /render, view frames and batch jobs share. */
enum refract_code io_encode_frame(const float *rgba, int width, int height,
                                  enum io_frame_format format, double exposure_ev,
                                  enum io_tonemap tonemap, int jpeg_quality, void **out_bytes,
                                  size_t *out_len, struct err *e);

/* Linear RGBA float -> OpenEXR bytes: channels R, G, B, A as 32-bit FLOAT, scanline,
 * ZIP compression, written with OpenEXR's C API (openexr.h) to memory. */
enum refract_code io_encode_exr(const float *rgba, int width, int height, void **out_bytes,
                                size_t *out_len, struct err *e);

#endif
