/*
 * io_image.c - the sRGB transfer function, tone mapping of linear radiance to display
 * pixels, and freeing decoded images.
 *
 * This file is pure C and arithmetic: no image library, no I/O. Decoding and the
 * PNG/JPEG encoders live in oiio_image.cpp (the project's one C++ file), the EXR
 * writer in exr_write.c.
 *
 * Rounding: io_tonemap_srgb8 must round sRGB(v) * 255 to nearest for every pixel of
 * every frame. Instead of a pow() per channel it compares the linear value against
 * the 255 linear thresholds decode((k + 0.5) / 255) (see srgb8_quantizer). Because
 * the transfer function is monotonic this gives exactly the rounded result (ties
 * aside) at a fraction of the cost.
 */
#include "io_image.h"

#include <math.h>
#include <stdlib.h>

/* IEC 61966-2-1:1999, section 5.2 (encode) and 5.3 (decode). The linear break point
 * 0.0031308 maps to the encoded break point 0.04045 (to about 1e-7; the standard's
 * constants are rounded, so the two pieces are continuous only to that precision). */
#define SRGB_LINEAR_BREAK 0.0031308
#define SRGB_ENCODED_BREAK 0.04045

double io_srgb_encode(double linear)
{
    if (!(linear > 0.0)) /* also catches NaN */
        return 0.0;
    if (linear >= 1.0)
        return 1.0;
    if (linear <= SRGB_LINEAR_BREAK)
        return 12.92 * linear;
    return 1.055 * pow(linear, 1.0 / 2.4) - 0.055;
}

double io_srgb_decode(double encoded)
{
    if (!(encoded > 0.0))
        return 0.0;
    if (encoded >= 1.0)
        return 1.0;
    if (encoded <= SRGB_ENCODED_BREAK)
        return encoded / 12.92;
    return pow((encoded + 0.055) / 1.055, 2.4);
}

/* Narkowicz 2015, "ACES Filmic Tone Mapping Curve": a rational fit of the ACES RRT +
 * ODT, applied to scene-linear x >= 0. Monotonic for x >= 0, f(0) = 0, and it tends
 * to 2.51 / 2.43 > 1, so the result is clamped to 1. */
static double filmic_aces(double x)
{
    if (isinf(x))
        return 1.0;
    double f = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
    return f < 1.0 ? f : 1.0;
}

/* Display value v in [0, 1] after tone mapping, from linear radiance and the exposure
 * scale. Non-finite radiance becomes 0 (the contract); a finite value that overflows
 * after scaling is merely bright and clamps to 1. */
static double display_value(float linear, double scale, enum io_tonemap tonemap)
{
    if (!isfinite(linear))
        return 0.0;
    double v = scale * (double)linear;
    if (!(v > 0.0))
        return 0.0;
    if (tonemap == IO_TONEMAP_FILMIC)
        return filmic_aces(v);
    return v < 1.0 ? v : 1.0;
}

/* The 8-bit quantizer: code k covers linear values in [thresholds[k-1], thresholds[k]),
 * where thresholds[k] = decode((k + 0.5) / 255) is the value at which code k rounds up
 * to k + 1. A coarse table gives the code at the start of each of QUANT_BINS equal
 * bins of [0, 1]; the code for v is that plus the few thresholds v passes inside its
 * bin. The steepest slope of 255 * encode is 12.92 * 255 = 3295 codes per unit (the
 * linear segment), so with 4096 bins a bin holds at most one threshold and the loop
 * runs at most once. */
#define QUANT_BINS 4096

struct srgb8_quantizer {
    double thresholds[255];
    uint8_t bin_code[QUANT_BINS];
};

static void quantizer_init(struct srgb8_quantizer *q)
{
    for (int k = 0; k < 255; k++)
        q->thresholds[k] = io_srgb_decode((k + 0.5) / 255.0);
    int code = 0;
    for (int b = 0; b < QUANT_BINS; b++) {
        double start = (double)b / QUANT_BINS;
        while (code < 255 && start >= q->thresholds[code])
            code++;
        q->bin_code[b] = (uint8_t)code;
    }
}

/* v in [0, 1] -> round(255 * encode(v)), exactly (up to ties at a threshold). */
static uint8_t quantize_srgb8(const struct srgb8_quantizer *q, double v)
{
    int bin = (int)(v * QUANT_BINS);
    if (bin >= QUANT_BINS)
        return 255;
    int code = q->bin_code[bin];
    while (code < 255 && v >= q->thresholds[code])
        code++;
    return (uint8_t)code;
}

void io_tonemap_srgb8(const float *rgba, int width, int height, double exposure_ev,
                      enum io_tonemap tonemap, uint8_t *out_rgba8)
{
    struct srgb8_quantizer q; /* 6 KB on the stack, rebuilt per call in about 10 us */
    quantizer_init(&q);

    double scale = exp2(exposure_ev);
    size_t n = (size_t)(width > 0 ? width : 0) * (size_t)(height > 0 ? height : 0);
    for (size_t i = 0; i < n; i++) {
        const float *px = rgba + 4 * i;
        uint8_t *out = out_rgba8 + 4 * i;
        for (int c = 0; c < 3; c++)
            out[c] = quantize_srgb8(&q, display_value(px[c], scale, tonemap));
        out[3] = 255;
    }
}

void io_image_free(struct io_image *img)
{
    if (img == NULL)
        return;
    free(img->rgba);
    img->rgba = NULL;
    img->width = 0;
    img->height = 0;
}
