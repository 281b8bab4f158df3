/*
 * test_jobs_api.c - the batch-job API's answers: every bad specification gets a precise
 * 4xx naming the field (unknown fields, missing and wrong values, limits from
 * --max-job-frames and --max-image-pixels, an unknown scene); DELETE cancels a running job
 * (it stops advancing, its finished frames stay readable) and then deletes it; GET /v1/jobs
 * filters by state and scene and refuses unknown filters; unknown jobs and frames are 404,
 * an unfinished frame 409.
 */
#include "expect.h"
#include "jobs_util.h"

static void bad_specs(struct test_daemon *d, const char *s)
{
    char buf[40][256];
    const char *fmt[] = {
        "{\"scene\": \"%s\", \"turntable\": {\"frames\": 2}, \"colour\": 1}",
        "{\"turntable\": {\"frames\": 2}}",
        "{\"scene\": \"%s\"}",
        "{\"scene\": \"%s\", \"frames\": [], \"turntable\": {\"frames\": 2}}",
        "{\"scene\": \"%s\", \"frames\": []}",
        "{\"scene\": \"%s\", \"frames\": {}}",
        "{\"scene\": \"%s\", \"frames\": [{\"fov\": 30}]}",
        "{\"scene\": \"%s\", \"frames\": [{}, {\"width\": 0}]}",
        "{\"scene\": \"%s\", \"frames\": [{\"format\": \"gif\"}]}",
        "{\"scene\": \"%s\", \"frames\": [{\"camera\": {\"eye\": [0, 0]}}]}",
        "{\"scene\": \"%s\", \"frames\": [{\"camera\": {\"zoom\": 2}}]}",
        "{\"scene\": \"%s\", \"frames\": [{\"camera\": {\"eye\": [0, 0, 0], \"look_at\": [0, 0, "
        "0]}}]}",
        "{\"scene\": \"%s\", \"turntable\": {\"frames\": 0}}",
        "{\"scene\": \"%s\", \"turntable\": {\"frames\": 2, \"axis\": [0, 0, 0]}}",
        "{\"scene\": \"%s\", \"turntable\": {\"frames\": 2, \"speed\": 1}}",
        "{\"scene\": \"%s\", \"turntable\": {\"frames\": 9}}",
        "{\"scene\": \"%s\", \"frames\": [{}, {}, {}, {}, {}, {}, {}, {}, {}]}",
        "{\"scene\": \"%s\", \"width\": 4000, \"height\": 4000, \"turntable\": {\"frames\": 2}}",
        "{\"scene\": \"%s\", \"exposure\": \"bright\", \"turntable\": {\"frames\": 2}}",
        "{\"scene\": \"%s\", \"light_path\": {\"light\": \"moon\", \"frames\": 2, \"keyframes\": "
        "[]}}",
        "{\"scene\": \"%s\", \"light_path\": {\"light\": \"sun\", \"frames\": 2, \"keyframes\": "
        "[{\"direction\": [0, -1, 0]}]}}",
        "{\"scene\": \"%s\", \"light_path\": {\"light\": \"sun\", \"frames\": 2, \"keyframes\": "
        "[{\"direction\": [0, -1, 0]}, {\"position\": [0, 1, 0]}]}}",
        "{\"scene\": \"%s\", \"light_path\": {\"light\": \"sun\", \"frames\": 2, \"keyframes\": "
        "[{\"position\": [0, 1, 0]}, {\"position\": [1, 1, 0]}]}}",
        "{\"scene\": \"%s\", \"light_path\": {\"light\": \"sun\", \"frames\": 2, \"keyframes\": "
        "[{\"direction\": [0, 0, 0]}, {\"direction\": [0, -1, 0]}]}}",
        "{\"scene\": \"%s\", \"light_path\": {\"light\": \"sun\", \"keyframes\": [{}, {}]}}",
        "{\"scene\": \"%s\", \"frames\": [{\"lights\": [{\"name\": \"moon\", \"direction\": [0, "
        "-1, 0]}]}]}",
        "{\"scene\": \"%s\", \"frames\": [{\"lights\": [{\"name\": \"sun\"}]}]}",
        "{\"scene\": \"%s\", \"frames\": [{\"lights\": [{\"name\": \"sun\", \"position\": [0, 1, "
        "0]}]}]}",
        "{\"scene\": \"%s\", \"frames\": [{\"lights\": [{\"name\": \"sun\", \"direction\": [0, -1, "
        "0]}, {\"name\": \"sun\", \"direction\": [0, -1, 0]}]}]}",
        "{\"scene\": \"%s\", \"frames\": [{\"lights\": {\"sun\": 1}}]}",
    };
    for (size_t i = 0; i < sizeof fmt / sizeof fmt[0]; i++)
        snprintf(buf[i], sizeof buf[i], fmt[i], s);
    const struct json_error_case cases[] = {
        {__LINE__, "{", 400, "invalid_json", {"byte"}},
        {__LINE__, "[1]", 400, "invalid_field", {"object"}},
        {__LINE__, buf[0], 400, "unknown_field", {"colour", "turntable"}},
        {__LINE__, buf[1], 400, "missing_field", {"scene"}},
        {__LINE__, buf[2], 400, "missing_field", {"frames", "turntable"}},
        {__LINE__, buf[3], 400, "invalid_field", {"exactly one", "more than one"}},
        {__LINE__, buf[4], 400, "invalid_field", {"frames", "non-empty"}},
        {__LINE__, buf[5], 400, "invalid_field", {"frames", "an object"}},
        {__LINE__, buf[6], 400, "unknown_field", {"frames[0]", "fov"}},
        {__LINE__, buf[7], 400, "invalid_field", {"frames[1].width"}},
        {__LINE__, buf[8], 400, "invalid_field", {"frames[0].format", "gif", "exr"}},
        {__LINE__, buf[9], 400, "invalid_field", {"frames[0].camera.eye"}},
        {__LINE__, buf[10], 400, "unknown_field", {"frames[0].camera", "zoom"}},
        {__LINE__, buf[11], 400, "invalid_field", {"frames[0].camera", "same point"}},
        {__LINE__, buf[12], 400, "invalid_field", {"turntable.frames"}},
        {__LINE__, buf[13], 400, "invalid_field", {"turntable.axis"}},
        {__LINE__, buf[14], 400, "unknown_field", {"turntable", "speed"}},
        {__LINE__, buf[15], 422, "limit_exceeded", {"turntable.frames", "--max-job-frames 8"}},
        {__LINE__, buf[16], 422, "limit_exceeded", {"frames", "--max-job-frames 8"}},
        {__LINE__, buf[17], 422, "limit_exceeded", {"--max-image-pixels"}},
        {__LINE__, buf[18], 400, "invalid_field", {"exposure"}},
        {__LINE__, buf[19], 400, "invalid_field", {"light_path.light", "moon"}},
        {__LINE__, buf[20], 400, "invalid_field", {"light_path.keyframes", "2..1000"}},
        {__LINE__, buf[21], 400, "invalid_field", {"keyframes[1]", "same field"}},
        {__LINE__, buf[22], 400, "invalid_field", {"keyframes[0].position", "directional"}},
        {__LINE__, buf[23], 400, "invalid_field", {"keyframes[0].direction"}},
        {__LINE__, buf[24], 400, "missing_field", {"light_path", "frames"}},
        {__LINE__, buf[25], 400, "invalid_field", {"frames[0].lights[0].name", "moon"}},
        {__LINE__, buf[26], 400, "missing_field", {"frames[0].lights[0]", "exactly one"}},
        {__LINE__, buf[27], 400, "invalid_field", {"frames[0].lights[0].position", "directional"}},
        {__LINE__, buf[28], 400, "invalid_field", {"frames[0].lights[1].name", "twice"}},
        {__LINE__, buf[29], 400, "invalid_field", {"frames[0].lights", "array"}},
        {__LINE__,
         "{\"scene\": \"nosuch\", \"turntable\": {\"frames\": 2}}",
         404,
         "scene_not_found",
         {"nosuch"}},
    };
    EXPECT_JSON_ERROR_CASES(d, "POST", "/v1/jobs", cases);
    char *body = NULL;
    CHECK_INT(test_request(d, "GET", "/v1/jobs", NULL, &body), 200);
    CHECK_CONTAINS(body, "\"jobs\":[]"); /* no bad specification made a job */
    free(body);
}

static int count_jobs(struct test_daemon *d, const char *query)
{
    char path[160], *body = NULL;
    snprintf(path, sizeof path, "/v1/jobs%s", query);
    long status = test_request(d, "GET", path, NULL, &body);
    cJSON *root = status == 200 && body ? cJSON_Parse(body) : NULL;
    int n = cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "jobs"));
    cJSON_Delete(root);
    free(body);
    return status == 200 ? n : -1;
}

static void cancel_and_list(struct test_daemon *d, const char *a, const char *b)
{
    char spec[256], small[64] = "", big[64] = "", other[64] = "";
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"width\": 24, \"height\": 18, \"turntable\": {\"frames\": 2}}",
             a);
    CHECK(job_submit_json(d, spec, small));
    cJSON_Delete(job_wait(d, small, 120));
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"width\": 24, \"height\": 18, \"turntable\": {\"frames\": 8}}",
             b);
    CHECK(job_submit_json(d, spec, other));
    cJSON_Delete(job_wait(d, other, 120));
    /* A long job (max 8 frames per job here: the frames are larger, so it is slow). */
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"width\": 320, \"height\": 240, \"turntable\": {\"frames\": 8}}",
             a);
    CHECK(job_submit_json(d, spec, big));
    int done = 0;
    for (int i = 0; i < 3000 && done < 1; i++) {
        cJSON *st = job_status_get(d, big);
        done = st ? job_int(st, "frames_done") : 0;
        cJSON_Delete(st);
        job_sleep_ms(10);
    }
    char path[128], *body = NULL;
    snprintf(path, sizeof path, "/v1/jobs/%s", big);
    CHECK_INT(test_request(d, "DELETE", path, NULL, &body), 200);
    cJSON *st = body ? cJSON_Parse(body) : NULL;
    CHECK_STR(job_str(st, "state"), "cancelled");
    int at_cancel = job_int(st, "frames_done");
    CHECK(at_cancel >= 1 && at_cancel < 8);
    cJSON_Delete(st);
    free(body);
    job_sleep_ms(1500);
    st = job_status_get(d, big);
    CHECK_STR(job_str(st, "state"), "cancelled");
    CHECK_MSG(job_int(st, "frames_done") <= at_cancel + 1, "a cancelled job went on: %d -> %d",
              at_cancel, job_int(st, "frames_done"));
    CHECK(job_int(st, "finished") > 0);
    cJSON_Delete(st);
    size_t len = 0;
    void *frame0 = job_frame_bytes(d, big, 0, &len, NULL, 0);
    CHECK(frame0 != NULL); /* finished frames of a cancelled job stay readable */
    free(frame0);

    /* Filters. */
    CHECK_INT(count_jobs(d, ""), 3);
    CHECK_INT(count_jobs(d, "?state=done"), 2);
    CHECK_INT(count_jobs(d, "?state=cancelled"), 1);
    CHECK_INT(count_jobs(d, "?state=running"), 0);
    char q[128];
    snprintf(q, sizeof q, "?scene=%s", b);
    CHECK_INT(count_jobs(d, q), 1);
    snprintf(q, sizeof q, "?scene=%s&state=done", a);
    CHECK_INT(count_jobs(d, q), 1);
    EXPECT_ERROR(d, "GET", "/v1/jobs?state=sleeping", NULL, 400, "invalid_field", "sleeping",
                 "queued");
    EXPECT_ERROR(d, "GET", "/v1/jobs?owner=me", NULL, 400, "invalid_field", "owner", "state");

    /* Frames and jobs that do not exist. */
    snprintf(path, sizeof path, "/v1/jobs/%s/frames/2", small);
    EXPECT_ERROR(d, "GET", path, NULL, 404, "not_found", "0..1");
    snprintf(path, sizeof path, "/v1/jobs/%s/frames/x", small);
    EXPECT_ERROR(d, "GET", path, NULL, 404, "not_found", "\"x\"");
    snprintf(path, sizeof path, "/v1/jobs/%s/frames/7", big);
    EXPECT_ERROR(d, "GET", path, NULL, 409, "conflict", "not finished");
    EXPECT_ERROR(d, "GET", "/v1/jobs/jnosuch", NULL, 404, "not_found", "jnosuch");
    EXPECT_ERROR(d, "DELETE", "/v1/jobs/jnosuch", NULL, 404, "not_found", "jnosuch");

    /* DELETE of a finished (here cancelled) job deletes it with its frames. */
    snprintf(path, sizeof path, "/v1/jobs/%s", big);
    CHECK_INT(test_request(d, "DELETE", path, NULL, NULL), 204);
    CHECK_INT(test_request(d, "GET", path, NULL, NULL), 404);
    snprintf(path, sizeof path, "/v1/jobs/%s/frames/0", big);
    CHECK_INT(test_request(d, "GET", path, NULL, NULL), 404);
    CHECK_INT(count_jobs(d, ""), 2);
}

int main(void)
{
    struct test_daemon d;
    const char *const args[] = {"--max-job-frames", "8", "--max-image-pixels", "1000000", NULL};
    if (!test_daemon_start(&d, args))
        test_setup_failed("test_jobs_api", d.why);
    size_t len = 0;
    char *doc = test_read_source_file("proto/examples/glass_sphere.json", &len);
    char a[REFRACT_ID_SIZE] = "", b[REFRACT_ID_SIZE] = "";
    CHECK(doc && test_create_scene(&d, doc, a) && test_create_scene(&d, doc, b));
    free(doc);
    if (a[0] && b[0]) {
        char path[128];
        snprintf(path, sizeof path, "/v1/scenes/%s/lights/sun", a);
        long put = test_request(&d, "PUT", path,
                                "{\"type\": \"directional\", \"direction\": [0, -1, 0]}", NULL);
        CHECK(put == 200 || put == 202);
        bad_specs(&d, a);
        cancel_and_list(&d, a, b);
    }
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_jobs_api");
}
