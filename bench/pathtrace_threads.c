/*
 * pathtrace_threads.c - the CPU reference path tracer over several threads (see the
 * header).
 */
#include "pathtrace_threads.h"

#include <pthread.h>
#include <time.h>

struct work {
    struct pathtrace_image *img;
    const struct pathtrace_scene *scene;
    const struct pathtrace_camera *cam;
    int index, threads, samples;
};

static void *run(void *arg)
{
    struct work *w = arg;
    for (int p = 0; p < w->samples; p++)
        for (int r = w->index; r < w->cam->height; r += w->threads)
            pathtrace_image_pass(w->img, w->scene, w->cam, 1, r, r + 1);
    return NULL;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double bench_pathtrace_threads(struct pathtrace_image *img, const struct pathtrace_scene *scene,
                               const struct pathtrace_camera *cam, int threads, int samples)
{
    threads = threads < 1 ? 1 : (threads > 64 ? 64 : threads);
    pthread_t tid[64];
    struct work wk[64];
    double t0 = now_s();
    for (int i = 0; i < threads; i++) {
        wk[i] = (struct work){img, scene, cam, i, threads, samples};
        pthread_create(&tid[i], NULL, run, &wk[i]);
    }
    for (int i = 0; i < threads; i++)
        pthread_join(tid[i], NULL);
    return now_s() - t0;
}
