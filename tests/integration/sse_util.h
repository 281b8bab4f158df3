/*
 * sse_util.h - a Server-Sent Events client for the events tests, header-only like
 * irradiance_util.h: one libcurl transfer driven by a multi handle on the test's own
 * thread (so no thread and no lock), parsed into events as the SSE format says: blocks
 * ended by a blank line, `field: value` lines, comments begin with ':'.
 *
 *     struct sse_client c;
 *     sse_open(&c, d, "/v1/scenes/abc/events", NULL);   // waits for the opening comment
 *     struct sse_event ev;
 *     if (sse_next(&c, &ev, 30) == SSE_EVENT) ... ev.id, ev.type, ev.data ...
 *     sse_close(&c);
 */
#ifndef REFRACT_TEST_SSE_UTIL_H
#define REFRACT_TEST_SSE_UTIL_H

#include <cjson/cJSON.h>
#include <curl/curl.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "daemon.h"
#include "test.h"

struct sse_event {
    bool has_id;
    uint64_t id;
    char type[64];   /* "message" when the block has no event: line */
    char data[2048]; /* data: lines joined by '\n' */
};

struct sse_client {
    CURLM *multi;
    CURL *easy;
    struct curl_slist *headers;
    char *buf; /* received, not yet parsed */
    size_t len, cap;
    bool ended; /* the transfer finished (the server ended the body, or an error) */
    CURLcode result;
    long status;
    char content_type[128];
    int comments; /* comment lines seen */
    char last_comment[256];
};

enum sse_result { SSE_EVENT = 1, SSE_TIMEOUT = 0, SSE_ENDED = -1 };

static inline size_t sse_write_cb(char *p, size_t size, size_t n, void *ud)
{
    struct sse_client *c = ud;
    size_t add = size * n;
    if (c->len + add + 1 > c->cap) {
        size_t cap = (c->len + add + 1) * 2;
        char *grown = realloc(c->buf, cap);
        if (grown == NULL)
            return 0;
        c->buf = grown;
        c->cap = cap;
    }
    memcpy(c->buf + c->len, p, add);
    c->len += add;
    c->buf[c->len] = '\0';
    return add;
}

static inline double sse_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Moves the transfer on for up to timeout_ms. */
static inline void sse_pump(struct sse_client *c, int timeout_ms)
{
    if (c->ended)
        return;
    int running = 0;
    curl_multi_perform(c->multi, &running);
    if (running)
        curl_multi_poll(c->multi, NULL, 0, timeout_ms, NULL);
    curl_multi_perform(c->multi, &running);
    CURLMsg *m;
    int left;
    while ((m = curl_multi_info_read(c->multi, &left)) != NULL) {
        if (m->msg == CURLMSG_DONE) {
            c->ended = true;
            c->result = m->data.result;
        }
    }
    if (c->status == 0)
        curl_easy_getinfo(c->easy, CURLINFO_RESPONSE_CODE, &c->status);
    if (c->content_type[0] == '\0') {
        char *ct = NULL;
        if (curl_easy_getinfo(c->easy, CURLINFO_CONTENT_TYPE, &ct) == CURLE_OK && ct)
            snprintf(c->content_type, sizeof c->content_type, "%s", ct);
    }
}

/* Takes one block (up to a blank line) off the buffer into ev; false when none is
 * complete. A block of comments only leaves ev->type empty. */
static inline bool sse_take_block(struct sse_client *c, struct sse_event *ev)
{
    char *end = c->buf ? strstr(c->buf, "\n\n") : NULL;
    if (end == NULL)
        return false;
    memset(ev, 0, sizeof *ev);
    bool has_data = false, has_type = false;
    *end = '\0';
    for (char *line = c->buf; line != NULL && line < end;) {
        char *nl = strchr(line, '\n');
        if (nl)
            *nl = '\0';
        const char *colon = strchr(line, ':');
        const char *value = colon ? colon + 1 : "";
        if (*value == ' ')
            value++;
        size_t name_len = colon ? (size_t)(colon - line) : strlen(line);
        if (name_len == 0 && colon) {
            c->comments++;
            snprintf(c->last_comment, sizeof c->last_comment, "%s", value);
        } else if (name_len == 2 && strncmp(line, "id", 2) == 0) {
            ev->has_id = true;
            ev->id = strtoull(value, NULL, 10);
        } else if (name_len == 5 && strncmp(line, "event", 5) == 0) {
            snprintf(ev->type, sizeof ev->type, "%s", value);
            has_type = true;
        } else if (name_len == 4 && strncmp(line, "data", 4) == 0) {
            size_t used = strlen(ev->data);
            snprintf(ev->data + used, sizeof ev->data - used, "%s%s", has_data ? "\n" : "", value);
            has_data = true;
        }
        line = nl ? nl + 1 : NULL;
    }
    size_t consumed = (size_t)(end + 2 - c->buf);
    memmove(c->buf, c->buf + consumed, c->len - consumed + 1);
    c->len -= consumed;
    if ((has_data || ev->has_id) && !has_type)
        snprintf(ev->type, sizeof ev->type, "message");
    return true;
}

/* The next event within timeout_s: SSE_EVENT (ev filled), SSE_TIMEOUT, or SSE_ENDED (the
 * body ended and everything in it was read). Comments are counted, not returned. */
static inline enum sse_result sse_next(struct sse_client *c, struct sse_event *ev, double timeout_s)
{
    double until = sse_now() + timeout_s;
    for (;;) {
        while (sse_take_block(c, ev)) {
            if (ev->type[0] != '\0')
                return SSE_EVENT;
        }
        if (c->ended)
            return SSE_ENDED;
        double left = until - sse_now();
        if (left <= 0)
            return SSE_TIMEOUT;
        sse_pump(c, left > 0.2 ? 200 : (int)(left * 1000) + 1);
    }
}

/* Waits until a comment has arrived (the stream's opening one). */
static inline bool sse_wait_comment(struct sse_client *c, double timeout_s)
{
    double until = sse_now() + timeout_s;
    int before = c->comments;
    struct sse_event ev;
    while (c->comments == before && sse_now() < until) {
        while (c->comments == before && sse_take_block(c, &ev)) {
            if (ev.type[0] != '\0') {
                fprintf(stderr, "sse: an event came before the opening comment\n");
                return false;
            }
        }
        if (c->comments > before || c->ended)
            break;
        sse_pump(c, 100);
    }
    return c->comments > before;
}

/* Opens path (with a Last-Event-ID header when last_event_id is not NULL) and waits up to
 * 10 s for the answer's headers and opening comment; c->status tells the status. An
 * answer that is not a stream (an error) is read whole into c->buf. */
static inline bool sse_open(struct sse_client *c, const struct test_daemon *d, const char *path,
                            const char *last_event_id)
{
    memset(c, 0, sizeof *c);
    char url[512];
    snprintf(url, sizeof url, "%s%s", d->url, path);
    c->easy = curl_easy_init();
    c->multi = curl_multi_init();
    if (last_event_id) {
        char h[128];
        snprintf(h, sizeof h, "Last-Event-ID: %s", last_event_id);
        c->headers = curl_slist_append(c->headers, h);
    }
    c->headers = curl_slist_append(c->headers, "Accept: text/event-stream");
    curl_easy_setopt(c->easy, CURLOPT_URL, url);
    curl_easy_setopt(c->easy, CURLOPT_HTTPHEADER, c->headers);
    curl_easy_setopt(c->easy, CURLOPT_WRITEFUNCTION, sse_write_cb);
    curl_easy_setopt(c->easy, CURLOPT_WRITEDATA, c);
    curl_multi_add_handle(c->multi, c->easy);
    double until = sse_now() + 10;
    while (c->status == 0 && !c->ended && sse_now() < until)
        sse_pump(c, 100);
    if (c->status != 200) {
        while (!c->ended && sse_now() < until)
            sse_pump(c, 100);
        return false;
    }
    return sse_wait_comment(c, until - sse_now());
}

static inline void sse_close(struct sse_client *c)
{
    if (c->multi && c->easy)
        curl_multi_remove_handle(c->multi, c->easy);
    curl_easy_cleanup(c->easy);
    curl_multi_cleanup(c->multi);
    curl_slist_free_all(c->headers);
    free(c->buf);
    memset(c, 0, sizeof *c);
}

/* A string or number field of an event's data ("" / -1 when absent). */
static inline const char *sse_str(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsString(v) ? v->valuestring : "";
}

static inline double sse_num(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : -1.0;
}

/* Reads events until one of type `type` (returned in ev, true) or timeout/end (false);
 * every event read on the way is appended to log (may be NULL) up to *count < max. */
static inline bool sse_until(struct sse_client *c, const char *type, double timeout_s,
                             struct sse_event *ev, struct sse_event *log, size_t *count, size_t max)
{
    double until = sse_now() + timeout_s;
    for (;;) {
        double left = until - sse_now();
        if (left <= 0 || sse_next(c, ev, left) != SSE_EVENT)
            return false;
        if (log && *count < max)
            log[(*count)++] = *ev;
        if (strcmp(ev->type, type) == 0)
            return true;
    }
}

#endif
