/*
 * bench_views.c - refract-views: how live views feel, measured against a running refractd
 * through librefract, for BENCHMARKS.md. Not a test: it asserts nothing and prints
 * Markdown tables.
 *
 *     build/refract-views URL [--sizes 640x480,1280x720] [--viewers 1,4,8] [--patches 30]
 *                             [--seconds 10] [--min-frames 3] [--scene ID]
 *                             [--resolution 64] [--quality normal]
 *
 * Latency: one session per size; after each frame the camera is PATCHed (the eye turns
 * 10 degrees about look_at) and the time from just before the PATCH is sent to the first
 * byte of the next frame's part (struct refract_frame.arrival_ms) is recorded, --patches
 * times. Measured twice: with progressive refinement off (the next frame is the full
 * frame) and on (the next frame is the half-size preview when full frames take over
 * 20 ms; the full frame is awaited before the next PATCH, and its latency is reported
 * too). The table gives the median and p95 (nearest rank), and the median render time of
 * those frames from X-Render-Time-Ms, so HTTP/encoding overhead shows as the difference.
 * A third run PATCHes only the exposure (alternating 0 and 0.5 EV; progressive off): the
 * session encodes its last full frame's image again instead of rendering (docs/views.md),
 * so that row shows what an exposure slider costs.
 *
 * Frames per second per viewer: N threads, each with its own session (progressive off)
 * on the same scene and its own two clients, PATCH the camera after every frame for
 * --seconds; a viewer's rate is (frames - 1) / (last arrival - first arrival). A viewer
 * with fewer than --min-frames frames by then keeps going until it has them (so the
 * slowest viewers run with less contention at the end: the rates are upper bounds).
 *
 * The scene is --scene, or a glass sphere of --resolution^3 voxels (proto/examples/
 * glass_sphere.json's shape) that the benchmark creates and deletes.
 */
#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "refract.h"

#define MAX_LIST 8
#define MAX_VIEWERS 64
#define MAX_SAMPLES 1024

struct options {
    const char *url;
    int sizes[MAX_LIST][2];
    int n_sizes;
    int viewers[MAX_LIST];
    int n_viewers;
    int patches;
    double seconds;
    int min_frames;
    const char *scene;
    int resolution;
    const char *quality;
};

static double now_ms(void)
{
    struct timespec ts;

    clock_gettime(CLOCK_MONOTONIC, &ts); /* the clock of refract_frame.arrival_ms */
    return (double)ts.tv_sec * 1000.0 + (double)ts.tv_nsec / 1e6;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a;
    double y = *(const double *)b;

    return (x > y) - (x < y);
}

/* Nearest-rank percentile (p in (0, 100]) of n samples; sorts them. */
static double percentile(double *v, int n, double p)
{
    int rank;

    if (n <= 0)
        return NAN;
    qsort(v, (size_t)n, sizeof(*v), cmp_double);
    rank = (int)ceil(p / 100.0 * n);
    return v[rank < 1 ? 0 : rank - 1];
}

/* The eye after `turn` steps of 10 degrees around the y axis through the origin, at the
 * glass sphere camera's distance and height. */
static void patch_body(char *buf, size_t size, int turn)
{
    double a = turn * 10.0 * M_PI / 180.0;

    snprintf(buf, size, "{\"camera\": {\"eye\": [%.6f, 1.0, %.6f], \"look_at\": [0, 0, 0]}}",
             3.7 * sin(a), 3.7 * cos(a));
}

/* ---- latency ------------------------------------------------------------------------ */

struct latency_run {
    refract_client *patcher;
    const char *view_id;
    int want; /* PATCHes */
    bool progressive;
    bool exposure; /* PATCH the exposure instead of the camera */
    int done;      /* PATCHes answered by a full frame */
    int turn;
    long long last_seq;
    bool waiting_first; /* a PATCH went out; its first frame has not come */
    double patch_ms;    /* when the last PATCH went out */
    double first[MAX_SAMPLES], full[MAX_SAMPLES], render[MAX_SAMPLES];
    int n_first, n_full, n_preview;
    int error;
};

static int send_patch(struct latency_run *r)
{
    char body[160];

    if (r->exposure)
        snprintf(body, sizeof body, "{\"exposure\": %.1f}", (++r->turn % 2) * 0.5);
    else
        patch_body(body, sizeof(body), ++r->turn);
    r->waiting_first = true;
    r->patch_ms = now_ms();
    r->error = refract_view_patch(r->patcher, r->view_id, body, NULL);
    return r->error != REFRACT_E_OK;
}

static int on_latency_frame(const struct refract_frame *f, void *user)
{
    struct latency_run *r = user;
    bool full = strcmp(f->kind, "preview") != 0;

    if (f->seq <= r->last_seq)
        return 0; /* a keep-alive resend */
    r->last_seq = f->seq;
    if (r->turn == 0)
        return full ? send_patch(r) : 0; /* the session's first frame: start */
    if (r->waiting_first) {
        r->waiting_first = false;
        r->first[r->n_first++] = f->arrival_ms - r->patch_ms;
        r->n_preview += !full;
    }
    if (!full)
        return 0;
    r->full[r->n_full] = f->arrival_ms - r->patch_ms;
    r->render[r->n_full++] = f->render_ms;
    if (++r->done >= r->want)
        return 1;
    return send_patch(r);
}

static int measure_latency(const struct options *o, const char *scene, int w, int h,
                           bool progressive, bool exposure)
{
    refract_client *c = refract_client_create(o->url);
    struct latency_run r = {
        .want = o->patches, .progressive = progressive, .exposure = exposure, .last_seq = -1};
    struct refract_view_options vo = {.width = w,
                                      .height = h,
                                      .quality = o->quality,
                                      .max_fps = 120,
                                      .progressive = progressive ? 1 : -1};
    struct refract_view v;
    int code;

    r.patcher = refract_client_create(o->url);
    code = refract_view_create_opts(c, scene, &vo, &v);
    if (code != REFRACT_E_OK) {
        fprintf(stderr, "refract-views: %s\n", refract_errmsg(c));
        refract_client_destroy(c);
        refract_client_destroy(r.patcher);
        return code;
    }
    r.view_id = v.id;
    code = refract_view_stream(c, v.id, on_latency_frame, &r);
    if (code != REFRACT_E_OK || r.error != REFRACT_E_OK)
        fprintf(stderr, "refract-views: latency %dx%d: %s\n", w, h,
                code != REFRACT_E_OK ? refract_errmsg(c) : refract_errmsg(r.patcher));
    refract_view_delete(r.patcher, v.id);
    refract_view_free(&v);
    if (progressive) {
        double first_med = percentile(r.first, r.n_first, 50);
        double first_p95 = percentile(r.first, r.n_first, 95);

        printf("| %dx%d | on | %d | first frame (%d of %d previews) | %.1f | %.1f | |\n", w, h,
               r.n_first, r.n_preview, r.n_first, first_med, first_p95);
    }
    {
        double med = percentile(r.full, r.n_full, 50);
        double p95 = percentile(r.full, r.n_full, 95);
        double render = percentile(r.render, r.n_full, 50);

        if (exposure)
            printf("| %dx%d | %s | %d | full frame after an exposure PATCH (re-encoded, not "
                   "rendered) | %.1f | %.1f | |\n",
                   w, h, progressive ? "on" : "off", r.n_full, med, p95);
        else
            printf("| %dx%d | %s | %d | full frame | %.1f | %.1f | %.1f |\n", w, h,
                   progressive ? "on" : "off", r.n_full, med, p95, render);
    }
    fflush(stdout);
    refract_client_destroy(c);
    refract_client_destroy(r.patcher);
    return code;
}

/* ---- frames per second --------------------------------------------------------------- */

struct viewer {
    const struct options *o;
    const char *scene;
    int w, h;
    int index;
    double deadline_ms;
    refract_client *patcher;
    char view_id[REFRACT_ID_SIZE];
    long long last_seq;
    int frames;
    int turn;
    double first_ms, last_ms;
    double render[MAX_SAMPLES];
    int code;
};

static int on_fps_frame(const struct refract_frame *f, void *user)
{
    struct viewer *v = user;
    char body[160];

    if (f->seq <= v->last_seq)
        return 0;
    v->last_seq = f->seq;
    if (v->frames == 0)
        v->first_ms = f->arrival_ms;
    v->last_ms = f->arrival_ms;
    if (v->frames < MAX_SAMPLES)
        v->render[v->frames] = f->render_ms;
    v->frames++;
    if (now_ms() >= v->deadline_ms && v->frames >= v->o->min_frames)
        return 1;
    patch_body(body, sizeof(body), ++v->turn + v->index * 9); /* viewers look differently */
    v->code = refract_view_patch(v->patcher, v->view_id, body, NULL);
    return v->code != REFRACT_E_OK;
}

static void *run_viewer(void *arg)
{
    struct viewer *v = arg;
    refract_client *c = refract_client_create(v->o->url);
    struct refract_view_options vo = {
        .width = v->w, .height = v->h, .quality = v->o->quality, .max_fps = 120, .progressive = -1};
    struct refract_view view;

    v->patcher = refract_client_create(v->o->url);
    v->last_seq = -1;
    v->code = refract_view_create_opts(c, v->scene, &vo, &view);
    if (v->code == REFRACT_E_OK) {
        snprintf(v->view_id, sizeof(v->view_id), "%s", view.id);
        refract_view_free(&view);
        v->code = refract_view_stream(c, v->view_id, on_fps_frame, v);
        refract_view_delete(v->patcher, v->view_id);
    }
    if (v->code != REFRACT_E_OK)
        fprintf(stderr, "refract-views: viewer %d: %s\n", v->index, refract_errmsg(c));
    refract_client_destroy(c);
    refract_client_destroy(v->patcher);
    return NULL;
}

static void measure_fps(const struct options *o, const char *scene, int w, int h, int n)
{
    static struct viewer viewers[MAX_VIEWERS];
    pthread_t threads[MAX_VIEWERS];
    double deadline = now_ms() + o->seconds * 1000.0;
    double sum = 0;
    double slowest = INFINITY;
    double renders[MAX_VIEWERS * 8];
    int n_renders = 0;
    int frames = 0;

    for (int i = 0; i < n; i++) {
        viewers[i] = (struct viewer){
            .o = o, .scene = scene, .w = w, .h = h, .index = i, .deadline_ms = deadline};
        pthread_create(&threads[i], NULL, run_viewer, &viewers[i]);
    }
    for (int i = 0; i < n; i++)
        pthread_join(threads[i], NULL);
    for (int i = 0; i < n; i++) {
        const struct viewer *v = &viewers[i];
        double fps = v->frames > 1 ? (v->frames - 1) * 1000.0 / (v->last_ms - v->first_ms) : 0;

        sum += fps;
        slowest = fps < slowest ? fps : slowest;
        frames += v->frames;
        for (int k = 1; k < v->frames && k < MAX_SAMPLES && n_renders < MAX_VIEWERS * 8; k++)
            renders[n_renders++] = v->render[k];
    }
    printf("| %dx%d | %d | %.2f | %.2f | %.2f | %d | %.1f |\n", w, h, n, sum / n, slowest, sum,
           frames, percentile(renders, n_renders, 50));
    fflush(stdout);
}

/* ---- set-up and report ------------------------------------------------------------- */

static bool parse_options(int argc, char **argv, struct options *o)
{
    const char *sizes = "640x480,1280x720";
    const char *viewers = "1,4,8";

    *o = (struct options){
        .patches = 30, .seconds = 10, .min_frames = 3, .resolution = 64, .quality = "normal"};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;

        if (a[0] != '-' && o->url == NULL) {
            o->url = a;
            continue;
        }
        if (val == NULL)
            return false;
        i++;
        if (strcmp(a, "--sizes") == 0)
            sizes = val;
        else if (strcmp(a, "--viewers") == 0)
            viewers = val;
        else if (strcmp(a, "--patches") == 0)
            o->patches = atoi(val);
        else if (strcmp(a, "--seconds") == 0)
            o->seconds = atof(val);
        else if (strcmp(a, "--min-frames") == 0)
            o->min_frames = atoi(val);
        else if (strcmp(a, "--scene") == 0)
            o->scene = val;
        else if (strcmp(a, "--resolution") == 0)
            o->resolution = atoi(val);
        else if (strcmp(a, "--quality") == 0)
            o->quality = val;
        else
            return false;
    }
    for (const char *p = sizes; *p != '\0' && o->n_sizes < MAX_LIST;) {
        int w, h, used = 0;

        if (sscanf(p, "%dx%d%n", &w, &h, &used) != 2 || w <= 0 || h <= 0)
            return false;
        o->sizes[o->n_sizes][0] = w;
        o->sizes[o->n_sizes++][1] = h;
        p += used;
        p += *p == ',';
    }
    for (const char *p = viewers; *p != '\0' && o->n_viewers < MAX_LIST;) {
        char *end;
        long n = strtol(p, &end, 10);

        if (end == p || n < 1 || n > MAX_VIEWERS)
            return false;
        o->viewers[o->n_viewers++] = (int)n;
        p = end + (*end == ',');
    }
    return o->url != NULL && o->patches > 0 && o->patches <= MAX_SAMPLES && o->seconds > 0 &&
           o->min_frames >= 2 && o->resolution >= 2;
}

/* GL_RENDERER and GL_VERSION of the daemon, from GET /v1/health. */
static void daemon_gpu(refract_client *c, char *renderer, char *version, size_t size)
{
    char *json = NULL;
    cJSON *root;
    const cJSON *gpu;
    const cJSON *r;
    const cJSON *v;

    snprintf(renderer, size, "unknown");
    snprintf(version, size, "unknown");
    if (refract_health(c, &json) != REFRACT_E_OK)
        return;
    root = cJSON_Parse(json);
    gpu = cJSON_GetObjectItemCaseSensitive(root, "gpu");
    r = cJSON_GetObjectItemCaseSensitive(gpu, "renderer");
    v = cJSON_GetObjectItemCaseSensitive(gpu, "version");
    if (cJSON_IsString(r))
        snprintf(renderer, size, "%s", r->valuestring);
    if (cJSON_IsString(v))
        snprintf(version, size, "%s", v->valuestring);
    cJSON_Delete(root);
    refract_free(json);
}

static void print_header(refract_client *c, int argc, char **argv)
{
    char cpu[300] = "unknown";
    char line[256];
    char renderer[256];
    char version[256];
    char date[32];
    time_t now = time(NULL);
    struct utsname u;
    FILE *f = fopen("/proc/cpuinfo", "r");

    while (f != NULL && fgets(line, sizeof(line), f) != NULL) {
        if (strncmp(line, "model name", 10) == 0 && strchr(line, ':') != NULL) {
            snprintf(cpu, sizeof(cpu), "%s", strchr(line, ':') + 2);
            cpu[strcspn(cpu, "\n")] = '\0';
            break;
        }
    }
    if (f != NULL)
        fclose(f);
    uname(&u);
    daemon_gpu(c, renderer, version, sizeof(renderer));
    strftime(date, sizeof(date), "%Y-%m-%d", gmtime(&now));
    printf("- date: %s\n- machine (of refract-views; refractd on the same one when URL is "
           "loopback): %s, %ld cores, %s %s\n- GL_RENDERER: %s\n- GL_VERSION: %s\n",
           date, cpu, sysconf(_SC_NPROCESSORS_ONLN), u.sysname, u.machine, renderer, version);
    printf("- command: `");
    for (int i = 0; i < argc; i++)
        printf("%s%s", i ? " " : "", argv[i]);
    printf("`\n\n");
}

static char *sphere_scene(int resolution)
{
    static const char fmt[] =
        "{\"name\": \"refract-views glass sphere\", \"camera\": {\"eye\": [0, 1.0, 3.7],"
        " \"look_at\": [0, 0, 0], \"fov_y_deg\": 40, \"width\": 640, \"height\": 480},"
        " \"objects\": [{\"name\": \"sphere\", \"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, "
        "1, 1]}, \"resolution\": %d, \"ior\": {\"shape\": \"sphere\", \"center\": [0, 0, 0],"
        " \"radius\": 0.8, \"inside\": 1.5}, \"attenuation\": {\"shape\": \"sphere\", \"center\":"
        " [0, 0, 0], \"radius\": 0.8, \"inside\": [0.02, 0.01, 0.02]}}]}";
    char *json = malloc(sizeof(fmt) + 16);

    if (json != NULL)
        snprintf(json, sizeof(fmt) + 16, fmt, resolution);
    return json;
}

int main(int argc, char **argv)
{
    struct options o;
    refract_client *c;
    char scene[REFRACT_ID_SIZE];
    bool own_scene;

    if (!parse_options(argc, argv, &o)) {
        fprintf(stderr, "usage: refract-views URL [--sizes 640x480,1280x720] [--viewers 1,4,8]"
                        " [--patches 30] [--seconds 10] [--min-frames 3] [--scene ID]"
                        " [--resolution 64] [--quality normal]\n");
        return 2;
    }
    c = refract_client_create(o.url);
    own_scene = o.scene == NULL;
    if (own_scene) {
        char *json = sphere_scene(o.resolution);

        if (json == NULL ||
            refract_scene_create(c, json, strlen(json), scene, sizeof(scene)) != REFRACT_E_OK) {
            fprintf(stderr, "refract-views: %s\n", refract_errmsg(c));
            free(json);
            refract_client_destroy(c);
            return 1;
        }
        free(json);
    } else {
        snprintf(scene, sizeof(scene), "%s", o.scene);
    }
    print_header(c, argc, argv);
    printf("Scene: %s (%s), quality %s.\n\n", own_scene ? "a glass sphere" : scene,
           own_scene ? "created by the benchmark" : "given", o.quality);
    printf("Latency from a camera (or exposure) PATCH to the first byte of the next frame "
           "(ms):\n\n"
           "| image | progressive | PATCHes | next frame | median ms | p95 ms | render ms "
           "(median) |\n|---|---|---|---|---|---|---|\n");
    for (int s = 0; s < o.n_sizes; s++) {
        measure_latency(&o, scene, o.sizes[s][0], o.sizes[s][1], false, false);
        measure_latency(&o, scene, o.sizes[s][0], o.sizes[s][1], true, false);
        measure_latency(&o, scene, o.sizes[s][0], o.sizes[s][1], false, true);
    }
    printf("\nFrames per second per viewer, each viewer PATCHing its camera after every frame "
           "(progressive off, %.0f s):\n\n"
           "| image | viewers | fps per viewer (mean) | slowest viewer | all viewers | frames | "
           "render ms (median) |\n|---|---|---|---|---|---|---|\n",
           o.seconds);
    for (int s = 0; s < o.n_sizes; s++)
        for (int k = 0; k < o.n_viewers; k++)
            measure_fps(&o, scene, o.sizes[s][0], o.sizes[s][1], o.viewers[k]);
    if (own_scene)
        refract_scene_delete(c, scene);
    refract_client_destroy(c);
    return 0;
}
