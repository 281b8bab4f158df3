/*
 * jobs_util.h - what the batch-job tests share: submitting a job, polling its status until
 * it finishes, and fetching and decoding its frames, all through librefract's raw requests
 * against the real refractd.
 */
#ifndef REFRACT_TEST_JOBS_UTIL_H
#define REFRACT_TEST_JOBS_UTIL_H

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../test.h"
#include "daemon.h"
#include "io/io_image.h"

/* POST /v1/jobs; writes the new job's id (64 bytes) and returns true on 202. */
static inline bool job_submit_json(struct test_daemon *d, const char *spec, char id[64])
{
    char *body = NULL;
    long status = test_request(d, "POST", "/v1/jobs", spec, &body);
    cJSON *root = body ? cJSON_Parse(body) : NULL;
    const cJSON *jid = cJSON_GetObjectItemCaseSensitive(root, "id");
    bool ok = status == 202 && cJSON_IsString(jid);
    if (ok)
        snprintf(id, 64, "%s", jid->valuestring);
    else
        fprintf(stderr, "POST /v1/jobs: %ld %s\n", status, body ? body : "(no answer)");
    cJSON_Delete(root);
    free(body);
    return ok;
}

/* GET /v1/jobs/{id} as a new cJSON tree (NULL unless 200). */
static inline cJSON *job_status_get(struct test_daemon *d, const char *id)
{
    char path[128], *body = NULL;
    snprintf(path, sizeof path, "/v1/jobs/%s", id);
    long status = test_request(d, "GET", path, NULL, &body);
    cJSON *root = status == 200 && body ? cJSON_Parse(body) : NULL;
    free(body);
    return root;
}

static inline int job_int(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valueint : -1;
}

static inline const char *job_str(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsString(v) ? v->valuestring : "";
}

static inline void job_sleep_ms(int ms)
{
    struct timespec ts = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

/* Polls until the job is done, failed or cancelled (or timeout_s passes); returns its last
 * status (new tree; NULL when it could not be read). */
static inline cJSON *job_wait(struct test_daemon *d, const char *id, double timeout_s)
{
    for (int i = 0; i < (int)(timeout_s * 20); i++) {
        cJSON *st = job_status_get(d, id);
        const char *state = st ? job_str(st, "state") : "";
        if (!strcmp(state, "done") || !strcmp(state, "failed") || !strcmp(state, "cancelled"))
            return st;
        cJSON_Delete(st);
        job_sleep_ms(50);
    }
    return job_status_get(d, id);
}

/* GET /v1/jobs/{id}/frames/{n}: the encoded bytes (new; caller frees) or NULL unless 200. */
static inline void *job_frame_bytes(struct test_daemon *d, const char *id, int n, size_t *len,
                                    char *content_type, size_t ct_size)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/jobs/%s/frames/%d", id, n);
    struct refract_response r;
    if (refract_request(d->client, "GET", path, NULL, 0, NULL, &r) != 0)
        return NULL;
    void *out = NULL;
    if (r.status == 200) {
        out = r.body;
        r.body = NULL;
        *len = r.body_len;
        if (content_type)
            snprintf(content_type, ct_size, "%.63s", r.content_type);
    }
    refract_response_free(&r);
    return out;
}

/* Frame n decoded (linear RGBA); false unless it is an image of width x height. */
static inline bool job_frame_image(struct test_daemon *d, const char *id, int n, int width,
                                   int height, struct io_image *out)
{
    size_t len = 0;
    void *bytes = job_frame_bytes(d, id, n, &len, NULL, 0);
    struct err e = {0};
    bool ok = bytes && io_image_decode(bytes, len, 1 << 24, out, &e) == REFRACT_E_OK;
    free(bytes);
    if (!ok) {
        fprintf(stderr, "frame %d of job %s: %s\n", n, id, bytes ? e.msg : "no 200 answer");
        return false;
    }
    return out->width == width && out->height == height;
}

/* The largest per-channel difference of two images of the same size. */
static inline double job_image_max_diff(const struct io_image *a, const struct io_image *b)
{
    double m = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height * 4; i++) {
        double dd = a->rgba[i] - b->rgba[i];
        m = dd > m ? dd : -dd > m ? -dd : m;
    }
    return m;
}

#endif
