/*
 * test_header_deadline.c - a client that trickles its request never stays silent long
 * enough for --header-timeout, so --header-deadline bounds the whole arrival (issue 13,
 * "Fair sharing"; docs/api.md "Fair sharing"), tried as an attacker would against a real
 * daemon (--header-deadline 2, --upload-min-rate 4K, --header-timeout 10):
 *   - a client sending its headers one byte every 0.3 s is closed at about 2 s (not
 *     before), as is one sending a JSON body that way after whole headers, one trickling
 *     an upload's headers, and one trickling an upload's body (far below 4K per second):
 *     that upload's temporary file, there while it trickled, is gone with it;
 *   - meanwhile a kept-alive client asking for /v1/health every 0.3 s is served all along,
 *     past the deadline (each answer starts its next request's time again);
 *   - an upload whose headers arrive at once but whose body takes longer than the deadline
 *     (three parts 1.2 s apart, about 28 kB/s) is stored (an upload's body is held to the
 *     rate, not to the deadline), as is a render that keeps its client waiting longer than
 *     the deadline; GET /v1/health reports both settings.
 */
#define _GNU_SOURCE /* strcasestr */
#include <arpa/inet.h>
#include <dirent.h>
#include <netinet/in.h>
#include <poll.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#include "integration/daemon.h"
#include "test.h"

#define DEADLINE_S 2.0
#define DRIP_MS 300

static const char scene_json[] =
    "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 32, "
    "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}}]}";

static void sleep_ms(int ms)
{
    struct timespec ts = {.tv_sec = ms / 1000, .tv_nsec = (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

static int connect_to(const struct test_daemon *d)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    if (fd < 0)
        return -1;
    struct sockaddr_in dst = {.sin_family = AF_INET, .sin_port = htons((uint16_t)d->port)};
    inet_pton(AF_INET, "127.0.0.1", &dst.sin_addr);
    struct timeval tv = {.tv_sec = 30};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    if (connect(fd, (struct sockaddr *)&dst, sizeof dst) != 0) {
        close(fd);
        return -1;
    }
    return fd;
}

static int status_of(const char *answer)
{
    int status = 0;
    return answer != NULL && sscanf(answer, "HTTP/1.%*d %d", &status) == 1 ? status : -1;
}

/* True when the daemon has closed fd: poll says readable and recv sees the end (or an
 * error), within timeout_ms. Bytes it sent (an answer) are read and ignored. */
static bool closed_within(int fd, int timeout_ms)
{
    double until = test_now_ms() + timeout_ms;
    for (;;) {
        int left = (int)(until - test_now_ms());
        struct pollfd p = {.fd = fd, .events = POLLIN};
        if (poll(&p, 1, left > 0 ? left : 0) <= 0)
            return false;
        char buf[4096];
        ssize_t n = recv(fd, buf, sizeof buf, MSG_DONTWAIT);
        if (n <= 0)
            return true;
    }
}

/* One trickling client: sends `head` at once (may be ""), then `drip` a byte every
 * DRIP_MS until the daemon closes the connection or the bytes run out. */
struct dripper {
    const struct test_daemon *d;
    const char *head, *drip;
    double start_ms, closed_ms; /* closed_ms: 0 = never closed */
    int sent;
};

static void *drip_main(void *arg)
{
    struct dripper *c = arg;
    int fd = connect_to(c->d);
    c->start_ms = test_now_ms();
    if (fd < 0 || !test_send_all(fd, c->head, strlen(c->head))) {
        if (fd >= 0)
            close(fd);
        return NULL;
    }
    for (size_t i = 0; c->drip[i] != '\0'; i++) {
        if (!test_send_all(fd, &c->drip[i], 1)) {
            c->closed_ms = test_now_ms();
            break;
        }
        c->sent++;
        if (closed_within(fd, DRIP_MS)) {
            c->closed_ms = test_now_ms();
            break;
        }
    }
    close(fd);
    return NULL;
}

/* A kept-alive client: GET /v1/health on one connection every DRIP_MS for `ms`. */
struct keeper {
    const struct test_daemon *d;
    int ms, asked, answered;
};

/* Reads one answer (headers, then Content-Length bytes) from a kept-alive connection. */
static bool read_answer(int fd, int *status)
{
    char buf[16384];
    size_t got = 0;
    for (;;) {
        ssize_t n = recv(fd, buf + got, sizeof buf - 1 - got, 0);
        if (n <= 0)
            return false;
        got += (size_t)n;
        buf[got] = '\0';
        const char *end = strstr(buf, "\r\n\r\n");
        if (end == NULL)
            continue;
        const char *cl = strcasestr(buf, "\r\nContent-Length:");
        size_t body = cl ? strtoul(cl + 17, NULL, 10) : 0;
        if (got >= (size_t)(end + 4 - buf) + body) {
            *status = status_of(buf);
            return true;
        }
    }
}

static void *keep_main(void *arg)
{
    struct keeper *k = arg;
    int fd = connect_to(k->d);
    static const char req[] = "GET /v1/health HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n";
    double until = test_now_ms() + k->ms;
    while (fd >= 0 && test_now_ms() < until) {
        k->asked++;
        int status = 0;
        if (!test_send_all(fd, req, strlen(req)) || !read_answer(fd, &status))
            break;
        k->answered += status == 200;
        sleep_ms(DRIP_MS);
    }
    if (fd >= 0)
        close(fd);
    return NULL;
}

static int tmp_files(const struct test_daemon *d)
{
    char path[400];
    snprintf(path, sizeof path, "%s/tmp", d->data_dir);
    DIR *dir = opendir(path);
    if (dir == NULL)
        return 0;
    int n = 0;
    struct dirent *e;
    while ((e = readdir(dir)) != NULL)
        n += e->d_name[0] != '.';
    closedir(dir);
    return n;
}

/* A render that keeps its client waiting longer than the deadline (a fine step, 4 rays
 * per pixel: about 3 s on an idle 2-core machine). */
struct slow_render {
    struct test_daemon *d;
    const char *scene;
    long status;
    double ms;
};

static void *render_main(void *arg)
{
    struct slow_render *r = arg;
    char path[128], *body = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s/render", r->scene);
    double t0 = test_now_ms();
    r->status = test_request(r->d, "POST", path,
                             "{\"width\": 128, \"height\": 72, \"step\": 0.02, "
                             "\"samples_per_pixel\": 4}",
                             &body);
    r->ms = test_now_ms() - t0;
    free(body);
    return NULL;
}

static void check_closed_at_deadline(const char *what, const struct dripper *c)
{
    double after = c->closed_ms > 0 ? c->closed_ms - c->start_ms : -1;
    printf("%s: closed after %.0f ms (%d bytes sent, --header-deadline %.0f s)\n", what, after,
           c->sent, DEADLINE_S);
    CHECK_MSG(c->closed_ms > 0, "%s: never closed", what);
    /* Not before the deadline (the daemon's clock starts a little after ours)... */
    CHECK_MSG(after >= DEADLINE_S * 1000.0 - 50.0, "%s: closed after %.0f ms", what, after);
    /* ...and soon after it: the reaper looks every 200 ms; a loaded machine adds a little. */
    CHECK_MSG(after < DEADLINE_S * 1000.0 + 1500.0, "%s: closed after %.0f ms", what, after);
}

int main(void)
{
    struct test_daemon d;
    const char *const args[] = {
        "--header-deadline", "2", "--upload-min-rate", "4K", "--header-timeout", "10", NULL};
    if (!test_daemon_start(&d, args))
        test_setup_failed("test_header_deadline", d.why);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, scene_json, id));

    /* 40 bytes each: 12 s of trickling, far past the deadline. */
    static const char pad[] = "X-Slow: aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa";
    char upload_head[512];
    snprintf(upload_head, sizeof upload_head,
             "PUT /v1/scenes/%s/volumes/density?dims=50,50,10&type=float32 HTTP/1.1\r\nHost: "
             "127.0.0.1\r\nContent-Type: application/octet-stream\r\nContent-Length: 100000\r\n",
             id);
    struct dripper headers = {.d = &d, .head = "GET /v1/health HTTP/1.1\r\n", .drip = pad};
    struct dripper body = {.d = &d,
                           .head = "POST /v1/scenes HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
                                   "application/json\r\nContent-Length: 200\r\n\r\n",
                           .drip = "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1]"};
    struct dripper upload = {.d = &d, .head = upload_head, .drip = pad};
    char upload_whole_head[600];
    snprintf(upload_whole_head, sizeof upload_whole_head, "%s\r\n", upload_head);
    struct dripper upload_body = {.d = &d, .head = upload_whole_head, .drip = pad};
    struct keeper keep = {.d = &d, .ms = 4500};
    struct slow_render render = {.d = &d, .scene = id};
    pthread_t th[6];
    pthread_create(&th[0], NULL, drip_main, &headers);
    pthread_create(&th[1], NULL, drip_main, &body);
    pthread_create(&th[2], NULL, drip_main, &upload);
    pthread_create(&th[3], NULL, keep_main, &keep);
    pthread_create(&th[4], NULL, render_main, &render);
    pthread_create(&th[5], NULL, drip_main, &upload_body);

    /* An upload whose body takes longer than the deadline is not cut off. */
    int fd = connect_to(&d);
    double t_up = test_now_ms();
    static char part[33336];
    CHECK(fd >= 0 && test_send_all(fd, upload_whole_head, strlen(upload_whole_head)));
    sleep_ms(900);
    int receiving = tmp_files(&d); /* the trickled upload's (this one has sent no body yet) */
    CHECK_MSG(receiving >= 1, "%d temporary files while an upload trickles", receiving);
    sleep_ms(300);
    for (int i = 0; i < 3; i++) {
        if (i > 0)
            sleep_ms(1200);
        size_t n = i < 2 ? sizeof part : 100000 - 2 * sizeof part;
        CHECK(test_send_all(fd, part, n));
    }
    char answer[2048] = "";
    ssize_t n = recv(fd, answer, sizeof answer - 1, 0);
    answer[n > 0 ? n : 0] = '\0';
    close(fd);
    printf("an upload whose body took %.0f ms: %d\n", test_now_ms() - t_up, status_of(answer));
    CHECK_INT(status_of(answer), 201);

    for (int i = 0; i < 6; i++)
        pthread_join(th[i], NULL);
    check_closed_at_deadline("headers trickled a byte every 0.3 s", &headers);
    check_closed_at_deadline("a JSON body trickled after whole headers", &body);
    check_closed_at_deadline("an upload's headers trickled", &upload);
    check_closed_at_deadline("an upload's body trickled (--upload-min-rate 4K)", &upload_body);
    printf("kept-alive client meanwhile: %d of %d health requests answered over %d ms\n",
           keep.answered, keep.asked, keep.ms);
    CHECK(keep.asked >= 10);
    CHECK_INT(keep.answered, keep.asked);
    printf("a render answered after %.0f ms: %ld\n", render.ms, render.status);
    CHECK_INT(render.status, 200);
    CHECK_INT(tmp_files(&d), 0);
    /* The trickled scene was never created. */
    char *health = NULL;
    CHECK_INT(test_request(&d, "GET", "/v1/health", NULL, &health), 200);
    CHECK(health != NULL && strstr(health, "\"scenes\":1,") != NULL);
    CHECK_CONTAINS(health, "\"header_deadline_s\":2,"); /* "fair_sharing" */
    CHECK_CONTAINS(health, "\"upload_min_rate\":4096,");
    free(health);

    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_header_deadline");
}
