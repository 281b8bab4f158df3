/*
 * io_frame.c - a rendered frame into PNG, JPEG or EXR bytes (io_image.h, io_encode_frame).
 */
#include <stdlib.h>

#include "io_image.h"

enum refract_code io_encode_frame(const float *rgba, int width, int height,
                                  enum io_frame_format format, double exposure_ev,
                                  enum io_tonemap tonemap, int jpeg_quality, void **out_bytes,
                                  size_t *out_len, struct err *e)
{
    if (format == IO_FRAME_EXR)
        return io_encode_exr(rgba, width, height, out_bytes, out_len, e);
    uint8_t *px = malloc((size_t)width * (size_t)height * 4);
    if (px == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory encoding a %dx%d image", width,
                       height);
    io_tonemap_srgb8(rgba, width, height, exposure_ev, tonemap, px);
    enum refract_code rc =
        format == IO_FRAME_JPEG
            ? io_encode_jpeg(px, width, height, jpeg_quality, out_bytes, out_len, e)
            : io_encode_png(px, width, height, out_bytes, out_len, e);
    free(px);
    return rc;
}
