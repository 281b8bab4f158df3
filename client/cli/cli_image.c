/*
 * cli_image.c - image size from the first bytes of a PNG, JPEG or OpenEXR file.
 *
 * Only headers are read, each the way its specification lays it out:
 *   PNG:  the 8-byte signature, then the IHDR chunk: width and height, big-endian
 *         uint32, at offsets 16 and 20 (PNG spec 11.2.2).
 *   JPEG: markers from SOI until a start-of-frame (SOF0..SOF15 except DHT C4, JPG C8 and
 *         DAC CC), whose segment holds precision, height, width (ITU T.81 B.2.2).
 *   EXR:  magic 76 2f 31 01, a version word, then attributes "name\0type\0size value"
 *         until an empty name; dataWindow (box2i: xMin yMin xMax yMax, little-endian
 *         int32) gives the size (OpenEXR file layout, "Header").
 * This is not a validator: the server produced the bytes, and a wrong guess only
 * changes a line printed to stderr.
 */
#include "cli_image.h"

#include <stdint.h>
#include <string.h>

static uint32_t be32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

static uint32_t be16(const unsigned char *p)
{
    return (uint32_t)p[0] << 8 | p[1];
}

static int32_t le32(const unsigned char *p)
{
    uint32_t u = (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
    int32_t v;

    memcpy(&v, &u, 4); /* two's complement reinterpretation without UB */
    return v;
}

static bool png_size(const unsigned char *b, size_t len, long *w, long *h)
{
    static const unsigned char signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

    if (len < 24 || memcmp(b, signature, 8) != 0 || memcmp(b + 12, "IHDR", 4) != 0)
        return false;
    *w = (long)be32(b + 16);
    *h = (long)be32(b + 20);
    return true;
}

static bool is_sof(unsigned char marker)
{
    return marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
}

static bool jpeg_size(const unsigned char *b, size_t len, long *w, long *h)
{
    size_t pos = 2;

    if (len < 4 || b[0] != 0xFF || b[1] != 0xD8)
        return false;
    while (pos + 4 <= len) {
        unsigned char marker;
        size_t seg;

        if (b[pos] != 0xFF)
            return false;
        while (pos < len && b[pos] == 0xFF) /* fill bytes */
            pos++;
        if (pos >= len)
            return false;
        marker = b[pos++];
        if (marker == 0x01 || (marker >= 0xD0 && marker <= 0xD8))
            continue; /* markers without a length */
        if (marker == 0xD9 || marker == 0xDA || pos + 2 > len)
            return false; /* end of image or scan data before any frame header */
        seg = be16(b + pos);
        if (is_sof(marker)) {
            if (seg < 7 || pos + 7 > len)
                return false;
            *h = (long)be16(b + pos + 3);
            *w = (long)be16(b + pos + 5);
            return true;
        }
        pos += seg;
    }
    return false;
}

static bool exr_size(const unsigned char *b, size_t len, long *w, long *h)
{
    static const unsigned char magic[4] = {0x76, 0x2F, 0x31, 0x01};
    size_t pos = 8;

    if (len < 8 || memcmp(b, magic, 4) != 0)
        return false;
    while (pos < len && b[pos] != '\0') {
        const unsigned char *name = b + pos;
        const unsigned char *nul = memchr(name, '\0', len - pos);
        const unsigned char *type;
        int32_t size;

        if (nul == NULL)
            return false;
        pos = (size_t)(nul - b) + 1;
        type = memchr(b + pos, '\0', len - pos);
        if (type == NULL)
            return false;
        pos = (size_t)(type - b) + 1;
        if (pos + 4 > len)
            return false;
        size = le32(b + pos);
        pos += 4;
        if (size < 0 || (size_t)size > len - pos)
            return false;
        if (strcmp((const char *)name, "dataWindow") == 0 && size == 16) {
            int64_t x_min = le32(b + pos), y_min = le32(b + pos + 4);
            int64_t x_max = le32(b + pos + 8), y_max = le32(b + pos + 12);

            *w = (long)(x_max - x_min + 1);
            *h = (long)(y_max - y_min + 1);
            return true;
        }
        pos += (size_t)size;
    }
    return false;
}

bool cli_image_size(const void *bytes, size_t len, long *width, long *height)
{
    const unsigned char *b = bytes;

    if (b == NULL)
        return false;
    return png_size(b, len, width, height) || jpeg_size(b, len, width, height) ||
           exr_size(b, len, width, height);
}
