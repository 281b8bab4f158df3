/*
 * test_access_control.c - refractd is safe to expose (issue 13, "Access control"; docs/api.md
 * "Security"), tried as an attacker would, against a real daemon:
 *   - a browser's cross-origin "simple" POST (text/plain, or no Content-Type) gets 415
 *     before it does anything; application/json (with a charset) works;
 *   - every answer says X-Content-Type-Options: nosniff (JSON, errors, pages, streams);
 *   - a foreign Host (DNS rebinding) gets 421 with our JSON error; loopback names with
 *     and without port, and --allow-host names, are served;
 *   - with --token-file: no token, another token or another scheme get 401 with
 *     WWW-Authenticate: Bearer; the right token works; GET /v1/health and the viewer's
 *     pages need none; the CLI works with REFRACT_TOKEN and with --token-file;
 *   - refractd refuses to start on a non-loopback --bind without a token, and refuses a
 *     bad token file, each with a message that says what to do.
 */
#include <arpa/inet.h>
#include <netinet/in.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include "integration/daemon.h"
#include "integration/support_cli.h"
#include "test.h"

#define TOKEN "s3cret-token-0123456789abcdef"

static const char scene_json[] = "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": "
                                 "[1, 1, 1]}, \"resolution\": 8, \"ior\": 1.2}]}";

/* One raw HTTP/1.1 exchange (Connection: close): the whole answer, headers and body, as a
 * new string ("" when nothing came). head holds the request line's method and path and
 * any headers ("GET /v1/health HTTP/1.1\r\nHost: x\r\n"); the body follows. */
static char *raw_http(const struct test_daemon *d, const char *head, const char *body)
{
    char *answer = calloc(1, 1 << 20);
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons((uint16_t)d->port)};
    inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
    struct timeval tv = {.tv_sec = 20};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    if (answer == NULL || fd < 0 || connect(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        if (fd >= 0)
            close(fd);
        return answer;
    }
    char req[4096];
    int n = snprintf(req, sizeof req, "%sConnection: close\r\nContent-Length: %zu\r\n\r\n%s", head,
                     body ? strlen(body) : 0, body ? body : "");
    if (send(fd, req, (size_t)n, 0) == n) {
        size_t got = 0;
        ssize_t r;
        while (got < (1 << 20) - 1 && (r = recv(fd, answer + got, (1 << 20) - 1 - got, 0)) > 0)
            got += (size_t)r;
        answer[got] = '\0';
    }
    close(fd);
    return answer;
}

static int status_of(const char *answer)
{
    int status = 0;
    return sscanf(answer, "HTTP/1.%*d %d", &status) == 1 ? status : -1;
}

/* True when the answer's headers include "name: value-prefix" (any case for the name). */
static bool has_header(const char *answer, const char *name, const char *value_prefix)
{
    const char *end = strstr(answer, "\r\n\r\n");
    size_t name_len = strlen(name);
    for (const char *p = strstr(answer, "\r\n"); p && (!end || p < end);
         p = strstr(p + 2, "\r\n")) {
        const char *line = p + 2;
        if (strncasecmp(line, name, name_len) == 0 && line[name_len] == ':') {
            const char *v = line + name_len + 1;
            v += strspn(v, " ");
            if (strncmp(v, value_prefix, strlen(value_prefix)) == 0)
                return true;
        }
    }
    return false;
}

static const char *body_of(const char *answer)
{
    const char *b = strstr(answer, "\r\n\r\n");
    return b ? b + 4 : "";
}

static void json_routes_want_json(struct test_daemon *d)
{
    char head[512];
    /* A form a foreign page can send without a CORS preflight. */
    snprintf(head, sizeof head,
             "POST /v1/scenes HTTP/1.1\r\nHost: 127.0.0.1:%d\r\nContent-Type: text/plain\r\n",
             d->port);
    char *a = raw_http(d, head, scene_json);
    CHECK_INT(status_of(a), 415);
    CHECK(test_error_is(body_of(a), "unsupported_media_type", "Content-Type: application/json"));
    CHECK(test_error_is(body_of(a), "unsupported_media_type", "\"text/plain\""));
    CHECK(has_header(a, "X-Content-Type-Options", "nosniff"));
    free(a);
    /* No Content-Type at all (fetch with no-cors and a body-less POST): 415 too, even for a
     * route whose empty body means {} and for a scene that does not exist. */
    snprintf(head, sizeof head, "POST /v1/scenes/nope/render HTTP/1.1\r\nHost: 127.0.0.1\r\n");
    a = raw_http(d, head, NULL);
    CHECK_INT(status_of(a), 415);
    CHECK(test_error_is(body_of(a), "unsupported_media_type", "no Content-Type"));
    free(a);
    snprintf(head, sizeof head,
             "POST /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
             "application/x-www-form-urlencoded\r\n");
    a = raw_http(d, head, "a=b");
    CHECK_INT(status_of(a), 415);
    free(a);
    snprintf(head, sizeof head,
             "PATCH /v1/views/v1 HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: multipart/form-data; "
             "boundary=x\r\n");
    a = raw_http(d, head, "{}");
    CHECK_INT(status_of(a), 415);
    free(a);
    /* Control bytes in the header never reach the message. */
    snprintf(head, sizeof head,
             "POST /v1/scenes HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: text/\x01\x7f\r\n");
    a = raw_http(d, head, "{}");
    CHECK_INT(status_of(a), 415);
    CHECK(strchr(body_of(a), '\x01') == NULL && strchr(body_of(a), '\x7f') == NULL);
    free(a);
    /* application/json with parameters, in any case, is JSON. */
    snprintf(head, sizeof head,
             "POST /v1/scenes HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: Application/JSON; "
             "charset=utf-8\r\n");
    a = raw_http(d, head, scene_json);
    CHECK_INT(status_of(a), 201);
    free(a);
    /* Through librefract: a text/plain body is refused the same way. */
    struct refract_response r;
    CHECK_INT(refract_request(d->client, "POST", "/v1/scenes", scene_json, strlen(scene_json),
                              "text/plain", &r),
              0);
    CHECK_INT(r.status, 415);
    refract_response_free(&r);
    /* librefract's own calls send the header: a view session made with no body at all. */
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(d, scene_json, id));
    struct refract_view v;
    CHECK_INT(refract_view_create(d->client, id, NULL, &v), 0);
    refract_view_free(&v);
}

static void every_answer_says_nosniff(struct test_daemon *d)
{
    static const char *const paths[] = {"/v1/health", "/v1/scenes",        "/v1/nope",
                                        "/",          "/assets/viewer.js", "/v1/scenes/nope"};
    for (size_t i = 0; i < sizeof paths / sizeof paths[0]; i++) {
        char head[256];
        snprintf(head, sizeof head, "GET %s HTTP/1.1\r\nHost: localhost\r\n", paths[i]);
        char *a = raw_http(d, head, NULL);
        CHECK_MSG(status_of(a) > 0, "GET %s: no answer", paths[i]);
        CHECK_MSG(has_header(a, "X-Content-Type-Options", "nosniff"), "GET %s lacks nosniff",
                  paths[i]);
        /* Once, not twice (the viewer's pages set their own security headers). */
        const char *first = strstr(a, "X-Content-Type-Options");
        CHECK_MSG(first && !strstr(first + 1, "X-Content-Type-Options"), "GET %s: nosniff twice",
                  paths[i]);
        free(a);
    }
}

static void foreign_hosts_are_misdirected(struct test_daemon *d)
{
    char head[256];
    static const char *const served[] = {"127.0.0.1", "localhost", "LOCALHOST", "[::1]",
                                         "localhost."};
    for (size_t i = 0; i < sizeof served / sizeof served[0]; i++) {
        for (int with_port = 0; with_port < 2; with_port++) {
            if (with_port)
                snprintf(head, sizeof head, "GET /v1/scenes HTTP/1.1\r\nHost: %s:%d\r\n", served[i],
                         d->port);
            else
                snprintf(head, sizeof head, "GET /v1/scenes HTTP/1.1\r\nHost: %s\r\n", served[i]);
            char *a = raw_http(d, head, NULL);
            CHECK_MSG(status_of(a) == 200, "Host %s (port %d): %d", served[i], with_port,
                      status_of(a));
            free(a);
        }
    }
    static const char *const foreign[] = {"evil.example",
                                          "evil.example:8750",
                                          "127.0.0.1.evil.example",
                                          "localhost.evil.example",
                                          "127.0.0.1:x",
                                          "[::1",
                                          "127.0.0.2"};
    for (size_t i = 0; i < sizeof foreign / sizeof foreign[0]; i++) {
        snprintf(head, sizeof head, "DELETE /v1/scenes/x HTTP/1.1\r\nHost: %s\r\n", foreign[i]);
        char *a = raw_http(d, head, NULL);
        CHECK_MSG(status_of(a) == 421, "Host %s: %d", foreign[i], status_of(a));
        CHECK(test_error_is(body_of(a), "host_not_allowed", "--allow-host"));
        CHECK(has_header(a, "X-Content-Type-Options", "nosniff"));
        free(a);
    }
    /* Even health: a rebinding page must learn nothing. */
    char *a = raw_http(d, "GET /v1/health HTTP/1.1\r\nHost: evil.example\r\n", NULL);
    CHECK_INT(status_of(a), 421);
    free(a);
}

static void allow_host_adds_names(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, (const char *[]){"--allow-host", "render.example.org",
                                                "--allow-host", "[2001:db8::7]", NULL})) {
        test_setup_failed("test_access_control", d.why);
        return;
    }
    char *a = raw_http(&d, "GET /v1/scenes HTTP/1.1\r\nHost: render.example.org:443\r\n", NULL);
    CHECK_INT(status_of(a), 200);
    free(a);
    a = raw_http(&d, "GET /v1/scenes HTTP/1.1\r\nHost: [2001:db8::7]\r\n", NULL);
    CHECK_INT(status_of(a), 200);
    free(a);
    a = raw_http(&d, "GET /v1/scenes HTTP/1.1\r\nHost: other.example.org\r\n", NULL);
    CHECK_INT(status_of(a), 421);
    free(a);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    /* A name with a port is a usage error that says how to write it. */
    char *out = NULL;
    CHECK_INT(test_run_refractd((const char *[]){"--allow-host", "example.org:80", NULL}, &out),
              REFRACT_E_USAGE);
    CHECK_CONTAINS(out, "without a port");
    free(out);
}

static void write_file(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    CHECK(f != NULL);
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static int one_frame(const struct refract_frame *frame, void *user)
{
    (void)frame;
    ++*(int *)user;
    return 1;
}

static void a_token_guards_every_route_but_health(void)
{
    char token_file[512];
    test_temp_template(token_file, sizeof token_file, "refract-token");
    int fd = mkstemp(token_file);
    CHECK(fd >= 0);
    close(fd);
    write_file(token_file, "  " TOKEN "  \n# the rest of the file is not the token\n");
    struct test_daemon d;
    /* The harness's own start-up check is GET /v1/health without a token. */
    if (!test_daemon_start(&d, (const char *[]){"--token-file", token_file, NULL})) {
        test_setup_failed("test_access_control", d.why);
        unlink(token_file);
        return;
    }
    char *body = NULL;
    CHECK_INT(test_request(&d, "GET", "/v1/health", NULL, &body), 200);
    free(body);
    /* No token. */
    CHECK_INT(test_request(&d, "GET", "/v1/scenes", NULL, &body), 401);
    CHECK(test_error_is(body, "unauthorized", "Authorization: Bearer"));
    free(body);
    CHECK_INT(test_request(&d, "POST", "/v1/scenes", scene_json, &body), 401);
    CHECK(test_error_is(body, "unauthorized", "--token-file"));
    free(body);
    CHECK_INT(test_request(&d, "DELETE", "/v1/scenes/x", NULL, &body), 401);
    free(body);
    /* Not even a 404 or a 415 before the token. */
    CHECK_INT(test_request(&d, "GET", "/v1/nope", NULL, &body), 401);
    free(body);
    char *a = raw_http(&d, "GET /v1/scenes HTTP/1.1\r\nHost: 127.0.0.1\r\n", NULL);
    CHECK_INT(status_of(a), 401);
    CHECK(has_header(a, "WWW-Authenticate", "Bearer"));
    CHECK(has_header(a, "X-Content-Type-Options", "nosniff"));
    free(a);
    /* Another token, a prefix of it, the token with more, another scheme. */
    static const char *const wrong[] = {
        "Authorization: Bearer s3cret-token-0123456789abcdeF\r\n",
        "Authorization: Bearer s3cret-token\r\n",
        "Authorization: Bearer " TOKEN "x\r\n",
        "Authorization: Bearer \r\n",
        "Authorization: Basic czNjcmV0LXRva2VuLTAxMjM0NTY3ODlhYmNkZWY=\r\n",
        "Authorization: " TOKEN "\r\n",
    };
    for (size_t i = 0; i < sizeof wrong / sizeof wrong[0]; i++) {
        char head[512];
        snprintf(head, sizeof head, "GET /v1/scenes HTTP/1.1\r\nHost: 127.0.0.1\r\n%s", wrong[i]);
        a = raw_http(&d, head, NULL);
        CHECK_MSG(status_of(a) == 401, "%s-> %d", wrong[i], status_of(a));
        CHECK(test_error_is(body_of(a), "unauthorized", NULL));
        CHECK(has_header(a, "WWW-Authenticate", "Bearer"));
        CHECK(strstr(a, TOKEN) == NULL); /* never echoed */
        free(a);
    }
    a = raw_http(&d,
                 "GET /v1/scenes HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: Bearer wrong-but-"
                 "long-enough\r\n",
                 NULL);
    CHECK(has_header(a, "WWW-Authenticate", "Bearer realm=\"refractd\", error=\"invalid_token\""));
    free(a);
    /* The right token, raw and through librefract (any case of the scheme). */
    a = raw_http(
        &d, "GET /v1/scenes HTTP/1.1\r\nHost: 127.0.0.1\r\nAuthorization: bearer " TOKEN "\r\n",
        NULL);
    CHECK_INT(status_of(a), 200);
    free(a);
    CHECK_INT(refract_set_token(d.client, TOKEN), 0);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, scene_json, id));
    CHECK_INT(test_request(&d, "GET", "/v1/scenes", NULL, &body), 200);
    CHECK_CONTAINS(body, id);
    free(body);
    /* A streaming GET (librefract's other transport) sends the token too. */
    struct refract_view v;
    CHECK_INT(refract_view_create(d.client, id, "{\"width\": 32, \"height\": 24}", &v), 0);
    int frames = 0;
    CHECK_INT(refract_view_stream(d.client, v.id, one_frame, &frames), 0);
    CHECK_INT(frames, 1);
    refract_view_free(&v);
    CHECK_INT(refract_set_token(d.client, "has space"), REFRACT_E_USAGE);
    CHECK_INT(refract_set_token(d.client, "another-token-0123456789"), 0);
    CHECK_INT(test_request(&d, "GET", "/v1/scenes", NULL, &body), 401);
    free(body);
    CHECK_INT(refract_set_token_file(d.client, token_file), 0);
    CHECK_INT(test_request(&d, "GET", "/v1/scenes", NULL, &body), 200);
    free(body);
    /* The viewer's pages hold no data: they load without a token and ask for it. */
    a = raw_http(&d, "GET / HTTP/1.1\r\nHost: 127.0.0.1\r\n", NULL);
    CHECK_INT(status_of(a), 200);
    free(a);
    a = raw_http(&d, "GET /assets/viewer.js HTTP/1.1\r\nHost: 127.0.0.1\r\n", NULL);
    CHECK_INT(status_of(a), 200);
    free(a);
    /* ...and do not tell who has no token which scene ids exist. */
    char head[256];
    snprintf(head, sizeof head, "GET /viewer/%s HTTP/1.1\r\nHost: 127.0.0.1\r\n", id);
    a = raw_http(&d, head, NULL);
    CHECK_INT(status_of(a), 200);
    free(a);
    a = raw_http(&d, "GET /viewer/no_such_scene HTTP/1.1\r\nHost: 127.0.0.1\r\n", NULL);
    CHECK_INT(status_of(a), 200);
    free(a);
    /* The token is not in the daemon's log. */
    char *log = cli_slurp(d.log_path);
    CHECK(log != NULL && strstr(log, TOKEN) == NULL);
    free(log);

    /* The CLI: REFRACT_TOKEN, --token-file, and neither. */
    setenv("REFRACT_TOKEN", TOKEN, 1);
    struct cli_run r = cli_run(&d, NULL, NULL, (const char *[]){"scene", "list", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, id);
    cli_run_free(&r);
    unsetenv("REFRACT_TOKEN");
    r = cli_run(&d, NULL, NULL, (const char *[]){"scene", "list", NULL});
    CHECK_INT(r.status, REFRACT_E_UNAUTHORIZED);
    CHECK_CONTAINS(r.err, "REFRACT_TOKEN");
    cli_run_free(&r);
    r = cli_run(&d, NULL, NULL,
                (const char *[]){"scene", "list", "--token-file", token_file, NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, id);
    cli_run_free(&r);
    r = cli_run(&d, NULL, NULL,
                (const char *[]){"--token-file", "/nonexistent/token", "scene", "list", NULL});
    CHECK_INT(r.status, REFRACT_E_USAGE);
    CHECK_CONTAINS(r.err, "/nonexistent/token");
    cli_run_free(&r);

    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    unlink(token_file);
}

static void refuses_to_start_exposed_or_with_a_bad_token(void)
{
    char *out = NULL;
    CHECK_INT(test_run_refractd((const char *[]){"--bind", "0.0.0.0", "--port", "0", NULL}, &out),
              REFRACT_E_USAGE);
    CHECK_CONTAINS(out, "--bind 0.0.0.0");
    CHECK_CONTAINS(out, "--token-file");
    CHECK_CONTAINS(out, "--trusted-proxy");
    free(out);

    char token_file[512];
    test_temp_template(token_file, sizeof token_file, "refract-token");
    int fd = mkstemp(token_file);
    CHECK(fd >= 0);
    close(fd);
    /* With a token, or --trusted-proxy, the guard lets a non-loopback --bind through: the
     * start then fails only at listening on 192.0.2.1 (TEST-NET-1, on no machine). */
    write_file(token_file, TOKEN "\n");
    CHECK(test_run_refractd((const char *[]){"--bind", "192.0.2.1", "--port", "0", "--token-file",
                                             token_file, NULL},
                            &out) != 0);
    CHECK(strstr(out, "reachable from other machines") == NULL);
    CHECK_CONTAINS(out, "cannot listen on 192.0.2.1");
    CHECK_CONTAINS(out, "clear text"); /* a token without TLS: warned */
    free(out);
    CHECK(test_run_refractd(
              (const char *[]){"--bind", "192.0.2.1", "--port", "0", "--trusted-proxy", NULL},
              &out) != 0);
    CHECK(strstr(out, "reachable from other machines") == NULL);
    CHECK_CONTAINS(out, "cannot listen on 192.0.2.1");
    free(out);

    write_file(token_file, "short\n");
    CHECK_INT(test_run_refractd((const char *[]){"--token-file", token_file, NULL}, &out),
              REFRACT_E_USAGE);
    CHECK_CONTAINS(out, "16 to");
    free(out);
    write_file(token_file, "a token with spaces in it\n");
    CHECK_INT(test_run_refractd((const char *[]){"--token-file", token_file, NULL}, &out),
              REFRACT_E_USAGE);
    CHECK_CONTAINS(out, "visible ASCII");
    free(out);
    unlink(token_file);
    CHECK_INT(test_run_refractd((const char *[]){"--token-file", token_file, NULL}, &out),
              REFRACT_E_USAGE);
    CHECK_CONTAINS(out, token_file);
    free(out);
    CHECK_INT(test_run_refractd((const char *[]){"--tls-cert", "/etc/hostname", NULL}, &out),
              REFRACT_E_USAGE);
    CHECK_CONTAINS(out, "--tls-key");
    free(out);
}

int main(void)
{
    if (getenv("REFRACTD") == NULL)
        test_skip("test_access_control", "REFRACTD is not set (run through ctest)");
    refuses_to_start_exposed_or_with_a_bad_token();
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL)) {
        test_setup_failed("test_access_control", d.why);
        return test_summary("test_access_control");
    }
    json_routes_want_json(&d);
    every_answer_says_nosniff(&d);
    foreign_hosts_are_misdirected(&d);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    allow_host_adds_names();
    a_token_guards_every_route_but_health();
    return test_summary("test_access_control");
}
