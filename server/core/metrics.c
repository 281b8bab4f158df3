/*
 * metrics.c - the counters behind GET /metrics: atomic adds on report, relaxed loads on
 * read (metrics.h says why no lock). Sums are kept in integer microseconds so they can be
 * atomic adds.
 */
#include "metrics.h"

#include <stdatomic.h>
#include <string.h>

const double metrics_bucket_le[METRICS_BUCKETS - 1] = {
    0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5, 1, 2.5, 5, 10, 30, 60, 600};

/* The statuses refractd and libmicrohttpd answer with. One that is not listed counts
 * under the first listed status of its class (a 418 as 400), so the table stays fixed;
 * 0 is a connection that ended without an answer. */
static const int status_codes[] = {0,   200, 201, 202, 204, 206, 301, 302, 304, 400, 401,
                                   403, 404, 405, 406, 409, 410, 413, 414, 415, 416, 421,
                                   422, 429, 431, 500, 501, 502, 503, 504, 505, 507};
#define STATUS_SLOTS (sizeof status_codes / sizeof status_codes[0])

struct histogram {
    atomic_ullong bucket[METRICS_BUCKETS];
    atomic_ullong count;
    atomic_ullong sum_us;
};

static atomic_ullong http_status[METRICS_ROUTES_MAX][STATUS_SLOTS];
static struct histogram http_latency[METRICS_ROUTES_MAX];
static struct histogram gpu_run[METRICS_GPU_KINDS];
static atomic_ullong gpu_wait_us[METRICS_GPU_KINDS];
static struct histogram render_times, lightsim_times;
static atomic_ullong cache_events[METRICS_CACHES][METRICS_EVENTS];

static void observe(struct histogram *h, double seconds)
{
    if (!(seconds >= 0.0)) /* NaN or a clock step backwards */
        seconds = 0.0;
    size_t b = 0;
    while (b < METRICS_BUCKETS - 1 && seconds > metrics_bucket_le[b])
        b++;
    atomic_fetch_add_explicit(&h->bucket[b], 1, memory_order_relaxed);
    atomic_fetch_add_explicit(&h->count, 1, memory_order_relaxed);
    atomic_fetch_add_explicit(&h->sum_us, (unsigned long long)(seconds * 1e6 + 0.5),
                              memory_order_relaxed);
}

static void read_histogram(struct histogram *h, struct metrics_histogram *out)
{
    for (size_t b = 0; b < METRICS_BUCKETS; b++)
        out->bucket[b] = atomic_load_explicit(&h->bucket[b], memory_order_relaxed);
    out->count = atomic_load_explicit(&h->count, memory_order_relaxed);
    out->sum_s = (double)atomic_load_explicit(&h->sum_us, memory_order_relaxed) * 1e-6;
}

/* The slot of a status: its own when listed, else the first listed status of its class
 * (1xx and unknown classes fold into 0: "no answer"). */
static size_t status_slot(int status)
{
    for (size_t i = 0; i < STATUS_SLOTS; i++) {
        if (status_codes[i] == status)
            return i;
    }
    for (size_t i = 1; i < STATUS_SLOTS; i++) {
        if (status_codes[i] / 100 == status / 100)
            return i;
    }
    return 0;
}

void metrics_http_request(size_t route, int status, double seconds)
{
    if (route >= METRICS_ROUTES_MAX)
        route = METRICS_NO_ROUTE;
    atomic_fetch_add_explicit(&http_status[route][status_slot(status)], 1, memory_order_relaxed);
    observe(&http_latency[route], seconds);
}

void metrics_gpu_work(int kind, double wait_s, double run_s)
{
    if (kind < 0 || kind >= METRICS_GPU_KINDS)
        return;
    observe(&gpu_run[kind], run_s);
    if (wait_s > 0.0)
        atomic_fetch_add_explicit(&gpu_wait_us[kind], (unsigned long long)(wait_s * 1e6 + 0.5),
                                  memory_order_relaxed);
}

void metrics_render(double seconds)
{
    observe(&render_times, seconds);
}

void metrics_lightsim(double seconds)
{
    observe(&lightsim_times, seconds);
}

void metrics_cache(enum metrics_cache cache, enum metrics_cache_event event)
{
    if ((unsigned)cache < METRICS_CACHES && (unsigned)event < METRICS_EVENTS)
        atomic_fetch_add_explicit(&cache_events[cache][event], 1, memory_order_relaxed);
}

size_t metrics_http_statuses(size_t route, int *status, unsigned long long *count, size_t max)
{
    size_t n = 0;
    if (route >= METRICS_ROUTES_MAX)
        return 0;
    for (size_t i = 0; i < STATUS_SLOTS && n < max; i++) {
        unsigned long long c = atomic_load_explicit(&http_status[route][i], memory_order_relaxed);
        if (c == 0)
            continue;
        status[n] = status_codes[i];
        count[n++] = c;
    }
    return n;
}

void metrics_http_latency(size_t route, struct metrics_histogram *out)
{
    memset(out, 0, sizeof *out);
    if (route < METRICS_ROUTES_MAX)
        read_histogram(&http_latency[route], out);
}

void metrics_gpu_run(int kind, struct metrics_histogram *out)
{
    memset(out, 0, sizeof *out);
    if (kind >= 0 && kind < METRICS_GPU_KINDS)
        read_histogram(&gpu_run[kind], out);
}

double metrics_gpu_wait_seconds(int kind)
{
    if (kind < 0 || kind >= METRICS_GPU_KINDS)
        return 0.0;
    return (double)atomic_load_explicit(&gpu_wait_us[kind], memory_order_relaxed) * 1e-6;
}

void metrics_render_times(struct metrics_histogram *out)
{
    read_histogram(&render_times, out);
}

void metrics_lightsim_times(struct metrics_histogram *out)
{
    read_histogram(&lightsim_times, out);
}

unsigned long long metrics_cache_count(enum metrics_cache cache, enum metrics_cache_event event)
{
    if ((unsigned)cache >= METRICS_CACHES || (unsigned)event >= METRICS_EVENTS)
        return 0;
    return atomic_load_explicit(&cache_events[cache][event], memory_order_relaxed);
}

void metrics_reset(void)
{
    for (size_t r = 0; r < METRICS_ROUTES_MAX; r++) {
        for (size_t i = 0; i < STATUS_SLOTS; i++)
            atomic_store(&http_status[r][i], 0);
    }
    struct histogram *all[METRICS_ROUTES_MAX + METRICS_GPU_KINDS + 2];
    size_t n = 0;
    for (size_t r = 0; r < METRICS_ROUTES_MAX; r++)
        all[n++] = &http_latency[r];
    for (int k = 0; k < METRICS_GPU_KINDS; k++) {
        all[n++] = &gpu_run[k];
        atomic_store(&gpu_wait_us[k], 0);
    }
    all[n++] = &render_times;
    all[n++] = &lightsim_times;
    for (size_t i = 0; i < n; i++) {
        for (size_t b = 0; b < METRICS_BUCKETS; b++)
            atomic_store(&all[i]->bucket[b], 0);
        atomic_store(&all[i]->count, 0);
        atomic_store(&all[i]->sum_us, 0);
    }
    for (int c = 0; c < METRICS_CACHES; c++) {
        for (int ev = 0; ev < METRICS_EVENTS; ev++)
            atomic_store(&cache_events[c][ev], 0);
    }
}
