/*
 * test_multipart_parse.c - librefract's multipart/x-mixed-replace parser
 * (client/multipart_parse.c) on byte streams, with no socket: every stream is fed whole,
 * byte by byte, and split into two and three chunks at every position, and each way must
 * give the same parts with the same bytes and headers. Then the malformed streams: a
 * Content-Length that lies either way, a stream that ends inside a part, bad headers,
 * something that is not a multipart stream at all; and the boundary taken from a
 * Content-Type.
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "test.h"

#include "../../client/multipart_parse.c"

#define LOG_MAX 8192

/* What a run saw: one line per part (its headers and a digest of its bytes), and how the
 * stream ended. */
struct run_log {
    char text[LOG_MAX];
    size_t len;
    long stop_after; /* the callback returns false after this many parts (0 = never) */
    long parts;
    double start_ms[8];
};

static void log_printf(struct run_log *log, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

static void log_printf(struct run_log *log, const char *fmt, ...)
{
    va_list ap;
    int n;

    va_start(ap, fmt);
    n = vsnprintf(log->text + log->len, sizeof(log->text) - log->len, fmt, ap);
    va_end(ap);
    if (n > 0)
        log->len += (size_t)n < sizeof(log->text) - log->len ? (size_t)n : 0;
}

static bool record_part(void *user, const struct refract_multipart_part *p)
{
    struct run_log *log = user;
    unsigned long sum = 5381;

    for (size_t i = 0; i < p->len; i++)
        sum = sum * 33 + p->body[i];
    log_printf(log, "part %ld type=%s len=%zu cl=%lld seq=%lld kind=%s ms=%.3f irr=%s sum=%lu\n",
               p->index, p->content_type, p->len, p->content_length, p->seq, p->kind, p->render_ms,
               p->irradiance, sum);
    if (log->parts < 8)
        log->start_ms[log->parts] = p->start_ms;
    log->parts++;
    return log->stop_after == 0 || log->parts < log->stop_after;
}

static const char *result_name(enum refract_multipart_result r)
{
    return r == REFRACT_MULTIPART_OK ? "ok" : r == REFRACT_MULTIPART_STOPPED ? "stopped" : "error";
}

/* Feeds stream[0..len) in chunks ending at cuts[0] < cuts[1] < ... (n_cuts of them), then
 * finishes; returns the final result and fills log. now_ms is the chunk's number. */
static enum refract_multipart_result run(const char *boundary, const char *stream, size_t len,
                                         const size_t *cuts, size_t n_cuts, struct run_log *log)
{
    struct refract_multipart m;
    enum refract_multipart_result r = REFRACT_MULTIPART_OK;
    size_t at = 0;

    if (!refract_multipart_init(&m, boundary, 1 << 20))
        return REFRACT_MULTIPART_ERROR;
    for (size_t k = 0; k <= n_cuts && r == REFRACT_MULTIPART_OK; k++) {
        size_t end = k < n_cuts ? cuts[k] : len;

        m.now_ms = (double)k;
        r = refract_multipart_feed(&m, stream + at, end - at, record_part, log);
        at = end;
    }
    if (r == REFRACT_MULTIPART_OK)
        r = refract_multipart_finish(&m);
    log_printf(log, "end %s%s%s\n", result_name(r), r == REFRACT_MULTIPART_ERROR ? ": " : "",
               r == REFRACT_MULTIPART_ERROR ? m.why : "");
    refract_multipart_fini(&m);
    return r;
}

/* The log of the whole stream must be the log of every split into 2 and 3 chunks and of
 * the byte-by-byte feed. Returns the whole stream's log (static). */
static const char *same_at_every_split(const char *boundary, const char *stream, size_t len)
{
    static struct run_log whole;
    struct run_log split;
    size_t *cuts = malloc((len + 1) * sizeof(*cuts));
    int mismatches = 0;

    memset(&whole, 0, sizeof(whole));
    run(boundary, stream, len, NULL, 0, &whole);
    for (size_t i = 1; i < len; i++) {
        for (size_t j = i; j < len; j++) {
            size_t two[2] = {i, j};

            memset(&split, 0, sizeof(split));
            run(boundary, stream, len, two, j == i ? 1 : 2, &split);
            if (strcmp(split.text, whole.text) != 0 && mismatches++ == 0)
                fprintf(stderr, "split at %zu,%zu:\n%s--- whole:\n%s", i, j, split.text,
                        whole.text);
        }
    }
    for (size_t i = 0; i < len; i++)
        cuts[i] = i + 1;
    memset(&split, 0, sizeof(split));
    run(boundary, stream, len, cuts, len > 0 ? len - 1 : 0, &split);
    CHECK_STR(split.text, whole.text);
    CHECK_INT(mismatches, 0);
    free(cuts);
    return whole.text;
}

/* Three JPEG-like frames as refractd writes them; bodies hold CR, LF, NUL and dashes. */
static const char frames[] = "--refract-frame\r\n"
                             "Content-Type: image/jpeg\r\n"
                             "Content-Length: 17\r\n"
                             "X-Frame-Seq: 7\r\n"
                             "X-Frame-Kind: preview\r\n"
                             "X-Render-Time-Ms: 35.100\r\n"
                             "X-Refract-Irradiance: ready\r\n"
                             "\r\n"
                             "\xff\xd8\xff\r\n--refract\0\xff\xd9\r\n"
                             "--refract-frame\r\n"
                             "content-type: image/jpeg\r\n"
                             "CONTENT-LENGTH:   5  \r\n"
                             "X-Frame-Seq: 8\r\n"
                             "\r\n"
                             "\r\n\r\n-\r\n"
                             "--refract-frame  \r\n"
                             "Content-Length: 0\r\n"
                             "X-Frame-Kind: full\r\n"
                             "\r\n"
                             "\r\n";

static void sized_parts_are_the_same_however_the_stream_is_split(void)
{
    const char *log = same_at_every_split("refract-frame", frames, sizeof(frames) - 1);

    CHECK_CONTAINS(log, "part 0 type=image/jpeg len=17 cl=17 seq=7 kind=preview ms=35.100 "
                        "irr=ready");
    CHECK_CONTAINS(log, "part 1 type=image/jpeg len=5 cl=5 seq=8 kind= ms=-1.000 irr=");
    CHECK_CONTAINS(log, "part 2 type= len=0 cl=0 seq=-1 kind=full");
    CHECK_CONTAINS(log, "end ok");
}

/* Without Content-Length a part ends at CRLF--BOUNDARY; near misses stay in the body. */
static const char scanned[] = "preamble text a server may send\r\n"
                              "--b0undary\r\n"
                              "X-Frame-Seq: 1\r\n"
                              "\r\n"
                              "ab\r\n--b0undar\r\n-b0undary--b0undary\r\n"
                              "--b0undary\r\n"
                              "\r\n"
                              "\r\n"
                              "--b0undary--\r\n"
                              "epilogue: ignored \r\n--b0undary\r\n\r\n";

static void scanned_parts_end_at_the_delimiter_and_only_there(void)
{
    const char *log = same_at_every_split("b0undary", scanned, sizeof(scanned) - 1);
    const char body0[] = "ab\r\n--b0undar\r\n-b0undary--b0undary";
    unsigned long sum = 5381;
    char expect[128];

    for (size_t i = 0; i < sizeof(body0) - 1; i++)
        sum = sum * 33 + (unsigned char)body0[i];
    snprintf(expect, sizeof(expect),
             "part 0 type= len=%zu cl=-1 seq=1 kind= ms=-1.000 irr= "
             "sum=%lu\n",
             sizeof(body0) - 1, sum);
    CHECK_CONTAINS(log, expect);
    CHECK_CONTAINS(log, "part 1 type= len=0 cl=-1");
    CHECK(strstr(log, "part 2") == NULL); /* the epilogue's boundary is not a part */
    CHECK_CONTAINS(log, "end ok");
}

static void bare_lf_line_ends_are_accepted(void)
{
    static const char lf[] = "--x\nContent-Length: 3\nX-Frame-Seq: 2\n\nabc\n--x\n"
                             "Content-Length: 1\n\nz\n";
    const char *log = same_at_every_split("x", lf, sizeof(lf) - 1);

    CHECK_CONTAINS(log, "part 0 type= len=3 cl=3 seq=2");
    CHECK_CONTAINS(log, "part 1 type= len=1 cl=1");
    CHECK_CONTAINS(log, "end ok");
}

static void a_content_length_too_short_is_caught_at_the_next_line(void)
{
    static const char lie[] = "--f\r\nContent-Length: 3\r\n\r\nabcdef\r\n--f\r\n\r\n";
    const char *log = same_at_every_split("f", lie, sizeof(lie) - 1);

    CHECK_CONTAINS(log, "part 0 type= len=3 cl=3");
    CHECK_CONTAINS(log, "end error: part 1 did not end at a boundary: after its 3 bytes came "
                        "\"def\" instead of \"--f\" (a wrong Content-Length?)");
}

static void a_content_length_too_long_ends_in_the_middle_of_a_part(void)
{
    static const char lie[] = "--f\r\nContent-Length: 40\r\n\r\nabc\r\n--f\r\n"
                              "Content-Length: 3\r\n\r\nxyz\r\n";
    const char *log = same_at_every_split("f", lie, sizeof(lie) - 1);

    CHECK(strstr(log, "part 0") == NULL);
    CHECK_CONTAINS(log, "end error: the stream ended in the middle of part 1: 36 of its "
                        "Content-Length 40 bytes came");
}

static void a_stream_that_closes_mid_frame_says_where(void)
{
    static const char in_body[] = "--f\r\nContent-Length: 10\r\n\r\nabcd";
    static const char in_headers[] = "--f\r\nContent-Length: 1\r\n\r\na\r\n--f\r\nX-Fr";
    static const char in_scan[] = "--f\r\n\r\nabc\r\n--";
    static const char in_boundary[] = "--f\r\nContent-Length: 1\r\n\r\na\r\n--";
    static const char between[] = "--f\r\nContent-Length: 1\r\n\r\na\r\n";
    static const char empty[] = "";
    /* refractd sends each frame's delimiter with it, so streams end after one. */
    static const char after_delimiter[] = "--f\r\nContent-Length: 1\r\n\r\na\r\n--f\r\n";

    CHECK_CONTAINS(same_at_every_split("f", in_body, sizeof(in_body) - 1),
                   "end error: the stream ended in the middle of part 1: 4 of its "
                   "Content-Length 10 bytes came");
    CHECK_CONTAINS(same_at_every_split("f", in_headers, sizeof(in_headers) - 1),
                   "end error: the stream ended inside the headers of part 2");
    CHECK_CONTAINS(same_at_every_split("f", in_scan, sizeof(in_scan) - 1),
                   "end error: the stream ended in the middle of part 1: 7 bytes came, with "
                   "no boundary after them");
    CHECK_CONTAINS(same_at_every_split("f", in_boundary, sizeof(in_boundary) - 1),
                   "end error: the stream ended inside the boundary line before part 2");
    CHECK_CONTAINS(same_at_every_split("f", between, sizeof(between) - 1), "end ok");
    CHECK_CONTAINS(same_at_every_split("f", after_delimiter, sizeof(after_delimiter) - 1),
                   "end ok");
    CHECK_CONTAINS(same_at_every_split("f", empty, 0), "end ok");
}

static void bad_headers_are_errors_that_name_the_part(void)
{
    static const char bad_length[] = "--f\r\nContent-Length: 1\r\n\r\na\r\n--f\r\n"
                                     "Content-Length: 12abc\r\n\r\n";
    static const char negative[] = "--f\r\nContent-Length: -1\r\n\r\n";
    static const char huge[] = "--f\r\nContent-Length: 99999999999\r\n\r\n";
    static const char no_colon[] = "--f\r\nContent-Length 1\r\n\r\n";
    static const char bad_seq[] = "--f\r\nX-Frame-Seq: seven\r\n\r\n";

    CHECK_CONTAINS(same_at_every_split("f", bad_length, sizeof(bad_length) - 1),
                   "end error: part 2: Content-Length \"12abc\" is not a byte count");
    CHECK_CONTAINS(same_at_every_split("f", negative, sizeof(negative) - 1),
                   "end error: part 1: Content-Length \"-1\" is not a byte count");
    CHECK_CONTAINS(same_at_every_split("f", huge, sizeof(huge) - 1),
                   "end error: part 1: Content-Length 99999999999 exceeds the limit of 1048576 "
                   "bytes");
    CHECK_CONTAINS(same_at_every_split("f", no_colon, sizeof(no_colon) - 1),
                   "end error: part 1: header line \"Content-Length 1\" has no ':'");
    CHECK_CONTAINS(same_at_every_split("f", bad_seq, sizeof(bad_seq) - 1),
                   "end error: part 1: X-Frame-Seq \"seven\" is not a number");
}

static void something_else_than_a_multipart_stream_is_refused(void)
{
    size_t n = REFRACT_MULTIPART_PREAMBLE_MAX + 100;
    char *junk = malloc(n);
    struct run_log log = {0};
    char *long_line = malloc(REFRACT_MULTIPART_LINE_MAX + 20);

    for (size_t i = 0; i < n; i++)
        junk[i] = (i % 50 == 49) ? '\n' : 'x';
    CHECK_INT(run("f", junk, n, NULL, 0, &log), REFRACT_MULTIPART_ERROR);
    CHECK_CONTAINS(log.text, "no boundary line \"--f\" in the first 65536 bytes");

    memcpy(long_line, "--f\r\nX: ", 8);
    memset(long_line + 8, 'y', REFRACT_MULTIPART_LINE_MAX + 10);
    memset(&log, 0, sizeof(log));
    CHECK_INT(run("f", long_line, REFRACT_MULTIPART_LINE_MAX + 18, NULL, 0, &log),
              REFRACT_MULTIPART_ERROR);
    CHECK_CONTAINS(log.text, "part 1: a header line is longer than 4096 bytes");
    free(junk);
    free(long_line);
}

static void a_callback_that_says_stop_stops_the_stream(void)
{
    struct refract_multipart m;
    struct run_log log = {.stop_after = 2};

    CHECK(refract_multipart_init(&m, "refract-frame", 0));
    CHECK_INT(refract_multipart_feed(&m, frames, sizeof(frames) - 1, record_part, &log),
              REFRACT_MULTIPART_STOPPED);
    CHECK_INT(log.parts, 2);
    CHECK_INT(refract_multipart_feed(&m, frames, 10, record_part, &log), REFRACT_MULTIPART_STOPPED);
    CHECK_INT(refract_multipart_finish(&m), REFRACT_MULTIPART_STOPPED);
    CHECK_INT(log.parts, 2);
    refract_multipart_fini(&m);
}

/* start_ms is the caller's clock when the part's first header line began, not when its
 * body ended, and not when its boundary line came: refractd sends the delimiter with the
 * frame before, so the boundary line would date the next frame to the previous one's
 * arrival. What a latency measurement needs. */
static void a_part_is_stamped_when_its_first_header_line_began(void)
{
    static const char two[] = "--f\r\nContent-Length: 3\r\n\r\nabc\r\n--f\r\nContent-Length: "
                              "2\r\n\r\nxy\r\n";
    size_t header0 = (size_t)(strstr(two, "Content") - two);
    size_t header1 = (size_t)(strstr(two + header0 + 1, "Content") - two);
    /* Chunks: "--" | "f\r\n" | part 0 up to and with part 1's "--f\r\n" | the rest. */
    size_t cuts[3] = {2, header0, header1};
    struct run_log log = {0};

    CHECK_INT(run("f", two, sizeof(two) - 1, cuts, 3, &log), REFRACT_MULTIPART_OK);
    CHECK_INT(log.parts, 2);
    CHECK_NEAR(log.start_ms[0], 2.0, 0); /* the chunk where part 0's header began */
    CHECK_NEAR(log.start_ms[1], 3.0, 0); /* not 2, where part 1's boundary line came */
}

static void the_boundary_is_read_from_the_content_type(void)
{
    char b[REFRACT_MULTIPART_BOUNDARY_MAX + 1];
    char why[256];
    char long_ct[200];

    CHECK(refract_multipart_boundary("multipart/x-mixed-replace; boundary=refract-frame", b,
                                     sizeof(b), why, sizeof(why)));
    CHECK_STR(b, "refract-frame");
    CHECK(refract_multipart_boundary("Multipart/X-Mixed-Replace;charset=x; BOUNDARY = \"a b;c\"", b,
                                     sizeof(b), why, sizeof(why)));
    CHECK_STR(b, "a b;c");
    CHECK(refract_multipart_boundary("multipart/x-mixed-replace;boundary=xyz;q=1", b, sizeof(b),
                                     why, sizeof(why)));
    CHECK_STR(b, "xyz");
    CHECK(!refract_multipart_boundary("image/jpeg", b, sizeof(b), why, sizeof(why)));
    CHECK_STR(why, "expected a multipart Content-Type, got \"image/jpeg\"");
    CHECK(!refract_multipart_boundary("multipart/x-mixed-replace", b, sizeof(b), why, sizeof(why)));
    CHECK_CONTAINS(why, "has no boundary parameter");
    CHECK(!refract_multipart_boundary("multipart/x-mixed-replace; boundary=\"\"", b, sizeof(b), why,
                                      sizeof(why)));
    CHECK_CONTAINS(why, "must have 1 to 70 characters");
    snprintf(long_ct, sizeof(long_ct), "multipart/mixed; boundary=%080d", 0);
    CHECK(!refract_multipart_boundary(long_ct, b, sizeof(b), why, sizeof(why)));
    CHECK_CONTAINS(why, "must have 1 to 70 characters");
}

int main(void)
{
    sized_parts_are_the_same_however_the_stream_is_split();
    scanned_parts_end_at_the_delimiter_and_only_there();
    bare_lf_line_ends_are_accepted();
    a_content_length_too_short_is_caught_at_the_next_line();
    a_content_length_too_long_ends_in_the_middle_of_a_part();
    a_stream_that_closes_mid_frame_says_where();
    bad_headers_are_errors_that_name_the_part();
    something_else_than_a_multipart_stream_is_refused();
    a_callback_that_says_stop_stops_the_stream();
    a_part_is_stamped_when_its_first_header_line_began();
    the_boundary_is_read_from_the_content_type();
    return test_summary("test_multipart_parse");
}
