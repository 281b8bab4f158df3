/*
 * test_metrics_counters.c - the counters behind GET /metrics (server/core/metrics.c):
 *   - a_value_on_a_bucket_bound_counts_in_that_bucket: Prometheus buckets are "le", so
 *     exactly 1 ms falls in le=0.001 and just above it in the next; beyond 600 s is +Inf;
 *     a negative or NaN duration (a clock step) counts as 0, never as a huge value;
 *   - sums_are_kept_to_the_microsecond;
 *   - statuses_are_counted_per_route_and_unknown_ones_fold_into_their_class: 418 counts
 *     as 400, 599 as 500, 0 (no answer) as itself; a route index out of range counts as
 *     METRICS_NO_ROUTE;
 *   - concurrent_reports_are_not_lost: 4 threads x 100000 reports add up exactly.
 */
#include <math.h>
#include <pthread.h>

#include "core/metrics.h"
#include "test.h"

static void a_value_on_a_bucket_bound_counts_in_that_bucket(void)
{
    metrics_reset();
    metrics_render(0.001);
    metrics_render(0.0010001);
    metrics_render(601.0);
    metrics_render(-5.0);
    metrics_render(NAN);
    struct metrics_histogram h;
    metrics_render_times(&h);
    CHECK_INT((long)h.bucket[0], 3); /* 0.001, and the two zeros */
    CHECK_INT((long)h.bucket[1], 1);
    CHECK_INT((long)h.bucket[METRICS_BUCKETS - 1], 1);
    CHECK_INT((long)h.count, 5);
    CHECK_NEAR(metrics_bucket_le[METRICS_BUCKETS - 2], 600.0, 0);
}

static void sums_are_kept_to_the_microsecond(void)
{
    metrics_reset();
    for (int i = 0; i < 1000; i++)
        metrics_lightsim(0.123456);
    struct metrics_histogram h;
    metrics_lightsim_times(&h);
    CHECK_NEAR(h.sum_s, 123.456, 1e-9);
    metrics_gpu_work(1, 0.5, 0.25);
    metrics_gpu_work(1, 0.5, 0.25);
    metrics_gpu_work(7, 1.0, 1.0); /* not a priority: ignored */
    metrics_gpu_run(1, &h);
    CHECK_NEAR(h.sum_s, 0.5, 1e-9);
    CHECK_NEAR(metrics_gpu_wait_seconds(1), 1.0, 1e-9);
    CHECK_NEAR(metrics_gpu_wait_seconds(0), 0.0, 0);
}

static unsigned long long count_of(size_t route, int status)
{
    int st[64];
    unsigned long long n[64];
    size_t k = metrics_http_statuses(route, st, n, 64);
    for (size_t i = 0; i < k; i++) {
        if (st[i] == status)
            return n[i];
    }
    return 0;
}

static void statuses_are_counted_per_route_and_unknown_ones_fold_into_their_class(void)
{
    metrics_reset();
    metrics_http_request(3, 200, 0.01);
    metrics_http_request(3, 200, 0.01);
    metrics_http_request(3, 418, 0.01);
    metrics_http_request(3, 599, 0.01);
    metrics_http_request(3, 0, 0.01);
    metrics_http_request(5, 404, 0.01);
    metrics_http_request(100000, 404, 0.01);
    CHECK_INT((long)count_of(3, 200), 2);
    CHECK_INT((long)count_of(3, 400), 1);
    CHECK_INT((long)count_of(3, 500), 1);
    CHECK_INT((long)count_of(3, 0), 1);
    CHECK_INT((long)count_of(3, 404), 0);
    CHECK_INT((long)count_of(5, 404), 1);
    CHECK_INT((long)count_of(METRICS_NO_ROUTE, 404), 1);
    struct metrics_histogram h;
    metrics_http_latency(3, &h);
    CHECK_INT((long)h.count, 5);
    metrics_cache(METRICS_CACHE_GPU_SCENE, METRICS_EVICTION);
    CHECK_INT((long)metrics_cache_count(METRICS_CACHE_GPU_SCENE, METRICS_EVICTION), 1);
    CHECK_INT((long)metrics_cache_count(METRICS_CACHE_IRRADIANCE, METRICS_EVICTION), 0);
}

static void *report_many(void *arg)
{
    (void)arg;
    for (int i = 0; i < 100000; i++) {
        metrics_http_request(1, 200, 0.002);
        metrics_cache(METRICS_CACHE_IRRADIANCE, METRICS_HIT);
    }
    return NULL;
}

static void concurrent_reports_are_not_lost(void)
{
    metrics_reset();
    pthread_t t[4];
    for (int i = 0; i < 4; i++)
        pthread_create(&t[i], NULL, report_many, NULL);
    for (int i = 0; i < 4; i++)
        pthread_join(t[i], NULL);
    CHECK_INT((long)count_of(1, 200), 400000);
    CHECK_INT((long)metrics_cache_count(METRICS_CACHE_IRRADIANCE, METRICS_HIT), 400000);
    struct metrics_histogram h;
    metrics_http_latency(1, &h);
    CHECK_NEAR(h.sum_s, 800.0, 1e-6);
}

int main(void)
{
    a_value_on_a_bucket_bound_counts_in_that_bucket();
    sums_are_kept_to_the_microsecond();
    statuses_are_counted_per_route_and_unknown_ones_fold_into_their_class();
    concurrent_reports_are_not_lost();
    return test_summary("test_metrics_counters");
}
