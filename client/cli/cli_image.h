/*
 * cli_image.h - reads the pixel size of an encoded PNG, JPEG or OpenEXR image from its
 * header, so `refract render` can report "640x480" without decoding the image.
 *
 * Pure functions on a byte buffer (no I/O), compiled directly by the unit test.
 */
#ifndef CLI_IMAGE_H
#define CLI_IMAGE_H

#include <stdbool.h>
#include <stddef.h>

/* Finds the width and height in pixels of the PNG, JPEG or OpenEXR image in
 * bytes[0..len). Returns false when the format is not one of those or the header is cut
 * short or malformed; *width and *height are then left alone. */
bool cli_image_size(const void *bytes, size_t len, long *width, long *height);

#endif
