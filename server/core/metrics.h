/*
 * metrics.h - refractd's process-wide counters and histograms, read by GET /metrics
 * (server/http/h_metrics.c writes them in the Prometheus text format; docs/api.md,
 * "Metrics"). A module reports an event with one call; nothing here formats text or
 * knows the route table, so the GPU queue, the renderer and the caches report without
 * including the HTTP layer.
 *
 * DESIGN: fixed arrays of C11 atomics, no lock: a report is a few relaxed atomic adds,
 * cheap enough for the GPU thread and every HTTP request. A snapshot read while reports
 * arrive may be a few events behind in one series and not another; Prometheus tolerates
 * that (each series stays monotonic). What a module already counts itself (queue length,
 * stored bytes, open views, the irradiance cache's evictions) is read from that module at
 * scrape time instead of being counted twice.
 *
 * Global state, like the logger: metrics belong to the process, and passing a context
 * through every reporter would touch every interface for no gain. Thread: any.
 */
#ifndef REFRACT_METRICS_H
#define REFRACT_METRICS_H

#include <stddef.h>

/* Route indexes are positions in the HTTP route table (http_routes()); METRICS_NO_ROUTE
 * counts requests that matched none (404, 405, and what was refused before routing). */
#define METRICS_ROUTES_MAX 64
#define METRICS_NO_ROUTE (METRICS_ROUTES_MAX - 1)

/* Histogram upper bounds in seconds, shared by every histogram (1 ms .. 10 min); one more
 * bucket, +Inf, follows them. */
#define METRICS_BUCKETS 17
extern const double metrics_bucket_le[METRICS_BUCKETS - 1];

/* The GPU queue's priorities (gpu/queue.h enum gpu_priority), as label values. */
#define METRICS_GPU_KINDS 4

enum metrics_cache { METRICS_CACHE_IRRADIANCE = 0, METRICS_CACHE_GPU_SCENE = 1, METRICS_CACHES };
enum metrics_cache_event {
    METRICS_HIT = 0,
    METRICS_MISS = 1,
    METRICS_EVICTION = 2,
    METRICS_EVENTS
};

struct metrics_histogram {
    unsigned long long bucket[METRICS_BUCKETS]; /* counts per bucket, NOT cumulative */
    unsigned long long count;
    double sum_s;
};

/* ---- reporting ---- */

/* An HTTP request was completed: its route index, the status it was answered with (0 when
 * the connection ended without an answer) and its duration from first byte to completion. */
void metrics_http_request(size_t route, int status, double seconds);
/* The GPU thread ran a work item of priority `kind`: how long it waited in the queue and
 * how long it ran (GPU busy time). */
void metrics_gpu_work(int kind, double wait_s, double run_s);
/* A view render (HTTP render, view frame or batch frame) took seconds on the GPU thread. */
void metrics_render(double seconds);
/* One light's irradiance volume was simulated in seconds (all its chunks). */
void metrics_lightsim(double seconds);
/* A cache hit, miss or eviction. */
void metrics_cache(enum metrics_cache cache, enum metrics_cache_event event);

/* ---- reading (GET /metrics) ---- */

/* The statuses seen on a route and their counts: fills up to max pairs, returns how many. */
size_t metrics_http_statuses(size_t route, int *status, unsigned long long *count, size_t max);
void metrics_http_latency(size_t route, struct metrics_histogram *out);
void metrics_gpu_run(int kind, struct metrics_histogram *out);
double metrics_gpu_wait_seconds(int kind);
void metrics_render_times(struct metrics_histogram *out);
void metrics_lightsim_times(struct metrics_histogram *out);
unsigned long long metrics_cache_count(enum metrics_cache cache, enum metrics_cache_event event);

/* Tests only: zeroes everything. */
void metrics_reset(void);

#endif
