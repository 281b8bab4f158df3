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

enum refract_code photon_map_trace(const struct pathtrace_scene *s, long count, uint64_t seed,
                                   int threads, struct photon_list *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    if (threads < 1)
        threads = 1;
    if (threads > 64)
        threads = 64;
    struct worker w[64];
    pthread_t tid[64];
    bool started[64] = {false};
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
    for (int t = 1; t < threads; t++)
        photon_list_free(&w[t].list);
    if (rc != REFRACT_E_OK)
        photon_list_free(&w[0].list);
    else
        *out = w[0].list;
    return rc;
}

enum refract_code photon_map_build(const struct pathtrace_scene *s, long count,
                                   double radius_setting, uint64_t seed, int threads,
                                   struct photon_grid *g, struct photon_map_stats *stats,
                                   struct err *e)
{
    memset(g, 0, sizeof *g);
    memset(stats, 0, sizeof *stats);
    struct photon_list l;
    double t0 = now_ms();
    enum refract_code rc = photon_map_trace(s, count, seed, threads, &l, e);
    stats->trace_ms = now_ms() - t0;
    stats->emitted = l.emitted;
    stats->landed = l.count;
    stats->radius = photon_radius(s, count, radius_setting);
    if (rc == REFRACT_E_OK) {
        double t1 = now_ms();
        rc = photon_grid_build(&l, stats->radius, g, e);
        stats->grid_ms = now_ms() - t1;
    }
    photon_list_free(&l);
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
    return level < PHOTON_LEVELS ? (uint64_t)(PHOTON_LEVELS - level) : (uint64_t)(100 + level);
}

int photon_initial_passes(long count)
{
    for (int k = 0; k < PHOTON_LEVELS; k++)
        if (photon_level_count(count, k) >= count)
            return k + 1;
    return PHOTON_LEVELS;
}

int photon_pass_count(long count, long count_max)
{
    int extra = 0;
    for (long total = count; total < count_max; total *= 2)
        extra++;
    return photon_initial_passes(count) + extra;
}

long photon_pass_total(long count, long count_max, int pass)
{
    int first = photon_initial_passes(count);
    if (pass < first)
        return photon_level_count(count, pass);
    long total = count;
    for (int k = first; k <= pass && total < count_max; k++)
        total *= 2; /* each pass doubles the photons: the lattice is built log2 times */
    return total < count_max ? total : count_max;
}

long photon_pass_batch(long count, long count_max, int pass)
{
    if (pass < photon_initial_passes(count))
        return photon_level_count(count, pass);
    return photon_pass_total(count, count_max, pass) -
           photon_pass_total(count, count_max, pass - 1);
}

void photon_scene_one_light(const struct pathtrace_scene *s, const struct pathtrace_light *l,
                            struct pathtrace_scene *out)
{
    *out = *s;
    out->lights[0] = *l;
    out->light_count = 1;
}
