/*
 * test_client_stream_transport.c - librefract's stream readers (refract_view_stream,
 * refract_events) over a real loopback socket against canned replies, in the way curl's
 * tests/data cases hold the exact bytes a server sends: replies refractd never sends on
 * purpose (a frame cut off by a closed connection, a Content-Length that lies, a
 * silence, a proxy's HTML page), written in small pieces so the client sees them split
 * across reads. What refractd itself sends is tested against the real daemon in
 * test_client_view.c and test_cli_view.c.
 *
 * The canned server is one thread with one listening socket: for each case it accepts
 * one connection, keeps the request's headers (to check Last-Event-ID), writes the reply
 * in 7-byte pieces and closes (or, for the silence case, waits first).
 */
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "refract.h"
#include "test.h"

struct canned {
    int listen_fd;
    int port;
    const char *reply; /* bytes to send */
    size_t reply_len;
    int silence_ms; /* after the reply's headers, before the rest */
    char request[4096];
    pthread_t thread;
};

static void sleep_ms(int ms)
{
    struct timespec ts = {.tv_sec = ms / 1000, .tv_nsec = (long)(ms % 1000) * 1000000L};

    nanosleep(&ts, NULL);
}

static void *serve_one(void *arg)
{
    struct canned *s = arg;
    int fd = accept(s->listen_fd, NULL, NULL);
    size_t got = 0;
    const char *body_start;
    size_t header_len;
    int one = 1;

    if (fd < 0)
        return NULL;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    while (got + 1 < sizeof(s->request) && strstr(s->request, "\r\n\r\n") == NULL) {
        ssize_t n = read(fd, s->request + got, sizeof(s->request) - 1 - got);

        if (n <= 0)
            break;
        got += (size_t)n;
        s->request[got] = '\0';
    }
    body_start = strstr(s->reply, "\r\n\r\n");
    header_len = body_start != NULL ? (size_t)(body_start - s->reply) + 4 : 0;
    for (size_t at = 0; at < s->reply_len;) {
        size_t n = s->reply_len - at < 7 ? s->reply_len - at : 7;

        if (at == header_len && s->silence_ms > 0)
            sleep_ms(s->silence_ms);
        if (at < header_len && at + n > header_len)
            n = header_len - at;
        if (send(fd, s->reply + at, n, MSG_NOSIGNAL) != (ssize_t)n)
            break;
        at += n;
    }
    shutdown(fd, SHUT_WR);
    sleep_ms(20); /* let the client read to the end before the reset of close */
    close(fd);
    return NULL;
}

static bool canned_open(struct canned *s)
{
    struct sockaddr_in addr = {.sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    socklen_t len = sizeof(addr);

    memset(s, 0, sizeof(*s));
    s->listen_fd = socket(AF_INET, SOCK_STREAM, 0);
    if (s->listen_fd < 0 || bind(s->listen_fd, (struct sockaddr *)&addr, sizeof(addr)) != 0 ||
        listen(s->listen_fd, 4) != 0 ||
        getsockname(s->listen_fd, (struct sockaddr *)&addr, &len) != 0)
        return false;
    s->port = ntohs(addr.sin_port);
    return true;
}

/* Serves `reply` to the next connection, in a thread. */
static void canned_serve(struct canned *s, const char *reply, size_t len, int silence_ms)
{
    s->reply = reply;
    s->reply_len = len;
    s->silence_ms = silence_ms;
    s->request[0] = '\0';
    pthread_create(&s->thread, NULL, serve_one, s);
}

static void canned_done(struct canned *s)
{
    pthread_join(s->thread, NULL);
}

#define MJPEG_HEADERS                                                                              \
    "HTTP/1.1 200 OK\r\n"                                                                          \
    "Content-Type: multipart/x-mixed-replace; boundary=refract-frame\r\n"                          \
    "Cache-Control: no-store\r\n"                                                                  \
    "Connection: close\r\n"                                                                        \
    "\r\n"

/* A "JPEG" of 10 bytes: SOI, an APP0 marker start, 4 bytes, EOI. */
#define JPEG10                                                                                     \
    "\xff\xd8\xff\xe0"                                                                             \
    "abcd"                                                                                         \
    "\xff\xd9"

#define FRAME(seq, kind)                                                                           \
    "--refract-frame\r\n"                                                                          \
    "Content-Type: image/jpeg\r\n"                                                                 \
    "Content-Length: 10\r\n"                                                                       \
    "X-Frame-Seq: " #seq "\r\n"                                                                    \
    "X-Frame-Kind: " kind "\r\n"                                                                   \
    "X-Render-Time-Ms: 12.5\r\n"                                                                   \
    "X-Refract-Irradiance: not-needed\r\n"                                                         \
    "\r\n" JPEG10 "\r\n"

struct frames_seen {
    long count;
    long stop_after; /* 0 = never */
    long long seq[8];
    char kind[8][16];
    size_t len[8];
    double render_ms[8];
    char irradiance[8][32];
    double arrival_ms[8];
};

static int on_frame(const struct refract_frame *f, void *user)
{
    struct frames_seen *seen = user;

    if (seen->count < 8) {
        seen->seq[seen->count] = f->seq;
        snprintf(seen->kind[seen->count], 16, "%s", f->kind);
        seen->len[seen->count] = f->len;
        seen->render_ms[seen->count] = f->render_ms;
        snprintf(seen->irradiance[seen->count], 32, "%s", f->irradiance);
        seen->arrival_ms[seen->count] = f->arrival_ms;
    }
    seen->count++;
    return seen->stop_after > 0 && seen->count >= seen->stop_after;
}

static int stream_case(struct canned *s, refract_client *c, const char *reply, size_t len,
                       int silence_ms, struct frames_seen *seen)
{
    int code;

    canned_serve(s, reply, len, silence_ms);
    code = refract_view_stream(c, "v0123456789abcdef", on_frame, seen);
    canned_done(s);
    return code;
}

static void frames_arrive_whole_with_their_headers(struct canned *s, refract_client *c)
{
    static const char reply[] =
        MJPEG_HEADERS FRAME(1, "preview") FRAME(2, "full") FRAME(3, "full") "--refract-frame--\r\n";
    struct frames_seen seen = {0};

    CHECK_INT(stream_case(s, c, reply, sizeof(reply) - 1, 0, &seen), REFRACT_E_OK);
    CHECK_INT(seen.count, 3);
    CHECK_INT(seen.seq[0], 1);
    CHECK_STR(seen.kind[0], "preview");
    CHECK_INT(seen.seq[2], 3);
    CHECK_STR(seen.kind[2], "full");
    CHECK_INT(seen.len[1], 10);
    CHECK_NEAR(seen.render_ms[1], 12.5, 1e-9);
    CHECK_STR(seen.irradiance[1], "not-needed");
    CHECK(seen.arrival_ms[0] > 0 && seen.arrival_ms[2] >= seen.arrival_ms[0]);
    CHECK_CONTAINS(s->request, "GET /v1/views/v0123456789abcdef/stream HTTP/1.1");
}

static void the_callback_stops_the_stream(struct canned *s, refract_client *c)
{
    static const char reply[] = MJPEG_HEADERS FRAME(1, "full") FRAME(2, "full") FRAME(3, "full");
    struct frames_seen seen = {.stop_after = 2};

    CHECK_INT(stream_case(s, c, reply, sizeof(reply) - 1, 0, &seen), REFRACT_E_OK);
    CHECK_INT(seen.count, 2);
}

static void a_stream_closed_mid_frame_is_a_clear_error(struct canned *s, refract_client *c)
{
    /* The second frame's body is cut after 4 of its 10 bytes. */
    static const char reply[] = MJPEG_HEADERS FRAME(
        1,
        "full") "--refract-frame\r\nContent-Length: 10\r\nX-Frame-Seq: 2\r\n\r\n\xff\xd8\xff\xe0";
    struct frames_seen seen = {0};

    CHECK_INT(stream_case(s, c, reply, sizeof(reply) - 1, 0, &seen), REFRACT_E_PROTOCOL);
    CHECK_INT(seen.count, 1);
    CHECK_CONTAINS(refract_errmsg(c), "GET /v1/views/v0123456789abcdef/stream: refractd closed "
                                      "the frame stream after 1 whole frames: the stream ended "
                                      "in the middle of part 2: 4 of its Content-Length 10 "
                                      "bytes came");
}

static void a_lying_content_length_is_caught(struct canned *s, refract_client *c)
{
    /* Says 6, sends 10: the part is cut before the JPEG's end marker. */
    static const char too_short[] = MJPEG_HEADERS
        "--refract-frame\r\nContent-Type: image/jpeg\r\nContent-Length: 6\r\nX-Frame-Seq: 1\r\n"
        "\r\n" JPEG10 "\r\n" FRAME(2, "full");
    /* Says 30, sends 10: the part swallows the next boundary and ends inside frame 2. */
    static const char too_long[] =
        MJPEG_HEADERS "--refract-frame\r\nContent-Length: 30\r\nX-Frame-Seq: 1\r\n\r\n" JPEG10
                      "\r\n" FRAME(2, "full");
    struct frames_seen seen = {0};

    CHECK_INT(stream_case(s, c, too_short, sizeof(too_short) - 1, 0, &seen), REFRACT_E_PROTOCOL);
    CHECK_INT(seen.count, 0);
    CHECK_CONTAINS(refract_errmsg(c), "frame 1 (seq 1, 6 bytes) is not a whole JPEG");
    memset(&seen, 0, sizeof(seen));
    CHECK_INT(stream_case(s, c, too_long, sizeof(too_long) - 1, 0, &seen), REFRACT_E_PROTOCOL);
    CHECK_INT(seen.count, 0);
    CHECK_CONTAINS(refract_errmsg(c), "frame 1 (seq 1, 30 bytes) is not a whole JPEG");
}

static void error_replies_and_strangers_are_named(struct canned *s, refract_client *c)
{
    static const char not_found[] =
        "HTTP/1.1 404 Not Found\r\nContent-Type: application/json\r\nConnection: close\r\n"
        "Content-Length: 80\r\n\r\n"
        "{\"error\": {\"code\": \"not_found\", \"message\": \"no view session "
        "v0123456789abcdef\"}}";
    static const char html[] = "HTTP/1.1 200 OK\r\nContent-Type: text/html\r\nConnection: "
                               "close\r\n\r\n<html>a proxy</html>";
    struct frames_seen seen = {0};

    CHECK(strlen(strstr(not_found, "\r\n\r\n") + 4) == 80);
    CHECK_INT(stream_case(s, c, not_found, sizeof(not_found) - 1, 0, &seen), REFRACT_E_NOT_FOUND);
    CHECK_STR(refract_errmsg(c), "no view session v0123456789abcdef");
    CHECK_INT(stream_case(s, c, html, sizeof(html) - 1, 0, &seen), REFRACT_E_PROTOCOL);
    CHECK_CONTAINS(refract_errmsg(c), "expected a frame reply (Content-Type multipart/...), got "
                                      "Content-Type \"text/html\"");
    CHECK_INT(seen.count, 0);
}

static void silence_longer_than_the_timeout_gives_up(struct canned *s, refract_client *c)
{
    static const char reply[] = MJPEG_HEADERS FRAME(1, "full");
    struct frames_seen seen = {0};

    refract_set_timeout_ms(c, 300);
    CHECK_INT(stream_case(s, c, reply, sizeof(reply) - 1, 2500, &seen), REFRACT_E_TIMEOUT);
    CHECK_CONTAINS(refract_errmsg(c), "no byte from refractd at");
    CHECK_CONTAINS(refract_errmsg(c), "for 300 ms (after 0 frames)");
    refract_set_timeout_ms(c, 10000);
}

struct events_seen {
    long count;
    char log[1024];
};

static int on_event(const struct refract_event *ev, void *user)
{
    struct events_seen *seen = user;
    size_t len = strlen(seen->log);

    snprintf(seen->log + len, sizeof(seen->log) - len, "%s|%s|%s\n", ev->id, ev->type, ev->data);
    return ++seen->count >= 2;
}

static void events_arrive_and_resume_from_an_id(struct canned *s, refract_client *c)
{
    static const char reply[] =
        "HTTP/1.1 200 OK\r\nContent-Type: text/event-stream\r\n"
        "Connection: close\r\n\r\n"
        ": keep-alive\n\n"
        "id: 8\nevent: scene.updated\ndata: {\"scene\":\"s\"}\n\n"
        "id: 9\r\nevent: irradiance.ready\r\ndata: {\"light\":\"sun\"}\r\n\r\n"
        "id: 10\nevent: never.seen\ndata: {}\n\n";
    struct events_seen seen = {0};
    int code;

    canned_serve(s, reply, sizeof(reply) - 1, 0);
    code = refract_events(c, "my scene", "7", on_event, &seen);
    canned_done(s);
    CHECK_INT(code, REFRACT_E_OK);
    CHECK_STR(seen.log,
              "8|scene.updated|{\"scene\":\"s\"}\n9|irradiance.ready|{\"light\":\"sun\"}\n");
    CHECK_CONTAINS(s->request, "GET /v1/scenes/my%20scene/events HTTP/1.1");
    CHECK_CONTAINS(s->request, "Last-Event-ID: 7\r\n");
    CHECK_INT(refract_events(c, "", NULL, on_event, &seen), REFRACT_E_USAGE);
    CHECK_INT(refract_events(c, NULL, "1\r\nX: y", on_event, &seen), REFRACT_E_USAGE);
}

int main(void)
{
    struct canned s;
    char url[64];
    refract_client *c;

    if (!canned_open(&s))
        test_setup_failed("test_client_stream_transport", "cannot listen on a loopback port");
    snprintf(url, sizeof(url), "http://127.0.0.1:%d", s.port);
    c = refract_client_create(url);
    refract_set_timeout_ms(c, 10000);
    frames_arrive_whole_with_their_headers(&s, c);
    the_callback_stops_the_stream(&s, c);
    a_stream_closed_mid_frame_is_a_clear_error(&s, c);
    a_lying_content_length_is_caught(&s, c);
    error_replies_and_strangers_are_named(&s, c);
    silence_longer_than_the_timeout_gives_up(&s, c);
    events_arrive_and_resume_from_an_id(&s, c);
    CHECK_INT(refract_view_stream(c, "", on_frame, NULL), REFRACT_E_USAGE);
    refract_client_destroy(c);
    close(s.listen_fd);
    return test_summary("test_client_stream_transport");
}
