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
 */
#include <arpa/inet.h>
#include <errno.h>
#include <stdatomic.h>
#include <time.h>
#include <netinet/in.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../core/log.h"
#include "../core/metrics.h"
#include "access.h"
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
};

struct http_stream_set *http_server_streams(const struct http_server *srv)
{
    return srv->streams;
}

/* Closes and removes the streamed upload file, unless a handler took it. */
static void upload_discard(struct http_request *req)
{
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
    if (req->job && req->job_free)
        req->job_free(req->job);
    upload_discard(req);
    free(req->body);
    free(req);
}

static void on_completed(void *cls, struct MHD_Connection *conn, void **con_cls,
                         enum MHD_RequestTerminationCode toe)
{
    (void)cls;
    (void)conn;
    struct http_request *req = *con_cls;
    if (req == NULL)
        return;
    if (toe != MHD_REQUEST_TERMINATED_COMPLETED_OK)
        log_debug("http", "request ended early (code %d)", (int)toe);
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
    req->sse = srv->sse;
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

static enum MHD_Result access_handler(void *cls, struct MHD_Connection *conn, const char *url,
                                      const char *method, const char *version,
                                      const char *upload_data, size_t *upload_data_size,
                                      void **con_cls)
{
    (void)version;
    struct http_server *srv = cls;
    struct http_request *req = *con_cls;
    if (req == NULL) {
        req = request_begin(srv, conn, url, method);
        if (req == NULL)
            return MHD_NO;
        *con_cls = req;
        if (atomic_load(&srv->closing))
            return http_respond_error(req, REFRACT_E_SHUTTING_DOWN,
                                      "refractd is shutting down; retry %s %s once it is back",
                                      method, url);
        enum MHD_Result answer;
        if (answer_access(req, method, &answer))
            return answer;
        if (req->route == NULL)
            return answer_no_route(req, url, method);
        if (req->route->body == HTTP_BODY_JSON) {
            const char *type = MHD_lookup_connection_value(conn, MHD_HEADER_KIND,
                                                           MHD_HTTP_HEADER_CONTENT_TYPE);
            if (!http_access_json_type(type)) {
                char message[ERR_MSG_MAX];
                http_access_type_message(method, req->route->pattern, type, message,
                                         sizeof message);
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

enum MHD_Result http_suspend_for_gpu(struct http_request *req, http_handler_fn on_resume)
{
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
    srv->streams = http_stream_set_create(e);
    if (srv->streams == NULL) {
        free(srv);
        return NULL;
    }
    srv->sse = http_sse_create(app->events, e);
    if (srv->sse == NULL) {
        http_stream_set_destroy(srv->streams);
        free(srv);
        return NULL;
    }
    struct sockaddr_in addr = {.sin_family = AF_INET, .sin_port = htons((uint16_t)cfg->port)};
    if (inet_pton(AF_INET, srv->cfg.bind_address, &addr.sin_addr) != 1) {
        err_set(e, REFRACT_E_USAGE, "--bind %s: not an IPv4 address (e.g. 127.0.0.1 or 0.0.0.0)",
                srv->cfg.bind_address);
        http_sse_destroy(srv->sse);
        http_stream_set_destroy(srv->streams);
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
            free(srv);
            return NULL;
        }
        flags |= MHD_USE_TLS;
        tls[0] = (struct MHD_OptionItem){MHD_OPTION_HTTPS_MEM_CERT, 0,
                                         (void *)srv->cfg.tls_cert_pem};
        tls[1] = (struct MHD_OptionItem){MHD_OPTION_HTTPS_MEM_KEY, 0,
                                         (void *)srv->cfg.tls_key_pem};
    }
    srv->daemon = MHD_start_daemon(
        flags, 0, NULL, NULL, access_handler, srv, MHD_OPTION_EXTERNAL_LOGGER, mhd_log, srv,
        MHD_OPTION_SOCK_ADDR, &addr, MHD_OPTION_THREAD_POOL_SIZE, (unsigned)srv->cfg.threads,
        MHD_OPTION_NOTIFY_COMPLETED, on_completed, srv, MHD_OPTION_CONNECTION_TIMEOUT,
        (unsigned)300, MHD_OPTION_UNESCAPE_CALLBACK, unescape_keep_nul, NULL, MHD_OPTION_ARRAY,
        tls, MHD_OPTION_END);
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
        http_sse_destroy(srv->sse);
        http_stream_set_destroy(srv->streams);
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
    http_sse_destroy(s->sse); /* after the daemon: no handler opens a stream any more */
    http_stream_set_destroy(s->streams);
    free(s);
}
