/*
 * access.c - who may use refractd (docs/api.md "Security"): the Host allow-list (421),
 * the bearer token (401), and the Content-Type of JSON bodies (415). server.c applies
 * them, in that order, on the first call of every request, before any handler runs.
 *
 *   Host: a browser sends the name in the page's address bar. A foreign site that makes
 *     its own DNS name resolve to 127.0.0.1 (DNS rebinding) is same-origin with itself,
 *     so only the Host header tells refractd that the request is not meant for it. The
 *     names served: 127.0.0.1, localhost, [::1], the --bind address, and each
 *     --allow-host NAME ("*" turns the check off, for a proxy that checks it); any port.
 *   Token: with --token-file, every request but GET /v1/health and the web viewer's
 *     static pages (GET /, /viewer/{id}, /assets/{file}: embedded files that hold no
 *     data; their scripts ask for the token and send it) needs
 *     "Authorization: Bearer <token>", compared in constant time.
 *   Content-Type: a browser sends a cross-origin POST without asking first (no CORS
 *     preflight) only with text/plain, form or multipart bodies, or none. Requiring
 *     application/json on every JSON route (an empty body too) makes such a request
 *     fail before it does anything. Uploads have their own types (checked by their
 *     handlers).
 */
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "access.h"

/* Copies at most 64 bytes of text into out, printable ASCII only (others become '?'), so
 * a hostile header cannot put control characters or broken UTF-8 into messages. */
static void printable(const char *text, char *out, size_t size)
{
    size_t n = 0;
    for (const char *p = text; *p && n + 4 < size && n < 64; p++)
        out[n++] = (*p >= 0x20 && *p < 0x7f) ? *p : '?';
    if (*text && strlen(text) > n && n + 4 <= size) {
        memcpy(out + n, "...", 3);
        n += 3;
    }
    out[n] = '\0';
}

/* The host part of a Host header value: "[::1]:8750" -> "[::1]", "localhost:80" ->
 * "localhost", "example.org" -> "example.org". Returns its length, or 0 when malformed. */
static size_t host_name_length(const char *host)
{
    size_t len;
    if (host[0] == '[') {
        const char *close = strchr(host, ']');
        if (close == NULL)
            return 0;
        len = (size_t)(close - host) + 1;
    } else {
        len = strcspn(host, ":");
    }
    if (host[len] == ':') {
        const char *port = host + len + 1;
        if (*port == '\0' || strspn(port, "0123456789") != strlen(port))
            return 0;
    } else if (host[len] != '\0') {
        return 0;
    }
    return len;
}

static bool name_is(const char *host, size_t len, const char *name)
{
    return name != NULL && strlen(name) == len && strncasecmp(host, name, len) == 0;
}

bool http_access_host_allowed(const struct http_config *cfg, const char *host)
{
    for (size_t i = 0; i < cfg->allow_host_count; i++) {
        if (strcmp(cfg->allow_hosts[i], "*") == 0)
            return true;
    }
    if (host == NULL)
        return false;
    /* A trailing dot names the same host ("localhost."). */
    size_t len = host_name_length(host);
    if (len == 0)
        return false;
    if (len > 1 && host[len - 1] == '.')
        len--;
    static const char *const loopback[] = {"127.0.0.1", "localhost", "[::1]"};
    for (size_t i = 0; i < sizeof loopback / sizeof loopback[0]; i++) {
        if (name_is(host, len, loopback[i]))
            return true;
    }
    if (strcmp(cfg->bind_address, "0.0.0.0") != 0 && name_is(host, len, cfg->bind_address))
        return true;
    for (size_t i = 0; i < cfg->allow_host_count; i++) {
        if (name_is(host, len, cfg->allow_hosts[i]))
            return true;
    }
    return false;
}

void http_access_host_message(const char *host, char *out, size_t size)
{
    char shown[80];
    if (host == NULL) {
        snprintf(out, size,
                 "the request has no Host header; refractd answers only requests for a host it "
                 "serves (127.0.0.1, localhost, [::1], its --bind address, --allow-host NAME)");
        return;
    }
    printable(host, shown, sizeof shown);
    snprintf(out, size,
             "Host \"%s\" is not served here (DNS rebinding guard); refractd serves 127.0.0.1, "
             "localhost, [::1] and its --bind address: start it with --allow-host NAME for the "
             "name clients use",
             shown);
}

bool http_access_token_exempt(const char *method, const char *pattern)
{
    if (strcmp(method, "GET") != 0)
        return false;
    return strcmp(pattern, "/v1/health") == 0 || strcmp(pattern, "/") == 0 ||
           strcmp(pattern, "/viewer/{id}") == 0 || strcmp(pattern, "/assets/{file}") == 0;
}

/* Equal strings, in a time that depends only on the length of want (the secret's length is
 * not a secret worth the complication), never on where the first difference is. */
static bool equal_constant_time(const char *given, size_t given_len, const char *want,
                                size_t want_len)
{
    volatile unsigned char diff = given_len != want_len;
    for (size_t i = 0; i < want_len; i++) {
        unsigned char g = i < given_len ? (unsigned char)given[i] : 0;
        diff |= (unsigned char)(g ^ (unsigned char)want[i]);
    }
    return diff == 0;
}

enum http_token_verdict http_access_token_check(const struct http_config *cfg,
                                                const char *authorization)
{
    if (cfg->token == NULL || cfg->token[0] == '\0')
        return HTTP_TOKEN_OK;
    if (authorization == NULL)
        return HTTP_TOKEN_MISSING;
    const char *p = authorization + strspn(authorization, " \t");
    if (strncasecmp(p, "Bearer", 6) != 0 || (p[6] != ' ' && p[6] != '\t'))
        return HTTP_TOKEN_NOT_BEARER;
    p += 6;
    p += strspn(p, " \t");
    size_t len = strlen(p);
    while (len > 0 && (p[len - 1] == ' ' || p[len - 1] == '\t'))
        len--;
    return equal_constant_time(p, len, cfg->token, strlen(cfg->token)) ? HTTP_TOKEN_OK
                                                                       : HTTP_TOKEN_WRONG;
}

bool http_access_json_type(const char *content_type)
{
    if (content_type == NULL)
        return false;
    const char *p = content_type + strspn(content_type, " \t");
    static const char json[] = "application/json";
    if (strncasecmp(p, json, sizeof json - 1) != 0)
        return false;
    p += sizeof json - 1;
    p += strspn(p, " \t");
    return *p == '\0' || *p == ';'; /* parameters (charset=utf-8) are fine */
}

void http_access_type_message(const char *method, const char *pattern, const char *content_type,
                              char *out, size_t size)
{
    char shown[80];
    if (content_type == NULL) {
        snprintf(out, size,
                 "%s %s takes a JSON body and needs the header Content-Type: application/json "
                 "(even for an empty body); the request has no Content-Type",
                 method, pattern);
        return;
    }
    printable(content_type, shown, sizeof shown);
    snprintf(out, size,
             "%s %s takes a JSON body and needs the header Content-Type: application/json, "
             "not \"%s\"; send the JSON with that header",
             method, pattern, shown);
}
