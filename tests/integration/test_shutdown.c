/*
 * test_shutdown.c - SIGTERM while renders are queued and running (main.c's shutdown
 * order): every client gets an answer, either its image (200) or 503 shutting_down,
 * none hangs or sees a dropped connection, and refractd exits 0 within the harness's
 * 20 s. Requests that arrive during the shutdown are answered 503 shutting_down until
 * the socket closes (answers go OK, then shutting_down, then connect_failed, in that order
 * and nothing else). Then a restart on the same data directory serves the scene again.
 */
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "daemon.h"
#include "test.h"

#define CLIENTS 8

static const char *const scene =
    "{\"camera\": {\"eye\": [0, 0, 4], \"width\": 320, \"height\": 240}, \"objects\": "
    "[{\"bounds\": "
    "{\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 64, "
    "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}}]}";

struct client_job {
    const char *url, *id;
    int rc;
    char msg[256];
};

static void *render_once(void *arg)
{
    struct client_job *j = arg;
    refract_client *c = refract_client_create(j->url);
    struct refract_image img;
    j->rc = refract_render(c, j->id, "{\"stepper\": \"rk4\", \"step\": 0.25}", &img);
    if (j->rc == REFRACT_E_OK)
        refract_image_free(&img);
    else
        snprintf(j->msg, sizeof j->msg, "%s", refract_errmsg(c));
    refract_client_destroy(c);
    return NULL;
}

/* Polls GET /v1/health from SIGTERM until the daemon is gone. */
struct poller {
    const char *url;
    int ok, shutting_down, connect_failed, other, out_of_order;
    double first_refusal_s, gone_s; /* after SIGTERM; -1 = not seen */
};

static double seconds_since(const struct timespec *t0)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)(t.tv_sec - t0->tv_sec) + 1e-9 * (double)(t.tv_nsec - t0->tv_nsec);
}

static void *poll_health(void *arg)
{
    struct poller *p = arg;
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    p->first_refusal_s = p->gone_s = -1;
    int stage = 0; /* 0 OK, 1 shutting_down, 2 gone */
    while (seconds_since(&t0) < 20) {
        refract_client *c = refract_client_create(p->url);
        char *json = NULL;
        int rc = refract_health(c, &json);
        refract_free(json);
        refract_client_destroy(c);
        int now = rc == REFRACT_E_OK               ? 0
                  : rc == REFRACT_E_SHUTTING_DOWN  ? 1
                  : rc == REFRACT_E_CONNECT_FAILED ? 2
                                                   : -1;
        if (now < 0) {
            p->other++;
            fprintf(stderr, "health during shutdown: code %d\n", rc);
        } else if (now < stage) {
            p->out_of_order++;
        } else {
            stage = now;
        }
        p->ok += now == 0;
        p->shutting_down += now == 1;
        if (now == 1 && p->first_refusal_s < 0)
            p->first_refusal_s = seconds_since(&t0);
        if (now == 2) {
            p->connect_failed++;
            p->gone_s = seconds_since(&t0);
            break;
        }
        usleep(10 * 1000);
    }
    return NULL;
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_shutdown", d.why);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, scene, id));
    struct refract_image warm; /* builds the scene and compiles the variant first */
    CHECK_INT(refract_render(d.client, id,
                             "{\"stepper\": \"rk4\", \"width\": 8, "
                             "\"height\": 8}",
                             &warm),
              REFRACT_E_OK);
    refract_image_free(&warm);

    pthread_t threads[CLIENTS];
    struct client_job jobs[CLIENTS];
    for (int i = 0; i < CLIENTS; i++) {
        jobs[i] = (struct client_job){.url = d.url, .id = id, .rc = -1};
        pthread_create(&threads[i], NULL, render_once, &jobs[i]);
    }
    usleep(400 * 1000); /* all connected and queued; a few renders done */
    pid_t pid = d.pid;
    kill(pid, SIGTERM);
    struct poller health = {.url = d.url};
    pthread_t poller;
    pthread_create(&poller, NULL, poll_health, &health);
    int ok = 0, refused = 0;
    for (int i = 0; i < CLIENTS; i++) {
        pthread_join(threads[i], NULL);
        if (jobs[i].rc == REFRACT_E_OK)
            ok++;
        else if (jobs[i].rc == REFRACT_E_SHUTTING_DOWN)
            refused++;
        else
            fprintf(stderr, "client %d: code %d: %s\n", i, jobs[i].rc, jobs[i].msg);
    }
    printf("SIGTERM with %d renders in flight: %d rendered, %d answered shutting_down\n", CLIENTS,
           ok, refused);
    CHECK_INT(ok + refused, CLIENTS);
    CHECK_INT(test_daemon_stop(&d), 0); /* already stopping: waits for the exit status */
    pthread_join(poller, NULL);
    printf("health during the shutdown: %d ok, %d shutting_down (first after %.3f s), gone "
           "after %.3f s\n",
           health.ok, health.shutting_down, health.first_refusal_s, health.gone_s);
    CHECK_INT(health.other, 0);
    CHECK_INT(health.out_of_order, 0);
    CHECK_INT(health.connect_failed, 1);
    /* The daemon stays up while the render in flight finishes (a 320x240 rk4 frame on
     * llvmpipe); a poll every 10 ms must meet the 503 in that time. */
    if (health.gone_s > 0.2)
        CHECK_MSG(health.shutting_down > 0, "no 503 shutting_down in %.3f s of shutdown",
                  health.gone_s);

    struct test_daemon again;
    char data_dir[sizeof d.data_dir];
    snprintf(data_dir, sizeof data_dir, "%s", d.data_dir);
    CHECK(test_daemon_start_in(&again, data_dir, NULL));
    struct refract_image img;
    CHECK_INT(refract_render(again.client, id, "{\"width\": 16, \"height\": 12}", &img),
              REFRACT_E_OK);
    refract_image_free(&img);
    CHECK_INT(test_daemon_stop(&again), 0);
    test_daemon_cleanup(&again);
    test_daemon_cleanup(&d);
    return test_summary("test_shutdown");
}
