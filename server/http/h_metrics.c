/*
 * h_metrics.c - GET /metrics: refractd's counters in the Prometheus text exposition format
 * (version 0.0.4; docs/api.md "Metrics" lists every family). Counters and histograms come
 * from core/metrics.h, where the GPU queue, the renderer, the caches and server.c report
 * them; gauges are read here, at scrape time, from the modules that own them (queue
 * length, stored bytes, open views and streams, jobs by state), so nothing is counted
 * twice. The token check applies as on every route but /v1/health (server.c).
 *
 * Not a Prometheus client library: the text is a few printf lines per family.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../cache/irradiance_cache.h"
#include "../core/metrics.h"
#include "../jobs/jobs.h"
#include "http_internal.h"
#include "stream.h"

/* The text being built; `failed` after an allocation failure (then answered 507). */
struct text {
    char *data;
    size_t len, cap;
    bool failed;
};

__attribute__((format(printf, 2, 3))) static void put(struct text *t, const char *fmt, ...)
{
    if (t->failed)
        return;
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int n = vsnprintf(t->data + t->len, t->cap - t->len, fmt, ap);
        va_end(ap);
        if (n < 0) {
            t->failed = true;
            return;
        }
        if ((size_t)n < t->cap - t->len) {
            t->len += (size_t)n;
            return;
        }
        size_t cap = t->cap * 2 + (size_t)n + 1;
        char *grown = realloc(t->data, cap);
        if (grown == NULL) {
            t->failed = true;
            return;
        }
        t->data = grown;
        t->cap = cap;
    }
}

static void family(struct text *t, const char *name, const char *type, const char *help)
{
    put(t, "# HELP %s %s\n# TYPE %s %s\n", name, help, name, type);
}

/* One histogram's series: cumulative buckets, +Inf, sum, count. labels is "" or
 * `key="value",` (with the trailing comma). */
static void histogram(struct text *t, const char *name, const char *labels,
                      const struct metrics_histogram *h)
{
    unsigned long long cumulative = 0;
    for (size_t b = 0; b < METRICS_BUCKETS - 1; b++) {
        cumulative += h->bucket[b];
        put(t, "%s_bucket{%sle=\"%g\"} %llu\n", name, labels, metrics_bucket_le[b], cumulative);
    }
    put(t, "%s_bucket{%sle=\"+Inf\"} %llu\n", name, labels, h->count);
    /* The labels without their trailing comma, for _sum and _count. */
    char plain[192] = "";
    size_t n = strlen(labels);
    if (n > 0)
        snprintf(plain, sizeof plain, "{%.*s}", (int)(n - 1), labels);
    put(t, "%s_sum%s %.6f\n%s_count%s %llu\n", name, plain, h->sum_s, name, plain, h->count);
}

static void http_families(struct text *t)
{
    const struct http_route_info *routes = NULL;
    size_t route_count = http_routes(&routes);
    family(t, "refractd_http_requests_total", "counter",
           "HTTP requests completed, by route (the pattern, \"none\" when no route matched) and "
           "status (0: the connection ended without an answer).");
    for (size_t r = 0; r <= route_count; r++) {
        size_t index = r < route_count ? r : METRICS_NO_ROUTE;
        int status[64];
        unsigned long long count[64];
        size_t n = metrics_http_statuses(index, status, count, 64);
        for (size_t i = 0; i < n; i++)
            put(t, "refractd_http_requests_total{method=\"%s\",route=\"%s\",status=\"%d\"} %llu\n",
                r < route_count ? routes[r].method : "",
                r < route_count ? routes[r].pattern : "none", status[i], count[i]);
    }
    family(t, "refractd_http_request_duration_seconds", "histogram",
           "Time from a request's first byte to its completion (for streams: how long they "
           "stayed open), by route.");
    for (size_t r = 0; r <= route_count; r++) {
        size_t index = r < route_count ? r : METRICS_NO_ROUTE;
        struct metrics_histogram h;
        metrics_http_latency(index, &h);
        if (h.count == 0)
            continue;
        char labels[160];
        snprintf(labels, sizeof labels, "method=\"%s\",route=\"%s\",",
                 r < route_count ? routes[r].method : "",
                 r < route_count ? routes[r].pattern : "none");
        histogram(t, "refractd_http_request_duration_seconds", labels, &h);
    }
}

static const char *const gpu_kinds[METRICS_GPU_KINDS] = {"interactive", "lightsim", "batch",
                                                         "maintenance"};

static void gpu_families(struct text *t, const struct http_app *app)
{
    family(t, "refractd_gpu_queue_length", "gauge", "GPU work items waiting in the queue.");
    put(t, "refractd_gpu_queue_length %zu\n", gpu_queue_length(app->gpu));
    struct metrics_histogram h[METRICS_GPU_KINDS];
    for (int k = 0; k < METRICS_GPU_KINDS; k++)
        metrics_gpu_run(k, &h[k]);
    family(t, "refractd_gpu_busy_seconds_total", "counter",
           "Time the GPU thread spent running work items, by priority (kind).");
    for (int k = 0; k < METRICS_GPU_KINDS; k++)
        put(t, "refractd_gpu_busy_seconds_total{kind=\"%s\"} %.6f\n", gpu_kinds[k], h[k].sum_s);
    family(t, "refractd_gpu_queue_wait_seconds_total", "counter",
           "Time work items waited in the GPU queue before they ran, by priority (kind).");
    for (int k = 0; k < METRICS_GPU_KINDS; k++)
        put(t, "refractd_gpu_queue_wait_seconds_total{kind=\"%s\"} %.6f\n", gpu_kinds[k],
            metrics_gpu_wait_seconds(k));
    family(t, "refractd_gpu_work_seconds", "histogram",
           "Run time of one GPU work item, by priority: interactive (renders, traces, view "
           "frames), lightsim (light-simulation chunks), batch (job frames), maintenance.");
    for (int k = 0; k < METRICS_GPU_KINDS; k++) {
        char labels[40];
        snprintf(labels, sizeof labels, "kind=\"%s\",", gpu_kinds[k]);
        histogram(t, "refractd_gpu_work_seconds", labels, &h[k]);
    }
    struct metrics_histogram one;
    metrics_render_times(&one);
    family(t, "refractd_render_seconds", "histogram",
           "GPU time of one view render (POST .../render, a view frame or a batch frame).");
    histogram(t, "refractd_render_seconds", "", &one);
    metrics_lightsim_times(&one);
    family(t, "refractd_lightsim_seconds", "histogram",
           "Time to simulate one light's irradiance volume, all its chunks together.");
    histogram(t, "refractd_lightsim_seconds", "", &one);
}

static void cache_families(struct text *t, const struct http_app *app)
{
    struct irradiance_cache_counters c = {0};
    if (app->irradiance)
        irradiance_cache_counters(app->irradiance, &c);
    unsigned long long irr_evictions =
        (unsigned long long)(c.evicted_gpu + c.evicted_host + c.evicted_disk);
    family(t, "refractd_cache_events_total", "counter",
           "Cache lookups that hit or missed, and evictions: cache irradiance (a light's "
           "volume; evictions from GPU, host memory and disk together) and gpu_scene (a "
           "scene's volumes on the GPU, --gpu-scene-budget).");
    static const char *const events[METRICS_EVENTS] = {"hit", "miss", "eviction"};
    for (int ev = 0; ev < METRICS_EVENTS; ev++) {
        unsigned long long irr = ev == METRICS_EVICTION
                                     ? irr_evictions
                                     : metrics_cache_count(METRICS_CACHE_IRRADIANCE, ev);
        put(t, "refractd_cache_events_total{cache=\"irradiance\",event=\"%s\"} %llu\n", events[ev],
            irr);
        put(t, "refractd_cache_events_total{cache=\"gpu_scene\",event=\"%s\"} %llu\n", events[ev],
            metrics_cache_count(METRICS_CACHE_GPU_SCENE, ev));
    }
    family(t, "refractd_irradiance_cache_bytes", "gauge",
           "Bytes of irradiance volumes held, by tier (gpu, host, disk).");
    put(t, "refractd_irradiance_cache_bytes{tier=\"gpu\"} %zu\n", c.gpu_bytes);
    put(t, "refractd_irradiance_cache_bytes{tier=\"host\"} %zu\n", c.host_bytes);
    put(t, "refractd_irradiance_cache_bytes{tier=\"disk\"} %llu\n",
        (unsigned long long)c.disk_bytes);
}

static void state_families(struct text *t, struct http_request *req)
{
    const struct http_app *app = req->app;
    struct store_usage u = {0};
    store_usage_get(app->store, &u);
    family(t, "refractd_stored_bytes", "gauge",
           "Bytes of uploaded content in the data directory (counted against "
           "--max-storage-bytes).");
    put(t, "refractd_stored_bytes %llu\n", u.blob_bytes);
    family(t, "refractd_storage_limit_bytes", "gauge", "--max-storage-bytes; 0 = no limit.");
    put(t, "refractd_storage_limit_bytes %llu\n", u.max_storage_bytes);
    struct view_session **views = NULL;
    size_t view_count = app->views ? view_session_list(app->views, &views) : 0;
    view_session_list_free(views, view_count);
    family(t, "refractd_views_open", "gauge", "Open view sessions.");
    put(t, "refractd_views_open %zu\n", view_count);
    family(t, "refractd_streams_open", "gauge",
           "Open streaming responses: MJPEG frame streams and Server-Sent Events streams.");
    put(t, "refractd_streams_open %zu\n", http_stream_set_count(http_server_streams(req->server)));
    static const char *const states[] = {"queued", "running", "done", "failed", "cancelled"};
    size_t by_state[5] = {0};
    struct job_status *jobs = NULL;
    size_t job_count = app->jobs ? job_list(app->jobs, NULL, NULL, &jobs) : 0;
    for (size_t i = 0; i < job_count; i++) {
        for (size_t s = 0; s < 5; s++)
            by_state[s] += strcmp(jobs[i].state, states[s]) == 0;
    }
    free(jobs);
    family(t, "refractd_jobs", "gauge", "Batch jobs in the data directory, by state.");
    for (size_t s = 0; s < 5; s++)
        put(t, "refractd_jobs{state=\"%s\"} %zu\n", states[s], by_state[s]);
}

enum MHD_Result http_handle_metrics(struct http_request *req)
{
    struct text t = {.data = malloc(16384), .cap = 16384};
    if (t.data == NULL)
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory writing /metrics");
    t.data[0] = '\0';
    http_families(&t);
    gpu_families(&t, req->app);
    cache_families(&t, req->app);
    state_families(&t, req);
    if (t.failed) {
        free(t.data);
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory writing /metrics");
    }
    return http_respond_bytes(req, MHD_HTTP_OK, t.data, t.len,
                              "text/plain; version=0.0.4; charset=utf-8", NULL);
}
