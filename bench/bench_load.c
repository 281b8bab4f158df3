/*
 * bench_load.c - refract-load: many clients at once against a running refractd, for
 * BENCHMARKS.md ("Fair sharing", issue 13). Not a test: it asserts nothing and prints a
 * Markdown table.
 *
 *     build/refract-load URL [--clients 64] [--seconds 60] [--pid PID]
 *
 * Each client is a thread with its own librefract client (one kept-alive connection) that
 * loops until the time is up over: GET /v1/health (half of its requests), a 32x24 render
 * (a third) and a trace of 16 rays (the rest), on a glass sphere of 32^3 voxels that the
 * benchmark creates and deletes. It counts answers by class (2xx, 4xx, 5xx, transport
 * errors) and reports health's latency (median, p99, max, nearest rank) and, with --pid,
 * the daemon's resident memory (VmRSS) before and after: the target is 0 errors,
 * 0 5xx, RSS growth under 5 MB and health p99 under 50 ms with 64 clients for 60 s.
 * Every client counts as the same client address (loopback): start refractd with
 * --max-queued-per-client at least --clients.
 */
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>

#include "refract.h"

#define MAX_CLIENTS 512
#define MAX_HEALTH 200000

static const char scene_json[] =
    "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 32, "
    "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}}]}";

struct shared {
    const char *url;
    char scene[REFRACT_ID_SIZE];
    double end_ms;
    pthread_mutex_t lock;
    double *health_ms;
    size_t health_count;
    long ok, client_errors, server_errors, transport_errors;
    long renders, traces, healths;
};

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

static void trace_body(char *out, size_t size)
{
    size_t n = (size_t)snprintf(out, size, "{\"rays\": [");
    for (int i = 0; i < 16 && n < size; i++)
        n += (size_t)snprintf(out + n, size - n,
                              "%s{\"origin\": [%.3f, 0.1, -3], \"direction\": [0, 0, 1]}",
                              i ? ", " : "", -0.6 + 0.08 * i);
    snprintf(out + n, size - n, "]}");
}

static void *client_main(void *arg)
{
    struct shared *s = arg;
    refract_client *c = refract_client_create(s->url);
    if (c == NULL)
        return NULL;
    char render_path[128], trace_path[128], trace[4096];
    snprintf(render_path, sizeof render_path, "/v1/scenes/%s/render", s->scene);
    snprintf(trace_path, sizeof trace_path, "/v1/scenes/%s/trace", s->scene);
    trace_body(trace, sizeof trace);
    static const char render[] = "{\"width\": 32, \"height\": 24}";
    for (unsigned k = 0; now_ms() < s->end_ms; k++) {
        int kind = k % 6 < 3 ? 0 : k % 6 < 5 ? 1 : 2; /* health, render, trace */
        struct refract_response r;
        double t0 = now_ms();
        int rc = kind == 0   ? refract_request(c, "GET", "/v1/health", NULL, 0, NULL, &r)
                 : kind == 1 ? refract_request(c, "POST", render_path, render, strlen(render),
                                               "application/json", &r)
                             : refract_request(c, "POST", trace_path, trace, strlen(trace),
                                               "application/json", &r);
        double ms = now_ms() - t0;
        pthread_mutex_lock(&s->lock);
        if (rc != REFRACT_E_OK) {
            s->transport_errors++;
        } else {
            s->ok += r.status < 400;
            s->client_errors += r.status >= 400 && r.status < 500;
            s->server_errors += r.status >= 500;
            if (r.status >= 400)
                fprintf(stderr, "refract-load: %ld %.200s\n", r.status, r.body ? r.body : "");
            refract_response_free(&r);
        }
        if (kind == 0 && s->health_count < MAX_HEALTH)
            s->health_ms[s->health_count++] = ms;
        s->healths += kind == 0;
        s->renders += kind == 1;
        s->traces += kind == 2;
        pthread_mutex_unlock(&s->lock);
    }
    refract_client_destroy(c);
    return NULL;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The report's header: date, machine, load average, command (Markdown list items). */
static void print_header(int argc, char **argv)
{
    char date[32] = "?", load[64] = "?";
    time_t t = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d", gmtime(&t));
    FILE *f = fopen("/proc/loadavg", "r");
    if (f != NULL) {
        if (fgets(load, sizeof load, f) != NULL)
            load[strcspn(load, "\n")] = '\0';
        fclose(f);
    }
    struct utsname u;
    uname(&u);
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    printf("- date: %s\n- machine: %ld cores, %s %s\n- load average at the end: %s\n- "
           "command:",
           date, cores, u.sysname, u.machine, load);
    for (int i = 0; i < argc; i++)
        printf(" %s", argv[i]);
    printf("\n");
}

/* VmRSS of pid in kB, or -1. */
static long rss_kb(int pid)
{
    char path[64], line[256];
    snprintf(path, sizeof path, "/proc/%d/status", pid);
    FILE *f = fopen(path, "r");
    long kb = -1;
    while (f != NULL && fgets(line, sizeof line, f)) {
        if (strncmp(line, "VmRSS:", 6) == 0)
            kb = atol(line + 6);
    }
    if (f != NULL)
        fclose(f);
    return kb;
}

static double rank(const double *sorted, size_t n, double q)
{
    if (n == 0)
        return 0.0;
    size_t i = (size_t)(q * (double)n + 0.999999);
    return sorted[i == 0 ? 0 : i > n ? n - 1 : i - 1];
}

int main(int argc, char **argv)
{
    struct shared s = {0};
    int clients = 64, pid = 0;
    double seconds = 60.0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--clients") && i + 1 < argc)
            clients = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--seconds") && i + 1 < argc)
            seconds = atof(argv[++i]);
        else if (!strcmp(argv[i], "--pid") && i + 1 < argc)
            pid = atoi(argv[++i]);
        else if (argv[i][0] != '-' && s.url == NULL)
            s.url = argv[i];
        else {
            fprintf(stderr, "usage: %s URL [--clients N] [--seconds S] [--pid PID]\n", argv[0]);
            return 2;
        }
    }
    if (s.url == NULL || clients < 1 || clients > MAX_CLIENTS || !(seconds > 0)) {
        fprintf(stderr, "usage: %s URL [--clients 1..%d] [--seconds S] [--pid PID]\n", argv[0],
                MAX_CLIENTS);
        return 2;
    }
    refract_client *admin = refract_client_create(s.url);
    if (admin == NULL || refract_scene_create(admin, scene_json, strlen(scene_json), s.scene,
                                              sizeof s.scene) != REFRACT_E_OK) {
        fprintf(stderr, "refract-load: cannot create the scene at %s: %s\n", s.url,
                admin ? refract_errmsg(admin) : "out of memory");
        return 1;
    }
    /* warm-up: the kernel variants compile on first use */
    struct refract_response r;
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/render", s.scene);
    if (refract_request(admin, "POST", path, "{}", 2, "application/json", &r) == REFRACT_E_OK)
        refract_response_free(&r);
    s.health_ms = calloc(MAX_HEALTH, sizeof *s.health_ms);
    pthread_mutex_init(&s.lock, NULL);
    long rss_before = pid ? rss_kb(pid) : -1;
    s.end_ms = now_ms() + seconds * 1000.0;
    pthread_t threads[MAX_CLIENTS];
    for (int i = 0; i < clients; i++)
        pthread_create(&threads[i], NULL, client_main, &s);
    for (int i = 0; i < clients; i++)
        pthread_join(threads[i], NULL);
    long rss_after = pid ? rss_kb(pid) : -1;
    snprintf(path, sizeof path, "/v1/scenes/%s", s.scene);
    if (refract_request(admin, "DELETE", path, NULL, 0, NULL, &r) == REFRACT_E_OK)
        refract_response_free(&r);
    refract_client_destroy(admin);
    qsort(s.health_ms, s.health_count, sizeof *s.health_ms, compare_doubles);
    print_header(argc, argv);
    printf("\n| clients | seconds | requests (health / render / trace) | 2xx | 4xx | 5xx | "
           "transport errors | health p50 | health p99 | health max | RSS before | RSS "
           "after |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- "
           "|\n");
    printf("| %d | %.0f | %ld / %ld / %ld | %ld | %ld | %ld | %ld | %.1f ms | %.1f ms | %.1f ms "
           "| %ld kB | %ld kB |\n",
           clients, seconds, s.healths, s.renders, s.traces, s.ok, s.client_errors, s.server_errors,
           s.transport_errors, rank(s.health_ms, s.health_count, 0.5),
           rank(s.health_ms, s.health_count, 0.99),
           s.health_count ? s.health_ms[s.health_count - 1] : 0.0, rss_before, rss_after);
    free(s.health_ms);
    pthread_mutex_destroy(&s.lock);
    return 0;
}
