/*
 * test_shutdown.c - SIGTERM while renders are queued and running (main.c's shutdown
 * order): every client gets an answer, either its image (200) or 503 shutting_down,
 * none hangs or sees a dropped connection, and refractd exits 0 within the harness's
 * 20 s. Then a restart on the same data directory serves the scene again.
 */
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
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
    j->rc = refract_render(c, j->id, "{\"integrator\": \"rk4\", \"step\": 0.25}", &img);
    if (j->rc == REFRACT_E_OK)
        refract_image_free(&img);
    else
        snprintf(j->msg, sizeof j->msg, "%s", refract_errmsg(c));
    refract_client_destroy(c);
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
                             "{\"integrator\": \"rk4\", \"width\": 8, "
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
