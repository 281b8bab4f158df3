/*
 * server.c - one request's life in libmicrohttpd, and the daemon's start and stop. See
 * http.h for the threading model.
 *
 * The access handler runs several times per request (libmicrohttpd's contract):
 *   1. first call: allocate struct http_request into *con_cls, find the route, reject an
 *      oversized Content-Length at once;
 *   2. calls with upload data: append to the body (or drain it when over the limit);
 *      an HTTP_BODY_UPLOAD route's body goes to a temporary file instead, hashed as it
 *      arrives, so an upload of any size costs no memory (http_internal.h);
 *   3. the call with no more data: run the route's handler, which answers or suspends;
 *   4. after a resume (the GPU finished): run on_resume, which answers.
 * The completion callback frees the request: one owner, one free.
 *
 * FAIR SHARING (docs/api.md "Fair sharing"): the connection callback counts each client's
 * connections (clients.h); a connection beyond --max-connections or
 * --max-connections-per-ip is still accepted, so that its first request can be answered
 * with a JSON error naming the limit (503 busy, 429 too_many_requests) before it is
 * closed, and it gets one second to send that request. libmicrohttpd itself refuses
 * connections only past a margin above --max-connections. A connection that has not sent
 * its headers and body gets --header-timeout seconds of silence, one that is being
 * answered --connection-timeout, and an idle keep-alive connection the short one again:
 * half-sent requests cannot hold connections for long. A client that is never silent for
 * long but sends its request a byte at a time is closed when the request is not in after
 * --header-deadline seconds, an upload whose body falls below --upload-min-rate bytes per
 * second once that time is spent (deadline.h). A request
 * waiting for the GPU is suspended and notices nothing, so its work item polls the socket
 * before each turn and is dropped once the client has gone (client_gone).
 */
#define _GNU_SOURCE /* POLLRDHUP */
#include <arpa/inet.h>
#include <errno.h>
#include <stdatomic.h>
#include <time.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "../core/log.h"
#include "../core/metrics.h"
#include "access.h"
#include "deadline.h"
#include "http_internal.h"
#include "routes.h"
#include "stream.h"

struct http_server {
    struct MHD_Daemon *daemon;
    struct http_config cfg;
    struct http_app app;
    int port;
    struct http_sse *sse;       /* the event streams (h_events.c) */
    atomic_int active_requests; /* request states alive (begun, not completed) */
    atomic_bool closing;        /* http_server_quiesce: new requests get 503 shutting_down */
    struct http_stream_set *streams;
    struct http_clients *clients; /* connections and GPU requests per client */
    struct http_deadlines *deadlines; /* --header-deadline (deadline.h); NULL = none */
};

/* What the server knows of one connection (libmicrohttpd's socket context): its client
 * and whether it was over a limit when it opened. Made and freed by on_connection. */
struct http_conn_state {
    struct http_client_key key;
    int client_connections, total; /* counts when it opened, itself included */
    bool over_total, over_client;
    struct http_deadline_entry deadline; /* --header-deadline: armed until a request is in */
};

static void set_timeout(struct MHD_Connection *conn, int seconds)
{
    MHD_set_connection_option(conn, MHD_CONNECTION_OPTION_TIMEOUT, (unsigned)seconds);
}

/* libmicrohttpd's connection callback: counts the client's connections (a connection is
 * in its daemon's timeout list by now, so its timeout may be changed). */
static void on_connection(void *cls, struct MHD_Connection *conn, void **socket_context,
                          enum MHD_ConnectionNotificationCode toe)
{
    struct http_server *srv = cls;
    struct http_conn_state *cs = *socket_context;
    if (toe == MHD_CONNECTION_NOTIFY_CLOSED) {
        if (cs != NULL) {
            /* Before libmicrohttpd closes the socket: the reaper must not touch it after. */
            http_deadlines_remove(srv->deadlines, &cs->deadline);
            http_clients_disconnect(srv->clients, &cs->key);
            free(cs);
        }
        *socket_context = NULL;
        return;
    }
    cs = calloc(1, sizeof *cs);
    if (cs == NULL)
        return; /* uncounted; its requests are answered without the limits */
    const union MHD_ConnectionInfo *info =
        MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CLIENT_ADDRESS);
    http_client_key_from(info ? info->client_addr : NULL, &cs->key);
    http_clients_connect(srv->clients, &cs->key, &cs->client_connections, &cs->total);
    cs->over_total = cs->total > srv->cfg.max_connections;
    cs->over_client = srv->cfg.max_connections_per_ip > 0 &&
                      cs->client_connections > srv->cfg.max_connections_per_ip;
    *socket_context = cs;
    set_timeout(conn, cs->over_total || cs->over_client ? 1 : srv->cfg.header_timeout_s);
    const union MHD_ConnectionInfo *fd_info =
        MHD_get_connection_info(conn, MHD_CONNECTION_INFO_CONNECTION_FD);
    if (fd_info != NULL)
        http_deadlines_add(srv->deadlines, &cs->deadline, fd_info->connect_fd, cs->key.ip);
}

static struct http_conn_state *conn_state(struct MHD_Connection *conn)
{
    const union MHD_ConnectionInfo *info =
        MHD_get_connection_info(conn, MHD_CONNECTION_INFO_SOCKET_CONTEXT);
    return info ? info->socket_context : NULL;
}

/* The server's --header-deadline list, for a request whose connection has an entry. */
static struct http_deadlines *deadlines_of(const struct http_request *req)
{
    return req->deadline ? ((const struct http_server *)req->server)->deadlines : NULL;
}

struct http_stream_set *http_server_streams(const struct http_server *srv)
{
    return srv->streams;
}

/* Gives back the upload's bytes counted against --max-storage-bytes. */
static void upload_unreserve(struct http_request *req)
{
    if (req->upload_reserved > 0)
        store_upload_tmp_release(req->app->store, req->upload_reserved);
    req->upload_reserved = 0;
}

/* Closes and removes the streamed upload file, unless a handler took it. */
static void upload_discard(struct http_request *req)
{
    upload_unreserve(req);
    if (req->upload_fd >= 0)
        close(req->upload_fd);
    req->upload_fd = -1;
    if (req->upload_path[0])
        unlink(req->upload_path);
    req->upload_path[0] = '\0';
}

static void request_free(struct http_request *req)
{
    struct http_server *srv = (struct http_server *)req->server;
    atomic_fetch_sub(&srv->active_requests, 1);
    if (req->gpu_counted)
        http_clients_dequeue(srv->clients, req->client);
    upload_unreserve(req);
    if (req->job && req->job_free)
        req->job_free(req->job);
    upload_discard(req);
    free(req->body);
    free(req);
}

static void on_completed(void *cls, struct MHD_Connection *conn, void **con_cls,
                         enum MHD_RequestTerminationCode toe)
{
    struct http_server *srv = cls;
    struct http_request *req = *con_cls;
    if (req == NULL)
        return;
    if (toe != MHD_REQUEST_TERMINATED_COMPLETED_OK) {
        log_debug("http", "request ended early (code %d)", (int)toe);
    } else {
        set_timeout(conn, srv->cfg.header_timeout_s); /* keep-alive: waits for headers */
        struct http_conn_state *cs = conn_state(conn);
        if (cs != NULL) /* and the next request has --header-deadline to arrive */
            http_deadlines_arm(srv->deadlines, &cs->deadline);
    }
    metrics_http_request(http_route_index(req->route), req->status,
                         (gpu_time_ms() - req->started_ms) * 1e-3);
    request_free(req);
    *con_cls = NULL;
}

static size_t body_limit(const struct http_config *cfg, enum http_body_kind kind)
{
    switch (kind) {
    case HTTP_BODY_JSON:
        return cfg->max_json_bytes;
    case HTTP_BODY_UPLOAD:
        return cfg->max_upload_bytes;
    case HTTP_BODY_NONE:
        break;
    }
    return 0;
}

static const char *body_limit_flag(enum http_body_kind kind)
{
    return kind == HTTP_BODY_UPLOAD ? "--max-upload-bytes" : "--max-json-bytes";
}

/* First call: state, route, early size check. Returns NULL when out of memory. */
static struct http_request *request_begin(struct http_server *srv, struct MHD_Connection *conn,
                                          const char *url, const char *method)
{
    struct http_request *req = calloc(1, sizeof *req);
    if (req == NULL)
        return NULL;
    atomic_fetch_add(&srv->active_requests, 1);
    req->conn = conn;
    req->server = srv;
    req->cfg = &srv->cfg;
    req->app = &srv->app;
    req->started_ms = gpu_time_ms();
    req->upload_fd = -1;
    req->client_fd = -1;
    req->sse = srv->sse;
    struct http_conn_state *cs = conn_state(conn);
    static const struct http_client_key unknown = {.ip = "unknown"};
    req->client = cs ? &cs->key : &unknown;
    req->deadline = cs ? &cs->deadline : NULL;
    bool path_known = false;
    req->route = http_route_find(method, url, req->params, &req->param_count, &path_known);
    if (req->route)
        req->body_limit = body_limit(&srv->cfg, req->route->body);
    return req;
}

static enum MHD_Result answer_no_route(struct http_request *req, const char *url,
                                       const char *method)
{
    char methods[64];
    if (http_route_methods(url, methods, sizeof methods) > 0) {
        const char *headers[] = {MHD_HTTP_HEADER_ALLOW, methods, NULL};
        return http_respond_error_with(req, headers, REFRACT_E_METHOD_NOT_ALLOWED,
                                       "%s is not allowed on %s; allowed: %s", method, url,
                                       methods);
    }
    return http_respond_error(req, REFRACT_E_NOT_FOUND,
                              "no route %s %s; proto/openapi.yaml lists the API (e.g. GET "
                              "/v1/health, POST /v1/scenes)",
                              method, url);
}

/* HTTP_BODY_UPLOAD: appends a chunk to the body's temporary file (opened on the first
 * chunk), hashing it. A write failure is recorded and answered once the body is in. */
static void upload_append(struct http_request *req, const char *data, size_t size)
{
    if (req->upload_err.code != REFRACT_E_OK)
        return;
    if (req->upload_fd < 0 && req->upload_path[0] == '\0') {
        req->upload_fd = store_upload_tmp_create(req->app->store, req->upload_path,
                                                 sizeof req->upload_path, &req->upload_err);
        if (req->upload_fd < 0) {
            req->upload_path[0] = '\0';
            return;
        }
        sha256_init(&req->upload_hash);
    }
    if (store_upload_tmp_reserve(req->app->store, req->upload_reserved, size, &req->upload_err) !=
        REFRACT_E_OK) {
        upload_discard(req);
        return;
    }
    req->upload_reserved += size;
    sha256_update(&req->upload_hash, data, size);
    while (size > 0) {
        ssize_t n = write(req->upload_fd, data, size);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            err_set(&req->upload_err, REFRACT_E_STORAGE,
                    "refractd could not write the upload to its data directory: %s (disk "
                    "full?)",
                    n < 0 ? strerror(errno) : "short write");
            upload_discard(req);
            return;
        }
        data += n;
        size -= (size_t)n;
    }
}

/* The whole upload body is in: closes its file (creating an empty one for an empty
 * body, so handlers always have a file) and finishes the hash. */
static void upload_finish(struct http_request *req)
{
    if (req->upload_err.code != REFRACT_E_OK)
        return;
    if (req->upload_fd < 0 && req->upload_path[0] == '\0')
        upload_append(req, "", 0);
    if (req->upload_fd >= 0) {
        close(req->upload_fd);
        req->upload_fd = -1;
        sha256_final_hex(&req->upload_hash, req->upload_sha256);
    }
}

static bool body_append(struct http_request *req, const char *data, size_t size)
{
    if (req->body_too_large || req->route == NULL || req->route->body == HTTP_BODY_NONE)
        return true; /* drained and ignored */
    if (req->body_len + size > req->body_limit) {
        req->body_too_large = true;
        free(req->body);
        req->body = NULL;
        req->body_len = req->body_cap = 0;
        upload_discard(req);
        return true;
    }
    if (req->route->body == HTTP_BODY_UPLOAD) {
        upload_append(req, data, size);
        req->body_len += size;
        http_deadlines_received(deadlines_of(req), req->deadline, size);
        return true;
    }
    if (req->body_len + size + 1 > req->body_cap) {
        size_t cap = req->body_cap ? req->body_cap : 16384;
        while (cap < req->body_len + size + 1)
            cap *= 2;
        char *grown = realloc(req->body, cap);
        if (grown == NULL)
            return false;
        req->body = grown;
        req->body_cap = cap;
    }
    memcpy(req->body + req->body_len, data, size);
    req->body_len += size;
    req->body[req->body_len] = '\0';
    return true;
}

static enum MHD_Result answer_too_large(struct http_request *req, unsigned long long announced)
{
    char size[48] = "more";
    if (announced)
        snprintf(size, sizeof size, "%llu bytes", announced);
    return http_respond_error(req, REFRACT_E_BODY_TOO_LARGE,
                              "the request body (%s) exceeds the limit of %zu bytes for %s %s; "
                              "send less, or raise refractd's %s",
                              size, req->body_limit, req->route->method, req->route->pattern,
                              body_limit_flag(req->route->body));
}

/* A connection opened beyond --max-connections (503 busy) or --max-connections-per-ip
 * (429): its request is answered with the limit, and the connection closed. Returns true
 * when it answered (*answer holds the result). */
static bool answer_over_limit(struct http_request *req, enum MHD_Result *answer)
{
    const struct http_conn_state *cs = conn_state(req->conn);
    if (cs == NULL || (!cs->over_total && !cs->over_client))
        return false;
    const char *headers[] = {MHD_HTTP_HEADER_CONNECTION, "close", MHD_HTTP_HEADER_RETRY_AFTER, "1",
                             NULL};
    if (cs->over_total)
        *answer = http_respond_error_with(
            req, headers, REFRACT_E_BUSY,
            "refractd holds %d connections, its limit (--max-connections %d); retry later, or "
            "raise --max-connections",
            cs->total - 1, req->cfg->max_connections);
    else
        *answer = http_respond_error_with(
            req, headers, REFRACT_E_TOO_MANY_REQUESTS,
            "this client (%s) holds %d connections, the limit for one client "
            "(--max-connections-per-ip %d); reuse or close connections, or raise "
            "--max-connections-per-ip (behind a proxy every client is the proxy)",
            cs->key.ip, cs->client_connections - 1, req->cfg->max_connections_per_ip);
    return true;
}

/* The Host allow-list (421) and the bearer token (401), before the route is answered
 * (access.c). Returns true when it answered (*answer holds the result). */
static bool answer_access(struct http_request *req, const char *method, enum MHD_Result *answer)
{
    const struct http_config *cfg = req->cfg;
    const char *host =
        MHD_lookup_connection_value(req->conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_HOST);
    if (!http_access_host_allowed(cfg, host)) {
        char message[ERR_MSG_MAX];
        http_access_host_message(host, message, sizeof message);
        *answer = http_respond_error(req, REFRACT_E_HOST_NOT_ALLOWED, "%s", message);
        return true;
    }
    if (req->route != NULL && http_access_token_exempt(method, req->route->pattern))
        return false;
    const char *auth =
        MHD_lookup_connection_value(req->conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_AUTHORIZATION);
    enum http_token_verdict v = http_access_token_check(cfg, auth);
    if (v == HTTP_TOKEN_OK)
        return false;
    const char *headers[] = {MHD_HTTP_HEADER_WWW_AUTHENTICATE,
                             v == HTTP_TOKEN_WRONG
                                 ? "Bearer realm=\"refractd\", error=\"invalid_token\""
                                 : "Bearer realm=\"refractd\"",
                             NULL};
    static const char how[] =
        "send the header \"Authorization: Bearer TOKEN\" with the token in the file refractd's "
        "--token-file names (refract: set REFRACT_TOKEN or pass --token-file FILE)";
    if (v == HTTP_TOKEN_MISSING)
        *answer = http_respond_error_with(req, headers, REFRACT_E_UNAUTHORIZED,
                                          "refractd requires a bearer token; %s", how);
    else if (v == HTTP_TOKEN_NOT_BEARER)
        *answer = http_respond_error_with(req, headers, REFRACT_E_UNAUTHORIZED,
                                          "the Authorization header is not a bearer token; %s",
                                          how);
    else
        *answer = http_respond_error_with(req, headers, REFRACT_E_UNAUTHORIZED,
                                          "the bearer token is not the one refractd was given; %s",
                                          how);
    return true;
}

/* The first call (the headers are in): state, route, the checks that need no body. */
static enum MHD_Result request_start(struct http_server *srv, struct MHD_Connection *conn,
                                     const char *url, const char *method, void **con_cls)
{
    struct http_request *req = request_begin(srv, conn, url, method);
    if (req == NULL)
        return MHD_NO;
    *con_cls = req;
    if (atomic_load(&srv->closing))
        return http_respond_error(req, REFRACT_E_SHUTTING_DOWN,
                                  "refractd is shutting down; retry %s %s once it is back", method,
                                  url);
    enum MHD_Result answer;
    if (answer_over_limit(req, &answer))
        return answer;
    if (answer_access(req, method, &answer))
        return answer;
    if (req->route == NULL)
        return answer_no_route(req, url, method);
    if (req->route->body == HTTP_BODY_JSON) {
        const char *type =
            MHD_lookup_connection_value(conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_TYPE);
        if (!http_access_json_type(type)) {
            char message[ERR_MSG_MAX];
            http_access_type_message(method, req->route->pattern, type, message, sizeof message);
            return http_respond_error(req, REFRACT_E_UNSUPPORTED_MEDIA_TYPE, "%s", message);
        }
    }
    const char *cl =
        MHD_lookup_connection_value(conn, MHD_HEADER_KIND, MHD_HTTP_HEADER_CONTENT_LENGTH);
    unsigned long long announced = cl ? strtoull(cl, NULL, 10) : 0;
    if (req->route->body != HTTP_BODY_NONE && announced > req->body_limit)
        return answer_too_large(req, announced);
    return MHD_YES;
}

static enum MHD_Result access_handler(void *cls, struct MHD_Connection *conn, const char *url,
                                      const char *method, const char *version,
                                      const char *upload_data, size_t *upload_data_size,
                                      void **con_cls)
{
    (void)version;
    struct http_server *srv = cls;
    struct http_request *req = *con_cls;
    if (req == NULL) {
        enum MHD_Result answer = request_start(srv, conn, url, method, con_cls);
        req = *con_cls;
        /* An upload's body streams to a file and may be large: from its headers on it is
         * held to --upload-min-rate instead of --header-deadline (deadline.h). The body of
         * a request answered early (drained), and any other body, stay under the deadline. */
        if (req != NULL && req->route != NULL && req->route->body == HTTP_BODY_UPLOAD &&
            req->phase != HTTP_PHASE_ANSWERED)
            http_deadlines_upload(deadlines_of(req), req->deadline);
        return answer;
    }
    if (req->phase == HTTP_PHASE_ANSWERED) {
        *upload_data_size = 0; /* answered early (404, 413): drain */
        return MHD_YES;
    }
    if (*upload_data_size > 0) {
        if (!body_append(req, upload_data, *upload_data_size))
            return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY,
                                      "out of memory receiving the request body");
        *upload_data_size = 0;
        return MHD_YES;
    }
    if (req->phase == HTTP_PHASE_RESUMED)
        return req->on_resume(req);
    /* Headers and body are in: from now on the connection is being answered. */
    set_timeout(req->conn, req->cfg->connection_timeout_s);
    http_deadlines_disarm(deadlines_of(req), req->deadline); /* the request is in */
    if (req->body_too_large)
        return answer_too_large(req, 0);
    if (req->route->body == HTTP_BODY_UPLOAD) {
        upload_finish(req);
        if (req->upload_err.code != REFRACT_E_OK)
            return http_respond_err(req, &req->upload_err);
    }
    return req->route->handler(req);
}

/* ---- GPU hand-off ---------------------------------------------------------------------- */

static void resume_on_done(struct gpu_work *w)
{
    struct http_request *req = w->user;
    req->phase = HTTP_PHASE_RESUMED;
    MHD_resume_connection(req->conn);
}

/* The work item's `abandoned`: the client closed its connection (or reset it) while the
 * request waited. A suspended connection's socket stays open and unread, so polling it
 * from the GPU thread races with nothing. */
static bool client_gone(struct gpu_work *w)
{
    const struct http_request *req = w->user;
    if (req->client_fd < 0)
        return false;
    struct pollfd p = {.fd = req->client_fd, .events = POLLIN | POLLRDHUP};
    if (poll(&p, 1, 0) <= 0)
        return false;
    return (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0;
}

enum MHD_Result http_suspend_for_gpu(struct http_request *req, http_handler_fn on_resume)
{
    struct http_server *srv = (struct http_server *)req->server;
    int queued = 0;
    if (!req->gpu_counted && !http_clients_queue(srv->clients, req->client,
                                                 req->cfg->max_queued_per_client, &queued)) {
        const char *headers[] = {MHD_HTTP_HEADER_RETRY_AFTER, "1", NULL};
        return http_respond_error_with(
            req, headers, REFRACT_E_TOO_MANY_REQUESTS,
            "this client (%s) has %d renders and traces queued or running, the limit for one "
            "client (--max-queued-per-client %d); wait for them to finish, or raise "
            "--max-queued-per-client",
            req->client->ip, queued, req->cfg->max_queued_per_client);
    }
    req->gpu_counted = true;
    const union MHD_ConnectionInfo *fd_info =
        MHD_get_connection_info(req->conn, MHD_CONNECTION_INFO_CONNECTION_FD);
    req->client_fd = fd_info ? fd_info->connect_fd : -1;
    req->work.abandoned = client_gone;
    req->on_resume = on_resume;
    req->work.priority = GPU_PRIORITY_INTERACTIVE;
    req->work.deadline_ms = gpu_now_ms() + req->cfg->request_timeout_ms;
    req->work.done = resume_on_done;
    req->work.user = req;
    req->phase = HTTP_PHASE_SUSPENDED;
    /* Suspend before submitting: the GPU thread may finish (and resume) at once. */
    MHD_suspend_connection(req->conn);
    struct err e;
    if (gpu_submit(req->app->gpu, &req->work, &e) != REFRACT_E_OK) {
        req->work.err = e;
        req->phase = HTTP_PHASE_RESUMED;
        MHD_resume_connection(req->conn);
    }
    return MHD_YES;
}

/* ---- start / stop ---------------------------------------------------------------------- */

static void mhd_log(void *cls, const char *fmt, va_list ap)
{
    (void)cls;
    char line[512];
    vsnprintf(line, sizeof line, fmt, ap);
    size_t n = strlen(line);
    while (n > 0 && line[n - 1] == '\n')
        line[--n] = '\0';
    log_warn("http", "libmicrohttpd: %s", line);
}

static void apply_defaults(struct http_config *c)
{
    if (c->threads <= 0)
        c->threads = 4;
    if (c->max_json_bytes == 0)
        c->max_json_bytes = (size_t)8 << 20;
    if (c->max_upload_bytes == 0)
        c->max_upload_bytes = (size_t)1 << 30;
    if (c->max_rays <= 0)
        c->max_rays = 65536;
    if (c->max_image_pixels <= 0)
        c->max_image_pixels = 4096LL * 4096;
    if (c->request_timeout_ms <= 0)
        c->request_timeout_ms = 120000;
    if (c->max_connections <= 0)
        c->max_connections = 2048;
    if (c->header_timeout_s <= 0)
        c->header_timeout_s = 10;
    if (c->connection_timeout_s <= 0)
        c->connection_timeout_s = 300;
    if (c->render_tile_pixels <= 0)
        c->render_tile_pixels = 65536;
    if (c->bind_address == NULL)
        c->bind_address = "127.0.0.1";
}

static int hex_value(char c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    if (c >= 'A' && c <= 'F')
        return c - 'A' + 10;
    return -1;
}

/* Percent-decoding for the path and the query (libmicrohttpd's unescape hook). It decodes
 * like the default except that "%00" stays literal: a decoded NUL would end the C string
 * early, so "DELETE /v1/scenes/<id>%00xyz" would delete <id>. Left as "%00", the id or
 * name fails validation and the client gets a clear error naming it. */
static size_t unescape_keep_nul(void *cls, struct MHD_Connection *conn, char *s)
{
    (void)cls;
    (void)conn;
    char *out = s;
    for (const char *in = s; *in != '\0';) {
        int hi, lo;
        if (in[0] == '%' && (hi = hex_value(in[1])) >= 0 && (lo = hex_value(in[2])) >= 0 &&
            (hi | lo) != 0) {
            *out++ = (char)(hi * 16 + lo);
            in += 3;
        } else {
            *out++ = *in++;
        }
    }
    *out = '\0';
    return (size_t)(out - s);
}

/* Each connection is a descriptor: raises the soft RLIMIT_NOFILE to the hard limit, and
 * lowers *max_connections (with a warning that says how to fix it) when even that leaves
 * too few, keeping `reserve` descriptors for the data directory, uploads and the GPU. */
static void fit_descriptor_limit(int *max_connections, int margin)
{
    const rlim_t reserve = 256;
    struct rlimit rl;
    if (getrlimit(RLIMIT_NOFILE, &rl) != 0)
        return;
    if (rl.rlim_cur < rl.rlim_max) {
        rlim_t old = rl.rlim_cur;
        rl.rlim_cur = rl.rlim_max;
        if (setrlimit(RLIMIT_NOFILE, &rl) != 0)
            rl.rlim_cur = old;
    }
    rlim_t want = (rlim_t)*max_connections + (rlim_t)margin + reserve;
    if (rl.rlim_cur == RLIM_INFINITY || rl.rlim_cur >= want)
        return;
    int fit = rl.rlim_cur > reserve + (rlim_t)margin ? (int)(rl.rlim_cur - reserve - margin) : 1;
    log_warn("http",
             "--max-connections %d needs about %llu file descriptors but the limit is %llu; "
             "serving at most %d connections. To fix this raise the limit (ulimit -n, or "
             "LimitNOFILE= in the systemd unit) or lower --max-connections",
             *max_connections, (unsigned long long)want, (unsigned long long)rl.rlim_cur, fit);
    *max_connections = fit;
}

struct http_server *http_server_start(const struct http_config *cfg, const struct http_app *app,
                                      struct err *e)
{
    struct http_server *srv = calloc(1, sizeof *srv);
    if (srv == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory starting the HTTP server");
        return NULL;
    }
    srv->cfg = *cfg;
    srv->app = *app;
    apply_defaults(&srv->cfg);
    /* Connections past --max-connections are accepted up to this margin so that they can
     * be told why (503 busy); past it libmicrohttpd closes them unanswered. */
    int margin = srv->cfg.max_connections / 16 > 16 ? srv->cfg.max_connections / 16 : 16;
    fit_descriptor_limit(&srv->cfg.max_connections, margin);
    srv->clients = http_clients_create(e);
    if (srv->clients == NULL) {
        free(srv);
        return NULL;
    }
    srv->streams = http_stream_set_create(e);
    if (srv->streams == NULL) {
        http_clients_destroy(srv->clients);
        free(srv);
        return NULL;
    }
    srv->sse = http_sse_create(app->events, e);
    if (srv->sse == NULL) {
        http_stream_set_destroy(srv->streams);
        http_clients_destroy(srv->clients);
        free(srv);
        return NULL;
    }
    struct sockaddr_in addr = {.sin_family = AF_INET, .sin_port = htons((uint16_t)cfg->port)};
    if (inet_pton(AF_INET, srv->cfg.bind_address, &addr.sin_addr) != 1) {
        err_set(e, REFRACT_E_USAGE, "--bind %s: not an IPv4 address (e.g. 127.0.0.1 or 0.0.0.0)",
                srv->cfg.bind_address);
        http_sse_destroy(srv->sse);
        http_stream_set_destroy(srv->streams);
        http_clients_destroy(srv->clients);
        free(srv);
        return NULL;
    }
    unsigned flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_EPOLL | MHD_ALLOW_SUSPEND_RESUME |
                     MHD_USE_ERROR_LOG;
    /* TLS (GnuTLS inside libmicrohttpd): the certificate and key as PEM text. */
    struct MHD_OptionItem tls[] = {{MHD_OPTION_END, 0, NULL},
                                   {MHD_OPTION_END, 0, NULL},
                                   {MHD_OPTION_END, 0, NULL}};
    bool use_tls = srv->cfg.tls_cert_pem != NULL && srv->cfg.tls_key_pem != NULL;
    if (use_tls) {
        if (MHD_is_feature_supported(MHD_FEATURE_TLS) != MHD_YES) {
            err_set(e, REFRACT_E_USAGE,
                    "--tls-cert/--tls-key: this libmicrohttpd was built without TLS; put a "
                    "TLS-terminating proxy in front of refractd instead (--trusted-proxy)");
            http_sse_destroy(srv->sse);
            http_stream_set_destroy(srv->streams);
            http_clients_destroy(srv->clients);
            free(srv);
            return NULL;
        }
        flags |= MHD_USE_TLS;
        tls[0] = (struct MHD_OptionItem){MHD_OPTION_HTTPS_MEM_CERT, 0,
                                         (void *)srv->cfg.tls_cert_pem};
        tls[1] = (struct MHD_OptionItem){MHD_OPTION_HTTPS_MEM_KEY, 0,
                                         (void *)srv->cfg.tls_key_pem};
    }
    srv->deadlines = http_deadlines_create(srv->cfg.header_deadline_s, srv->cfg.upload_min_rate, e);
    if (srv->deadlines == NULL && srv->cfg.header_deadline_s > 0) {
        http_sse_destroy(srv->sse);
        http_stream_set_destroy(srv->streams);
        http_clients_destroy(srv->clients);
        free(srv);
        return NULL;
    }
    srv->daemon = MHD_start_daemon(
        flags, 0, NULL, NULL, access_handler, srv, MHD_OPTION_EXTERNAL_LOGGER, mhd_log, srv,
        MHD_OPTION_SOCK_ADDR, &addr, MHD_OPTION_THREAD_POOL_SIZE, (unsigned)srv->cfg.threads,
        MHD_OPTION_NOTIFY_COMPLETED, on_completed, srv, MHD_OPTION_NOTIFY_CONNECTION,
        on_connection, srv, MHD_OPTION_CONNECTION_TIMEOUT,
        (unsigned)srv->cfg.connection_timeout_s, MHD_OPTION_CONNECTION_LIMIT,
        (unsigned)(srv->cfg.max_connections + margin), MHD_OPTION_UNESCAPE_CALLBACK,
        unescape_keep_nul, NULL, MHD_OPTION_ARRAY, tls, MHD_OPTION_END);
    if (srv->daemon == NULL) {
        if (use_tls)
            err_set(e, REFRACT_E_IO,
                    "cannot listen with TLS on %s:%d: is the port taken, or are --tls-cert and "
                    "--tls-key not a matching PEM certificate and private key? (the log above "
                    "may say which)",
                    srv->cfg.bind_address, cfg->port);
        else
            err_set(e, REFRACT_E_IO,
                    "cannot listen on %s:%d (is the port taken by another process? pick another "
                    "with --port, or --port 0 for any free port)",
                    srv->cfg.bind_address, cfg->port);
        http_deadlines_destroy(srv->deadlines);
        http_sse_destroy(srv->sse);
        http_stream_set_destroy(srv->streams);
        http_clients_destroy(srv->clients);
        free(srv);
        return NULL;
    }
    const union MHD_DaemonInfo *info = MHD_get_daemon_info(srv->daemon, MHD_DAEMON_INFO_BIND_PORT);
    srv->port = info ? info->port : cfg->port;
    return srv;
}

int http_server_port(const struct http_server *s)
{
    return s->port;
}

/* Not MHD_quiesce_daemon: on an epoll daemon with its own threads it races with the
 * workers' event loop over removing the listen socket from their epoll sets, and the
 * loser aborts the process ("Failed to remove listen FD from epoll set"; an open
 * libmicrohttpd defect, seen once in our tests). The socket stays open until
 * http_server_stop; what arrives meanwhile is answered 503 at once. */
void http_server_quiesce(struct http_server *s)
{
    if (s != NULL)
        atomic_store(&s->closing, true);
}

void http_server_end_streams(struct http_server *s)
{
    if (s != NULL)
        http_stream_set_end_all(s->streams);
}

bool http_server_wait_idle(struct http_server *s, int timeout_ms)
{
    for (int waited = 0; waited < timeout_ms; waited += 10) {
        if (atomic_load(&s->active_requests) == 0)
            return true;
        struct timespec ts = {.tv_sec = 0, .tv_nsec = 10 * 1000 * 1000};
        nanosleep(&ts, NULL);
    }
    return atomic_load(&s->active_requests) == 0;
}

void http_server_stop(struct http_server *s)
{
    if (s == NULL)
        return;
    MHD_stop_daemon(s->daemon);
    http_deadlines_destroy(s->deadlines); /* after the daemon: every entry unlisted */
    http_sse_destroy(s->sse); /* after the daemon: no handler opens a stream any more */
    http_stream_set_destroy(s->streams);
    http_clients_destroy(s->clients); /* after the daemon: every connection closed */
    free(s);
}
