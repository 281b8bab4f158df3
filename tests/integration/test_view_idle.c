/*
 * test_view_idle.c - a view session that has had no request and no open stream for
 * --view-idle-timeout seconds ends (docs/views.md), here with a 2 s timeout:
 *   - left alone, a session answers 404 not_found after the timeout, and GET /v1/views no
 *     longer lists it;
 *   - requests keep it alive (each one restarts the timeout);
 *   - an open stream keeps it alive however long; the timeout counts from when the server
 *     notices the stream left (at its next frame or keep-alive at the latest), and then
 *     the session ends.
 */
#include "view_util.h"

static long get_status(struct test_daemon *d, const char *vid)
{
    char path[96], *body = NULL;
    snprintf(path, sizeof path, "/v1/views/%s", vid);
    long status = test_request(d, "GET", path, NULL, &body);
    if (status == 404)
        CHECK(test_error_is(body, "not_found", vid));
    free(body);
    return status;
}

static int listed(struct test_daemon *d)
{
    char *body = NULL;
    test_request(d, "GET", "/v1/views", NULL, &body);
    cJSON *root = body ? cJSON_Parse(body) : NULL;
    int n = cJSON_GetArraySize(cJSON_GetObjectItem(root, "views"));
    cJSON_Delete(root);
    free(body);
    return n;
}

int main(void)
{
    const char *const args[] = {"--view-idle-timeout", "2", NULL};
    struct test_daemon d;
    if (!test_daemon_start(&d, args))
        test_setup_failed("test_view_idle", d.why);
    char scene[REFRACT_ID_SIZE], alone[32], kept[32], watched[32];
    CHECK(test_create_scene(&d, view_sphere_scene, scene));
    cJSON *st = NULL;
    CHECK_INT(view_open(&d, scene, "{\"width\": 32, \"height\": 24}", alone, &st), 201);
    const cJSON *timeout = cJSON_GetObjectItemCaseSensitive(st, "idle_timeout_s");
    CHECK(cJSON_IsNumber(timeout) && timeout->valuedouble == 2);
    cJSON_Delete(st);
    CHECK_INT(view_open(&d, scene, "{\"width\": 32, \"height\": 24}", kept, NULL), 201);
    CHECK_INT(view_open(&d, scene, "{\"width\": 32, \"height\": 24}", watched, NULL), 201);
    struct mjpeg_stream s;
    CHECK_INT(mjpeg_open(&d, watched, 0, &s), 200);
    struct mjpeg_frame f;
    CHECK_INT(mjpeg_next(&s, &f, 30000), 1);
    free(f.jpeg);

    /* 3.5 s: `kept` gets a request every 0.5 s, `watched` has its stream open. */
    for (int i = 0; i < 7; i++) {
        view_sleep_ms(500);
        CHECK_INT(get_status(&d, kept), 200);
    }
    CHECK_INT(get_status(&d, alone), 404);
    CHECK_INT(get_status(&d, watched), 200);
    CHECK_INT(listed(&d), 2);

    /* The stream leaves; the timeout runs from when the server notices, which for a
     * sleeping stream is its next frame or keep-alive (the newest frame again, 15 s after
     * the last), and the session ends. */
    mjpeg_abort(&s);
    view_sleep_ms(1000);
    CHECK_INT(listed(&d), 2); /* `kept` and `watched`: not yet */
    bool ended = false;
    double until = view_now_ms() + 25000;
    while (!ended && view_now_ms() < until) {
        view_sleep_ms(250);
        char *body = NULL;
        test_request(&d, "GET", "/v1/views", NULL, &body); /* lists without touching */
        ended = body != NULL && strstr(body, watched) == NULL;
        free(body);
    }
    CHECK_MSG(ended, "%s still listed 25 s after its stream left", watched);
    CHECK_INT(get_status(&d, watched), 404);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_view_idle");
}
