/*
 * multipart_parse.c - the multipart/x-mixed-replace push parser (multipart_parse.h has
 * the stream format and the states).
 *
 * Lines (boundaries and headers) are gathered byte by byte into a fixed buffer, so a line
 * split across chunks needs no special case; bodies are copied in bulk when their length
 * is known. This file does not know what a frame is (JPEG checks belong to
 * refract_view_stream.c) and never allocates more than one part's body.
 */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "multipart_parse.h"

#define DEFAULT_MAX_PART_BYTES ((size_t)256 << 20)

static enum refract_multipart_result fail(struct refract_multipart *m, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

static enum refract_multipart_result fail(struct refract_multipart *m, const char *fmt, ...)
{
    va_list ap;

    va_start(ap, fmt);
    vsnprintf(m->why, sizeof(m->why), fmt, ap);
    va_end(ap);
    m->state = REFRACT_MP_FAILED;
    return REFRACT_MULTIPART_ERROR;
}

static const char *skip_blanks(const char *s)
{
    while (*s == ' ' || *s == '\t')
        s++;
    return s;
}

bool refract_multipart_boundary(const char *content_type, char *out, size_t out_size, char *why,
                                size_t why_size)
{
    const char *p;
    size_t n = 0;

    if (content_type == NULL || strncasecmp(content_type, "multipart/", 10) != 0) {
        snprintf(why, why_size, "expected a multipart Content-Type, got \"%s\"",
                 content_type != NULL ? content_type : "");
        return false;
    }
    for (p = strchr(content_type, ';'); p != NULL; p = strchr(p + 1, ';')) {
        const char *name = skip_blanks(p + 1);

        if (strncasecmp(name, "boundary", 8) == 0 && *skip_blanks(name + 8) == '=') {
            p = skip_blanks(skip_blanks(name + 8) + 1);
            break;
        }
    }
    if (p == NULL) {
        snprintf(why, why_size, "the Content-Type \"%s\" has no boundary parameter", content_type);
        return false;
    }
    if (*p == '"') {
        for (p++; *p != '\0' && *p != '"'; p++) {
            if (n + 1 < out_size)
                out[n] = *p;
            n++;
        }
    } else {
        for (; *p != '\0' && *p != ';' && *p != ' ' && *p != '\t'; p++) {
            if (n + 1 < out_size)
                out[n] = *p;
            n++;
        }
    }
    if (n == 0 || n > REFRACT_MULTIPART_BOUNDARY_MAX || n + 1 > out_size) {
        snprintf(why, why_size, "the boundary in \"%s\" must have 1 to %d characters", content_type,
                 REFRACT_MULTIPART_BOUNDARY_MAX);
        return false;
    }
    out[n] = '\0';
    return true;
}

static void reset_part(struct refract_multipart *m)
{
    struct refract_multipart_part *part = &m->part;

    memset(part, 0, sizeof(*part));
    part->index = m->parts;
    part->content_length = -1;
    part->seq = -1;
    part->render_ms = -1.0;
    part->start_ms = m->line_start_ms;
    m->body_len = 0;
}

bool refract_multipart_init(struct refract_multipart *m, const char *boundary,
                            size_t max_part_bytes)
{
    size_t n = boundary != NULL ? strlen(boundary) : 0;

    memset(m, 0, sizeof(*m));
    m->max_part_bytes = max_part_bytes > 0 ? max_part_bytes : DEFAULT_MAX_PART_BYTES;
    if (n == 0 || n > REFRACT_MULTIPART_BOUNDARY_MAX || strpbrk(boundary, "\r\n") != NULL) {
        fail(m, "the boundary must have 1 to %d characters and no line break",
             REFRACT_MULTIPART_BOUNDARY_MAX);
        return false;
    }
    m->delimiter_len = (size_t)snprintf(m->delimiter, sizeof(m->delimiter), "\r\n--%s", boundary);
    m->state = REFRACT_MP_PREAMBLE;
    return true;
}

void refract_multipart_fini(struct refract_multipart *m)
{
    free(m->body);
    memset(m, 0, sizeof(*m));
}

/* 1 for "--BOUNDARY" (a part follows), 2 for "--BOUNDARY--" (the end), each with
 * optional trailing blanks (RFC 2046 transport padding); 0 for any other line. */
static int boundary_kind(const struct refract_multipart *m, const char *line, size_t len)
{
    const char *dash_boundary = m->delimiter + 2; /* "--BOUNDARY" */
    size_t n = m->delimiter_len - 2;
    int kind = 1;

    if (len < n || memcmp(line, dash_boundary, n) != 0)
        return 0;
    if (len >= n + 2 && line[n] == '-' && line[n + 1] == '-') {
        kind = 2;
        n += 2;
    }
    for (; n < len; n++) {
        if (line[n] != ' ' && line[n] != '\t')
            return 0;
    }
    return kind;
}

/* Makes room for a body of `need` bytes. */
static bool body_reserve(struct refract_multipart *m, size_t need)
{
    size_t cap = m->body_cap > 0 ? m->body_cap : 65536;
    unsigned char *grown;

    if (need <= m->body_cap)
        return true;
    while (cap < need)
        cap = cap <= SIZE_MAX / 2 ? cap * 2 : need;
    grown = realloc(m->body, cap);
    if (grown == NULL)
        return false;
    m->body = grown;
    m->body_cap = cap;
    return true;
}

/* Parses a decimal number header value into *out; false when it is not one. */
static bool parse_count(const char *value, long long *out)
{
    char *end;
    long long v;

    if (!isdigit((unsigned char)value[0]))
        return false;
    errno = 0;
    v = strtoll(value, &end, 10);
    if (errno != 0 || *skip_blanks(end) != '\0')
        return false;
    *out = v;
    return true;
}

static void copy_value(char *dst, size_t dst_size, const char *value)
{
    snprintf(dst, dst_size, "%s", value);
}

/* One header line of the current part (NUL-terminated, no line end). */
static enum refract_multipart_result header_line(struct refract_multipart *m, char *line)
{
    struct refract_multipart_part *part = &m->part;
    char *colon = strchr(line, ':');
    char *value;
    char *end;

    m->header_lines++;
    if (colon == NULL)
        return fail(m, "part %ld: header line \"%.60s\" has no ':'", m->parts + 1, line);
    *colon = '\0';
    value = (char *)skip_blanks(colon + 1);
    end = value + strlen(value);
    while (end > value && (end[-1] == ' ' || end[-1] == '\t'))
        *--end = '\0';
    if (strcasecmp(line, "Content-Type") == 0) {
        copy_value(part->content_type, sizeof(part->content_type), value);
    } else if (strcasecmp(line, "Content-Length") == 0) {
        if (!parse_count(value, &part->content_length))
            return fail(m, "part %ld: Content-Length \"%.40s\" is not a byte count", m->parts + 1,
                        value);
        if ((unsigned long long)part->content_length > m->max_part_bytes)
            return fail(m, "part %ld: Content-Length %lld exceeds the limit of %zu bytes",
                        m->parts + 1, part->content_length, m->max_part_bytes);
    } else if (strcasecmp(line, "X-Frame-Seq") == 0) {
        if (!parse_count(value, &part->seq))
            return fail(m, "part %ld: X-Frame-Seq \"%.40s\" is not a number", m->parts + 1, value);
    } else if (strcasecmp(line, "X-Frame-Kind") == 0) {
        copy_value(part->kind, sizeof(part->kind), value);
    } else if (strcasecmp(line, "X-Render-Time-Ms") == 0) {
        double ms = strtod(value, &end);

        part->render_ms = (end != value && *end == '\0' && isfinite(ms) && ms >= 0) ? ms : -1.0;
    } else if (strcasecmp(line, "X-Refract-Irradiance") == 0) {
        copy_value(part->irradiance, sizeof(part->irradiance), value);
    } else if (strcasecmp(line, "X-Frame-Repeat") == 0) {
        part->repeat = strcmp(value, "1") == 0;
    }
    return REFRACT_MULTIPART_OK;
}

/* The blank line after a part's headers: the body begins. */
static enum refract_multipart_result begin_body(struct refract_multipart *m)
{
    size_t need = m->part.content_length >= 0 ? (size_t)m->part.content_length : 0;

    if (!body_reserve(m, need + 1))
        return fail(m, "part %ld: out of memory for its %zu bytes", m->parts + 1, need);
    m->state = m->part.content_length >= 0 ? REFRACT_MP_BODY_SIZED : REFRACT_MP_BODY_SCAN;
    return REFRACT_MULTIPART_OK;
}

static enum refract_multipart_result deliver(struct refract_multipart *m,
                                             refract_multipart_part_fn fn, void *user)
{
    m->part.body = m->body;
    m->part.len = m->body_len;
    m->parts++;
    m->state = REFRACT_MP_AFTER_BODY;
    if (!fn(user, &m->part)) {
        m->state = REFRACT_MP_STOPPED;
        return REFRACT_MULTIPART_STOPPED;
    }
    return REFRACT_MULTIPART_OK;
}

/* A boundary line in PREAMBLE or AFTER_BODY: a part begins, or the stream ends. */
static void boundary_seen(struct refract_multipart *m, int kind)
{
    if (kind == 2) {
        m->state = REFRACT_MP_EPILOGUE;
        return;
    }
    reset_part(m);
    m->header_lines = 0;
    m->state = REFRACT_MP_HEADERS;
}

/* A complete line (line end removed) in a line state. */
static enum refract_multipart_result line_done(struct refract_multipart *m)
{
    int kind;

    m->line[m->line_len] = '\0';
    switch (m->state) {
    case REFRACT_MP_PREAMBLE:
        kind = boundary_kind(m, m->line, m->line_len);
        if (kind != 0) {
            boundary_seen(m, kind);
        } else {
            m->preamble_bytes += m->line_len + 1;
            if (m->preamble_bytes > REFRACT_MULTIPART_PREAMBLE_MAX)
                return fail(m,
                            "no boundary line \"%s\" in the first %d bytes: this is not a "
                            "refractd frame stream",
                            m->delimiter + 2, REFRACT_MULTIPART_PREAMBLE_MAX);
        }
        return REFRACT_MULTIPART_OK;
    case REFRACT_MP_HEADERS:
        /* A part is stamped when its first header line began, not its boundary line:
         * refractd sends the delimiter with the frame before it (docs/views.md), so the
         * boundary line says when the previous frame came. */
        if (m->header_lines == 0)
            m->part.start_ms = m->line_start_ms;
        return m->line_len == 0 ? begin_body(m) : header_line(m, m->line);
    case REFRACT_MP_AFTER_BODY:
        if (m->line_len == 0)
            return REFRACT_MULTIPART_OK; /* the CRLF that ends a body */
        kind = boundary_kind(m, m->line, m->line_len);
        if (kind == 0)
            return fail(m,
                        "part %ld did not end at a boundary: after its %zu bytes came \"%.40s\" "
                        "instead of \"%s\" (a wrong Content-Length?)",
                        m->parts, m->part.len, m->line, m->delimiter + 2);
        boundary_seen(m, kind);
        return REFRACT_MULTIPART_OK;
    default:
        return REFRACT_MULTIPART_OK;
    }
}

/* Takes bytes into the current line; returns how many were used (up to and including a
 * LF), with *result set when something happened. */
static size_t take_line_bytes(struct refract_multipart *m, const unsigned char *p, size_t n,
                              enum refract_multipart_result *result)
{
    for (size_t i = 0; i < n; i++) {
        if (p[i] == '\n') {
            if (m->line_len > 0 && m->line[m->line_len - 1] == '\r')
                m->line_len--;
            *result = line_done(m);
            m->line_len = 0;
            return i + 1;
        }
        if (m->line_len == 0)
            m->line_start_ms = m->now_ms;
        if (m->line_len + 1 >= sizeof(m->line)) {
            *result = fail(m, "part %ld: a %s line is longer than %d bytes", m->parts + 1,
                           m->state == REFRACT_MP_HEADERS ? "header" : "boundary",
                           REFRACT_MULTIPART_LINE_MAX);
            return i + 1;
        }
        m->line[m->line_len++] = (char)p[i];
    }
    return n;
}

static size_t take_sized_body(struct refract_multipart *m, const unsigned char *p, size_t n,
                              refract_multipart_part_fn fn, void *user,
                              enum refract_multipart_result *result)
{
    size_t want = (size_t)m->part.content_length - m->body_len;
    size_t take = n < want ? n : want;

    memcpy(m->body + m->body_len, p, take);
    m->body_len += take;
    if (m->body_len == (size_t)m->part.content_length)
        *result = deliver(m, fn, user);
    return take;
}

/* Without Content-Length: bytes until the delimiter "\r\n--BOUNDARY", whose dashes and
 * boundary then become the start of the next boundary line. */
static size_t take_scanned_body(struct refract_multipart *m, const unsigned char *p, size_t n,
                                refract_multipart_part_fn fn, void *user,
                                enum refract_multipart_result *result)
{
    const unsigned char last = (unsigned char)m->delimiter[m->delimiter_len - 1];

    for (size_t i = 0; i < n; i++) {
        if (m->body_len + 1 > m->max_part_bytes + m->delimiter_len) {
            *result = fail(m, "part %ld is larger than the limit of %zu bytes", m->parts + 1,
                           m->max_part_bytes);
            return i;
        }
        if (!body_reserve(m, m->body_len + 1)) {
            *result = fail(m, "part %ld: out of memory after %zu bytes", m->parts + 1, m->body_len);
            return i;
        }
        m->body[m->body_len++] = p[i];
        if (p[i] == last && m->body_len >= m->delimiter_len &&
            memcmp(m->body + m->body_len - m->delimiter_len, m->delimiter, m->delimiter_len) == 0) {
            m->body_len -= m->delimiter_len;
            *result = deliver(m, fn, user);
            /* The delimiter's "--BOUNDARY" starts the line that AFTER_BODY reads. */
            m->line_len = m->delimiter_len - 2;
            memcpy(m->line, m->delimiter + 2, m->line_len);
            m->line_start_ms = m->now_ms;
            return i + 1;
        }
    }
    return n;
}

enum refract_multipart_result refract_multipart_feed(struct refract_multipart *m, const void *data,
                                                     size_t len, refract_multipart_part_fn fn,
                                                     void *user)
{
    const unsigned char *p = data;
    size_t used = 0;

    while (used < len) {
        enum refract_multipart_result result = REFRACT_MULTIPART_OK;

        switch (m->state) {
        case REFRACT_MP_STOPPED:
            return REFRACT_MULTIPART_STOPPED;
        case REFRACT_MP_FAILED:
            return REFRACT_MULTIPART_ERROR;
        case REFRACT_MP_EPILOGUE:
            return REFRACT_MULTIPART_OK;
        case REFRACT_MP_BODY_SIZED:
            used += take_sized_body(m, p + used, len - used, fn, user, &result);
            break;
        case REFRACT_MP_BODY_SCAN:
            used += take_scanned_body(m, p + used, len - used, fn, user, &result);
            break;
        default:
            used += take_line_bytes(m, p + used, len - used, &result);
            break;
        }
        if (result != REFRACT_MULTIPART_OK)
            return result;
    }
    if (m->state == REFRACT_MP_STOPPED)
        return REFRACT_MULTIPART_STOPPED;
    return m->state == REFRACT_MP_FAILED ? REFRACT_MULTIPART_ERROR : REFRACT_MULTIPART_OK;
}

enum refract_multipart_result refract_multipart_finish(struct refract_multipart *m)
{
    long next = m->parts + 1;

    switch (m->state) {
    case REFRACT_MP_STOPPED:
        return REFRACT_MULTIPART_STOPPED;
    case REFRACT_MP_FAILED:
        return REFRACT_MULTIPART_ERROR;
    case REFRACT_MP_HEADERS:
        /* refractd sends the delimiter with the frame before it (docs/views.md), so a
         * stream that ends between frames ends right after a delimiter: a clean end. */
        if (m->header_lines == 0 && m->line_len == 0)
            return REFRACT_MULTIPART_OK;
        return fail(m, "the stream ended inside the headers of part %ld", next);
    case REFRACT_MP_BODY_SIZED:
        return fail(m,
                    "the stream ended in the middle of part %ld: %zu of its Content-Length "
                    "%lld bytes came",
                    next, m->body_len, m->part.content_length);
    case REFRACT_MP_BODY_SCAN:
        return fail(m,
                    "the stream ended in the middle of part %ld: %zu bytes came, with no "
                    "boundary after them",
                    next, m->body_len);
    case REFRACT_MP_AFTER_BODY:
        if (m->line_len > 0)
            return fail(m, "the stream ended inside the boundary line before part %ld", next);
        return REFRACT_MULTIPART_OK;
    default:
        return REFRACT_MULTIPART_OK;
    }
}
