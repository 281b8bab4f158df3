/*
 * h_jobs.c - batch jobs (docs/api.md "Batch jobs"): POST /v1/jobs, GET /v1/jobs,
 * GET/DELETE /v1/jobs/{id}, GET /v1/jobs/{id}/frames/{n}, GET /v1/jobs/{id}/archive.
 * The work is server/jobs/'s; this file only translates.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../core/log.h"

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

/* ---- archive: a POSIX ustar file of the finished frames, frame_00000.png ... ----------
 *
 * The archive is made while it is sent: libmicrohttpd pulls it through archive_read, which
 * writes an entry's 512-byte header when it gets there and then copies the frame from its
 * blob file (pread), so a download holds one header and the frames' refs (about 80 bytes a
 * frame), never the frames themselves, whatever the size of the job. Its length is known
 * up front (Content-Length: the sizes are in job_frames). It holds the frames finished when
 * the request came (X-Job-Frames). A job deleted during its download (its blobs go) cuts
 * the download short, which the client sees as a body shorter than Content-Length. */

#define TAR_BLOCK 512

struct archive {
    struct store *store; /* borrowed: the store outlives every connection */
    char job[STORE_ID_MAX];
    long mtime; /* every entry's: the job's creation time */
    struct store_job_frame_ref *refs;
    int count;
    int index;            /* the entry being sent; count: the two zero blocks that end it */
    uint64_t entry_start; /* archive offset of entry `index` */
    uint64_t sent;        /* bytes produced so far */
    uint64_t total;
    int fd; /* entry `index`'s blob, or -1 */
    unsigned char header[TAR_BLOCK];
};

static uint64_t padded(size_t len)
{
    return ((uint64_t)len + TAR_BLOCK - 1) / TAR_BLOCK * TAR_BLOCK;
}

/* A ustar header for a regular file (mode 0644, uid and gid 0). */
static void tar_header(unsigned char h[TAR_BLOCK], const char *name, size_t len, long mtime)
{
    memset(h, 0, TAR_BLOCK);
    snprintf((char *)h, 100, "%.99s", name);
    snprintf((char *)h + 100, 8, "%07o", 0644);
    snprintf((char *)h + 108, 8, "%07o", 0);
    snprintf((char *)h + 116, 8, "%07o", 0);
    snprintf((char *)h + 124, 12, "%011llo", (unsigned long long)len);
    snprintf((char *)h + 136, 12, "%011lo", (unsigned long)mtime);
    h[156] = '0';
    memcpy(h + 257, "ustar", 6);
    memcpy(h + 263, "00", 2);
    memset(h + 148, ' ', 8); /* the checksum counts its own field as spaces */
    unsigned sum = 0;
    for (int i = 0; i < TAR_BLOCK; i++)
        sum += h[i];
    snprintf((char *)h + 148, 8, "%06o", sum);
}

/* Opens entry a->index's blob and makes its header (the name's extension from the
 * frame's first bytes). False when the blob cannot be read. */
static bool entry_begin(struct archive *a)
{
    const struct store_job_frame_ref *ref = &a->refs[a->index];
    struct err e = {0};
    a->fd = store_job_frame_open(a->store, ref, &e);
    if (a->fd < 0) {
        log_warn("http", "archive of job %s cut short: %s", a->job, e.msg);
        return false;
    }
    unsigned char magic[8] = {0};
    size_t want = ref->bytes < sizeof magic ? ref->bytes : sizeof magic;
    ssize_t got = pread(a->fd, magic, want, 0);
    enum job_format f = JOB_FORMAT_PNG;
    job_format_sniff(magic, got > 0 ? (size_t)got : 0, &f);
    char name[STORE_ID_MAX + 32];
    snprintf(name, sizeof name, "%s/frame_%05d.%s", a->job, a->index, job_format_extension(f));
    tar_header(a->header, name, ref->bytes, a->mtime);
    return true;
}

/* Up to max bytes of entry a->index from its offset `off`: header, data, zero padding.
 * Returns the count, or -1 when its blob cannot be read. */
static ssize_t entry_part(struct archive *a, uint64_t off, char *out, size_t max)
{
    size_t bytes = a->refs[a->index].bytes;
    uint64_t left;
    if (off < TAR_BLOCK) {
        left = TAR_BLOCK - off;
        size_t n = left < max ? (size_t)left : max;
        memcpy(out, a->header + off, n);
        return (ssize_t)n;
    }
    if (off < TAR_BLOCK + (uint64_t)bytes) {
        left = TAR_BLOCK + (uint64_t)bytes - off;
        size_t n = left < max ? (size_t)left : max;
        ssize_t got = pread(a->fd, out, n, (off_t)(off - TAR_BLOCK));
        return got > 0 ? got : -1;
    }
    left = TAR_BLOCK + padded(bytes) - off;
    size_t n = left < max ? (size_t)left : max;
    memset(out, 0, n);
    return (ssize_t)n;
}

static ssize_t archive_read(void *cls, uint64_t pos, char *buf, size_t max)
{
    struct archive *a = cls;
    if (pos != a->sent) /* libmicrohttpd reads a body once, in order */
        return MHD_CONTENT_READER_END_WITH_ERROR;
    size_t n = 0;
    while (n < max && a->sent < a->total) {
        ssize_t got;
        if (a->index == a->count) { /* the two zero blocks that end a tar file */
            uint64_t left = a->total - a->sent;
            got = (ssize_t)(left < max - n ? left : max - n);
            memset(buf + n, 0, (size_t)got);
        } else {
            uint64_t off = a->sent - a->entry_start;
            if (off == 0 && !entry_begin(a))
                return MHD_CONTENT_READER_END_WITH_ERROR;
            got = entry_part(a, off, buf + n, max - n);
            if (got < 0)
                return MHD_CONTENT_READER_END_WITH_ERROR;
            uint64_t size = TAR_BLOCK + padded(a->refs[a->index].bytes);
            if (off + (uint64_t)got == size) {
                close(a->fd);
                a->fd = -1;
                a->entry_start += size;
                a->index++;
            }
        }
        n += (size_t)got;
        a->sent += (uint64_t)got;
    }
    return n > 0 ? (ssize_t)n : MHD_CONTENT_READER_END_OF_STREAM;
}

static void archive_free(void *cls)
{
    struct archive *a = cls;
    if (a->fd >= 0)
        close(a->fd);
    free(a->refs);
    free(a);
}

enum MHD_Result http_handle_job_archive(struct http_request *req)
{
    struct job_status st;
    enum MHD_Result answer = MHD_NO;
    if (!job_or_404(req, &st, &answer))
        return answer;
    struct archive *a = calloc(1, sizeof *a);
    if (a == NULL)
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY,
                                  "out of memory for the archive of job %s", st.id);
    struct err e = {0};
    if (store_job_frame_refs(req->app->store, st.id, st.frames_done, &a->refs, &e) !=
        REFRACT_E_OK) {
        free(a);
        return http_respond_err(req, &e);
    }
    a->store = req->app->store;
    snprintf(a->job, sizeof a->job, "%s", st.id);
    a->mtime = (long)st.created_unix;
    a->count = st.frames_done;
    a->fd = -1;
    for (int n = 0; n < a->count; n++)
        a->total += TAR_BLOCK + padded(a->refs[n].bytes);
    a->total += 2 * TAR_BLOCK;
    struct MHD_Response *resp =
        MHD_create_response_from_callback(a->total, 64 * 1024, archive_read, a, archive_free);
    if (resp == NULL) {
        archive_free(a);
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY,
                                  "out of memory for the archive of job %s", st.id);
    }
    char done[32];
    snprintf(done, sizeof done, "%d", st.frames_done);
    MHD_add_response_header(resp, MHD_HTTP_HEADER_CONTENT_TYPE, "application/x-tar");
    MHD_add_response_header(resp, "X-Job-Frames", done);
    MHD_add_response_header(resp, "X-Job-State", st.state);
    http_response_common_headers(resp);
    enum MHD_Result r = MHD_queue_response(req->conn, MHD_HTTP_OK, resp);
    req->status = MHD_HTTP_OK;
    MHD_destroy_response(resp);
    req->phase = HTTP_PHASE_ANSWERED;
    return r;
}
