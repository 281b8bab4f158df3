/*
 * view_util.h - what the view session tests share, header-only like expect.h: a small
 * scene that renders in milliseconds on llvmpipe, opening sessions, reading their status,
 * and a raw-socket reader of the MJPEG frame stream (HTTP/1.1, chunked transfer coding,
 * multipart/x-mixed-replace; boundary=refract-frame, docs/views.md "The stream"), so the
 * tests see exactly the bytes a browser gets, and can stop reading like a slow client.
 */
#ifndef REFRACT_TEST_VIEW_UTIL_H
#define REFRACT_TEST_VIEW_UTIL_H

#include <arpa/inet.h>
#include <cjson/cJSON.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "daemon.h"
#include "test.h"

/* A glass sphere on a coarse grid (24 voxels, step 1): a 64x48 frame renders in a few
 * milliseconds on llvmpipe once the scene is built. */
static const char *const view_sphere_scene =
    "{\"name\": \"view sphere\", \"camera\": {\"eye\": [0, 0, 4], \"look_at\": [0, 0, 0], "
    "\"up\": [0, 1, 0], \"fov_y_deg\": 40, \"width\": 64, \"height\": 48}, "
    "\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 24, "
    "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5, \"outside\": 1.0}}], "
    "\"render\": {\"step\": 1.0}}";

static inline double view_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1000.0 + ts.tv_nsec / 1e6;
}

static inline void view_sleep_ms(int ms)
{
    struct timespec ts = {.tv_sec = ms / 1000, .tv_nsec = (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

/* POST /v1/scenes/{scene}/views with body; writes the session id (>= 18 bytes). Returns
 * the HTTP status; *status_out (may be NULL) gets the parsed answer (caller deletes). */
static inline long view_open(struct test_daemon *d, const char *scene, const char *body, char *vid,
                             cJSON **status_out)
{
    char path[160], *answer = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s/views", scene);
    long status = test_request(d, "POST", path, body, &answer);
    cJSON *root = answer ? cJSON_Parse(answer) : NULL;
    const cJSON *id = cJSON_GetObjectItemCaseSensitive(root, "id");
    if (vid)
        snprintf(vid, 32, "%s", cJSON_IsString(id) ? id->valuestring : "");
    if (status != 201)
        fprintf(stderr, "POST %s: %ld %s\n", path, status, answer ? answer : "");
    free(answer);
    if (status_out)
        *status_out = root;
    else
        cJSON_Delete(root);
    return status;
}

/* GET /v1/views/{vid} parsed (caller deletes), or NULL when it did not answer 200. */
static inline cJSON *view_status(struct test_daemon *d, const char *vid)
{
    char path[96], *answer = NULL;
    snprintf(path, sizeof path, "/v1/views/%s", vid);
    long status = test_request(d, "GET", path, NULL, &answer);
    cJSON *root = status == 200 && answer ? cJSON_Parse(answer) : NULL;
    free(answer);
    return root;
}

/* frame.seq of a status (0 when frame is null). */
static inline double view_status_seq(const cJSON *status)
{
    const cJSON *frame = cJSON_GetObjectItemCaseSensitive(status, "frame");
    const cJSON *seq = cJSON_GetObjectItemCaseSensitive(frame, "seq");
    return cJSON_IsNumber(seq) ? seq->valuedouble : 0;
}

static inline long view_patch(struct test_daemon *d, const char *vid, const char *body)
{
    char path[96], *answer = NULL;
    snprintf(path, sizeof path, "/v1/views/%s", vid);
    long status = test_request(d, "PATCH", path, body, &answer);
    if (status != 200)
        fprintf(stderr, "PATCH %s %s: %ld %s\n", path, body, status, answer ? answer : "");
    free(answer);
    return status;
}

/* Waits until the session's newest frame has seq >= at_least and it is idle; returns its
 * seq (0 on timeout). */
static inline double view_wait_seq(struct test_daemon *d, const char *vid, double at_least,
                                   int timeout_ms)
{
    double until = view_now_ms() + timeout_ms;
    while (view_now_ms() < until) {
        cJSON *st = view_status(d, vid);
        double seq = view_status_seq(st);
        const cJSON *state = cJSON_GetObjectItemCaseSensitive(st, "state");
        bool idle = cJSON_IsString(state) && strcmp(state->valuestring, "idle") == 0;
        cJSON_Delete(st);
        if (seq >= at_least && idle)
            return seq;
        view_sleep_ms(10);
    }
    return 0;
}

/* ---- the MJPEG stream reader ---------------------------------------------------------- */

struct mjpeg_stream {
    int fd;
    int status; /* the HTTP status */
    char content_type[128];
    bool chunked;
    bool first_chunk;
    size_t chunk_left; /* body bytes left in the current chunk */
    bool eof;
    bool in_part; /* a delimiter was read: the next part's headers come next */
    unsigned char raw[16384];
    size_t raw_len, raw_pos;
};

struct mjpeg_frame {
    unsigned char *jpeg; /* owned; free() */
    size_t len;
    long long seq;
    char kind[16];
    char irradiance[16];
    double render_ms;
    bool repeat; /* X-Frame-Repeat: the part repeats the one before (docs/views.md) */
};

/* Next raw byte, waiting until deadline_ms: 1 = got one, 0 = timeout, -1 = closed. */
static inline int mjpeg_raw_byte(struct mjpeg_stream *s, double deadline_ms, unsigned char *out)
{
    if (s->raw_pos == s->raw_len) {
        if (s->eof)
            return -1;
        double left = deadline_ms - view_now_ms();
        struct pollfd p = {.fd = s->fd, .events = POLLIN};
        int ready = left > 0 ? poll(&p, 1, (int)left + 1) : 0;
        if (ready <= 0)
            return 0;
        ssize_t n = recv(s->fd, s->raw, sizeof s->raw, 0);
        if (n <= 0) {
            s->eof = true;
            return -1;
        }
        s->raw_len = (size_t)n;
        s->raw_pos = 0;
    }
    *out = s->raw[s->raw_pos++];
    return 1;
}

/* A raw line without its CRLF into buf: 1, 0 (timeout), -1 (closed). */
static inline int mjpeg_raw_line(struct mjpeg_stream *s, double deadline_ms, char *buf, size_t size)
{
    size_t n = 0;
    for (;;) {
        unsigned char c;
        int rc = mjpeg_raw_byte(s, deadline_ms, &c);
        if (rc <= 0)
            return rc;
        if (c == '\n')
            break;
        if (c != '\r' && n + 1 < size)
            buf[n++] = (char)c;
    }
    buf[n] = '\0';
    return 1;
}

/* Next body byte (through the chunked coding): 1, 0 (timeout), -1 (end or closed). */
static inline int mjpeg_body_byte(struct mjpeg_stream *s, double deadline_ms, unsigned char *out)
{
    if (s->chunked && s->chunk_left == 0) {
        char line[64];
        int rc;
        if (!s->first_chunk && (rc = mjpeg_raw_line(s, deadline_ms, line, sizeof line)) <= 0)
            return rc; /* the CRLF after the previous chunk */
        s->first_chunk = false;
        if ((rc = mjpeg_raw_line(s, deadline_ms, line, sizeof line)) <= 0)
            return rc;
        s->chunk_left = strtoul(line, NULL, 16);
        if (s->chunk_left == 0) {
            s->eof = true;
            return -1; /* the last chunk: the body ended */
        }
    }
    int rc = mjpeg_raw_byte(s, deadline_ms, out);
    if (rc == 1 && s->chunked)
        s->chunk_left--;
    return rc;
}

static inline int mjpeg_body_line(struct mjpeg_stream *s, double deadline_ms, char *buf,
                                  size_t size)
{
    size_t n = 0;
    for (;;) {
        unsigned char c;
        int rc = mjpeg_body_byte(s, deadline_ms, &c);
        if (rc <= 0)
            return rc;
        if (c == '\n')
            break;
        if (c != '\r' && n + 1 < size)
            buf[n++] = (char)c;
    }
    buf[n] = '\0';
    return 1;
}

/* Connects to the daemon and sends GET path. rcvbuf > 0 sets SO_RCVBUF first (a slow
 * client's small window). Returns false when the connection failed. */
static inline bool mjpeg_connect(struct test_daemon *d, const char *path, int rcvbuf,
                                 struct mjpeg_stream *s)
{
    memset(s, 0, sizeof *s);
    s->first_chunk = true;
    s->fd = socket(AF_INET, SOCK_STREAM, 0);
    if (s->fd < 0)
        return false;
    if (rcvbuf > 0)
        setsockopt(s->fd, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
    struct sockaddr_in addr = {.sin_family = AF_INET, .sin_port = htons((uint16_t)d->port)};
    inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
    if (connect(s->fd, (struct sockaddr *)&addr, sizeof addr) != 0) {
        close(s->fd);
        s->fd = -1;
        return false;
    }
    char req[512];
    int n = snprintf(req, sizeof req, "GET %s HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n", path);
    return send(s->fd, req, (size_t)n, 0) == n;
}

/* Reads the status line and headers. Returns the HTTP status, or -1. */
static inline int mjpeg_read_head(struct mjpeg_stream *s, int timeout_ms)
{
    double deadline = view_now_ms() + timeout_ms;
    char line[1024];
    if (mjpeg_raw_line(s, deadline, line, sizeof line) <= 0)
        return -1;
    if (sscanf(line, "HTTP/1.%*d %d", &s->status) != 1)
        return -1;
    while (mjpeg_raw_line(s, deadline, line, sizeof line) == 1 && line[0] != '\0') {
        if (strncasecmp(line, "Content-Type:", 13) == 0)
            snprintf(s->content_type, sizeof s->content_type, "%.127s", line + 14);
        if (strncasecmp(line, "Transfer-Encoding:", 18) == 0 && strstr(line, "chunked"))
            s->chunked = true;
    }
    return s->status;
}

/* Opens a frame stream and reads its head; returns the status (200) or -1. */
static inline int mjpeg_open(struct test_daemon *d, const char *vid, int rcvbuf,
                             struct mjpeg_stream *s)
{
    char path[96];
    snprintf(path, sizeof path, "/v1/views/%s/stream", vid);
    if (!mjpeg_connect(d, path, rcvbuf, s))
        return -1;
    return mjpeg_read_head(s, 10000);
}

/* The next frame: 1 = *f filled (free f->jpeg), 0 = none within timeout_ms, -1 = the
 * stream ended (or is malformed: then it says so on stderr). */
/* Reads a delimiter line (after blank lines): 1 = "--refract-frame" (a part follows),
 * -1 = the closing "--refract-frame--" or the end (s->eof set) or garbage (said on
 * stderr), 0 = timeout. */
static inline int mjpeg_delimiter(struct mjpeg_stream *s, double deadline)
{
    char line[512];
    int rc;
    do {
        if ((rc = mjpeg_body_line(s, deadline, line, sizeof line)) <= 0)
            return rc;
    } while (line[0] == '\0');
    if (strcmp(line, "--refract-frame--") == 0) {
        s->eof = true;
        return -1;
    }
    if (strcmp(line, "--refract-frame") != 0) {
        fprintf(stderr, "stream: expected --refract-frame, got \"%s\"\n", line);
        return -1;
    }
    s->in_part = true;
    return 1;
}

static inline int mjpeg_next_part(struct mjpeg_stream *s, struct mjpeg_frame *f, int timeout_ms)
{
    memset(f, 0, sizeof *f);
    double deadline = view_now_ms() + timeout_ms;
    char line[512];
    int rc;
    /* The daemon sends the delimiter right after each frame (docs/views.md), so usually
     * it has been read already and the wait is for the next part's headers. */
    if (!s->in_part && (rc = mjpeg_delimiter(s, deadline)) <= 0)
        return rc;
    if ((rc = mjpeg_body_line(s, deadline, line, sizeof line)) <= 0)
        return rc; /* 0: no new frame within the timeout */
    s->in_part = false;
    /* The rest of a part is on its way: give it time even past the caller's timeout. */
    deadline = view_now_ms() + 10000;
    long long len = -1;
    do {
        if (strncasecmp(line, "Content-Length: ", 16) == 0)
            len = atoll(line + 16);
        else if (strncasecmp(line, "X-Frame-Seq: ", 13) == 0)
            f->seq = atoll(line + 13);
        else if (strncasecmp(line, "X-Frame-Kind: ", 14) == 0)
            snprintf(f->kind, sizeof f->kind, "%.15s", line + 14);
        else if (strncasecmp(line, "X-Refract-Irradiance: ", 22) == 0)
            snprintf(f->irradiance, sizeof f->irradiance, "%.15s", line + 22);
        else if (strncasecmp(line, "X-Render-Time-Ms: ", 18) == 0)
            f->render_ms = atof(line + 18);
        else if (strncasecmp(line, "X-Frame-Repeat: 1", 17) == 0)
            f->repeat = true;
    } while ((rc = mjpeg_body_line(s, deadline, line, sizeof line)) == 1 && line[0] != '\0');
    if (rc <= 0 || len < 0) {
        fprintf(stderr, "stream: a part without Content-Length or cut short\n");
        return -1;
    }
    f->jpeg = malloc((size_t)len + 1);
    for (long long i = 0; i < len; i++) {
        if (mjpeg_body_byte(s, deadline, &f->jpeg[i]) != 1) {
            fprintf(stderr, "stream: JPEG cut short at %lld of %lld bytes\n", i, len);
            free(f->jpeg);
            f->jpeg = NULL;
            return -1;
        }
    }
    f->len = (size_t)len;
    if (mjpeg_body_line(s, deadline, line, sizeof line) != 1 || line[0] != '\0') {
        fprintf(stderr, "stream: no CRLF after the JPEG\n");
        free(f->jpeg);
        f->jpeg = NULL;
        return -1;
    }
    /* The delimiter that ends the part comes with it (the closing one ends the stream). */
    if (mjpeg_delimiter(s, deadline) == 0)
        fprintf(stderr, "stream: no delimiter after frame %lld\n", f->seq);
    return 1;
}

/* The next new frame, skipping repeats (X-Frame-Repeat: the one-time repeat after a
 * stream goes quiet, and keep-alives): as mjpeg_next_part otherwise. */
static inline int mjpeg_next(struct mjpeg_stream *s, struct mjpeg_frame *f, int timeout_ms)
{
    double deadline = view_now_ms() + timeout_ms;
    for (;;) {
        int left = (int)(deadline - view_now_ms());
        int rc = mjpeg_next_part(s, f, left > 0 ? left : 0);
        if (rc != 1 || !f->repeat)
            return rc;
        free(f->jpeg);
        f->jpeg = NULL;
    }
}

/* Reads frames until one of kind "full" with seq > after; returns 1 (f filled) or <= 0. */
static inline int mjpeg_next_full(struct mjpeg_stream *s, struct mjpeg_frame *f, long long after,
                                  int timeout_ms)
{
    double deadline = view_now_ms() + timeout_ms;
    for (;;) {
        int left = (int)(deadline - view_now_ms());
        int rc = mjpeg_next(s, f, left > 0 ? left : 0);
        if (rc <= 0)
            return rc;
        if (f->seq > after && strcmp(f->kind, "full") == 0)
            return 1;
        free(f->jpeg);
    }
}

static inline void mjpeg_close(struct mjpeg_stream *s)
{
    if (s->fd >= 0)
        close(s->fd);
    s->fd = -1;
}

/* Closes the connection with a reset (SO_LINGER 0), as a client that vanished: the
 * daemon's next write to it fails at once. */
static inline void mjpeg_abort(struct mjpeg_stream *s)
{
    struct linger lg = {.l_onoff = 1, .l_linger = 0};
    if (s->fd >= 0)
        setsockopt(s->fd, SOL_SOCKET, SO_LINGER, &lg, sizeof lg);
    mjpeg_close(s);
}

#endif
