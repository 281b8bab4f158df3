/*
 * fuzz_sse.c - libFuzzer harness of librefract's text/event-stream parser
 * (client/sse_parse.c), which reads refractd's GET /v1/events streams and so any bytes a
 * server or a proxy sends. docs/fuzzing.md.
 *
 * Input layout: byte 0 sets the chunk size of the feeds (1..256: a stream arrives split
 * anywhere, a CRLF across two chunks included); byte 1 the parser's max_bytes (64..16384,
 * small so that the line and event limits are reached); the rest is the stream, followed
 * by refract_sse_finish.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "sse_parse.h"

/* Where the callbacks read every byte to (a body pointer into short or freed memory is
 * then an ASan report); volatile, so the reads are not optimised away. */
static volatile char touched;

static bool on_event(void *user, const struct refract_sse_event *ev)
{
    size_t max_bytes = *(const size_t *)user;
    if (ev->type[0] == '\0' || strlen(ev->type) >= REFRACT_SSE_TYPE_MAX)
        abort();
    if (strlen(ev->id) >= REFRACT_SSE_ID_MAX)
        abort();
    if (ev->data[ev->data_len] != '\0' || ev->data_len > max_bytes)
        abort(); /* data is NUL-terminated at data_len, within the limit */
    for (size_t i = 0; i < ev->data_len; i++)
        touched ^= ev->data[i];
    return ev->data_len != 13; /* sometimes stop, to run the STOPPED state */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2)
        return 0;
    size_t chunk = (size_t)data[0] + 1;
    size_t max_bytes = 64 + (size_t)data[1] * 64;
    data += 2;
    size -= 2;
    struct refract_sse p;
    refract_sse_init(&p, max_bytes);
    enum refract_sse_result r = REFRACT_SSE_OK;
    for (size_t off = 0; off < size && r == REFRACT_SSE_OK; off += chunk) {
        size_t n = size - off < chunk ? size - off : chunk;
        uint8_t *piece = malloc(n); /* borrowed only until return: a private copy */
        if (piece == NULL)
            break;
        memcpy(piece, data + off, n);
        r = refract_sse_feed(&p, piece, n, on_event, &max_bytes);
        free(piece);
    }
    bool partial = false;
    r = refract_sse_finish(&p, &partial);
    if (r == REFRACT_SSE_ERROR && p.why[0] == '\0')
        abort();
    refract_sse_fini(&p);
    return 0;
}
