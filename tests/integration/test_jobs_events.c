/*
 * test_jobs_events.c - a batch job's job.progress events, read through librefract's
 * refract_events from GET /v1/events while the job runs (docs/api.md "Batch jobs" and
 * "Events"): first "queued" (done 0, eta_s null), then "running", then exactly one event
 * per finished frame with done going 1, 2, ... total, total fixed, eta_s a finite number
 * >= 0 from the first finished frame on, and the last frame's event in state "done" with
 * eta_s 0; nothing after "done". The scene's own stream holds the same events; an inline
 * scene's job publishes "scene": null on /v1/events.
 */
#include <math.h>
#include <pthread.h>

#include "jobs_util.h"

#define FRAMES 5
#define MAX_EVENTS 64

struct progress {
    char job[64];
    char scene[64]; /* "(null)" for "scene": null */
    char state[16];
    int done, total;
    bool eta_null;
    double eta;
};

struct collector {
    const char *url;
    const char *scene; /* NULL: /v1/events */
    const char *job;   /* NULL: every job, until `stop_after` done events */
    int stop_after;
    struct progress ev[MAX_EVENTS];
    int count, finished;
    int code;
};

static int on_event(const struct refract_event *ev, void *user)
{
    struct collector *c = user;
    if (strcmp(ev->type, "job.progress") != 0)
        return 0;
    cJSON *o = cJSON_ParseWithLength(ev->data, ev->data_len);
    const cJSON *scene = cJSON_GetObjectItemCaseSensitive(o, "scene");
    const cJSON *eta = cJSON_GetObjectItemCaseSensitive(o, "eta_s");
    struct progress p = {.done = job_int(o, "done"), .total = job_int(o, "total")};
    snprintf(p.job, sizeof p.job, "%s", job_str(o, "job"));
    snprintf(p.scene, sizeof p.scene, "%s", cJSON_IsNull(scene) ? "(null)" : job_str(o, "scene"));
    snprintf(p.state, sizeof p.state, "%s", job_str(o, "state"));
    p.eta_null = cJSON_IsNull(eta);
    p.eta = cJSON_IsNumber(eta) ? eta->valuedouble : NAN;
    cJSON_Delete(o);
    if (c->job && strcmp(p.job, c->job) != 0)
        return 0;
    if (c->count < MAX_EVENTS)
        c->ev[c->count++] = p;
    if (!strcmp(p.state, "done") || !strcmp(p.state, "failed") || !strcmp(p.state, "cancelled"))
        c->finished++;
    return c->finished >= c->stop_after;
}

static void *collect(void *arg)
{
    struct collector *c = arg;
    refract_client *client = refract_client_create(c->url);
    refract_set_timeout_ms(client, 60000);
    /* since 0: the history from the daemon's start, then live; so no event is missed
     * whenever the connection is made. */
    c->code = refract_events(client, c->scene, "0", on_event, c);
    refract_client_destroy(client);
    return NULL;
}

/* The events of job id among c's, in order, checked against the documented sequence. */
static void check_sequence(const struct collector *c, const char *id, const char *scene)
{
    const struct progress *e[MAX_EVENTS];
    int n = 0;
    for (int i = 0; i < c->count; i++) {
        if (strcmp(c->ev[i].job, id) == 0)
            e[n++] = &c->ev[i];
    }
    CHECK_MSG(n == FRAMES + 2,
              "job %s: %d job.progress events, expected %d (queued, running, "
              "one per frame)",
              id, n, FRAMES + 2);
    if (n < 2)
        return;
    CHECK_STR(e[0]->state, "queued");
    CHECK_INT(e[0]->done, 0);
    CHECK(e[0]->eta_null);
    CHECK_STR(e[1]->state, "running");
    CHECK_INT(e[1]->done, 0);
    for (int i = 0; i < n; i++) {
        CHECK_STR(e[i]->scene, scene);
        CHECK_INT(e[i]->total, FRAMES);
        if (i >= 2) {
            CHECK_MSG(e[i]->done == i - 1, "event %d has done %d, expected %d", i, e[i]->done,
                      i - 1);
            CHECK_MSG(!e[i]->eta_null && isfinite(e[i]->eta) && e[i]->eta >= 0,
                      "event %d (done %d): eta_s %g%s", i, e[i]->done, e[i]->eta,
                      e[i]->eta_null ? " (null)" : "");
            CHECK_STR(e[i]->state, i == n - 1 ? "done" : "running");
        }
    }
    CHECK(e[n - 1]->eta == 0);
}

static void job_events(struct test_daemon *d, const char *scene, const char *doc)
{
    struct collector *all = calloc(1, sizeof *all);
    all->url = d->url;
    all->stop_after = 2; /* both jobs below */
    pthread_t thread;
    CHECK_INT(pthread_create(&thread, NULL, collect, all), 0);

    char spec[256], id[64] = "", inline_id[64] = "";
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"width\": 24, \"height\": 18, \"turntable\": {\"frames\": %d}}",
             scene, FRAMES);
    CHECK(job_submit_json(d, spec, id));
    size_t size = strlen(doc) + 128;
    char *inl = malloc(size);
    snprintf(inl, size,
             "{\"scene\": %s, \"width\": 24, \"height\": 18, \"turntable\": "
             "{\"frames\": %d}}",
             doc, FRAMES);
    CHECK(job_submit_json(d, inl, inline_id));
    free(inl);
    pthread_join(thread, NULL);
    CHECK_INT(all->code, REFRACT_E_OK);
    check_sequence(all, id, scene);
    check_sequence(all, inline_id, "(null)");

    /* The scene's stream has the same events of its job (and none of the inline one). */
    struct collector *mine = calloc(1, sizeof *mine);
    mine->url = d->url;
    mine->scene = scene;
    mine->stop_after = 1;
    collect(mine);
    CHECK_INT(mine->code, REFRACT_E_OK);
    check_sequence(mine, id, scene);
    for (int i = 0; i < mine->count; i++)
        CHECK(strcmp(mine->ev[i].job, inline_id) != 0);
    free(mine);
    free(all);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_jobs_events", d.why);
    size_t len = 0;
    char *doc = test_read_source_file("proto/examples/glass_sphere.json", &len);
    char scene[REFRACT_ID_SIZE] = "";
    if (!doc || !test_create_scene(&d, doc, scene))
        test_setup_failed("test_jobs_events", "could not create the scene");
    job_events(&d, scene, doc);
    free(doc);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_jobs_events");
}
