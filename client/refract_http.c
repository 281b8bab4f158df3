/*
 * refract_http.c - librefract's transport: one HTTP exchange with refractd over the
 * client's CURL easy handle, and the reading of refractd's error replies.
 *
 * An exchange resets the easy handle (curl_easy_reset keeps live connections, so the
 * keep-alive connection survives), sets every option it needs, performs, and collects
 * the body and four reply headers: Content-Type, X-Render-Time-Ms, X-Renderer and
 * X-Refract-Irradiance.
 * Failures are mapped onto the shared code table here, and only here:
 *
 *   no connection (refused, unresolvable, connect timeout)  REFRACT_E_CONNECT_FAILED
 *   connected, but no complete reply within timeout_ms      REFRACT_E_TIMEOUT
 *   malloc failed (ours or libcurl's)                       REFRACT_E_OUT_OF_MEMORY
 *   anything else that broke the exchange                   REFRACT_E_PROTOCOL
 *   a reply that is not 2xx                                 its JSON "error.code"
 *
 * A body is a buffer, or (uploads, refract_upload.c) read by libcurl from a source as it
 * is sent, so a file of any size never has to be in memory.
 * This file does not know the API's routes; refract_calls.c does.
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "refract_internal.h"
#include "refract_url.h"

#ifndef REFRACT_VERSION
#define REFRACT_VERSION "0"
#endif

/* State of one exchange, borrowed by the libcurl callbacks during curl_easy_perform. */
struct exchange {
    struct refract_response *out; /* borrowed; the body grows here */
    size_t body_cap;              /* bytes allocated for out->body */
    bool out_of_memory;           /* a callback failed to allocate */
};

static size_t on_body(char *data, size_t size, size_t nmemb, void *userp)
{
    struct exchange *x = userp;
    struct refract_response *r = x->out;
    size_t n = size * nmemb; /* libcurl documents size as always 1 */

    if (n > SIZE_MAX - 1 - r->body_len) {
        x->out_of_memory = true;
        return 0;
    }
    if (r->body_len + n + 1 > x->body_cap) {
        size_t need = r->body_len + n + 1;
        size_t cap = x->body_cap > 0 ? x->body_cap : 16384;
        char *grown;

        while (cap < need)
            cap = cap <= SIZE_MAX / 2 ? cap * 2 : need;
        grown = realloc(r->body, cap);
        if (grown == NULL) {
            x->out_of_memory = true;
            return 0; /* makes curl_easy_perform fail with CURLE_WRITE_ERROR */
        }
        r->body = grown;
        x->body_cap = cap;
    }
    memcpy(r->body + r->body_len, data, n);
    r->body_len += n;
    r->body[r->body_len] = '\0';
    return n;
}

/* If line (len bytes, "Name: value\r\n") is the header name, points *value at its value
 * without surrounding blanks and returns its length; returns -1 otherwise. */
static long header_value(const char *line, size_t len, const char *name, const char **value)
{
    size_t name_len = strlen(name);
    size_t start;
    size_t end = len;

    if (len <= name_len || line[name_len] != ':' || strncasecmp(line, name, name_len) != 0)
        return -1;
    start = name_len + 1;
    while (start < end && (line[start] == ' ' || line[start] == '\t'))
        start++;
    while (end > start && (line[end - 1] == '\r' || line[end - 1] == '\n' || line[end - 1] == ' ' ||
                           line[end - 1] == '\t'))
        end--;
    *value = line + start;
    return (long)(end - start);
}

static void copy_value(char *dst, size_t dst_size, const char *value, long len)
{
    size_t n = (size_t)len < dst_size - 1 ? (size_t)len : dst_size - 1;

    memcpy(dst, value, n);
    dst[n] = '\0';
}

static size_t on_header(char *data, size_t size, size_t nitems, void *userp)
{
    struct refract_response *r = ((struct exchange *)userp)->out;
    size_t n = size * nitems;
    const char *value;
    long len;

    /* A status line starts each reply's headers ("HTTP/1.1 100 Continue" comes before the
     * real one), so only the last reply's headers are kept. */
    if (n >= 5 && memcmp(data, "HTTP/", 5) == 0) {
        r->content_type[0] = '\0';
        r->renderer[0] = '\0';
        r->irradiance[0] = '\0';
        r->render_ms = -1.0;
        return n;
    }
    len = header_value(data, n, "Content-Type", &value);
    if (len >= 0)
        copy_value(r->content_type, sizeof(r->content_type), value, len);
    len = header_value(data, n, "X-Renderer", &value);
    if (len >= 0)
        copy_value(r->renderer, sizeof(r->renderer), value, len);
    len = header_value(data, n, "X-Refract-Irradiance", &value);
    if (len >= 0)
        copy_value(r->irradiance, sizeof(r->irradiance), value, len);
    len = header_value(data, n, "X-Render-Time-Ms", &value);
    if (len >= 0) {
        char number[64];
        char *end;
        double ms;

        copy_value(number, sizeof(number), value, len);
        ms = strtod(number, &end);
        r->render_ms = (end != number && *end == '\0' && isfinite(ms) && ms >= 0) ? ms : -1.0;
    }
    return n;
}

static bool is_method_token(const char *method)
{
    if (*method == '\0')
        return false;
    for (; *method != '\0'; method++) {
        if (*method < 'A' || *method > 'Z')
            return false;
    }
    return true;
}

/* Sets the request line and body options; POSTFIELDS with an explicit size sends body
 * bytes as they are (NULs included) for any method. */
static void set_method(CURL *curl, const char *method, const void *body, size_t body_len)
{
    bool sends_body = body != NULL || strcmp(method, "POST") == 0 || strcmp(method, "PUT") == 0 ||
                      strcmp(method, "PATCH") == 0;

    if (sends_body) {
        curl_easy_setopt(curl, CURLOPT_POSTFIELDS, body != NULL ? body : "");
        curl_easy_setopt(curl, CURLOPT_POSTFIELDSIZE_LARGE, (curl_off_t)body_len);
        if (strcmp(method, "POST") != 0)
            curl_easy_setopt(curl, CURLOPT_CUSTOMREQUEST, method);
    } else if (strcmp(method, "HEAD") == 0) {
        curl_easy_setopt(curl, CURLOPT_NOBODY, 1L);
    } else if (strcmp(method, "GET") == 0) {
        curl_easy_setopt(curl, CURLOPT_HTTPGET, 1L);
    } else {
        curl_easy_setopt(curl, CURLOPT_CUSTOMREQUEST, method);
    }
}

void refract_http_set_common(refract_client *c, const char *url, struct curl_slist *headers)
{
    CURL *curl = c->curl;
    long connect_ms = REFRACT_CONNECT_TIMEOUT_MS;

    if (c->timeout_ms > 0 && c->timeout_ms < connect_ms)
        connect_ms = c->timeout_ms;
    curl_easy_setopt(curl, CURLOPT_URL, url);
    curl_easy_setopt(curl, CURLOPT_PROTOCOLS_STR, "http,https");
    /* Scene ids are escaped, but "." segments must not be squashed by libcurl either. */
    curl_easy_setopt(curl, CURLOPT_PATH_AS_IS, 1L);
    curl_easy_setopt(curl, CURLOPT_ERRORBUFFER, c->curl_error);
    /* No signals: timeouts must not use SIGALRM in a library that may run in threads. */
    curl_easy_setopt(curl, CURLOPT_NOSIGNAL, 1L);
    curl_easy_setopt(curl, CURLOPT_CONNECTTIMEOUT_MS, connect_ms);
    curl_easy_setopt(curl, CURLOPT_USERAGENT, "librefract/" REFRACT_VERSION);
    curl_easy_setopt(curl, CURLOPT_HTTPHEADER, headers);
    if (c->token != NULL) {
        /* Sent with the first request (the only method allowed), never in the URL. */
        curl_easy_setopt(curl, CURLOPT_HTTPAUTH, (long)CURLAUTH_BEARER);
        curl_easy_setopt(curl, CURLOPT_XOAUTH2_BEARER, c->token);
    }
    if (c->cacert != NULL)
        curl_easy_setopt(curl, CURLOPT_CAINFO, c->cacert);
}

static void set_options(refract_client *c, const char *url, struct curl_slist *headers,
                        struct exchange *x)
{
    CURL *curl = c->curl;

    refract_http_set_common(c, url, headers);
    curl_easy_setopt(curl, CURLOPT_TIMEOUT_MS, c->timeout_ms);
    curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, on_body);
    curl_easy_setopt(curl, CURLOPT_WRITEDATA, x);
    curl_easy_setopt(curl, CURLOPT_HEADERFUNCTION, on_header);
    curl_easy_setopt(curl, CURLOPT_HEADERDATA, x);
}

static bool is_connect_failure(CURLcode rc)
{
    switch (rc) {
    case CURLE_COULDNT_CONNECT:
    case CURLE_COULDNT_RESOLVE_HOST:
    case CURLE_COULDNT_RESOLVE_PROXY:
    case CURLE_URL_MALFORMAT:
    case CURLE_UNSUPPORTED_PROTOCOL:
    case CURLE_SSL_CONNECT_ERROR:
    case CURLE_PEER_FAILED_VERIFICATION:
        return true;
    default:
        return false;
    }
}

int refract_http_transport_failure(refract_client *c, CURLcode rc, const char *method,
                                   const char *path, bool out_of_memory)
{
    const char *why = c->curl_error[0] != '\0' ? c->curl_error : curl_easy_strerror(rc);
    long request_bytes = 0;

    if (out_of_memory || rc == CURLE_OUT_OF_MEMORY)
        return refract_fail(c, REFRACT_E_OUT_OF_MEMORY,
                            "out of memory while receiving the reply to %s %s", method, path);
    /* A timeout before the request went out is a connect failure; after it, a slow reply. */
    curl_easy_getinfo(c->curl, CURLINFO_REQUEST_SIZE, &request_bytes);
    if (is_connect_failure(rc) || (rc == CURLE_OPERATION_TIMEDOUT && request_bytes == 0))
        return refract_fail(c, REFRACT_E_CONNECT_FAILED,
                            "could not connect to refractd at %s: %s. Is refractd running? "
                            "Start it, or point --url (or REFRACT_URL) at the address it "
                            "listens on",
                            c->base_url, why);
    if (rc == CURLE_OPERATION_TIMEDOUT)
        return refract_fail(c, REFRACT_E_TIMEOUT,
                            "%s %s: no complete reply from refractd at %s within %ld ms (%s); "
                            "raise the timeout (refract --timeout SECONDS, 0 = none)",
                            method, path, c->base_url, c->timeout_ms, why);
    return refract_fail(c, REFRACT_E_PROTOCOL,
                        "%s %s: the exchange with refractd at %s broke "
                        "off: %s",
                        method, path, c->base_url, why);
}

static int check_arguments(refract_client *c, const char *method, const char *path,
                           const void *body, size_t body_len, const char *content_type)
{
    if (method == NULL || !is_method_token(method))
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_request: method must be an upper-"
                            "case HTTP method such as \"GET\", got \"%s\"",
                            method != NULL ? method : "(null)");
    if (path == NULL || path[0] != '/')
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_request: path must start with '/', "
                            "got \"%s\"",
                            path != NULL ? path : "(null)");
    if (body == NULL && body_len > 0)
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_request: body is NULL but body_len "
                            "is %zu",
                            body_len);
    if (content_type != NULL && strpbrk(content_type, "\r\n") != NULL)
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_request: content_type contains a "
                            "line break");
    return REFRACT_E_OK;
}

/* Returns the request's header list (NULL when none is needed) through *headers. A body
 * of unknown size goes chunked, which libcurl does only when asked by this header. */
static int build_headers(const void *body, const char *content_type, bool chunked,
                         struct curl_slist **headers)
{
    char line[256];
    struct curl_slist *list = NULL;

    *headers = NULL;
    if (content_type != NULL)
        snprintf(line, sizeof(line), "Content-Type: %s", content_type);
    else if (body != NULL)
        snprintf(line, sizeof(line), "Content-Type:"); /* drop libcurl's form default */
    else
        line[0] = '\0';
    if (line[0] != '\0') {
        list = curl_slist_append(NULL, line);
        if (list == NULL)
            return REFRACT_E_OUT_OF_MEMORY;
    }
    if (chunked) {
        struct curl_slist *grown = curl_slist_append(list, "Transfer-Encoding: chunked");

        if (grown == NULL) {
            curl_slist_free_all(list);
            return REFRACT_E_OUT_OF_MEMORY;
        }
        list = grown;
    }
    *headers = list;
    return REFRACT_E_OK;
}

/* The options of a body that libcurl reads as it sends (CURLOPT_UPLOAD is a PUT; another
 * method is named). The whole-request timeout is off: an upload of any size must not be
 * cut short for taking long, so the source's xferinfo callback bounds its silences. */
static void set_source(CURL *curl, const char *method, const struct refract_http_body_source *src)
{
    curl_easy_setopt(curl, CURLOPT_UPLOAD, 1L);
    if (strcmp(method, "PUT") != 0)
        curl_easy_setopt(curl, CURLOPT_CUSTOMREQUEST, method);
    curl_easy_setopt(curl, CURLOPT_READFUNCTION, src->read);
    curl_easy_setopt(curl, CURLOPT_READDATA, src->user);
    if (src->seek != NULL) {
        curl_easy_setopt(curl, CURLOPT_SEEKFUNCTION, src->seek);
        curl_easy_setopt(curl, CURLOPT_SEEKDATA, src->user);
    }
    if (src->size >= 0)
        curl_easy_setopt(curl, CURLOPT_INFILESIZE_LARGE, (curl_off_t)src->size);
    curl_easy_setopt(curl, CURLOPT_TIMEOUT_MS, 0L);
    if (src->xferinfo != NULL) {
        curl_easy_setopt(curl, CURLOPT_XFERINFOFUNCTION, src->xferinfo);
        curl_easy_setopt(curl, CURLOPT_XFERINFODATA, src->xferinfo_user);
        curl_easy_setopt(curl, CURLOPT_NOPROGRESS, 0L);
    }
}

/* One exchange whose body is a buffer (src NULL) or read from src as it is sent. */
static int exchange(refract_client *c, const char *method, const char *path, const void *body,
                    size_t body_len, const struct refract_http_body_source *src,
                    const char *content_type, struct refract_response *out)
{
    struct exchange x = {.out = out};
    struct curl_slist *headers = NULL;
    char *url = NULL;
    CURLcode rc;
    int code;

    memset(out, 0, sizeof(*out));
    out->render_ms = -1.0;
    code = check_arguments(c, method, path, body, body_len, content_type);
    if (code != REFRACT_E_OK)
        return code;
    url = refract_url_join(c->base_url, path);
    if (url == NULL ||
        build_headers(body, content_type, src != NULL && src->size < 0, &headers) != REFRACT_E_OK) {
        free(url);
        return refract_fail(c, REFRACT_E_OUT_OF_MEMORY, "out of memory preparing %s %s", method,
                            path);
    }

    curl_easy_reset(c->curl);
    set_options(c, url, headers, &x);
    if (src != NULL)
        set_source(c->curl, method, src);
    else
        set_method(c->curl, method, body, body_len);
    c->curl_error[0] = '\0';
    rc = curl_easy_perform(c->curl);
    curl_easy_setopt(c->curl, CURLOPT_HTTPHEADER, NULL); /* the list is freed below */
    curl_slist_free_all(headers);
    free(url);

    if (rc == CURLE_OK && out->body == NULL) {
        out->body = malloc(1); /* the contract promises a string, even for a 204 */
        if (out->body != NULL)
            out->body[0] = '\0';
        else
            x.out_of_memory = true;
    }
    if (rc != CURLE_OK || x.out_of_memory) {
        code = refract_http_transport_failure(c, rc, method, path, x.out_of_memory);
        refract_response_free(out);
        return code;
    }
    curl_easy_getinfo(c->curl, CURLINFO_RESPONSE_CODE, &out->status);
    return REFRACT_E_OK;
}

int refract_http_exchange(refract_client *c, const char *method, const char *path, const void *body,
                          size_t body_len, const char *content_type, struct refract_response *out)
{
    return exchange(c, method, path, body, body_len, NULL, content_type, out);
}

int refract_http_exchange_source(refract_client *c, const char *method, const char *path,
                                 const struct refract_http_body_source *src,
                                 const char *content_type, struct refract_response *out)
{
    return exchange(c, method, path, NULL, 0, src, content_type, out);
}

int refract_request(refract_client *c, const char *method, const char *path, const void *body,
                    size_t body_len, const char *content_type, struct refract_response *out)
{
    if (c == NULL || out == NULL) {
        if (out != NULL)
            memset(out, 0, sizeof(*out));
        return REFRACT_E_USAGE;
    }
    refract_clear_error(c);
    return refract_http_exchange(c, method, path, body, body_len, content_type, out);
}

void refract_response_free(struct refract_response *r)
{
    if (r == NULL)
        return;
    free(r->body);
    memset(r, 0, sizeof(*r));
    r->render_ms = -1.0;
}

/* Copies up to max printable bytes of a reply body into dst for an error message. */
static void body_excerpt(char *dst, size_t dst_size, const char *body, size_t len)
{
    size_t max = dst_size - 4;
    size_t n = len < max ? len : max;

    for (size_t i = 0; i < n; i++) {
        unsigned char ch = (unsigned char)body[i];
        dst[i] = (ch < ' ' || ch == 0x7F) ? ' ' : (char)ch;
    }
    strcpy(dst + n, len > max ? "..." : "");
}

static int not_an_error_body(refract_client *c, const char *method, const char *path,
                             const struct refract_response *r)
{
    char excerpt[160];

    if (r->body_len == 0)
        return refract_fail(c, REFRACT_E_PROTOCOL,
                            "%s %s: refractd at %s answered HTTP %ld "
                            "with an empty body",
                            method, path, c->base_url, r->status);
    body_excerpt(excerpt, sizeof(excerpt), r->body, r->body_len);
    return refract_fail(c, REFRACT_E_PROTOCOL,
                        "%s %s: %s answered HTTP %ld with a body that "
                        "is not a refractd error (Content-Type \"%s\"): %s; is --url "
                        "pointing at refractd?",
                        method, path, c->base_url, r->status, r->content_type, excerpt);
}

int refract_http_check(refract_client *c, const char *method, const char *path,
                       const struct refract_response *r)
{
    const cJSON *error;
    const cJSON *code_item;
    const cJSON *message;
    cJSON *root;
    int code;

    if (r->status >= 200 && r->status < 300)
        return REFRACT_E_OK;
    root = cJSON_ParseWithLengthOpts(r->body, r->body_len, NULL, 0);
    error = cJSON_GetObjectItemCaseSensitive(root, "error");
    code_item = cJSON_GetObjectItemCaseSensitive(error, "code");
    message = cJSON_GetObjectItemCaseSensitive(error, "message");
    if (!cJSON_IsObject(error) || !cJSON_IsString(code_item)) {
        cJSON_Delete(root);
        return not_an_error_body(c, method, path, r);
    }
    code = refract_code_from_name(code_item->valuestring);
    if (code <= REFRACT_E_OK) {
        refract_fail(c, REFRACT_E_PROTOCOL,
                     "%s %s: refractd answered HTTP %ld with the "
                     "unknown error code \"%s\": %s",
                     method, path, r->status, code_item->valuestring,
                     cJSON_IsString(message) ? message->valuestring : "(no message)");
        code = REFRACT_E_PROTOCOL;
    } else if (cJSON_IsString(message) && message->valuestring[0] != '\0') {
        refract_fail(c, code, "%s", message->valuestring);
    } else {
        refract_fail(c, code, "%s (HTTP %ld from %s %s)", refract_strerror(code), r->status, method,
                     path);
    }
    cJSON_Delete(root);
    return code;
}
