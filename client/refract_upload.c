/*
 * refract_upload.c - uploads of files (refract.h, "Uploads streamed from a file"): the
 * route and query of each kind of upload, and the body read from the file by libcurl
 * as it sends it, with progress and a bound on silences.
 *
 * The file is never read whole: on_read hands libcurl as many bytes as it asks for
 * (CURLOPT_READFUNCTION, 64 KiB at most at a time), so an upload costs the same few
 * kilobytes whatever its size, which is what makes a 1 GiB volume uploadable from a
 * small machine. The size is sent up front (CURLOPT_INFILESIZE_LARGE), so refractd
 * can refuse an upload over --max-upload-bytes before the body goes (libcurl sends
 * "Expect: 100-continue" for a large body and waits for the go-ahead); a stream of
 * unknown size goes chunked.
 *
 * Progress comes from libcurl's transfer counter (CURLOPT_XFERINFOFUNCTION), capped at
 * the bytes read so far, and is reported only when it grows, so the caller sees a
 * monotone count; libcurl may restart a request on a dead keep-alive connection,
 * rewinding the file (on_seek) and its counter, and the cap hides that.
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

#include "refract_internal.h"
#include "refract_url.h"

/* The state of one upload, borrowed by the libcurl callbacks. */
struct upload {
    FILE *f;              /* borrowed */
    const char *label;    /* "'path'" or "the stream", for messages */
    long long size;       /* bytes to send; -1 = up to the end of f */
    off_t start;          /* f's position when the upload began; -1 = cannot seek */
    long long read_bytes; /* handed to libcurl so far (since the last rewind) */
    long long reported;   /* the last sent_bytes given to progress */
    bool read_failed;     /* on_read stopped the transfer; why says why */
    char why[512];        /* why on_read failed */
    long timeout_ms;      /* the longest silence; 0 = none */
    double last_move_ms;  /* refract_monotonic_ms() when a byte last moved */
    curl_off_t last_ul;   /* libcurl's counters when last seen */
    curl_off_t last_dl;   /* (either growing counts as a move) */
    bool timed_out;       /* on_xferinfo stopped the transfer */
    refract_upload_progress_fn progress;
    void *user;
};

static void report(struct upload *u, long long sent)
{
    if (sent > u->read_bytes)
        sent = u->read_bytes; /* libcurl cannot have sent what it was not given */
    if (sent <= u->reported)
        return;
    u->reported = sent;
    if (u->progress != NULL)
        u->progress(sent, u->size, u->user);
}

static size_t on_read(char *buf, size_t size, size_t nitems, void *userp)
{
    struct upload *u = userp;
    size_t want = size * nitems;
    size_t n;

    if (u->size >= 0 && (long long)want > u->size - u->read_bytes)
        want = (size_t)(u->size - u->read_bytes);
    if (want == 0)
        return 0;
    n = fread(buf, 1, want, u->f);
    if (n == 0 && ferror(u->f)) {
        snprintf(u->why, sizeof(u->why), "reading %s failed after %lld bytes: %s", u->label,
                 u->read_bytes, strerror(errno));
        u->read_failed = true;
        return CURL_READFUNC_ABORT;
    }
    if (n == 0 && u->size >= 0) {
        snprintf(u->why, sizeof(u->why),
                 "%s ended after %lld bytes, but it had %lld when the upload began; was it "
                 "changed while it was being sent?",
                 u->label, u->read_bytes, u->size);
        u->read_failed = true;
        return CURL_READFUNC_ABORT;
    }
    u->read_bytes += (long long)n;
    return n;
}

/* libcurl rewinds (offset 0 from SEEK_SET) to send the body again on a new connection. */
static int on_seek(void *userp, curl_off_t offset, int origin)
{
    struct upload *u = userp;

    if (origin != SEEK_SET || offset < 0 || u->start < 0)
        return CURL_SEEKFUNC_CANTSEEK;
    if (fseeko(u->f, u->start + (off_t)offset, SEEK_SET) != 0)
        return CURL_SEEKFUNC_FAIL;
    clearerr(u->f);
    u->read_bytes = (long long)offset;
    return CURL_SEEKFUNC_OK;
}

/* Called by libcurl often (at least once a second while idle): reports progress and
 * enforces the silence limit. Non-zero aborts with CURLE_ABORTED_BY_CALLBACK. */
static int on_xferinfo(void *userp, curl_off_t dltotal, curl_off_t dlnow, curl_off_t ultotal,
                       curl_off_t ulnow)
{
    struct upload *u = userp;
    double now = refract_monotonic_ms();

    (void)dltotal;
    (void)ultotal;
    if (ulnow != u->last_ul || dlnow != u->last_dl) {
        u->last_ul = ulnow;
        u->last_dl = dlnow;
        u->last_move_ms = now;
    } else if (u->timeout_ms > 0 && now - u->last_move_ms > (double)u->timeout_ms) {
        u->timed_out = true;
        return 1;
    }
    report(u, (long long)ulnow);
    return 0;
}

/* Appends "&key=value" (value percent-encoded; "?" before the first) to q. */
static bool add_param(char *q, size_t size, const char *key, const char *value)
{
    char esc[256];
    size_t used = strlen(q);
    int n;

    if (refract_url_escape(esc, sizeof(esc), value) >= sizeof(esc))
        return false;
    n = snprintf(q + used, size - used, "%s%s=%s", used == 0 ? "?" : "&", key, esc);
    return n > 0 && (size_t)n < size - used;
}

/* The query of a volume upload: only what desc sets. */
static bool volume_query(const struct refract_upload_desc *d, char *q, size_t size)
{
    char v[96];
    bool ok = true;

    q[0] = '\0';
    if (d->format != NULL)
        ok = ok && add_param(q, size, "format", d->format);
    if (d->dims[0] != 0) {
        snprintf(v, sizeof(v), "%d,%d,%d", d->dims[0], d->dims[1], d->dims[2]);
        ok = ok && add_param(q, size, "dims", v);
    }
    if (d->type != NULL)
        ok = ok && add_param(q, size, "type", d->type);
    if (d->components != 0) {
        snprintf(v, sizeof(v), "%d", d->components);
        ok = ok && add_param(q, size, "components", v);
    }
    if (d->has_scale) {
        snprintf(v, sizeof(v), "%.17g", d->scale);
        ok = ok && add_param(q, size, "scale", v);
    }
    if (d->has_offset) {
        snprintf(v, sizeof(v), "%.17g", d->offset);
        ok = ok && add_param(q, size, "offset", v);
    }
    return ok;
}

static bool has_volume_fields(const struct refract_upload_desc *d)
{
    return d->dims[0] != 0 || d->dims[1] != 0 || d->dims[2] != 0 || d->type != NULL ||
           d->components != 0 || d->has_scale || d->has_offset;
}

/* Checks the parts of desc that do not depend on its kind. */
static int check_volume_fields(refract_client *c, const char *call,
                               const struct refract_upload_desc *d)
{
    bool no_dims = d->dims[0] == 0 && d->dims[1] == 0 && d->dims[2] == 0;

    if (!no_dims && (d->dims[0] < 1 || d->dims[1] < 1 || d->dims[2] < 1))
        return refract_fail(c, REFRACT_E_USAGE,
                            "%s: dims %d,%d,%d: give each dimension as at least 1, or all three "
                            "as 0 to send none",
                            call, d->dims[0], d->dims[1], d->dims[2]);
    if (d->components < 0)
        return refract_fail(c, REFRACT_E_USAGE, "%s: components is %d; use 1, 3 or 0 (not sent)",
                            call, d->components);
    if ((d->has_scale && !isfinite(d->scale)) || (d->has_offset && !isfinite(d->offset)))
        return refract_fail(c, REFRACT_E_USAGE, "%s: scale and offset must be finite numbers",
                            call);
    return REFRACT_E_OK;
}

/* Checks desc and builds the method and path of its route (*path_out: caller frees). */
static int route(refract_client *c, const char *call, const char *scene_id,
                 const struct refract_upload_desc *d, const char **method, char **path_out)
{
    static const char *const kind_names[] = {"", "volume", "mesh", "environment"};
    char suffix[1024];
    char query[768];
    char *esc = NULL;
    int code;

    *path_out = NULL;
    if (d == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "%s: desc is NULL", call);
    if (d->kind < REFRACT_UPLOAD_VOLUME || d->kind > REFRACT_UPLOAD_ENVIRONMENT)
        return refract_fail(c, REFRACT_E_USAGE,
                            "%s: desc->kind is %d; use REFRACT_UPLOAD_VOLUME, _MESH or "
                            "_ENVIRONMENT",
                            call, (int)d->kind);
    if (d->kind != REFRACT_UPLOAD_VOLUME && has_volume_fields(d))
        return refract_fail(c, REFRACT_E_USAGE,
                            "%s: dims, type, components, scale and offset apply to volumes "
                            "only, not to a%s %s upload",
                            call, d->kind == REFRACT_UPLOAD_ENVIRONMENT ? "n" : "",
                            kind_names[d->kind]);
    if (d->kind == REFRACT_UPLOAD_ENVIRONMENT && (d->name != NULL || d->format != NULL))
        return refract_fail(c, REFRACT_E_USAGE,
                            "%s: a scene has one environment image, which takes no name and "
                            "no format (refractd recognises EXR, HDR, PNG and JPEG files)",
                            call);
    code = d->kind == REFRACT_UPLOAD_ENVIRONMENT
               ? REFRACT_E_OK
               : refract_check_segment(c, call,
                                       d->kind == REFRACT_UPLOAD_MESH ? "mesh name" : "volume name",
                                       d->name);
    if (code == REFRACT_E_OK && d->kind == REFRACT_UPLOAD_VOLUME)
        code = check_volume_fields(c, call, d);
    if (code != REFRACT_E_OK)
        return code;

    query[0] = '\0';
    if (d->kind == REFRACT_UPLOAD_VOLUME) {
        esc = refract_url_escape_dup(d->name);
        if (esc == NULL)
            return refract_out_of_memory(c, "building the request path");
        if (!volume_query(d, query, sizeof(query)))
            code = refract_fail(c, REFRACT_E_USAGE, "%s: the upload's query is too long", call);
        snprintf(suffix, sizeof(suffix), "/volumes/%s%s", esc, query);
        *method = "PUT";
    } else if (d->kind == REFRACT_UPLOAD_MESH) {
        if (!add_param(query, sizeof(query), "name", d->name) ||
            (d->format != NULL && !add_param(query, sizeof(query), "format", d->format)))
            code = refract_fail(c, REFRACT_E_USAGE, "%s: the upload's query is too long", call);
        snprintf(suffix, sizeof(suffix), "/meshes%s", query);
        *method = "POST";
    } else {
        snprintf(suffix, sizeof(suffix), "/environment");
        *method = "PUT";
    }
    free(esc);
    if (code == REFRACT_E_OK)
        code = refract_scene_route(c, call, scene_id, suffix, path_out);
    return code;
}

/* The upload itself, after the arguments were checked and f opened. */
static int upload(refract_client *c, const char *method, const char *path, FILE *f,
                  const char *label, long long size, const struct refract_upload_desc *d,
                  char **json_out)
{
    struct upload u = {.f = f,
                       .label = label,
                       .size = size,
                       .start = ftello(f),
                       .reported = -1,
                       .timeout_ms = c->timeout_ms,
                       .last_move_ms = refract_monotonic_ms(),
                       .progress = d->progress,
                       .user = d->user};
    struct refract_http_body_source src = {.read = on_read,
                                           .seek = on_seek,
                                           .user = &u,
                                           .size = size,
                                           .xferinfo = on_xferinfo,
                                           .xferinfo_user = &u};
    struct refract_response r;
    curl_off_t sent = 0;
    int code;

    report(&u, 0);
    code = refract_http_exchange_source(c, method, path, &src, "application/octet-stream", &r);
    if (code != REFRACT_E_OK && u.read_failed)
        return refract_fail(c, REFRACT_E_IO, "%s %s: %s", method, path, u.why);
    if (code != REFRACT_E_OK && u.timed_out)
        return refract_fail(c, REFRACT_E_TIMEOUT,
                            "%s %s: nothing moved between here and refractd at %s for %ld ms, "
                            "after %lld bytes of %s were sent; raise the timeout (refract "
                            "--timeout SECONDS, 0 = none)",
                            method, path, c->base_url, c->timeout_ms, u.reported, label);
    if (code != REFRACT_E_OK)
        return code;
    curl_easy_getinfo(c->curl, CURLINFO_SIZE_UPLOAD_T, &sent);
    report(&u, (long long)sent);
    return refract_take_json(c, method, path, &r, json_out);
}

int refract_upload_stream(refract_client *c, const char *scene_id, FILE *f, long long size,
                          const struct refract_upload_desc *desc, char **json_out)
{
    const char *call = "refract_upload_stream";
    const char *method = NULL;
    char *path = NULL;
    int code;

    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (f == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "%s: f is NULL", call);
    code = route(c, call, scene_id, desc, &method, &path);
    if (code == REFRACT_E_OK)
        code = upload(c, method, path, f, "the stream", size < 0 ? -1 : size, desc, json_out);
    free(path);
    return code;
}

int refract_upload_file(refract_client *c, const char *scene_id, const char *file_path,
                        const struct refract_upload_desc *desc, char **json_out)
{
    const char *call = "refract_upload_file";
    const char *method = NULL;
    char label[600];
    char *path = NULL;
    struct stat st;
    FILE *f = NULL;
    int code;

    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (file_path == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "%s: path is NULL", call);
    code = route(c, call, scene_id, desc, &method, &path);
    if (code == REFRACT_E_OK) {
        f = fopen(file_path, "rb");
        if (f == NULL)
            code =
                refract_fail(c, REFRACT_E_IO, "cannot open '%s': %s", file_path, strerror(errno));
    }
    if (code == REFRACT_E_OK && fstat(fileno(f), &st) != 0)
        code = refract_fail(c, REFRACT_E_IO, "cannot read '%s': %s", file_path, strerror(errno));
    if (code == REFRACT_E_OK && S_ISDIR(st.st_mode))
        code =
            refract_fail(c, REFRACT_E_IO, "'%s' is a directory, not a file to upload", file_path);
    if (code == REFRACT_E_OK) {
        snprintf(label, sizeof(label), "'%s'", file_path);
        /* A pipe or device has no size: it goes chunked, to its end. */
        code = upload(c, method, path, f, label, S_ISREG(st.st_mode) ? (long long)st.st_size : -1,
                      desc, json_out);
    }
    if (f != NULL)
        fclose(f);
    free(path);
    return code;
}
