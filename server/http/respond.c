/*
 * respond.c - every HTTP answer refractd gives goes through here: JSON bodies, the one
 * error body shape {"error": {"code", "message"}}, and image bytes. Errors are logged
 * once, here, at the edge.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/log.h"
#include "../core/utf8.h"
#include "http_internal.h"

void http_response_common_headers(struct MHD_Response *resp)
{
    /* Browsers must take every answer as the type it says (an error's JSON never runs as
     * a script or renders as a page). */
    MHD_add_response_header(resp, "X-Content-Type-Options", "nosniff");
}

static enum MHD_Result queue(struct http_request *req, unsigned status, void *bytes, size_t len,
                             const char *content_type, const char *const *headers)
{
    struct MHD_Response *resp =
        MHD_create_response_from_buffer_with_free_callback(len, bytes, free);
    if (resp == NULL) {
        free(bytes);
        return MHD_NO;
    }
    if (content_type)
        MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, content_type);
    http_response_common_headers(resp);
    for (size_t i = 0; headers && headers[i] && headers[i + 1]; i += 2)
        MHD_add_response_header(resp, headers[i], headers[i + 1]);
    enum MHD_Result r = MHD_queue_response(req->conn, status, resp);
    MHD_destroy_response(resp);
    req->phase = HTTP_PHASE_ANSWERED;
    req->status = (int)status;
    return r;
}

enum MHD_Result http_respond_bytes(struct http_request *req, unsigned status, void *bytes,
                                   size_t len, const char *content_type, const char *const *headers)
{
    return queue(req, status, bytes, len, content_type, headers);
}

enum MHD_Result http_respond_json(struct http_request *req, unsigned status, cJSON *json)
{
    char *text = json ? cJSON_PrintUnformatted(json) : NULL;
    cJSON_Delete(json);
    if (text == NULL)
        return MHD_NO;
    size_t len = strlen(text);
    /* cJSON allocates with malloc (no hooks installed), so free() releases it. */
    char *body = realloc(text, len + 2);
    if (body == NULL) {
        free(text);
        return MHD_NO;
    }
    body[len] = '\n';
    body[len + 1] = '\0';
    return queue(req, status, body, len + 1, "application/json", NULL);
}

enum MHD_Result http_respond_empty(struct http_request *req, unsigned status)
{
    return queue(req, status, NULL, 0, NULL, NULL);
}

static enum MHD_Result respond_error_text(struct http_request *req, enum refract_code code,
                                          const char *raw_message, const char *const *headers)
{
    /* Messages quote what clients sent (URL parts, file headers): what is not printable
     * UTF-8 is written as \xNN, so the body is valid JSON and shows every byte. */
    char message[ERR_MSG_MAX * 4];
    utf8_escape(message, sizeof message, raw_message, strlen(raw_message), NULL);
    int status = err_code_http_status(code);
    const char *route = req->route ? req->route->pattern : "(no route)";
    if (status >= 500)
        log_warn("http", "%d %s %s: %s", status, err_code_json(code), route, message);
    else
        log_info("http", "%d %s %s: %s", status, err_code_json(code), route, message);
    cJSON *root = cJSON_CreateObject();
    cJSON *err = cJSON_AddObjectToObject(root, "error");
    cJSON_AddStringToObject(err, "code", err_code_json(code));
    cJSON_AddStringToObject(err, "message", message);
    char *text = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    if (text == NULL)
        return MHD_NO;
    return queue(req, (unsigned)status, text, strlen(text), "application/json", headers);
}

__attribute__((format(printf, 4, 0))) static enum MHD_Result
respond_error_v(struct http_request *req, const char *const *headers, enum refract_code code,
                const char *fmt, va_list ap)
{
    char message[ERR_MSG_MAX];
    vsnprintf(message, sizeof message, fmt, ap);
    return respond_error_text(req, code, message, headers);
}

enum MHD_Result http_respond_error(struct http_request *req, enum refract_code code,
                                   const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    enum MHD_Result r = respond_error_v(req, NULL, code, fmt, ap);
    va_end(ap);
    return r;
}

enum MHD_Result http_respond_error_with(struct http_request *req, const char *const *headers,
                                        enum refract_code code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    enum MHD_Result r = respond_error_v(req, headers, code, fmt, ap);
    va_end(ap);
    return r;
}

enum MHD_Result http_respond_err(struct http_request *req, const struct err *e)
{
    enum refract_code code = e->code == REFRACT_E_OK ? REFRACT_E_INTERNAL : e->code;
    return respond_error_text(req, code, e->msg[0] ? e->msg : err_code_text(code), NULL);
}
