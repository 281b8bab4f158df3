/*
 * test_sse_parse.c - librefract's Server-Sent Events parser (client/sse_parse.c) on byte
 * streams, with no socket: each stream is fed whole, byte by byte, and split into two and
 * three chunks at every position, and each way must dispatch the same events. The
 * expectations are the WHATWG "event stream interpretation" rules: CRLF, LF and CR line
 * ends; a leading BOM dropped; comments; one space after the colon removed; data lines
 * joined with LF; the last event id kept; no dispatch without data; an unfinished event
 * dropped at the end; and the limits.
 */
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"

#include "../../client/sse_parse.c"

struct run_log {
    char text[8192];
    size_t len;
    long stop_after; /* the callback returns false after this many events (0 = never) */
    long events;
};

static bool record_event(void *user, const struct refract_sse_event *ev)
{
    struct run_log *log = user;
    int n = snprintf(log->text + log->len, sizeof(log->text) - log->len,
                     "[id=%s type=%s data=%s len=%zu]\n", ev->id, ev->type, ev->data, ev->data_len);

    if (n > 0 && (size_t)n < sizeof(log->text) - log->len)
        log->len += (size_t)n;
    log->events++;
    return log->stop_after == 0 || log->events < log->stop_after;
}

/* Feeds the stream in chunks ending at cuts[], finishes, and appends how it ended. */
static void run(const char *stream, size_t len, const size_t *cuts, size_t n_cuts, size_t max_bytes,
                struct run_log *log)
{
    struct refract_sse p;
    enum refract_sse_result r = REFRACT_SSE_OK;
    size_t at = 0;
    bool partial = false;

    refract_sse_init(&p, max_bytes);
    for (size_t k = 0; k <= n_cuts && r == REFRACT_SSE_OK; k++) {
        size_t end = k < n_cuts ? cuts[k] : len;

        r = refract_sse_feed(&p, stream + at, end - at, record_event, log);
        at = end;
    }
    r = refract_sse_finish(&p, &partial);
    snprintf(log->text + log->len, sizeof(log->text) - log->len, "end %s%s%s comments=%ld%s\n",
             r == REFRACT_SSE_OK        ? "ok"
             : r == REFRACT_SSE_STOPPED ? "stopped"
                                        : "error",
             r == REFRACT_SSE_ERROR ? ": " : "", r == REFRACT_SSE_ERROR ? p.why : "", p.comments,
             partial ? " partial" : "");
    refract_sse_fini(&p);
}

static const char *same_at_every_split(const char *stream, size_t len)
{
    static struct run_log whole;
    struct run_log split;
    int mismatches = 0;
    size_t *cuts = malloc((len + 1) * sizeof(*cuts));

    memset(&whole, 0, sizeof(whole));
    run(stream, len, NULL, 0, 0, &whole);
    for (size_t i = 1; i < len; i++) {
        for (size_t j = i; j < len; j++) {
            size_t two[2] = {i, j};

            memset(&split, 0, sizeof(split));
            run(stream, len, two, j == i ? 1 : 2, 0, &split);
            if (strcmp(split.text, whole.text) != 0 && mismatches++ == 0)
                fprintf(stderr, "split at %zu,%zu:\n%s--- whole:\n%s", i, j, split.text,
                        whole.text);
        }
    }
    for (size_t i = 0; i < len; i++)
        cuts[i] = i + 1;
    memset(&split, 0, sizeof(split));
    run(stream, len, cuts, len > 0 ? len - 1 : 0, 0, &split);
    CHECK_STR(split.text, whole.text);
    CHECK_INT(mismatches, 0);
    free(cuts);
    return whole.text;
}

/* refractd's events, with a keep-alive comment between them, in the three line ends. */
static void refractd_events_are_the_same_however_the_stream_is_split(void)
{
    static const char s[] = ": keep-alive\n\n"
                            "id: 41\nevent: scene.updated\n"
                            "data: {\"scene\":\"a\",\"what\":\"lights\"}\n\n"
                            "id: 42\r\nevent: irradiance.progress\r\n"
                            "data: {\"progress\":0.4}\r\n\r\n"
                            "id: 43\revent: irradiance.ready\rdata: {}\r\r";
    const char *log = same_at_every_split(s, sizeof(s) - 1);

    CHECK_STR(log, "[id=41 type=scene.updated data={\"scene\":\"a\",\"what\":\"lights\"} len=29]\n"
                   "[id=42 type=irradiance.progress data={\"progress\":0.4} len=16]\n"
                   "[id=43 type=irradiance.ready data={} len=2]\n"
                   "end ok comments=1\n");
}

static void fields_follow_the_standard(void)
{
    static const char s[] = "\xEF\xBB\xBF"        /* a BOM at the start: dropped */
                            "data:no space\n"     /* no space after the colon */
                            "data:  two spaces\n" /* only one is removed */
                            "data\n"              /* no colon: an empty data line */
                            "retry: 3000\n"       /* ignored */
                            "unknown: x\n"        /* ignored */
                            "\n"
                            "id: 7\n"
                            "event: only-type\n"
                            "\n" /* no data: nothing is dispatched, the type is forgotten */
                            "data: after\n"
                            "\n" /* the id stays; the type is "message" again */
                            "id\n"
                            "data\n"
                            "\n" /* an empty id; data "" is still an event */
                            "data: cut off at the end\n";
    const char *log = same_at_every_split(s, sizeof(s) - 1);

    CHECK_STR(log, "[id= type=message data=no space\n two spaces\n len=21]\n"
                   "[id=7 type=message data=after len=5]\n"
                   "[id= type=message data= len=0]\n"
                   "end ok comments=0 partial\n");
}

static void a_bom_later_on_is_not_dropped(void)
{
    static const char s[] = "data: x\n\n\xEF\xBB\xBF"
                            "data: y\n\n";
    static const char half_bom[] = "\xEF\xBB"
                                   "data: z\n\n";

    /* The second BOM makes the field name "\xEF\xBB\xBF" "data", which is unknown. */
    CHECK_STR(same_at_every_split(s, sizeof(s) - 1),
              "[id= type=message data=x len=1]\nend ok comments=0\n");
    CHECK_STR(same_at_every_split(half_bom, sizeof(half_bom) - 1), "end ok comments=0\n");
}

static void a_callback_that_says_stop_stops_the_stream(void)
{
    static const char s[] = "data: 1\n\ndata: 2\n\ndata: 3\n\n";
    struct run_log log = {.stop_after = 2};

    run(s, sizeof(s) - 1, NULL, 0, 0, &log);
    CHECK_INT(log.events, 2);
    CHECK_CONTAINS(log.text, "end stopped");
}

static void lines_and_events_over_the_limit_are_errors(void)
{
    static const char long_line[] = "data: 0123456789012345678901234567890123456789\n\n";
    static const char long_event[] = "data: 0123456789\ndata: 0123456789\ndata: 0123456789\n"
                                     "data: 0123456789\n\n";
    struct run_log log = {0};

    run(long_line, sizeof(long_line) - 1, NULL, 0, 32, &log);
    CHECK_CONTAINS(log.text, "end error: a line is longer than the limit of 32 bytes");
    CHECK_INT(log.events, 0);
    memset(&log, 0, sizeof(log));
    run(long_event, sizeof(long_event) - 1, NULL, 0, 32, &log);
    CHECK_CONTAINS(log.text, "end error: an event's data is longer than the limit of 32 bytes");
    CHECK_INT(log.events, 0);
}

int main(void)
{
    refractd_events_are_the_same_however_the_stream_is_split();
    fields_follow_the_standard();
    a_bom_later_on_is_not_dropped();
    a_callback_that_says_stop_stops_the_stream();
    lines_and_events_over_the_limit_are_errors();
    return test_summary("test_sse_parse");
}
