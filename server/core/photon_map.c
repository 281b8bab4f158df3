/*
 * photon_map.c - a scene's whole photon map (photon.h): photons traced on several threads
 * (thread t takes photons t, t + threads, ...: the list is the same set whatever the
 * thread count, photon_trace's streams being per photon), merged, then the grid.
 */
#include "photon.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct worker {
    const struct pathtrace_scene *s;
    long count, first, stride;
    uint64_t seed;
    struct photon_list list;
    enum refract_code rc;
    struct err e;
};

static void *run(void *arg)
{
    struct worker *w = arg;
    w->rc = photon_trace(w->s, w->count, w->seed, w->first, w->stride, &w->list, &w->e);
    return NULL;
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

enum refract_code photon_map_build(const struct pathtrace_scene *s, long count,
                                   double radius_setting, uint64_t seed, int threads,
                                   struct photon_grid *g, struct photon_map_stats *stats,
                                   struct err *e)
{
    memset(g, 0, sizeof *g);
    memset(stats, 0, sizeof *stats);
    if (threads < 1)
        threads = 1;
    if (threads > 64)
        threads = 64;
    struct worker w[64];
    pthread_t tid[64];
    bool started[64] = {false};
    double t0 = now_ms();
    for (int t = 0; t < threads; t++) {
        w[t] = (struct worker){.s = s, .count = count, .first = t, .stride = threads, .seed = seed};
        started[t] = t > 0 && pthread_create(&tid[t], NULL, run, &w[t]) == 0;
    }
    run(&w[0]);
    for (int t = 1; t < threads; t++) {
        if (started[t])
            pthread_join(tid[t], NULL);
        else
            run(&w[t]); /* no thread: the work is done here */
    }
    enum refract_code rc = REFRACT_E_OK;
    for (int t = 0; t < threads && rc == REFRACT_E_OK; t++) {
        if (w[t].rc != REFRACT_E_OK) {
            rc = w[t].rc;
            if (e)
                *e = w[t].e;
        }
    }
    for (int t = 1; t < threads && rc == REFRACT_E_OK; t++)
        rc = photon_list_merge(&w[0].list, &w[t].list, e);
    stats->trace_ms = now_ms() - t0;
    stats->emitted = w[0].list.emitted;
    stats->landed = w[0].list.count;
    stats->radius = photon_radius(s, count, radius_setting);
    if (rc == REFRACT_E_OK) {
        double t1 = now_ms();
        rc = photon_grid_build(&w[0].list, stats->radius, g, e);
        stats->grid_ms = now_ms() - t1;
    }
    for (int t = 0; t < threads; t++)
        photon_list_free(&w[t].list);
    return rc;
}

long photon_level_count(long count, int level)
{
    int shift = 2 * (PHOTON_LEVELS - 1 - level);
    long n = shift > 0 ? count >> shift : count;
    if (n < 1024)
        n = 1024;
    return n < count ? n : count;
}

uint64_t photon_level_seed(int level)
{
    return (uint64_t)(PHOTON_LEVELS - level);
}

void photon_scene_one_light(const struct pathtrace_scene *s, const struct pathtrace_light *l,
                            struct pathtrace_scene *out)
{
    *out = *s;
    out->lights[0] = *l;
    out->light_count = 1;
}
