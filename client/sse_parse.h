/*
 * sse_parse.h - a push parser for text/event-stream (Server-Sent Events, as the WHATWG
 * HTML standard's "event stream interpretation" defines it), for refractd's
 * GET /v1/events and GET /v1/scenes/{id}/events (docs/views.md "Events").
 *
 * Bytes go in as they arrive, split anywhere; a callback gets every dispatched event.
 * Pure byte work with no libcurl, so tests/unit/test_sse_parse.c feeds it streams split
 * at every position. Internal to the client; refract_events.c drives it.
 *
 * The rules it follows: a line ends at CRLF, LF or CR (a CRLF split across two chunks is
 * one line end); a UTF-8 byte order mark at the very start is dropped; a line starting
 * with ':' is a comment (refractd's ": keep-alive"); "field: value" loses one space after
 * the colon, and a line without a colon is a field with an empty value; "data" lines are
 * joined with '\n'; "event" sets the type (default "message"); "id" sets the last event
 * id, which stays for the events after it (and is ignored when it contains a NUL); a
 * blank line dispatches the event, unless it has no data (then nothing happens); other
 * fields ("retry" included) are ignored. An event still being gathered when the stream
 * ends is dropped (the standard says so); refract_sse_finish reports that it was there.
 */
#ifndef REFRACT_SSE_PARSE_H
#define REFRACT_SSE_PARSE_H

#include <stdbool.h>
#include <stddef.h>

#define REFRACT_SSE_ID_MAX 256
#define REFRACT_SSE_TYPE_MAX 64
#define REFRACT_SSE_WHY_SIZE 256

/* One event; borrowed strings, valid only during the callback. */
struct refract_sse_event {
    const char *id;   /* the last event id ("" when none was ever set) */
    const char *type; /* "message" when the event named none */
    const char *data; /* the data lines joined with '\n', NUL-terminated */
    size_t data_len;
};

/* Gets each event; returns false to stop the stream. */
typedef bool (*refract_sse_event_fn)(void *user, const struct refract_sse_event *ev);

enum refract_sse_result {
    REFRACT_SSE_OK,      /* all bytes taken */
    REFRACT_SSE_STOPPED, /* the callback returned false */
    REFRACT_SSE_ERROR,   /* a line or an event exceeded max_bytes; why says which */
};

/* A parser, held by value: refract_sse_init, feeds, refract_sse_finish, refract_sse_fini. */
struct refract_sse {
    enum refract_sse_result result; /* sticky once not OK */
    size_t max_bytes;               /* of one line and of one event's data */
    char *line;                     /* owned; the current line */
    size_t line_len;
    size_t line_cap;
    char *data; /* owned; the current event's data, '\n' after each line */
    size_t data_len;
    size_t data_cap;
    char type[REFRACT_SSE_TYPE_MAX];
    char last_id[REFRACT_SSE_ID_MAX];
    bool cr_seen;     /* the last byte was CR: a LF right after it ends nothing */
    bool at_start;    /* nothing but (a prefix of) a BOM has come yet */
    size_t bom_bytes; /* how many BOM bytes came at the start */
    bool event_begun; /* some field line came since the last dispatch */
    long events;      /* dispatched */
    long comments;    /* comment lines (keep-alives) seen */
    char why[REFRACT_SSE_WHY_SIZE];
};

/* Prepares p; max_bytes 0 = 1 MiB. */
void refract_sse_init(struct refract_sse *p, size_t max_bytes);

/* Takes len more bytes (borrowed until return); calls fn for each event dispatched. */
enum refract_sse_result refract_sse_feed(struct refract_sse *p, const void *data, size_t len,
                                         refract_sse_event_fn fn, void *user);

/* The stream ended. Returns the sticky result; *partial (may be NULL) is set to whether an
 * event had begun and was dropped because no blank line ended it. */
enum refract_sse_result refract_sse_finish(struct refract_sse *p, bool *partial);

/* Frees what p owns. */
void refract_sse_fini(struct refract_sse *p);

#endif
