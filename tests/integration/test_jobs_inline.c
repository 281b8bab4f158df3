/*
 * test_jobs_inline.c - batch jobs whose "scene" is a whole scene document (an inline
 * scene): a bad document gets exactly the error POST /v1/scenes gives it (same status,
 * code and message, the path prefixed with "scene."), a document that refers to uploads is
 * refused naming the field, the job's status reports "scene": null and "inline_scene": true,
 * no scene is installed, each frame equals the same frame of a job on a stored scene with
 * the same document (byte for byte: renders are deterministic; also for a scene whose
 * light needs the light simulation, which the inline job waits for), and a kill -9 while an
 * inline-scene job renders is survived like a scene-id job: it resumes after the restart
 * and finishes with every frame exactly once and in its place.
 */
#include <signal.h>
#include <sys/wait.h>

#include "expect.h"
#include "jobs_util.h"

#define OBJ                                                                                        \
    "{\"name\": \"s\", \"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": "  \
    "16, "

/* The answer of POST path with body: status, error code and message (new strings). */
static long post_error(struct test_daemon *d, const char *path, const char *body, char **code,
                       char **msg)
{
    char *reply = NULL;
    long status = test_request(d, "POST", path, body, &reply);
    cJSON *root = reply ? cJSON_Parse(reply) : NULL;
    const cJSON *err = cJSON_GetObjectItemCaseSensitive(root, "error");
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(err, "code");
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(err, "message");
    *code = strdup(cJSON_IsString(c) ? c->valuestring : "");
    *msg = strdup(cJSON_IsString(m) ? m->valuestring : "");
    cJSON_Delete(root);
    free(reply);
    return status;
}

/* A document POST /v1/scenes refuses is refused the same way inline. */
static void same_error_as_scenes(struct test_daemon *d, int line, const char *doc)
{
    char *scode = NULL, *smsg = NULL, *jcode = NULL, *jmsg = NULL;
    section_cases++;
    long sstatus = post_error(d, "/v1/scenes", doc, &scode, &smsg);
    size_t size = strlen(doc) + 128;
    char *job = malloc(size);
    snprintf(job, size, "{\"scene\": %s, \"turntable\": {\"frames\": 2}}", doc);
    long jstatus = post_error(d, "/v1/jobs", job, &jcode, &jmsg);
    char want[1024];
    if (strncmp(smsg, "(root)", 6) == 0)
        snprintf(want, sizeof want, "scene%s", smsg + 6);
    else
        snprintf(want, sizeof want, "scene.%s", smsg);
    CHECK_MSG(sstatus >= 400 && sstatus < 500 && scode[0], "line %d: POST /v1/scenes took it",
              line);
    CHECK_MSG(jstatus == sstatus && strcmp(jcode, scode) == 0 && strcmp(jmsg, want) == 0,
              "line %d: the job got %ld %s \"%s\"; POST /v1/scenes %ld %s \"%s\"", line, jstatus,
              jcode, jmsg, sstatus, scode, smsg);
    free(job);
    free(scode);
    free(smsg);
    free(jcode);
    free(jmsg);
}

static void bad_inline(struct test_daemon *d)
{
    section("inline scene: the scene parser's errors");
    same_error_as_scenes(d, __LINE__,
                         "{\"objects\": [" OBJ "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, "
                         "\"inside\": 1.5}, \"resolution\": 5000}]}");
    same_error_as_scenes(d, __LINE__,
                         "{\"colour\": 1, \"objects\": [" OBJ "\"ior\": {\"shape\": \"sphere\", "
                         "\"radius\": 0.8, \"inside\": 1.5}}]}");
    same_error_as_scenes(d, __LINE__,
                         "{\"camera\": {\"width\": 0}, \"objects\": [" OBJ
                         "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}}]}");
    same_error_as_scenes(
        d, __LINE__, "{\"objects\": [" OBJ "\"ior\": {\"shape\": \"torus\", \"inside\": 1.5}}]}");

    section("inline scene: uploads and types");
    const struct json_error_case cases[] = {
        {__LINE__,
         "{\"scene\": {\"objects\": [" OBJ "\"ior\": {\"volume\": \"ct\"}}]}, \"turntable\": "
         "{\"frames\": 2}}",
         400,
         "invalid_field",
         {"scene.objects[0].ior", "uploaded volume \"ct\"", "scene id"}},
        {__LINE__,
         "{\"scene\": {\"objects\": [" OBJ "\"ior\": {\"shape\": \"mesh\", \"mesh\": \"gem\", "
         "\"inside\": 1.5}}]}, \"turntable\": {\"frames\": 2}}",
         400,
         "invalid_field",
         {"scene.objects[0].ior", "uploaded mesh \"gem\"", "scene id"}},
        {__LINE__,
         "{\"scene\": {\"environment\": {\"type\": \"image\"}, \"objects\": [" OBJ
         "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}}]}, \"turntable\": "
         "{\"frames\": 2}}",
         400,
         "invalid_field",
         {"scene.environment.type", "environment image", "scene id"}},
        {__LINE__,
         "{\"scene\": 7, \"turntable\": {\"frames\": 2}}",
         400,
         "invalid_field",
         {"scene", "scene id", "scene document"}},
        {__LINE__,
         "{\"scene\": {\"objects\": [" OBJ "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, "
         "\"inside\": 1.5}}]}, \"turntable\": {\"frames\": 2}, \"fps\": 3}",
         400,
         "unknown_field",
         {"fps"}},
    };
    EXPECT_JSON_ERROR_CASES(d, "POST", "/v1/jobs", cases);
    section("");
    char *body = NULL;
    CHECK_INT(test_request(d, "GET", "/v1/jobs", NULL, &body), 200);
    CHECK_CONTAINS(body, "\"jobs\":[]"); /* no refused job was made */
    free(body);
}

/* {"scene": <doc or "id">, <rest>} as a new string. */
static char *job_spec(const char *scene, bool quoted, const char *rest)
{
    size_t size = strlen(scene) + strlen(rest) + 64;
    char *s = malloc(size);
    snprintf(s, size, "{\"scene\": %s%s%s, %s}", quoted ? "\"" : "", scene, quoted ? "\"" : "",
             rest);
    return s;
}

static void same_frames(struct test_daemon *d, const char *a, const char *b, int frames)
{
    for (int n = 0; n < frames; n++) {
        size_t la = 0, lb = 0;
        void *x = job_frame_bytes(d, a, n, &la, NULL, 0);
        void *y = job_frame_bytes(d, b, n, &lb, NULL, 0);
        CHECK_MSG(x && y && la == lb && memcmp(x, y, la) == 0,
                  "frame %d of inline job %s differs from scene job %s's", n, a, b);
        free(x);
        free(y);
    }
}

static int scene_count(struct test_daemon *d)
{
    char *body = NULL;
    long status = test_request(d, "GET", "/v1/scenes", NULL, &body);
    cJSON *root = status == 200 && body ? cJSON_Parse(body) : NULL;
    int n = cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "scenes"));
    cJSON_Delete(root);
    free(body);
    return status == 200 ? n : -1;
}

/* An inline job renders what a job on the stored scene renders, and installs nothing. */
static void inline_equals_stored(struct test_daemon *d, const char *doc, const char *scene)
{
    const char *rest = "\"width\": 24, \"height\": 18, \"turntable\": {\"frames\": 3}";
    char *inl = job_spec(doc, false, rest), *stored = job_spec(scene, true, rest);
    char a[64] = "", b[64] = "";
    CHECK(job_submit_json(d, inl, a) && job_submit_json(d, stored, b));
    cJSON *st = job_wait(d, a, 120);
    CHECK_STR(job_str(st, "state"), "done");
    CHECK_INT(job_int(st, "frames_done"), 3);
    CHECK(cJSON_IsNull(cJSON_GetObjectItemCaseSensitive(st, "scene")));
    CHECK(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(st, "inline_scene")));
    cJSON_Delete(st);
    st = job_wait(d, b, 120);
    CHECK_STR(job_str(st, "state"), "done");
    CHECK_STR(job_str(st, "scene"), scene);
    CHECK(cJSON_IsFalse(cJSON_GetObjectItemCaseSensitive(st, "inline_scene")));
    cJSON_Delete(st);
    same_frames(d, a, b, 3);
    CHECK_INT(scene_count(d), 1); /* the inline scene was never installed */
    char q[160], *body = NULL;
    snprintf(q, sizeof q, "/v1/jobs?scene=%s", scene);
    CHECK_INT(test_request(d, "GET", q, NULL, &body), 200);
    CHECK_MSG(body && strstr(body, b) && !strstr(body, a), "?scene= lists %s", body);
    free(body);
    free(inl);
    free(stored);
}

/* An inline scene whose spot light needs the light simulation: the job waits for the
 * volume on its own cache slot, and its frames equal those of the stored scene's job. */
static void inline_lit(struct test_daemon *d)
{
    /* smoke_spot.json on coarse grids, so that its light simulation takes little time. */
    static const char doc[] =
        "{\"name\": \"small smoke spot\", \"camera\": {\"eye\": [0, 0.8, 4.2], \"look_at\": "
        "[0, 0, 0], \"fov_y_deg\": 40}, \"environment\": {\"intensity\": 0.12}, \"lights\": "
        "[{\"name\": \"spot\", \"type\": \"spot\", \"position\": [0, 3, 0], \"direction\": "
        "[0, -1, 0], \"angle_deg\": 12, \"intensity\": 40}], \"lightsim\": {\"resolution\": "
        "16, \"initial_patches\": 16, \"max_level\": 2}, \"objects\": [" OBJ
        "\"ior\": {\"shape\": \"sphere\", \"center\": [0, 0.4, 0], \"radius\": 0.4, "
        "\"inside\": 1.5}, \"scattering\": [0.3, {\"shape\": \"sphere\", \"center\": [0, "
        "0.4, 0], \"radius\": 0.4, \"inside\": 0}], \"anisotropy\": 0.3}]}";
    char scene[REFRACT_ID_SIZE] = "", a[64] = "", b[64] = "";
    CHECK(test_create_scene(d, doc, scene));
    const char *rest = "\"width\": 24, \"height\": 18, \"turntable\": {\"frames\": 2}";
    char *inl = job_spec(doc, false, rest), *stored = job_spec(scene, true, rest);
    CHECK(job_submit_json(d, inl, a));
    cJSON *st = job_wait(d, a, 120);
    CHECK_STR(job_str(st, "state"), "done");
    cJSON_Delete(st);
    CHECK(job_submit_json(d, stored, b));
    st = job_wait(d, b, 120);
    CHECK_STR(job_str(st, "state"), "done");
    cJSON_Delete(st);
    same_frames(d, a, b, 2);
    free(inl);
    free(stored);
}

static void kill9(struct test_daemon *d)
{
    refract_client_destroy(d->client);
    d->client = NULL;
    kill(d->pid, SIGKILL);
    int status;
    waitpid(d->pid, &status, 0);
    d->pid = 0;
}

#define FRAMES 10

/* kill -9 while an inline job renders; after the restart it resumes and finishes. */
static void survives_kill(struct test_daemon *d, const char *doc, const char *scene)
{
    const char *rest = "\"width\": 48, \"height\": 36, \"turntable\": {\"frames\": 10}";
    char *inl = job_spec(doc, false, rest), *stored = job_spec(scene, true, rest);
    char id[64] = "", ref[64] = "";
    CHECK(job_submit_json(d, inl, id));
    int before = -1;
    for (int i = 0; i < 6000 && before < 2; i++) {
        cJSON *st = job_status_get(d, id);
        before = st ? job_int(st, "frames_done") : -1;
        cJSON_Delete(st);
        if (before < 2)
            job_sleep_ms(10);
    }
    CHECK_MSG(before >= 2 && before < FRAMES, "frames_done %d when killed", before);
    kill9(d);
    struct test_daemon d2;
    if (!test_daemon_start_in(&d2, d->data_dir, NULL))
        test_setup_failed("test_jobs_inline (restart)", d2.why);
    cJSON *st = job_wait(&d2, id, 180);
    CHECK_STR(job_str(st, "state"), "done");
    CHECK_INT(job_int(st, "frames_done"), FRAMES);
    CHECK(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(st, "inline_scene")));
    CHECK(job_int(st, "frames_done") >= before);
    cJSON_Delete(st);
    FILE *log = fopen(d2.log_path, "r");
    char line[1024];
    bool resumed = false;
    while (log && fgets(line, sizeof line, log))
        resumed |= strstr(line, id) && strstr(line, "resumes at frame");
    if (log)
        fclose(log);
    CHECK(resumed);
    CHECK(job_submit_json(&d2, stored, ref));
    st = job_wait(&d2, ref, 180);
    CHECK_STR(job_str(st, "state"), "done");
    cJSON_Delete(st);
    same_frames(&d2, id, ref, FRAMES);
    char path[128];
    snprintf(path, sizeof path, "/v1/jobs/%s/frames/%d", id, FRAMES);
    CHECK_INT(test_request(&d2, "GET", path, NULL, NULL), 404);
    CHECK_INT(scene_count(&d2), 2); /* the two stored scenes; no inline one */
    CHECK_INT(test_daemon_stop(&d2), 0);
    test_daemon_cleanup(&d2);
    free(inl);
    free(stored);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_jobs_inline", d.why);
    size_t len = 0;
    char *doc = test_read_source_file("proto/examples/glass_sphere.json", &len);
    char scene[REFRACT_ID_SIZE] = "";
    if (!doc || !test_create_scene(&d, doc, scene))
        test_setup_failed("test_jobs_inline", "could not create the scene");
    bad_inline(&d);
    inline_equals_stored(&d, doc, scene);
    inline_lit(&d);
    survives_kill(&d, doc, scene);
    free(doc);
    test_daemon_cleanup(&d);
    return test_summary("test_jobs_inline");
}
