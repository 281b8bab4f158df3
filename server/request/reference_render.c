/*
 * reference_render.c - a path-traced reference image on CPU threads (reference_render.h).
 */
#include "reference_render.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <unistd.h>

#include "../gpu/queue.h"

static atomic_int running;
static atomic_bool cancel_all;

bool reference_begin(void)
{
    int expected = 0;
    return atomic_compare_exchange_strong(&running, &expected, 1);
}

void reference_end(void)
{
    atomic_fetch_sub(&running, 1);
}

void reference_cancel_all(void)
{
    atomic_store(&cancel_all, true);
}

bool reference_cancelled(void)
{
    return atomic_load(&cancel_all);
}

bool reference_start_detached(void *(*fn)(void *), void *arg)
{
    pthread_t tid;
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setdetachstate(&attr, PTHREAD_CREATE_DETACHED);
    int rc = pthread_create(&tid, &attr, fn, arg);
    pthread_attr_destroy(&attr);
    return rc == 0;
}

int reference_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    if (n < 1)
        return 1;
    return n > REFERENCE_MAX_THREADS ? REFERENCE_MAX_THREADS : (int)n;
}

struct run {
    const struct pathtrace_scene *s;
    const struct pathtrace_camera *cam;
    struct pathtrace_image *img;
    int samples, threads;
    double deadline_ms;
    uint64_t seed;
};

struct worker {
    const struct run *run;
    int index;
};

static bool out_of_time(const struct run *r)
{
    return atomic_load(&cancel_all) || gpu_time_ms() >= r->deadline_ms;
}

static void *worker_main(void *arg)
{
    struct worker *w = arg;
    const struct run *r = w->run;
    /* Pass-major, so that a deadline leaves the rows within one sample of each other; a
     * row that already has `samples` (an image refined before: a view's) is skipped. */
    for (int pass = 0; pass < r->samples; pass++) {
        for (int row = w->index; row < r->cam->height; row += r->threads) {
            if (pass > 0 && out_of_time(r))
                return NULL;
            if (r->img->samples[(int64_t)row * r->img->width] >= (uint32_t)r->samples)
                continue;
            pathtrace_image_pass(r->img, r->s, r->cam, r->seed, row, row + 1);
        }
    }
    return NULL;
}

double reference_render(const struct pathtrace_scene *s, const struct pathtrace_camera *cam,
                        struct pathtrace_image *img, int samples, double deadline_ms,
                        uint64_t seed, int threads, bool *cancelled)
{
    if (threads < 1)
        threads = 1;
    if (threads > REFERENCE_MAX_THREADS)
        threads = REFERENCE_MAX_THREADS;
    struct run r = {s, cam, img, samples, threads, deadline_ms, seed};
    double t0 = gpu_time_ms();
    pthread_t tid[REFERENCE_MAX_THREADS];
    struct worker workers[REFERENCE_MAX_THREADS];
    int started = 0;
    for (int i = 0; i < threads; i++) {
        workers[i] = (struct worker){&r, i};
        if (i > 0 && pthread_create(&tid[i], NULL, worker_main, &workers[i]) == 0)
            started = i;
        else if (i > 0)
            break;
    }
    worker_main(&workers[0]);
    /* Workers that could not be started are covered here, after this one's rows. */
    for (int i = started + 1; i < threads; i++)
        worker_main(&workers[i]);
    for (int i = 1; i <= started; i++)
        pthread_join(tid[i], NULL);
    if (cancelled)
        *cancelled = atomic_load(&cancel_all);
    return gpu_time_ms() - t0;
}

bool reference_image_floats(const struct pathtrace_image *img, float **rgba, float **exr7,
                            uint32_t *min_n, uint32_t *max_n, double *rel_noise)
{
    int64_t n = (int64_t)img->width * img->height;
    *rgba = malloc((size_t)n * 4 * sizeof(float));
    float *exr = exr7 ? malloc((size_t)n * 7 * sizeof(float)) : NULL;
    if (*rgba == NULL || (exr7 && exr == NULL)) {
        free(*rgba);
        free(exr);
        *rgba = NULL;
        return false;
    }
    *min_n = UINT32_MAX;
    *max_n = 0;
    double sum_mean = 0.0, sum_sd = 0.0;
    for (int64_t i = 0; i < n; i++) {
        double m[3], v[3];
        pathtrace_image_pixel(img, i, m, v);
        for (int c = 0; c < 3; c++) {
            (*rgba)[4 * i + c] = (float)m[c];
            if (exr) {
                exr[7 * i + c] = (float)m[c];
                exr[7 * i + 4 + c] = (float)v[c];
            }
        }
        (*rgba)[4 * i + 3] = 1.0f;
        if (exr)
            exr[7 * i + 3] = 1.0f;
        uint32_t k = img->samples[i];
        *min_n = k < *min_n ? k : *min_n;
        *max_n = k > *max_n ? k : *max_n;
        sum_mean += (m[0] + m[1] + m[2]) / 3.0;
        sum_sd += sqrt((v[0] + v[1] + v[2]) / 3.0);
    }
    *rel_noise = sum_mean > 0.0 ? sum_sd / sum_mean : 0.0;
    if (exr7)
        *exr7 = exr;
    return true;
}
