/*
 * test_view_bad_input.c - every way a view session request can be wrong gets its exact
 * error (status, error.code, the path or the flag in the message), and a refused PATCH
 * changes nothing (docs/views.md, docs/api.md "Errors"):
 *   - POST /v1/scenes/{id}/views and PATCH /v1/views/{vid}: invalid JSON, unknown fields
 *     (root and camera), wrong types and ranges of every field, a degenerate camera,
 *     image limits (--max-image-dim, --max-image-pixels, --max-steps);
 *   - an unknown scene (404 scene_not_found), an unknown view id on every view route
 *     (404 not_found naming the id), methods the routes do not have (405);
 *   - the stream's query: frames out of range or not a number, an unknown parameter;
 *   - more sessions than --max-views (422 limit_exceeded naming the flag);
 *   - the view status echoes what was set, and the quality presets act on the scene's
 *     render settings with explicit fields winning.
 */
#include "expect.h"
#include "view_util.h"

static const struct json_error_case body_cases[] = {
    {__LINE__, "{", 400, "invalid_json", {"byte"}},
    {__LINE__, "[1]", 400, "invalid_field", {"object"}},
    {__LINE__, "{\"fps\": 10}", 400, "unknown_field", {"fps", "max_fps"}},
    {__LINE__, "{\"camera\": {\"fov\": 30}}", 400, "unknown_field", {"camera", "fov_y_deg"}},
    {__LINE__, "{\"camera\": 3}", 400, "invalid_field", {"camera"}},
    {__LINE__, "{\"camera\": {\"eye\": [0, 0]}}", 400, "invalid_field", {"camera.eye"}},
    {__LINE__, "{\"camera\": {\"eye\": [0, 0, 0]}}", 400, "invalid_field", {"look_at"}},
    {__LINE__, "{\"camera\": {\"up\": [0, 0, 1]}}", 400, "invalid_field", {"camera.up"}},
    {__LINE__, "{\"camera\": {\"fov_y_deg\": 180}}", 400, "invalid_field", {"fov_y_deg"}},
    {__LINE__, "{\"width\": 0}", 400, "invalid_field", {"width"}},
    {__LINE__, "{\"height\": 2.5}", 400, "invalid_field", {"height"}},
    {__LINE__, "{\"width\": 5000}", 422, "limit_exceeded", {"width", "--max-image-dim"}},
    {__LINE__,
     "{\"width\": 1000, \"height\": 1000}",
     422,
     "limit_exceeded",
     {"--max-image-pixels"}},
    {__LINE__, "{\"exposure\": 30}", 400, "invalid_field", {"exposure"}},
    {__LINE__, "{\"tonemap\": \"aces\"}", 400, "invalid_field", {"tonemap", "filmic"}},
    {__LINE__, "{\"quality\": \"ultra\"}", 400, "invalid_field", {"quality", "draft"}},
    {__LINE__, "{\"stepper\": \"rk45\"}", 400, "invalid_field", {"stepper", "rk4"}},
    {__LINE__, "{\"step\": 0}", 400, "invalid_field", {"step"}},
    {__LINE__, "{\"max_steps\": 0}", 400, "invalid_field", {"max_steps"}},
    {__LINE__, "{\"max_steps\": 200000}", 422, "limit_exceeded", {"max_steps", "--max-steps"}},
    {__LINE__, "{\"boundary_threshold\": -1}", 400, "invalid_field", {"boundary_threshold"}},
    {__LINE__, "{\"jpeg_quality\": 101}", 400, "invalid_field", {"jpeg_quality"}},
    {__LINE__, "{\"max_fps\": 0}", 400, "invalid_field", {"max_fps", "0.1"}},
    {__LINE__, "{\"max_fps\": 500}", 400, "invalid_field", {"max_fps", "120"}},
    {__LINE__, "{\"progressive\": \"yes\"}", 400, "invalid_field", {"progressive"}},
};

static double number(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : -1;
}

static const char *string(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsString(v) ? v->valuestring : "";
}

/* The scene's render block is step 1.0 (view_sphere_scene) with the default stepper. */
static void status_echoes_settings(struct test_daemon *d, const char *scene)
{
    char vid[32];
    cJSON *st = NULL;
    CHECK_INT(view_open(d, scene,
                        "{\"quality\": \"draft\", \"width\": 32, \"height\": 24, "
                        "\"jpeg_quality\": 55, \"max_fps\": 12.5, \"tonemap\": \"filmic\", "
                        "\"exposure\": -1, \"camera\": {\"fov_y_deg\": 30}}",
                        vid, &st),
              201);
    CHECK(strcmp(string(st, "quality"), "draft") == 0);
    CHECK(strcmp(string(st, "stepper"), "euler") == 0);
    CHECK_NEAR(number(st, "step"), 2.0, 1e-12); /* draft doubles the scene's 1.0 */
    CHECK_INT((int)number(st, "width"), 32);
    CHECK_INT((int)number(st, "jpeg_quality"), 55);
    CHECK_NEAR(number(st, "max_fps"), 12.5, 1e-12);
    CHECK(strcmp(string(st, "tonemap"), "filmic") == 0);
    CHECK_NEAR(number(st, "exposure"), -1, 1e-12);
    CHECK_NEAR(number(cJSON_GetObjectItem(st, "camera"), "fov_y_deg"), 30, 1e-12);
    CHECK(cJSON_IsNull(cJSON_GetObjectItem(st, "frame")) ||
          cJSON_IsObject(cJSON_GetObjectItem(st, "frame")));
    char stream[96];
    snprintf(stream, sizeof stream, "/v1/views/%s/stream", vid);
    CHECK(strcmp(string(st, "stream"), stream) == 0);
    CHECK(strstr(string(st, "viewer"), vid) != NULL);
    CHECK(string(st, "renderer")[0] != '\0');
    cJSON_Delete(st);

    /* An explicit step wins over the preset; "final" halves and uses rk4. */
    char path[96], *body = NULL;
    snprintf(path, sizeof path, "/v1/views/%s", vid);
    body = EXPECT_STATUS(d, "PATCH", path, "{\"step\": 0.75}", 200);
    st = body ? cJSON_Parse(body) : NULL;
    CHECK_NEAR(number(st, "step"), 0.75, 1e-12);
    CHECK(strcmp(string(st, "stepper"), "euler") == 0);
    cJSON_Delete(st);
    free(body);
    body = EXPECT_STATUS(d, "PATCH", path, "{\"quality\": \"final\"}", 200);
    st = body ? cJSON_Parse(body) : NULL;
    CHECK_NEAR(number(st, "step"), 0.5, 1e-12);
    CHECK(strcmp(string(st, "stepper"), "rk4") == 0);
    CHECK_INT((int)number(st, "width"), 32); /* what the PATCH does not name stays */
    cJSON_Delete(st);
    free(body);
    /* Every stepper is reported as set (a two-entry copy of the words once said "euler"
     * for rk2 and adaptive). */
    const char *const steppers[] = {"rk2", "adaptive", "euler", "rk4"};
    for (int k = 0; k < 4; k++) {
        char patch[64];
        snprintf(patch, sizeof patch, "{\"stepper\": \"%s\"}", steppers[k]);
        body = EXPECT_STATUS(d, "PATCH", path, patch, 200);
        st = body ? cJSON_Parse(body) : NULL;
        CHECK_MSG(st != NULL && strcmp(string(st, "stepper"), steppers[k]) == 0,
                  "set %s, status says %s", steppers[k], st ? string(st, "stepper") : "?");
        cJSON_Delete(st);
        free(body);
    }

    /* renamed: the stepper's old key sets it too; both together are refused. */
    body = EXPECT_STATUS(d, "PATCH", path, "{\"integrator\": \"rk2\"}", 200); /* renamed: */
    st = body ? cJSON_Parse(body) : NULL;
    CHECK(st != NULL && strcmp(string(st, "stepper"), "rk2") == 0);
    cJSON_Delete(st);
    free(body);
    EXPECT_ERROR(d, "PATCH", path, "{\"stepper\": \"rk4\", \"integrator\": \"rk2\"}", /* renamed: */
                 400, "invalid_field", "old name of \"stepper\"");

    /* A refused PATCH changes nothing. */
    EXPECT_ERROR(d, "PATCH", path, "{\"width\": 40, \"max_fps\": 0}", 400, "invalid_field",
                 "max_fps");
    st = view_status(d, vid);
    CHECK_INT((int)number(st, "width"), 32);
    cJSON_Delete(st);
    free(EXPECT_STATUS(d, "DELETE", path, NULL, 204));
}

static void unknown_ids(struct test_daemon *d)
{
    section("unknown scene and view ids");
    EXPECT_ERROR(d, "POST", "/v1/scenes/nosuchscene/views", "{}", 404, "scene_not_found",
                 "nosuchscene");
    const char *vid = "v0123456789abcdef";
    EXPECT_ERROR(d, "GET", "/v1/views/v0123456789abcdef", NULL, 404, "not_found", vid,
                 "--view-idle-timeout");
    EXPECT_ERROR(d, "PATCH", "/v1/views/v0123456789abcdef", "{}", 404, "not_found", vid);
    EXPECT_ERROR(d, "DELETE", "/v1/views/v0123456789abcdef", NULL, 404, "not_found", vid);
    EXPECT_ERROR(d, "GET", "/v1/views/v0123456789abcdef/stream", NULL, 404, "not_found", vid);
    EXPECT_ERROR(d, "PUT", "/v1/views/v0123456789abcdef", "{}", 405, "method_not_allowed", "PATCH");
    EXPECT_ERROR(d, "POST", "/v1/views", "{}", 405, "method_not_allowed", "GET");
}

static void stream_queries(struct test_daemon *d, const char *scene)
{
    section("GET /v1/views/{vid}/stream?...");
    char vid[32], path[128];
    CHECK_INT(view_open(d, scene, "{\"width\": 16, \"height\": 12}", vid, NULL), 201);
    snprintf(path, sizeof path, "/v1/views/%s/stream?frames=0", vid);
    EXPECT_ERROR(d, "GET", path, NULL, 400, "invalid_field", "frames", "1..1000000");
    snprintf(path, sizeof path, "/v1/views/%s/stream?frames=two", vid);
    EXPECT_ERROR(d, "GET", path, NULL, 400, "invalid_field", "frames", "two");
    snprintf(path, sizeof path, "/v1/views/%s/stream?frame=1", vid);
    EXPECT_ERROR(d, "GET", path, NULL, 400, "unknown_field", "frame", "allowed: frames");
    snprintf(path, sizeof path, "/v1/views/%s", vid);
    free(EXPECT_STATUS(d, "DELETE", path, NULL, 204));
}

static void too_many_views(struct test_daemon *d, const char *scene)
{
    section("--max-views 3");
    char vids[3][32];
    for (int i = 0; i < 3; i++)
        CHECK_INT(view_open(d, scene, "{\"width\": 16, \"height\": 12}", vids[i], NULL), 201);
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/views", scene);
    EXPECT_ERROR(d, "POST", path, "{}", 422, "limit_exceeded", "--max-views", "3");
    char *list = EXPECT_STATUS(d, "GET", "/v1/views", NULL, 200);
    cJSON *root = list ? cJSON_Parse(list) : NULL;
    CHECK_INT(cJSON_GetArraySize(cJSON_GetObjectItem(root, "views")), 3);
    cJSON_Delete(root);
    free(list);
    snprintf(path, sizeof path, "/v1/views/%s", vids[0]);
    free(EXPECT_STATUS(d, "DELETE", path, NULL, 204));
    CHECK_INT(view_open(d, scene, "{\"width\": 16, \"height\": 12}", vids[0], NULL), 201);
}

int main(void)
{
    const char *const args[] = {"--max-views", "3", "--max-image-pixels", "500000", NULL};
    struct test_daemon d;
    if (!test_daemon_start(&d, args))
        test_setup_failed("test_view_bad_input", d.why);
    char scene[REFRACT_ID_SIZE], vid[32];
    CHECK(test_create_scene(&d, view_sphere_scene, scene));

    char path[128];
    section("POST /v1/scenes/{id}/views");
    snprintf(path, sizeof path, "/v1/scenes/%s/views", scene);
    EXPECT_JSON_ERROR_CASES(&d, "POST", path, body_cases);
    section("PATCH /v1/views/{vid}");
    CHECK_INT(view_open(&d, scene, "{\"width\": 16, \"height\": 12}", vid, NULL), 201);
    snprintf(path, sizeof path, "/v1/views/%s", vid);
    EXPECT_JSON_ERROR_CASES(&d, "PATCH", path, body_cases);
    free(EXPECT_STATUS(&d, "DELETE", path, NULL, 204));
    section("view status");
    status_echoes_settings(&d, scene);
    unknown_ids(&d);
    stream_queries(&d, scene);
    too_many_views(&d, scene);
    section("");
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_view_bad_input");
}
