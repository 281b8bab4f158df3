/*
 * refract_stream.c - librefract's transport for long-lived streaming GETs (frame
 * streams, Server-Sent Events): the body goes to a sink chunk by chunk as libcurl
 * receives it, instead of being gathered whole as refract_http.c does.
 *
 * CONCEPT. A stream has no end the client can wait for, so the request timeout of the
 * other calls cannot apply. What matters is silence: refractd sends a keep-alive (the
 * newest frame again, or an SSE comment) every 15 s, so a stream that stays silent much
 * longer is dead. The client's timeout_ms is therefore the longest silence allowed,
 * checked in libcurl's progress callback (called about once a second while idle).
 *
 * Outcomes, and only these:
 *   the sink stopped the stream                      REFRACT_E_OK
 *   refractd ended it cleanly (the sink agrees)      REFRACT_E_OK
 *   a non-2xx reply                                  its JSON error code
 *   not the expected Content-Type, malformed bytes,
 *   or an end in the middle of an item               REFRACT_E_PROTOCOL
 *   no byte for timeout_ms                           REFRACT_E_TIMEOUT
 *   no connection                                    REFRACT_E_CONNECT_FAILED
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "refract_internal.h"
#include "refract_url.h"

#ifndef REFRACT_VERSION
#define REFRACT_VERSION "0"
#endif

double refract_monotonic_ms(void)
{
    struct timespec ts;

    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1000.0 + (double)ts.tv_nsec / 1e6;
}

/* One streaming exchange, borrowed by the libcurl callbacks. */
struct streaming {
    refract_client *c;
    const struct refract_stream_sink *sink;
    struct refract_response error_reply; /* a non-2xx reply's body, for refract_http_check */
    size_t error_cap;
    bool decided;   /* the status is known: streaming (2xx) or error_reply */
    bool streaming; /* a 2xx reply, handed to the sink */
    bool stopped;   /* the sink stopped it (chunk returned 1) */
    bool failed;    /* the sink found the bytes malformed; why says how */
    bool timed_out; /* no byte for timeout_ms */
    bool out_of_memory;
    double last_byte_ms;
    char content_type[128];
    char why[REFRACT_ERRMSG_SIZE / 2];
};

static size_t keep_error_body(struct streaming *s, const char *data, size_t n)
{
    struct refract_response *r = &s->error_reply;

    if (r->body_len + n + 1 > s->error_cap) {
        size_t cap = (r->body_len + n + 1) * 2;
        char *grown = realloc(r->body, cap);

        if (grown == NULL) {
            s->out_of_memory = true;
            return 0;
        }
        r->body = grown;
        s->error_cap = cap;
    }
    memcpy(r->body + r->body_len, data, n);
    r->body_len += n;
    r->body[r->body_len] = '\0';
    return n;
}

/* The first body bytes: is this the stream we asked for? */
static bool decide(struct streaming *s)
{
    long status = 0;

    s->decided = true;
    curl_easy_getinfo(s->c->curl, CURLINFO_RESPONSE_CODE, &status);
    s->error_reply.status = status;
    snprintf(s->error_reply.content_type, sizeof(s->error_reply.content_type), "%s",
             s->content_type);
    if (status < 200 || status >= 300)
        return true; /* the body is an error reply, kept for refract_http_check */
    s->streaming = true;
    if (strncasecmp(s->content_type, s->sink->content_type, strlen(s->sink->content_type)) != 0) {
        snprintf(s->why, sizeof(s->why),
                 "expected a %s reply (Content-Type %s...), got Content-Type \"%s\"; is --url "
                 "pointing at refractd?",
                 s->sink->item, s->sink->content_type, s->content_type);
        s->failed = true;
        return false;
    }
    if (s->sink->begin != NULL &&
        !s->sink->begin(s->sink->user, s->content_type, s->why, sizeof(s->why))) {
        s->failed = true;
        return false;
    }
    return true;
}

static size_t on_stream_body(char *data, size_t size, size_t nmemb, void *userp)
{
    struct streaming *s = userp;
    size_t n = size * nmemb;
    int verdict;

    s->last_byte_ms = refract_monotonic_ms();
    if (!s->decided && !decide(s))
        return 0;
    if (!s->streaming)
        return keep_error_body(s, data, n);
    verdict = s->sink->chunk(s->sink->user, data, n, s->last_byte_ms, s->why, sizeof(s->why));
    if (verdict == 0)
        return n;
    if (verdict > 0)
        s->stopped = true;
    else
        s->failed = true;
    return 0; /* ends curl_easy_perform with CURLE_WRITE_ERROR */
}

static size_t on_stream_header(char *data, size_t size, size_t nitems, void *userp)
{
    struct streaming *s = userp;
    size_t n = size * nitems;
    size_t name_len = strlen("Content-Type:");

    s->last_byte_ms = refract_monotonic_ms();
    if (n >= 5 && memcmp(data, "HTTP/", 5) == 0) {
        s->content_type[0] = '\0';
    } else if (n > name_len && strncasecmp(data, "Content-Type:", name_len) == 0) {
        size_t start = name_len;
        size_t end = n;

        while (start < end && (data[start] == ' ' || data[start] == '\t'))
            start++;
        while (end > start &&
               (data[end - 1] == '\r' || data[end - 1] == '\n' || data[end - 1] == ' '))
            end--;
        snprintf(s->content_type, sizeof(s->content_type), "%.*s", (int)(end - start),
                 data + start);
    }
    return n;
}

/* Called by libcurl often (at least once a second while idle): enforces the silence
 * limit. Returning non-zero aborts the transfer with CURLE_ABORTED_BY_CALLBACK. */
static int on_progress(void *userp, curl_off_t dltotal, curl_off_t dlnow, curl_off_t ultotal,
                       curl_off_t ulnow)
{
    struct streaming *s = userp;
    long limit = s->c->timeout_ms;

    (void)dltotal;
    (void)dlnow;
    (void)ultotal;
    (void)ulnow;
    if (limit > 0 && refract_monotonic_ms() - s->last_byte_ms > (double)limit) {
        s->timed_out = true;
        return 1;
    }
    return 0;
}

static void set_stream_options(refract_client *c, const char *url, struct curl_slist *headers,
                               struct streaming *s)
{
    CURL *curl = c->curl;

    /* No CURLOPT_TIMEOUT_MS: a stream has no end; on_progress bounds its silences. */
    refract_http_set_common(c, url, headers);
    curl_easy_setopt(curl, CURLOPT_HTTPGET, 1L);
    curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, on_stream_body);
    curl_easy_setopt(curl, CURLOPT_WRITEDATA, s);
    curl_easy_setopt(curl, CURLOPT_HEADERFUNCTION, on_stream_header);
    curl_easy_setopt(curl, CURLOPT_HEADERDATA, s);
    curl_easy_setopt(curl, CURLOPT_XFERINFOFUNCTION, on_progress);
    curl_easy_setopt(curl, CURLOPT_XFERINFODATA, s);
    curl_easy_setopt(curl, CURLOPT_NOPROGRESS, 0L);
    /* Frames must reach the sink as they arrive, not when a buffer fills. */
    curl_easy_setopt(curl, CURLOPT_TCP_NODELAY, 1L);
}

static int build_header_list(const char *const *headers, struct curl_slist **out)
{
    *out = NULL;
    for (size_t i = 0; headers != NULL && headers[i] != NULL; i++) {
        struct curl_slist *grown = curl_slist_append(*out, headers[i]);

        if (grown == NULL) {
            curl_slist_free_all(*out);
            *out = NULL;
            return REFRACT_E_OUT_OF_MEMORY;
        }
        *out = grown;
    }
    return REFRACT_E_OK;
}

/* What the exchange's ending means, after curl_easy_perform returned rc. */
static int outcome(refract_client *c, const char *path, struct streaming *s, CURLcode rc)
{
    const struct refract_stream_sink *sink = s->sink;

    if (s->out_of_memory || rc == CURLE_OUT_OF_MEMORY)
        return refract_fail(c, REFRACT_E_OUT_OF_MEMORY, "GET %s: out of memory", path);
    if (s->stopped)
        return REFRACT_E_OK;
    if (s->failed)
        return refract_fail(c, REFRACT_E_PROTOCOL, "GET %s: %s", path, s->why);
    if (s->timed_out)
        return refract_fail(c, REFRACT_E_TIMEOUT,
                            "GET %s: no byte from refractd at %s for %ld ms (after %ld %ss); "
                            "raise the timeout (refract --timeout SECONDS, 0 = none)",
                            path, c->base_url, c->timeout_ms, sink->delivered(sink->user),
                            sink->item);
    if (rc == CURLE_OK && !s->decided && !decide(s))
        return refract_fail(c, REFRACT_E_PROTOCOL, "GET %s: %s", path, s->why);
    if (s->decided && !s->streaming)
        return refract_http_check(c, "GET", path, &s->error_reply);
    if (!s->decided)
        return refract_http_transport_failure(c, rc, "GET", path, false);
    /* A 2xx stream that ended: cleanly only if it ended between two items. */
    if (!sink->end(sink->user, s->why, sizeof(s->why)))
        return refract_fail(
            c, REFRACT_E_PROTOCOL, "GET %s: %s%s%s", path, s->why,
            rc != CURLE_OK ? "; libcurl: " : "",
            rc != CURLE_OK ? (c->curl_error[0] != '\0' ? c->curl_error : curl_easy_strerror(rc))
                           : "");
    if (rc != CURLE_OK)
        return refract_fail(c, REFRACT_E_PROTOCOL, "GET %s: the stream broke off after %ld %ss: %s",
                            path, sink->delivered(sink->user), sink->item,
                            c->curl_error[0] != '\0' ? c->curl_error : curl_easy_strerror(rc));
    return REFRACT_E_OK;
}

int refract_stream_get(refract_client *c, const char *path, const char *const *headers,
                       const struct refract_stream_sink *sink)
{
    struct streaming s = {.c = c, .sink = sink};
    struct curl_slist *list = NULL;
    char *url = refract_url_join(c->base_url, path);
    CURLcode rc;
    int code;

    if (url == NULL || build_header_list(headers, &list) != REFRACT_E_OK) {
        free(url);
        return refract_fail(c, REFRACT_E_OUT_OF_MEMORY, "out of memory preparing GET %s", path);
    }
    curl_easy_reset(c->curl);
    set_stream_options(c, url, list, &s);
    c->curl_error[0] = '\0';
    s.last_byte_ms = refract_monotonic_ms();
    rc = curl_easy_perform(c->curl);
    curl_easy_setopt(c->curl, CURLOPT_HTTPHEADER, NULL);
    curl_slist_free_all(list);
    free(url);
    code = outcome(c, path, &s, rc);
    refract_response_free(&s.error_reply);
    return code;
}
