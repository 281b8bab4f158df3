/*
 * test_client_view.c - librefract's view sessions, frame streams and events against a
 * real refractd (docs/views.md):
 *   - refract_view_create_opts makes a session of the asked size; refract_view_stream
 *     delivers three frames while the test PATCHes the camera between them (from the
 *     frame callback, through a second client): each a JPEG that decodes to that size,
 *     with growing seqs, the headers read, and pixels that change with the camera;
 *   - refract_view_status reads the newest frame, the renderer and the stream count;
 *     refract_view_list lists the session;
 *   - a DELETE during the stream ends it cleanly; the session then answers not_found,
 *     and so does its stream; a missing scene gives scene_not_found; a PATCH with a typo
 *     gives refractd's unknown_field with its message;
 *   - refract_events: a scene's history from since 0 (scene.created), and a live
 *     scene.updated (what = lights) while a thread reads the stream.
 */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "daemon.h"
#include "io/io_image.h"
#include "test.h"

#define W 80
#define H 60

static const char scene_json[] =
    "{\"name\": \"client view ball\", \"camera\": {\"eye\": [0, 0.5, 4], \"look_at\": [0, 0, 0],"
    " \"width\": 32, \"height\": 24},"
    " \"objects\": [{\"bounds\": {\"min\": [-0.5, -0.5, -0.5], \"max\": [0.5, 0.5, 0.5]},"
    "   \"resolution\": 16, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.45, \"inside\": 1.5},"
    "   \"attenuation\": {\"shape\": \"sphere\", \"radius\": 0.45, \"inside\": [0.5, 1.5, 3.0]}}]}";

struct three_frames {
    refract_client *patcher; /* PATCHes while the stream's client reads */
    const char *view_id;
    long count;
    long long seq[3];
    char kind[3][16];
    double render_ms[3];
    char irradiance[3][32];
    double arrival_ms[3];
    struct io_image image[3];
    int patch_code;
};

static int keep_three(const struct refract_frame *f, void *user)
{
    static const char *const eyes[] = {"{\"camera\": {\"eye\": [1.5, 0.5, 3.5]}}",
                                       "{\"camera\": {\"eye\": [-2, 1, 3]}}"};
    struct three_frames *t = user;
    struct err e = {0};
    long i = t->count;

    if (i >= 3)
        return 1;
    t->seq[i] = f->seq;
    snprintf(t->kind[i], sizeof(t->kind[i]), "%s", f->kind);
    t->render_ms[i] = f->render_ms;
    snprintf(t->irradiance[i], sizeof(t->irradiance[i]), "%s", f->irradiance);
    t->arrival_ms[i] = f->arrival_ms;
    CHECK_STR(f->content_type, "image/jpeg");
    CHECK_INT(io_image_decode(f->bytes, f->len, 1 << 24, &t->image[i], &e), REFRACT_E_OK);
    t->count++;
    if (t->count == 3)
        return 1;
    t->patch_code = refract_view_patch(t->patcher, t->view_id, eyes[i], NULL);
    return t->patch_code != REFRACT_E_OK;
}

static double mean_abs_difference(const struct io_image *a, const struct io_image *b)
{
    double sum = 0;
    size_t n = (size_t)a->width * (size_t)a->height * 4;

    if (a->rgba == NULL || b->rgba == NULL || a->width != b->width || a->height != b->height)
        return -1;
    for (size_t i = 0; i < n; i++)
        sum += fabs(a->rgba[i] - b->rgba[i]);
    return sum / (double)n;
}

static void three_frames_follow_three_cameras(struct test_daemon *d, refract_client *patcher,
                                              const char *scene)
{
    struct refract_view_options o = {.width = W, .height = H, .progressive = -1};
    struct refract_view v;
    struct refract_view st;
    struct three_frames t = {.patcher = patcher};
    char *list = NULL;

    CHECK_INT(refract_view_create_opts(d->client, scene, &o, &v), REFRACT_E_OK);
    CHECK_INT(strlen(v.id), 17);
    CHECK(v.id[0] == 'v' && strspn(v.id + 1, "0123456789abcdef") == 16);
    CHECK_STR(v.scene, scene);
    CHECK_INT(v.width, W);
    CHECK_INT(v.height, H);
    CHECK_CONTAINS(v.json, "\"progressive\":false");
    CHECK_CONTAINS(v.stream, v.id);
    t.view_id = v.id;

    CHECK_INT(refract_view_stream(d->client, v.id, keep_three, &t), REFRACT_E_OK);
    CHECK_INT(t.patch_code, REFRACT_E_OK);
    CHECK_INT(t.count, 3);
    for (int i = 0; i < 3 && t.count == 3; i++) {
        CHECK_INT(t.image[i].width, W);
        CHECK_INT(t.image[i].height, H);
        CHECK_STR(t.kind[i], "full");
        CHECK(t.render_ms[i] > 0);
        CHECK_STR(t.irradiance[i], "not-needed");
        if (i > 0) {
            CHECK_MSG(t.seq[i] > t.seq[i - 1], "seq %lld after %lld", t.seq[i], t.seq[i - 1]);
            CHECK(t.arrival_ms[i] >= t.arrival_ms[i - 1]);
            /* Another camera, other pixels: the frame is new, not the old one again. */
            CHECK_MSG(mean_abs_difference(&t.image[i], &t.image[i - 1]) > 1e-3,
                      "frames %d and %d differ by %g", i - 1, i,
                      mean_abs_difference(&t.image[i], &t.image[i - 1]));
        }
    }

    CHECK_INT(refract_view_status(d->client, v.id, &st), REFRACT_E_OK);
    CHECK_INT(st.has_frame, 1);
    CHECK_INT(st.frame.seq, t.seq[2]);
    CHECK_INT(st.frame.width, W);
    CHECK(st.frame.bytes > 0);
    CHECK(st.renderer[0] != '\0');
    CHECK_CONTAINS(st.json, "[-2,1,3]"); /* the last PATCH's eye */
    refract_view_free(&st);
    CHECK_INT(refract_view_list(d->client, &list), REFRACT_E_OK);
    CHECK_CONTAINS(list, v.id);
    refract_free(list);
    CHECK_INT(refract_view_delete(d->client, v.id), REFRACT_E_OK);
    for (int i = 0; i < 3; i++)
        io_image_free(&t.image[i]);
    refract_view_free(&v);
}

struct delete_during {
    refract_client *patcher;
    const char *view_id;
    long frames;
    int delete_code;
};

static int delete_after_first(const struct refract_frame *f, void *user)
{
    struct delete_during *dd = user;

    (void)f;
    if (dd->frames++ == 0)
        dd->delete_code = refract_view_delete(dd->patcher, dd->view_id);
    return 0; /* go on: the stream must end by itself */
}

static void a_deleted_session_ends_its_stream_and_is_gone(struct test_daemon *d,
                                                          refract_client *patcher,
                                                          const char *scene)
{
    struct refract_view v;
    struct refract_view st;
    struct delete_during dd = {.patcher = patcher};

    CHECK_INT(refract_view_create(d->client, scene, "{\"width\": 40, \"height\": 30}", &v),
              REFRACT_E_OK);
    dd.view_id = v.id;
    CHECK_INT(refract_view_stream(d->client, v.id, delete_after_first, &dd), REFRACT_E_OK);
    CHECK_INT(dd.delete_code, REFRACT_E_OK);
    CHECK(dd.frames >= 1);
    CHECK_INT(refract_view_status(d->client, v.id, &st), REFRACT_E_NOT_FOUND);
    CHECK(refract_errmsg(d->client)[0] != '\0');
    CHECK_INT(refract_view_stream(d->client, v.id, delete_after_first, &dd), REFRACT_E_NOT_FOUND);
    CHECK_INT(refract_view_patch(d->client, v.id, "{\"width\": 50}", NULL), REFRACT_E_NOT_FOUND);
    refract_view_free(&v);
}

static void bad_requests_get_refractds_codes(struct test_daemon *d, const char *scene)
{
    struct refract_view v;

    CHECK_INT(refract_view_create(d->client, "no_such_scene", NULL, &v), REFRACT_E_SCENE_NOT_FOUND);
    CHECK_CONTAINS(refract_errmsg(d->client), "no_such_scene");
    CHECK_INT(refract_view_create(d->client, scene, "{\"widht\": 64}", &v),
              REFRACT_E_UNKNOWN_FIELD);
    CHECK_CONTAINS(refract_errmsg(d->client), "widht");
    CHECK_INT(refract_view_create(d->client, scene, NULL, &v), REFRACT_E_OK);
    CHECK_INT(refract_view_patch(d->client, v.id, "{\"camera\": {\"eyes\": [0, 0, 1]}}", NULL),
              REFRACT_E_UNKNOWN_FIELD);
    CHECK_CONTAINS(refract_errmsg(d->client), "eyes");
    CHECK_INT(refract_view_delete(d->client, v.id), REFRACT_E_OK);
    refract_view_free(&v);
    CHECK_INT(refract_view_create(d->client, "", NULL, &v), REFRACT_E_USAGE);
    CHECK_INT(refract_view_patch(d->client, NULL, "{}", NULL), REFRACT_E_USAGE);
    CHECK_INT(refract_view_status(d->client, "v0", NULL), REFRACT_E_USAGE);
}

struct event_wait {
    struct test_daemon *d;
    const char *scene;
    const char *want_type;
    char data[1024];
    char id[64];
    int code;
    volatile int done;
};

static int until_type(const struct refract_event *ev, void *user)
{
    struct event_wait *w = user;

    if (strcmp(ev->type, w->want_type) != 0)
        return 0;
    snprintf(w->data, sizeof(w->data), "%s", ev->data);
    snprintf(w->id, sizeof(w->id), "%s", ev->id);
    return 1;
}

static void *read_events(void *arg)
{
    struct event_wait *w = arg;
    refract_client *c = refract_client_create(w->d->url);

    refract_set_timeout_ms(c, 30000);
    w->code = refract_events(c, w->scene, NULL, until_type, w);
    refract_client_destroy(c);
    w->done = 1;
    return NULL;
}

static void events_come_from_history_and_live(struct test_daemon *d, const char *scene)
{
    struct event_wait history = {.d = d, .scene = scene, .want_type = "scene.created"};
    struct event_wait live = {.d = d, .scene = scene, .want_type = "scene.updated"};
    pthread_t thread;
    char light[128];

    CHECK_INT(refract_events(d->client, scene, "0", until_type, &history), REFRACT_E_OK);
    CHECK_CONTAINS(history.data, scene);
    CHECK(atoi(history.id) >= 1);

    /* Live: the reader may connect after any change, so changes go on until it saw one. */
    pthread_create(&thread, NULL, read_events, &live);
    for (int i = 0; i < 100 && !live.done; i++) {
        struct timespec ts = {0, 200 * 1000000L};

        snprintf(light, sizeof(light),
                 "{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0.%d, -1, 0]}",
                 i % 10);
        CHECK_INT(refract_light_put(d->client, scene, "sun", light, NULL), REFRACT_E_OK);
        nanosleep(&ts, NULL);
    }
    pthread_join(thread, NULL);
    CHECK_INT(live.code, REFRACT_E_OK);
    CHECK_CONTAINS(live.data, "\"what\":\"lights\"");
    CHECK(atoi(live.id) > atoi(history.id));
    CHECK_INT(refract_events(d->client, "no_such_scene", NULL, until_type, &live),
              REFRACT_E_SCENE_NOT_FOUND);
}

int main(void)
{
    struct test_daemon d;
    char scene[REFRACT_ID_SIZE];
    refract_client *patcher;

    if (getenv("REFRACTD") == NULL)
        test_skip("test_client_view", "REFRACTD is not set (run it through ctest)");
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_client_view", d.why);
    patcher = refract_client_create(d.url);
    CHECK(test_create_scene(&d, scene_json, scene));
    three_frames_follow_three_cameras(&d, patcher, scene);
    a_deleted_session_ends_its_stream_and_is_gone(&d, patcher, scene);
    bad_requests_get_refractds_codes(&d, scene);
    events_come_from_history_and_live(&d, scene);
    refract_client_destroy(patcher);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_client_view");
}
