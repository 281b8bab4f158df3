/*
 * sse_parse.c - the text/event-stream push parser (sse_parse.h has the rules).
 *
 * Bytes are taken one at a time: events are small (refractd's are under 1 KiB), and a
 * byte loop makes the split-anywhere cases (CR at the end of one chunk, LF at the start
 * of the next; a BOM cut in two) the same code as the unsplit ones.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sse_parse.h"

#define DEFAULT_MAX_BYTES ((size_t)1 << 20)

static const unsigned char bom[3] = {0xEF, 0xBB, 0xBF};

void refract_sse_init(struct refract_sse *p, size_t max_bytes)
{
    memset(p, 0, sizeof(*p));
    p->max_bytes = max_bytes > 0 ? max_bytes : DEFAULT_MAX_BYTES;
    p->at_start = true;
}

void refract_sse_fini(struct refract_sse *p)
{
    free(p->line);
    free(p->data);
    memset(p, 0, sizeof(*p));
}

static enum refract_sse_result fail(struct refract_sse *p, const char *what)
{
    snprintf(p->why, sizeof(p->why), "%s is longer than the limit of %zu bytes", what,
             p->max_bytes);
    p->result = REFRACT_SSE_ERROR;
    return p->result;
}

/* Appends n bytes to a growable buffer, keeping room for a NUL. */
static bool append(char **buf, size_t *len, size_t *cap, const char *bytes, size_t n)
{
    if (*len + n + 1 > *cap) {
        size_t grown_cap = *cap > 0 ? *cap : 256;
        char *grown;

        while (grown_cap < *len + n + 1)
            grown_cap *= 2;
        grown = realloc(*buf, grown_cap);
        if (grown == NULL)
            return false;
        *buf = grown;
        *cap = grown_cap;
    }
    memcpy(*buf + *len, bytes, n);
    *len += n;
    (*buf)[*len] = '\0';
    return true;
}

static enum refract_sse_result dispatch(struct refract_sse *p, refract_sse_event_fn fn, void *user)
{
    struct refract_sse_event ev;

    p->event_begun = false;
    if (p->data_len == 0) {
        p->type[0] = '\0';
        return REFRACT_SSE_OK;
    }
    p->data[--p->data_len] = '\0'; /* the '\n' after the last data line */
    ev.id = p->last_id;
    ev.type = p->type[0] != '\0' ? p->type : "message";
    ev.data = p->data;
    ev.data_len = p->data_len;
    p->events++;
    if (!fn(user, &ev))
        p->result = REFRACT_SSE_STOPPED;
    p->data_len = 0;
    p->data[0] = '\0';
    p->type[0] = '\0';
    return p->result;
}

/* One complete line (p->line, p->line_len bytes, line end removed). */
static enum refract_sse_result line_done(struct refract_sse *p, refract_sse_event_fn fn, void *user)
{
    const char *line = p->line != NULL ? p->line : "";
    size_t len = p->line_len;
    const char *colon = memchr(line, ':', len);
    size_t name_len = colon != NULL ? (size_t)(colon - line) : len;
    const char *value = colon != NULL ? colon + 1 : line + len;
    size_t value_len = (size_t)(line + len - value);

    if (len == 0)
        return dispatch(p, fn, user);
    if (name_len == 0) {
        p->comments++;
        return REFRACT_SSE_OK;
    }
    if (value_len > 0 && value[0] == ' ') {
        value++;
        value_len--;
    }
    p->event_begun = true;
    if (name_len == 4 && memcmp(line, "data", 4) == 0) {
        if (p->data_len + value_len + 1 > p->max_bytes)
            return fail(p, "an event's data");
        if (!append(&p->data, &p->data_len, &p->data_cap, value, value_len) ||
            !append(&p->data, &p->data_len, &p->data_cap, "\n", 1)) {
            snprintf(p->why, sizeof(p->why), "out of memory for an event's data");
            return p->result = REFRACT_SSE_ERROR;
        }
    } else if (name_len == 5 && memcmp(line, "event", 5) == 0) {
        snprintf(p->type, sizeof(p->type), "%.*s", (int)value_len, value);
    } else if (name_len == 2 && memcmp(line, "id", 2) == 0) {
        if (memchr(value, '\0', value_len) == NULL)
            snprintf(p->last_id, sizeof(p->last_id), "%.*s", (int)value_len, value);
    }
    return REFRACT_SSE_OK;
}

/* Drops a BOM at the very start; returns true when byte b was part of it. */
static bool take_bom_byte(struct refract_sse *p, unsigned char b)
{
    if (!p->at_start)
        return false;
    if (p->bom_bytes < 3 && b == bom[p->bom_bytes]) {
        p->bom_bytes++;
        if (p->bom_bytes == 3)
            p->at_start = false;
        return true;
    }
    /* Not a BOM after all: the bytes held back were line content. */
    p->at_start = false;
    for (size_t i = 0; i < p->bom_bytes; i++)
        if (!append(&p->line, &p->line_len, &p->line_cap, (const char *)&bom[i], 1))
            p->result = REFRACT_SSE_ERROR;
    return false;
}

enum refract_sse_result refract_sse_feed(struct refract_sse *p, const void *data, size_t len,
                                         refract_sse_event_fn fn, void *user)
{
    const unsigned char *bytes = data;

    for (size_t i = 0; i < len && p->result == REFRACT_SSE_OK; i++) {
        unsigned char b = bytes[i];

        if (take_bom_byte(p, b))
            continue;
        if (b == '\n' && p->cr_seen) {
            p->cr_seen = false; /* the LF of a CRLF: the line already ended at its CR */
            continue;
        }
        p->cr_seen = b == '\r';
        if (b == '\r' || b == '\n') {
            line_done(p, fn, user);
            p->line_len = 0;
            continue;
        }
        if (p->line_len + 1 > p->max_bytes)
            return fail(p, "a line");
        if (!append(&p->line, &p->line_len, &p->line_cap, (const char *)&b, 1)) {
            snprintf(p->why, sizeof(p->why), "out of memory for a line");
            p->result = REFRACT_SSE_ERROR;
        }
    }
    return p->result;
}

enum refract_sse_result refract_sse_finish(struct refract_sse *p, bool *partial)
{
    if (partial != NULL)
        *partial = p->event_begun || p->line_len > 0;
    return p->result;
}
