/*
 * test_bad_bytes.c - bytes that would break refractd's clients never reach them (issue 13,
 * part 4; docs/api.md "Bytes"):
 *   - invalid_utf8_name_is_400_and_the_listing_stays_json: a scene whose name holds the
 *     bytes FF FE is refused (400 invalid_json naming the byte), a name with valid
 *     non-ASCII characters is stored and echoed exactly, and GET /v1/scenes stays
 *     well-formed UTF-8 JSON;
 *   - error_messages_escape_raw_url_bytes: an id with %ff and %01 comes back in the
 *     error message as \xff and \x01, in a body that is valid UTF-8;
 *   - error_messages_escape_raw_file_header_bytes: a NRRD header line with ESC and FF;
 *   - percent_0a_id_leaves_one_log_line: a request whose id carries "%0a" and a forged
 *     log line leaves exactly one line in the daemon's log, and no line that starts with
 *     the forged timestamp;
 *   - parser_level_errors_are_what_docs_api_md_says: requests that libmicrohttpd rejects
 *     before refractd sees them (no hook in 0.9.75) get the statuses docs/api.md lists,
 *     while those that reach refractd (no Host header) get the JSON error body; the daemon
 *     serves on afterwards.
 */
#include <arpa/inet.h>
#include <cjson/cJSON.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include "core/utf8.h"
#include "daemon.h"
#include "test.h"
#include "upload_util.h"

#define SCENE_WITH_NAME(name)                                                                      \
    "{\"name\": \"" name "\", \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, "    \
    "1, 1]}, \"resolution\": 8, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": "    \
    "1.5}}]}"

/* True when body is well-formed UTF-8 and parses as JSON. */
static bool valid_json_text(const char *body)
{
    if (body == NULL || !utf8_valid(body, strlen(body)))
        return false;
    cJSON *root = cJSON_Parse(body);
    cJSON_Delete(root);
    return root != NULL;
}

static void invalid_utf8_name_is_400_and_the_listing_stays_json(struct test_daemon *d)
{
    char *body = NULL;
    long status =
        test_request(d, "POST", "/v1/scenes", SCENE_WITH_NAME("bad \xff\xfe name"), &body);
    CHECK_INT(status, 400);
    CHECK(test_error_is(body, "invalid_json", "byte 0xff is not valid UTF-8"));
    CHECK(valid_json_text(body));
    free(body);
    /* An overlong '/' and a lone surrogate are not UTF-8 either. */
    CHECK_INT(test_request(d, "POST", "/v1/scenes", SCENE_WITH_NAME("x\xc0\xaf"), &body), 400);
    free(body);
    CHECK_INT(test_request(d, "POST", "/v1/scenes", SCENE_WITH_NAME("x\xed\xa0\x80"), &body), 400);
    free(body);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(d, SCENE_WITH_NAME("Glas \xc3\xa9 \xe2\x82\xac"), id));
    CHECK_INT(test_request(d, "GET", "/v1/scenes", NULL, &body), 200);
    CHECK(valid_json_text(body));
    CHECK(body != NULL && strstr(body, "Glas \xc3\xa9 \xe2\x82\xac") != NULL);
    CHECK(body != NULL && strstr(body, "bad ") == NULL);
    free(body);
}

static void error_messages_escape_raw_url_bytes(struct test_daemon *d)
{
    char *body = NULL;
    CHECK_INT(test_request(d, "GET", "/v1/scenes/ab%ffcd%01ef", NULL, &body), 404);
    CHECK(valid_json_text(body));
    CHECK(test_error_is(body, "scene_not_found", "ab\\xffcd\\x01ef"));
    free(body);
}

static void error_messages_escape_raw_file_header_bytes(struct test_daemon *d)
{
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(d, SCENE_WITH_NAME("nrrd"), id));
    static const char nrrd[] = "NRRD0004\ntype: \x1b[31mred\xff\ndimension: 3\nsizes: 2 2 2\n"
                               "encoding: raw\n\n01234567";
    char path[128], *body = NULL;
    snprintf(path, sizeof path, "/v1/scenes/%s/volumes/v", id);
    CHECK_INT(upload_put(d, path, nrrd, sizeof nrrd - 1, &body), 400);
    CHECK(valid_json_text(body));
    CHECK(test_error_is(body, "invalid_volume", "\\x1b[31mred\\xff"));
    free(body);
}

static void percent_0a_id_leaves_one_log_line(struct test_daemon *d)
{
    char *body = NULL;
    CHECK_INT(test_request(d, "GET",
                           "/v1/scenes/x%0a1999-01-01T00:00:00.000Z%20error%20http%20FORGED13%0d",
                           NULL, &body),
              404);
    free(body);
    FILE *f = fopen(d->log_path, "r");
    CHECK(f != NULL);
    if (f == NULL)
        return;
    char line[4096];
    int with_marker = 0, forged = 0;
    while (fgets(line, sizeof line, f)) {
        with_marker += strstr(line, "FORGED13") != NULL;
        forged += strncmp(line, "1999-01-01", 10) == 0;
        if (strstr(line, "FORGED13"))
            CHECK(strstr(line, "x\\x0a1999-01-01") != NULL && strstr(line, "\\x0d") != NULL);
    }
    fclose(f);
    CHECK_INT(with_marker, 1);
    CHECK_INT(forged, 0);
}

/* Sends raw bytes on a new connection; returns the status of the answer (0 when the
 * connection closed without one) and whether its Content-Type was application/json. */
static int raw_http(int port, const char *req, size_t len, bool *json)
{
    *json = false;
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port)};
    inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
    struct timeval tv = {.tv_sec = 5};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    if (connect(fd, (struct sockaddr *)&a, sizeof a) != 0) {
        close(fd);
        return -1;
    }
    for (size_t off = 0; off < len;) {
        ssize_t n = send(fd, req + off, len - off, MSG_NOSIGNAL);
        if (n <= 0)
            break;
        off += (size_t)n;
    }
    char reply[4096];
    size_t got = 0;
    for (ssize_t n;
         got + 1 < sizeof reply && (n = recv(fd, reply + got, sizeof reply - 1 - got, 0)) > 0;)
        got += (size_t)n;
    reply[got] = '\0';
    close(fd);
    int status = 0;
    if (sscanf(reply, "HTTP/1.%*d %d", &status) != 1)
        return 0;
    char *end = strstr(reply, "\r\n\r\n");
    if (end)
        *end = '\0';
    *json = strstr(reply, "Content-Type: application/json") != NULL;
    return status;
}

static void parser_level_errors_are_what_docs_api_md_says(struct test_daemon *d)
{
    static char big_header[40000], big_url[40000];
    int n = snprintf(big_header, sizeof big_header,
                     "GET /v1/health HTTP/1.1\r\nHost: localhost\r\nX-Big: ");
    memset(big_header + n, 'a', sizeof big_header - (size_t)n - 5);
    memcpy(big_header + sizeof big_header - 5, "\r\n\r\n", 5);
    n = snprintf(big_url, sizeof big_url, "GET /v1/scenes/");
    memset(big_url + n, 'a', sizeof big_url - (size_t)n - 40);
    snprintf(big_url + sizeof big_url - 40, 40, " HTTP/1.1\r\nHost: localhost\r\n\r\n");
    static const struct {
        const char *what, *req;
        int status;
        bool json;
    } cases[] = {
        {"HTTP/2.0 request line", "GET /v1/health HTTP/2.0\r\nHost: localhost\r\n\r\n", 505, false},
        {"malformed version", "GET /v1/health HTTP/1.x\r\nHost: localhost\r\n\r\n", 400, false},
        {"header line without a colon", "GET /v1/health HTTP/1.1\r\nHost: l\r\nNoColon\r\n\r\n",
         400, false},
        {"bad chunk size",
         "POST /v1/scenes HTTP/1.1\r\nHost: localhost\r\nContent-Type: application/json\r\n"
         "Transfer-Encoding: chunked\r\n\r\nzz\r\n{}\r\n0\r\n\r\n",
         400, false},
        {"chunk size beyond 64 bits",
         "POST /v1/scenes HTTP/1.1\r\nHost: localhost\r\nContent-Type: application/json\r\n"
         "Transfer-Encoding: chunked\r\n\r\nffffffffffffffffffff\r\n{}\r\n0\r\n\r\n",
         413, false},
        {"no Host header (reaches refractd)", "GET /v1/health HTTP/1.1\r\n\r\n", 421, true},
    };
    bool json = false;
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int status = raw_http(d->port, cases[i].req, strlen(cases[i].req), &json);
        CHECK_MSG(status == cases[i].status && json == cases[i].json,
                  "%s: HTTP %d%s, expected %d%s", cases[i].what, status, json ? " JSON" : "",
                  cases[i].status, cases[i].json ? " JSON" : "");
    }
    CHECK_INT(raw_http(d->port, big_header, strlen(big_header), &json), 431);
    CHECK_INT(raw_http(d->port, big_url, strlen(big_url), &json), 414);
    char *body = NULL;
    CHECK_INT(test_request(d, "GET", "/v1/health", NULL, &body), 200);
    free(body);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_bad_bytes", d.why);
    invalid_utf8_name_is_400_and_the_listing_stays_json(&d);
    error_messages_escape_raw_url_bytes(&d);
    error_messages_escape_raw_file_header_bytes(&d);
    percent_0a_id_leaves_one_log_line(&d);
    parser_level_errors_are_what_docs_api_md_says(&d);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_bad_bytes");
}
