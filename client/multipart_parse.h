/*
 * multipart_parse.h - a push parser for multipart/x-mixed-replace bodies (refractd's
 * MJPEG frame streams, docs/views.md "The stream"): bytes go in as they arrive, in
 * chunks split anywhere, and a callback gets every complete part with its headers.
 *
 * Pure byte work with no libcurl and no clock, so tests/unit/test_multipart_parse.c can
 * feed it streams split at every position. Internal to the client: refract_view_stream.c
 * drives it; it is not part of refract.h.
 *
 * What a stream looks like (RFC 2046 section 5.1.1, as refractd writes it):
 *
 *     --BOUNDARY\r\n                     boundary line (trailing blanks allowed)
 *     Content-Type: image/jpeg\r\n       part headers (LF alone is accepted too)
 *     Content-Length: 41234\r\n
 *     X-Frame-Seq: 7\r\n ...
 *     \r\n
 *     <41234 bytes>\r\n                  the body, then CRLF
 *     --BOUNDARY\r\n ...                 the next part, or --BOUNDARY-- to end
 *
 * A part with Content-Length is delivered as soon as its last byte arrived, without
 * waiting for the next boundary (which refractd sends only with the next frame); what
 * follows must then be blank lines and a boundary line, or the stream is in error (a
 * Content-Length that lied). A part without Content-Length ends at "\r\n--BOUNDARY".
 *
 * States (one at a time; FAILED and STOPPED are final):
 *   PREAMBLE   lines before the first boundary (at most REFRACT_MULTIPART_PREAMBLE_MAX bytes)
 *   HEADERS    header lines of a part, up to the blank line
 *   BODY_SIZED copying Content-Length bytes
 *   BODY_SCAN  copying bytes until the delimiter "\r\n--BOUNDARY"
 *   AFTER_BODY blank lines, then the next boundary line
 *   EPILOGUE   after "--BOUNDARY--": everything is ignored
 */
#ifndef REFRACT_MULTIPART_PARSE_H
#define REFRACT_MULTIPART_PARSE_H

#include <stdbool.h>
#include <stddef.h>

#define REFRACT_MULTIPART_BOUNDARY_MAX 70 /* RFC 2046: 1 to 70 characters */
#define REFRACT_MULTIPART_LINE_MAX 4096   /* a boundary or header line */
#define REFRACT_MULTIPART_PREAMBLE_MAX 65536
#define REFRACT_MULTIPART_WHY_SIZE 256

/* One complete part. body is borrowed: valid only during the callback. */
struct refract_multipart_part {
    const unsigned char *body;
    size_t len;
    long index;               /* 0 for the stream's first part */
    char content_type[64];    /* "" when absent */
    long long content_length; /* -1 when absent */
    long long seq;            /* X-Frame-Seq; -1 when absent */
    char kind[16];            /* X-Frame-Kind: "full", "preview"; "" when absent */
    double render_ms;         /* X-Render-Time-Ms; -1 when absent */
    char irradiance[32];      /* X-Refract-Irradiance; "" when absent */
    bool repeat;              /* X-Frame-Repeat: 1 (the part repeats the one before) */
    double start_ms;          /* the caller's now_ms when the part's first header line (or,
                                 without headers, the blank line) began: not the boundary
                                 line, which refractd sends with the part before */
};

/* Gets each complete part; returns false to stop the stream (the parser is then STOPPED). */
typedef bool (*refract_multipart_part_fn)(void *user, const struct refract_multipart_part *part);

enum refract_multipart_result {
    REFRACT_MULTIPART_OK,      /* all bytes taken; more may come */
    REFRACT_MULTIPART_STOPPED, /* the callback returned false */
    REFRACT_MULTIPART_ERROR,   /* the stream is malformed; why says how */
};

enum refract_multipart_state {
    REFRACT_MP_PREAMBLE,
    REFRACT_MP_HEADERS,
    REFRACT_MP_BODY_SIZED,
    REFRACT_MP_BODY_SCAN,
    REFRACT_MP_AFTER_BODY,
    REFRACT_MP_EPILOGUE,
    REFRACT_MP_STOPPED,
    REFRACT_MP_FAILED,
};

/* A parser, held by value: refract_multipart_init, feeds, refract_multipart_finish,
 * refract_multipart_fini. */
struct refract_multipart {
    enum refract_multipart_state state;
    char delimiter[4 + REFRACT_MULTIPART_BOUNDARY_MAX + 1]; /* "\r\n--" BOUNDARY */
    size_t delimiter_len;
    size_t max_part_bytes;
    char line[REFRACT_MULTIPART_LINE_MAX];
    size_t line_len;
    double line_start_ms; /* now_ms when the current line's first byte came */
    unsigned char *body;  /* owned; the current part's bytes */
    size_t body_len;
    size_t body_cap;
    size_t preamble_bytes;
    struct refract_multipart_part part;   /* the current part's headers */
    int header_lines;                     /* header lines of the current part so far */
    long parts;                           /* parts delivered so far */
    double now_ms;                        /* set by the caller before each feed: stamps start_ms */
    char why[REFRACT_MULTIPART_WHY_SIZE]; /* after ERROR: what was wrong */
};

/* Reads the boundary parameter of a Content-Type ("multipart/x-mixed-replace;
 * boundary=refract-frame", quoted or not) into out (out_size bytes). Returns false with
 * why filled when content_type is not multipart or has no usable boundary. */
bool refract_multipart_boundary(const char *content_type, char *out, size_t out_size, char *why,
                                size_t why_size);

/* Prepares m for a stream with this boundary (1..70 characters, no CR/LF); parts larger
 * than max_part_bytes (0 = 256 MiB) are an error. Returns false with m->why filled when
 * the boundary is unusable. */
bool refract_multipart_init(struct refract_multipart *m, const char *boundary,
                            size_t max_part_bytes);

/* Takes len more bytes of the stream (borrowed until return). Calls fn for each part that
 * completes. After STOPPED or ERROR, further feeds return the same result. */
enum refract_multipart_result refract_multipart_feed(struct refract_multipart *m, const void *data,
                                                     size_t len, refract_multipart_part_fn fn,
                                                     void *user);

/* The stream ended (the server closed it). Returns ERROR, with m->why naming the part and
 * how far it got, when it ended inside a part's headers or body or inside a boundary
 * line; OK when it ended between parts (or before the first boundary: an empty stream).
 * STOPPED streams stay STOPPED. */
enum refract_multipart_result refract_multipart_finish(struct refract_multipart *m);

/* Frees what m owns; m may be initialised again afterwards. */
void refract_multipart_fini(struct refract_multipart *m);

#endif
