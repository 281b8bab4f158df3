/*
 * refract_jobs.c - librefract's batch-job calls (refract.h, "batch jobs"): thin wrappers
 * of /v1/jobs whose replies are JSON, and a frame as a struct refract_image.
 */
#include <stdlib.h>
#include <string.h>

#include "refract_internal.h"
#include "refract_url.h"

/* *path = "/v1/jobs/<escaped id><suffix>" (new); the code of a bad id or of no memory. */
static int job_path(refract_client *c, const char *call, const char *id, const char *suffix,
                    char **path)
{
    *path = NULL;
    int code = refract_check_segment(c, call, "job id", id);
    if (code != REFRACT_E_OK)
        return code;
    char *esc = refract_url_escape_dup(id);
    *path = esc != NULL ? refract_path_printf("/v1/jobs/%s%s", esc, suffix) : NULL;
    free(esc);
    return *path != NULL ? REFRACT_E_OK : refract_out_of_memory(c, "building the request path");
}

int refract_job_submit(refract_client *c, const char *spec_json, size_t len, char **json_out)
{
    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (spec_json == NULL || json_out == NULL)
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_job_submit: spec_json or json_out is NULL");
    return refract_call_json(c, "POST", "/v1/jobs", spec_json, len, "application/json", json_out);
}

int refract_job_get(refract_client *c, const char *job_id, char **json_out)
{
    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (json_out == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_job_get: json_out is NULL");
    char *path = NULL;
    int pc = job_path(c, "refract_job_get", job_id, "", &path);
    if (pc != REFRACT_E_OK)
        return pc;
    int code = refract_call_json(c, "GET", path, NULL, 0, NULL, json_out);
    free(path);
    return code;
}

int refract_job_list(refract_client *c, const char *state, const char *scene, char **json_out)
{
    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (json_out == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_job_list: json_out is NULL");
    char *st = refract_url_escape_dup(state ? state : "");
    char *sc = refract_url_escape_dup(scene ? scene : "");
    char *path = st && sc ? refract_path_printf("/v1/jobs%s%s%s%s%s", (state || scene) ? "?" : "",
                                                state ? "state=" : "", state ? st : "",
                                                state && scene ? "&" : "", scene ? "scene=" : "")
                          : NULL;
    char *full = path ? refract_path_printf("%s%s", path, scene ? sc : "") : NULL;
    free(st);
    free(sc);
    free(path);
    if (full == NULL)
        return refract_out_of_memory(c, "building the request path");
    int code = refract_call_json(c, "GET", full, NULL, 0, NULL, json_out);
    free(full);
    return code;
}

int refract_job_cancel(refract_client *c, const char *job_id, char **json_out)
{
    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    char *path = NULL;
    int pc = job_path(c, "refract_job_cancel", job_id, "", &path);
    if (pc != REFRACT_E_OK)
        return pc;
    char *reply = NULL;
    int code = refract_call_json(c, "DELETE", path, NULL, 0, NULL, &reply);
    free(path);
    if (json_out != NULL && reply != NULL && reply[0] != '\0') {
        *json_out = reply;
        reply = NULL;
    }
    refract_free(reply);
    return code;
}

int refract_job_frame(refract_client *c, const char *job_id, int n, struct refract_image *out)
{
    if (out != NULL) {
        memset(out, 0, sizeof(*out));
        out->render_ms = -1.0;
    }
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (out == NULL || n < 0)
        return refract_fail(c, REFRACT_E_USAGE, "refract_job_frame: out is NULL or n < 0");
    char suffix[32];
    snprintf(suffix, sizeof(suffix), "/frames/%d", n);
    char *path = NULL;
    int pc = job_path(c, "refract_job_frame", job_id, suffix, &path);
    if (pc != REFRACT_E_OK)
        return pc;
    struct refract_response r;
    int code = refract_http_exchange(c, "GET", path, NULL, 0, NULL, &r);
    if (code == REFRACT_E_OK) {
        code = refract_http_check(c, "GET", path, &r);
        if (code == REFRACT_E_OK && strncmp(r.content_type, "image/", 6) != 0)
            code = refract_fail(c, REFRACT_E_PROTOCOL,
                                "GET %s: expected an image, got Content-Type \"%s\"", path,
                                r.content_type);
        if (code == REFRACT_E_OK) {
            out->bytes = r.body; /* ownership moves to the caller */
            out->len = r.body_len;
            r.body = NULL;
            snprintf(out->content_type, sizeof(out->content_type), "%.63s", r.content_type);
        }
        refract_response_free(&r);
    }
    free(path);
    return code;
}
