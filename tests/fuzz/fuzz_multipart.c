/*
 * fuzz_multipart.c - libFuzzer harness of librefract's multipart/x-mixed-replace parser
 * (client/multipart_parse.c), which reads refractd's MJPEG frame streams and so any bytes
 * a server or a proxy sends. docs/fuzzing.md.
 *
 * Input layout: byte 0 sets the chunk size of the feeds (1..256: a stream arrives split
 * anywhere); then the Content-Type header value up to the first '\n'; the rest is the
 * stream, followed by refract_multipart_finish.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "multipart_parse.h"

#define MAX_PART 4096 /* small, so that the part-size limit is reached */

/* Where the callbacks read every byte to (a body pointer into short or freed memory is
 * then an ASan report); volatile, so the reads are not optimised away. */
static volatile unsigned char touched;

static bool on_part(void *user, const struct refract_multipart_part *part)
{
    long *parts = user;
    if (part->index != *parts)
        abort(); /* parts are numbered in order */
    if (part->content_length >= 0 && (size_t)part->content_length != part->len)
        abort(); /* a sized part is delivered whole */
    if (part->len > MAX_PART)
        abort();
    /* Touch every byte: a body pointer into freed or short memory is an ASan report. */
    for (size_t i = 0; i < part->len; i++)
        touched ^= part->body[i];
    (*parts)++;
    return (part->len & 0xff) != 0x7f; /* sometimes stop, to run the STOPPED state */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    size_t chunk = (size_t)data[0] + 1;
    data++;
    size--;
    const uint8_t *nl = memchr(data, '\n', size);
    size_t ct_len = nl ? (size_t)(nl - data) : size;
    char *content_type = malloc(ct_len + 1);
    if (content_type == NULL)
        return 0;
    memcpy(content_type, data, ct_len);
    content_type[ct_len] = '\0';
    const uint8_t *stream = nl ? nl + 1 : data + size;
    size_t stream_len = (size_t)(data + size - stream);

    char boundary[REFRACT_MULTIPART_BOUNDARY_MAX + 1];
    char why[REFRACT_MULTIPART_WHY_SIZE];
    struct refract_multipart m;
    if (refract_multipart_boundary(content_type, boundary, sizeof boundary, why, sizeof why) &&
        refract_multipart_init(&m, boundary, MAX_PART)) {
        long parts = 0;
        enum refract_multipart_result r = REFRACT_MULTIPART_OK;
        for (size_t off = 0; off < stream_len && r == REFRACT_MULTIPART_OK; off += chunk) {
            size_t n = stream_len - off < chunk ? stream_len - off : chunk;
            /* Each chunk a private copy: the parser borrows it only until return. */
            uint8_t *piece = malloc(n);
            if (piece == NULL)
                break;
            memcpy(piece, stream + off, n);
            m.now_ms = (double)off;
            r = refract_multipart_feed(&m, piece, n, on_part, &parts);
            free(piece);
        }
        r = refract_multipart_finish(&m);
        if (r == REFRACT_MULTIPART_ERROR && m.why[0] == '\0')
            abort(); /* an error says why */
        if (parts != m.parts)
            abort();
        refract_multipart_fini(&m);
    }
    free(content_type);
    return 0;
}
