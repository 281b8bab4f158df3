/*
 * h_jobs.c - batch jobs (docs/api.md "Batch jobs"): POST /v1/jobs, GET /v1/jobs,
 * GET/DELETE /v1/jobs/{id}, GET /v1/jobs/{id}/frames/{n}, GET /v1/jobs/{id}/archive.
 * The work is server/jobs/'s; this file only translates.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../jobs/jobs.h"
#include "http_internal.h"

static cJSON *status_json(const struct job_status *st)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "id", st->id);
    if (st->inline_scene)
        cJSON_AddNullToObject(o, "scene"); /* the specification holds the document */
    else
        cJSON_AddStringToObject(o, "scene", st->scene);
    cJSON_AddBoolToObject(o, "inline_scene", st->inline_scene);
    cJSON_AddStringToObject(o, "state", st->state);
    cJSON_AddNumberToObject(o, "frames_total", st->frames_total);
    cJSON_AddNumberToObject(o, "frames_done", st->frames_done);
    cJSON_AddNumberToObject(o, "progress",
                            st->frames_total ? (double)st->frames_done / st->frames_total : 0);
    if (st->eta_s >= 0)
        cJSON_AddNumberToObject(o, "eta_s", st->eta_s);
    else
        cJSON_AddNullToObject(o, "eta_s");
    cJSON_AddNumberToObject(o, "created", (double)st->created_unix);
    if (st->started_unix)
        cJSON_AddNumberToObject(o, "started", (double)st->started_unix);
    else
        cJSON_AddNullToObject(o, "started");
    if (st->finished_unix)
        cJSON_AddNumberToObject(o, "finished", (double)st->finished_unix);
    else
        cJSON_AddNullToObject(o, "finished");
    if (st->message[0])
        cJSON_AddStringToObject(o, "message", st->message);
    else
        cJSON_AddNullToObject(o, "message");
    return o;
}

enum MHD_Result http_handle_job_create(struct http_request *req)
{
    struct job_status st;
    struct err e = {0};
    const char *body = req->body && req->body_len ? req->body : "{}";
    size_t len = req->body && req->body_len ? req->body_len : 2;
    if (job_submit(req->app->jobs, body, len, &st, &e) != REFRACT_E_OK)
        return http_respond_err(req, &e);
    return http_respond_json(req, MHD_HTTP_ACCEPTED, status_json(&st));
}

static const char *const states[] = {"queued", "running", "done", "failed", "cancelled", NULL};

enum MHD_Result http_handle_job_list(struct http_request *req)
{
    static const char *const allowed[] = {"state", "scene", NULL};
    const char *unknown = http_query_unknown(req, allowed);
    if (unknown)
        return http_respond_error(req, REFRACT_E_INVALID_FIELD,
                                  "query parameter \"%s\" is not known; allowed: state, scene",
                                  unknown);
    const char *state = MHD_lookup_connection_value(req->conn, MHD_GET_ARGUMENT_KIND, "state");
    const char *scene = MHD_lookup_connection_value(req->conn, MHD_GET_ARGUMENT_KIND, "scene");
    if (state) {
        bool known = false;
        for (int i = 0; states[i]; i++)
            known |= strcmp(states[i], state) == 0;
        if (!known)
            return http_respond_error(req, REFRACT_E_INVALID_FIELD,
                                      "state: \"%.40s\" is not a job state; one of queued, "
                                      "running, done, failed, cancelled",
                                      state);
    }
    struct job_status *list = NULL;
    size_t n = job_list(req->app->jobs, state, scene, &list);
    if (list == NULL)
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory listing jobs");
    cJSON *root = cJSON_CreateObject();
    cJSON *arr = cJSON_AddArrayToObject(root, "jobs");
    for (size_t i = 0; i < n; i++)
        cJSON_AddItemToArray(arr, status_json(&list[i]));
    free(list);
    return http_respond_json(req, MHD_HTTP_OK, root);
}

static bool job_or_404(struct http_request *req, struct job_status *st, enum MHD_Result *answer)
{
    if (job_get(req->app->jobs, req->params[0], st))
        return true;
    *answer = http_respond_error(req, REFRACT_E_NOT_FOUND, "no job \"%s\"; GET /v1/jobs lists them",
                                 req->params[0]);
    return false;
}

enum MHD_Result http_handle_job_get(struct http_request *req)
{
    struct job_status st;
    enum MHD_Result answer = MHD_NO;
    if (!job_or_404(req, &st, &answer))
        return answer;
    return http_respond_json(req, MHD_HTTP_OK, status_json(&st));
}

enum MHD_Result http_handle_job_delete(struct http_request *req)
{
    struct job_status st;
    bool deleted = false;
    struct err e = {0};
    if (job_cancel_or_delete(req->app->jobs, req->params[0], &deleted, &st, &e) != REFRACT_E_OK)
        return http_respond_err(req, &e);
    if (deleted)
        return http_respond_empty(req, MHD_HTTP_NO_CONTENT);
    return http_respond_json(req, MHD_HTTP_OK, status_json(&st));
}

enum MHD_Result http_handle_job_frame(struct http_request *req)
{
    struct job_status st;
    enum MHD_Result answer = MHD_NO;
    if (!job_or_404(req, &st, &answer))
        return answer;
    char *end = NULL;
    long n = strtol(req->params[1], &end, 10);
    if (end == req->params[1] || *end != '\0' || n < 0 || n >= st.frames_total)
        return http_respond_error(req, REFRACT_E_NOT_FOUND,
                                  "job %s has frames 0..%d; \"%s\" is not one of them", st.id,
                                  st.frames_total - 1, req->params[1]);
    if (n >= st.frames_done)
        return http_respond_error(req, REFRACT_E_CONFLICT,
                                  "frame %ld of job %s is not finished yet (%d of %d done, %s)", n,
                                  st.id, st.frames_done, st.frames_total, st.state);
    void *bytes = NULL;
    size_t len = 0;
    struct err e = {0};
    if (store_job_frame_read(req->app->store, st.id, (int)n, &bytes, &len, &e) != REFRACT_E_OK)
        return http_respond_err(req, &e);
    enum job_format f = JOB_FORMAT_PNG;
    job_format_sniff(bytes, len, &f);
    return http_respond_bytes(req, MHD_HTTP_OK, bytes, len, job_format_content_type(f), NULL);
}

/* ---- archive: a POSIX ustar file of the finished frames, frame_00000.png ... ---------- */

struct tar {
    unsigned char *buf;
    size_t len, cap;
};

static bool tar_reserve(struct tar *t, size_t more)
{
    if (t->len + more <= t->cap)
        return true;
    size_t cap = t->cap ? t->cap : 65536;
    while (cap < t->len + more)
        cap *= 2;
    void *grown = realloc(t->buf, cap);
    if (grown == NULL)
        return false;
    t->buf = grown;
    t->cap = cap;
    return true;
}

static bool tar_add(struct tar *t, const char *name, const void *data, size_t len, long mtime)
{
    size_t padded = (len + 511) / 512 * 512;
    if (!tar_reserve(t, 512 + padded))
        return false;
    unsigned char *h = t->buf + t->len;
    memset(h, 0, 512);
    snprintf((char *)h, 100, "%.99s", name);
    snprintf((char *)h + 100, 8, "%07o", 0644);
    snprintf((char *)h + 108, 8, "%07o", 0);
    snprintf((char *)h + 116, 8, "%07o", 0);
    snprintf((char *)h + 124, 12, "%011llo", (unsigned long long)len);
    snprintf((char *)h + 136, 12, "%011lo", (unsigned long)mtime);
    h[156] = '0';
    memcpy(h + 257, "ustar", 6);
    memcpy(h + 263, "00", 2);
    memset(h + 148, ' ', 8);
    unsigned sum = 0;
    for (int i = 0; i < 512; i++)
        sum += h[i];
    snprintf((char *)h + 148, 8, "%06o", sum);
    memcpy(h + 512, data, len);
    memset(h + 512 + len, 0, padded - len);
    t->len += 512 + padded;
    return true;
}

enum MHD_Result http_handle_job_archive(struct http_request *req)
{
    struct job_status st;
    enum MHD_Result answer = MHD_NO;
    if (!job_or_404(req, &st, &answer))
        return answer;
    struct tar t = {0};
    for (int n = 0; n < st.frames_done; n++) {
        void *bytes = NULL;
        size_t len = 0;
        struct err e = {0};
        if (store_job_frame_read(req->app->store, st.id, n, &bytes, &len, &e) != REFRACT_E_OK) {
            free(t.buf);
            return http_respond_err(req, &e);
        }
        enum job_format f = JOB_FORMAT_PNG;
        job_format_sniff(bytes, len, &f);
        char name[STORE_ID_MAX + 32];
        snprintf(name, sizeof name, "%s/frame_%05d.%s", st.id, n, job_format_extension(f));
        bool ok = tar_add(&t, name, bytes, len, (long)st.created_unix);
        free(bytes);
        if (!ok) {
            free(t.buf);
            return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY,
                                      "out of memory building the archive of job %s", st.id);
        }
    }
    if (!tar_reserve(&t, 1024)) {
        free(t.buf);
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory");
    }
    memset(t.buf + t.len, 0, 1024); /* two zero blocks end a tar file */
    t.len += 1024;
    char done[32];
    snprintf(done, sizeof done, "%d", st.frames_done);
    const char *headers[] = {"X-Job-Frames", done, "X-Job-State", st.state, NULL};
    return http_respond_bytes(req, MHD_HTTP_OK, t.buf, t.len, "application/x-tar", headers);
}
