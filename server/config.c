/*
 * config.c - flags and config file for refractd, from one table: each option's name,
 * kind, limits, default and help line. --help prints the table; deploy/refractd.conf
 * documents the same keys.
 */
#include "config.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bindings.h"
#include "core/log.h"

enum opt_kind { OPT_INT, OPT_SIZE, OPT_REAL, OPT_STRING, OPT_FLAG, OPT_GPU, OPT_LOG, OPT_CONFIG };

/* OPT_REAL values must lie in (0, REAL_MAX]: tolerances. */
#define REAL_MAX 1.0

struct option_def {
    const char *name;
    enum opt_kind kind;
    long long min, max;
    const char *arg;
    const char *help;
};

static const struct option_def options[] = {
    {"bind", OPT_STRING, 0, 0, "ADDR", "IPv4 address to listen on (default 127.0.0.1)"},
    {"port", OPT_INT, 0, 65535, "N", "TCP port (default 8750; 0 = any free port)"},
    {"allow-host", OPT_STRING, 0, 0, "NAME",
     "also serve requests whose Host is NAME (repeatable; loopback names and the --bind "
     "address always; * = any)"},
    {"token-file", OPT_STRING, 0, 0, "FILE",
     "require \"Authorization: Bearer TOKEN\" (TOKEN: FILE's first line) on every route "
     "but GET /v1/health and the viewer pages"},
    {"trusted-proxy", OPT_FLAG, 0, 0, NULL,
     "allow a non-loopback --bind without --token-file (a proxy in front authenticates)"},
    {"tls-cert", OPT_STRING, 0, 0, "FILE", "serve https with this PEM certificate (chain)"},
    {"tls-key", OPT_STRING, 0, 0, "FILE", "the PEM private key of --tls-cert"},
    {"port-file", OPT_STRING, 0, 0, "FILE", "write the bound port to FILE once listening"},
    {"data-dir", OPT_STRING, 0, 0, "DIR",
     "where scenes and uploads persist (default $XDG_STATE_HOME/refract)"},
    {"scene-dir", OPT_STRING, 0, 0, "DIR",
     "load every *.json in DIR at start-up as a scene whose id is the file name"},
    {"shader-dir", OPT_STRING, 0, 0, "DIR", "read GLSL from DIR instead of the embedded copy"},
    {"gpu", OPT_GPU, 0, 0, "auto|hardware|software",
     "EGL device choice (default auto: a hardware GPU if any; env REFRACT_GPU)"},
    {"gpu-device", OPT_INT, -1, 64, "N", "use EGL device N (see the log's device list)"},
    {"gl-debug", OPT_FLAG, 0, 0, NULL, "log KHR_debug messages from the GL driver"},
    {"threads", OPT_INT, 1, 256, "N", "HTTP worker threads (default 4)"},
    {"max-queued", OPT_INT, 1, 1000000, "N", "GPU queue length before 503 busy (default 256)"},
    {"request-timeout-ms", OPT_INT, 100, 86400000, "MS",
     "deadline for a request's GPU work: every tile of a render must start before it "
     "(default 120000)"},
    {"max-connections", OPT_INT, 1, 1000000, "N",
     "open connections at most; beyond, 503 busy (default 2048)"},
    {"max-connections-per-ip", OPT_INT, 0, 1000000, "N",
     "open connections of one client address; beyond, 429 (default 256; 0 = no limit)"},
    {"max-queued-per-client", OPT_INT, 0, 1000000, "N",
     "renders and traces of one client address queued or running; beyond, 429 (default 64; "
     "0 = no limit)"},
    {"header-timeout", OPT_INT, 1, 3600, "S",
     "close a connection silent for S seconds before its request's headers and body are in, "
     "or between keep-alive requests (default 10)"},
    {"header-deadline", OPT_INT, 0, 86400, "S",
     "close a connection whose request's headers and body (not an upload's body) are not in "
     "S seconds after it began, however they trickle in (default 30; 0 = no deadline)"},
    {"upload-min-rate", OPT_SIZE, 0, 1ll << 40, "BYTES",
     "an upload's body must arrive at BYTES per second on average once --header-deadline is "
     "spent, or it is closed and its file removed (default 1K; 0 = no minimum)"},
    {"connection-timeout", OPT_INT, 1, 86400, "S",
     "close a connection silent for S seconds while it is answered (default 300)"},
    {"render-tile-pixels", OPT_SIZE, 1, 1ll << 28, "N",
     "pixels a render, view frame or job frame draws per GPU turn; larger ones are drawn in "
     "tiles of rows with other work between (default 64K)"},
    {"max-json-bytes", OPT_SIZE, 1024, 1ll << 32, "BYTES", "JSON body limit (default 8M)"},
    {"max-upload-bytes", OPT_SIZE, 1024, 1ll << 40, "BYTES", "upload body limit (default 1G)"},
    {"max-storage-bytes", OPT_SIZE, 0, 1ll << 50, "BYTES",
     "total bytes of the data directory's blobs (uploads); 0 = unlimited (default 10G)"},
    {"max-rays", OPT_INT, 1, 100000000, "N", "rays per trace request (default 65536)"},
    {"max-resolution", OPT_INT, 2, 4096, "N", "voxels per axis of an object (default 512)"},
    {"max-voxels", OPT_SIZE, 8, 1ll << 36, "N", "voxels per scene (default 64M)"},
    {"max-upload-voxels", OPT_SIZE, 1, 1ll << 36, "N",
     "decoded voxels of one uploaded volume (default 32M, e.g. 512x512x128)"},
    {"max-objects", OPT_INT, 1, MAX_OBJECTS, "N", "objects per scene (default 8, at most 8)"},
    {"max-layers", OPT_INT, 1, 100000, "N", "layers per channel (default 64)"},
    {"max-profile-points", OPT_INT, 3, 1000000, "N", "lathe profile points (default 1024)"},
    {"max-text-length", OPT_INT, 1, 100000, "N", "characters of a text shape (default 64)"},
    {"max-image-dim", OPT_INT, 1, 16384, "N", "image width/height (default 4096)"},
    {"max-image-pixels", OPT_SIZE, 1, 1ll << 28, "N",
     "width x height of a render (default 16M = 4096x4096)"},
    {"max-env-pixels", OPT_SIZE, 1, 1ll << 30, "N",
     "pixels of an uploaded environment image (default 8M = 4096x2048)"},
    {"max-steps", OPT_INT, 1, 10000000, "N", "integration steps per ray (default 100000)"},
    {"max-samples-per-pixel", OPT_INT, 1, 4096, "N",
     "jittered rays per pixel of a render or view (default 64)"},
    {"max-reference-samples", OPT_INT, 1, 1 << 30, "N",
     "samples per pixel of a \"mode\": \"reference\" render (default 65536)"},
    {"max-reference-ms", OPT_INT, 1, 86400000, "MS",
     "time a \"mode\": \"reference\" render may take (default 120000)"},
    {"max-mesh-triangles", OPT_SIZE, 1, 1ll << 31, "N",
     "triangles of an uploaded mesh, after splitting polygons (default 2M)"},
    {"max-scenes", OPT_INT, 1, 1000000, "N", "scenes held (default 64)"},
    {"gpu-scene-budget", OPT_SIZE, 1 << 20, 1ll << 40, "BYTES",
     "GPU memory for cached scenes before LRU eviction (default 2G)"},
    {"irradiance-gpu-budget", OPT_SIZE, 1, 1ll << 40, "BYTES",
     "GPU memory for cached irradiance volumes before LRU eviction (default 1G)"},
    {"irradiance-host-budget", OPT_SIZE, 1, 1ll << 40, "BYTES",
     "host memory for cached irradiance volumes (they stay on disk; default 2G)"},
    {"irradiance-disk-budget", OPT_SIZE, 1, 1ll << 50, "BYTES",
     "disk for cached irradiance volumes under DATA/irradiance before LRU removal "
     "(default 8G)"},
    {"light-position-tolerance", OPT_REAL, 0, 0, "UNITS",
     "light moves below this (world units) reuse the cached irradiance (default 0.001)"},
    {"light-direction-tolerance", OPT_REAL, 0, 0, "RAD",
     "light turns below this (radians) reuse the cached irradiance (default 0.001)"},
    {"lightsim-chunk-steps", OPT_INT, 1, 100000, "N",
     "wavefront steps per GPU work item of a light simulation (default 16)"},
    {"max-job-frames", OPT_INT, 1, 10000000, "N",
     "frames of one batch job (POST /v1/jobs) at most (default 10000)"},
    {"max-views", OPT_INT, 1, 100000, "N",
     "open view sessions (POST /v1/scenes/{id}/views) at most (default 64)"},
    {"view-idle-timeout", OPT_INT, 1, 604800, "S",
     "end a view session after S seconds without a request or an open stream (default 120)"},
    {"view-encoder-threads", OPT_INT, 1, 64, "N",
     "threads that tone-map and JPEG-encode view frames (default 2)"},
    {"event-history", OPT_INT, 1, 1000000, "N",
     "events kept for SSE clients that reconnect with Last-Event-ID (default 1024)"},
    {"batch", OPT_STRING, 0, 0, "JOB.json",
     "one-shot: render frames of this job specification (POST /v1/jobs's) into --out, "
     "without HTTP, then exit (docs/slurm.md)"},
    {"frames", OPT_STRING, 0, 0, "A-B", "--batch: the frames to render (0-based, inclusive)"},
    {"task", OPT_STRING, 0, 0, "I/N",
     "--batch: render task I's share of N tasks (0-based; Slurm array, Kubernetes Indexed Job)"},
    {"out", OPT_STRING, 0, 0, "DIR",
     "--batch: the output directory the tasks share (frame_NNNNN.<ext>, progress.json)"},
    {"log-level", OPT_LOG, 0, 0, "debug|info|warn|error", "log verbosity (default info)"},
    {"config", OPT_CONFIG, 0, 0, "FILE", "read 'key value' lines with these option names"},
    {"help", OPT_FLAG, 0, 0, NULL, "print this help"},
    {"version", OPT_FLAG, 0, 0, NULL, "print the version"},
};

#define OPTION_COUNT (sizeof options / sizeof options[0])

void config_defaults(struct config *c)
{
    memset(c, 0, sizeof *c);
    c->http.bind_address = "127.0.0.1";
    c->http.port = 8750;
    c->http.threads = 4;
    c->http.max_json_bytes = (size_t)8 << 20;
    c->http.max_upload_bytes = (size_t)1 << 30;
    c->http.max_rays = 65536;
    c->http.request_timeout_ms = 120000;
    c->http.max_connections = 2048;
    c->http.max_connections_per_ip = 256;
    c->http.max_queued_per_client = 64;
    c->http.header_timeout_s = 10;
    c->http.header_deadline_s = 30;
    c->http.upload_min_rate = 1024;
    c->http.connection_timeout_s = 300;
    c->http.render_tile_pixels = 65536;
    c->http.limits = scene_limits_default();
    c->gpu.context.device = GPU_DEVICE_AUTO;
    c->gpu.context.device_index = -1;
    c->gpu.max_queued = 256;
    c->gpu_scene_budget_bytes = (size_t)2 << 30;
    c->irradiance.gpu_budget_bytes = (size_t)1 << 30;
    c->irradiance.host_budget_bytes = (size_t)2 << 30;
    c->irradiance.disk_budget_bytes = (size_t)8 << 30;
    c->irradiance.position_tolerance = 1e-3;
    c->irradiance.direction_tolerance = 1e-3;
    c->irradiance.chunk_steps = 16;
    c->max_scenes = 64;
    c->views.max_views = 64;
    c->max_job_frames = 10000;
    c->views.idle_timeout_s = 120;
    c->views.encoder_threads = 2;
    c->event_history = 1024;
    /* Finite defaults against amplification (docs/api.md "Limits"): a 49 KB PNG of
     * 4096 x 4096 pixels decodes to 256 MiB of float RGBA, and an unlimited data directory
     * fills its disk. */
    c->max_env_pixels = 8ll << 20;
    c->max_storage_bytes = 10ull << 30;
    c->http.max_image_pixels = 4096LL * 4096;
    c->log_level = LOG_INFO;
    const char *state = getenv("XDG_STATE_HOME");
    const char *home = getenv("HOME");
    if (state && state[0])
        snprintf(c->data_dir, sizeof c->data_dir, "%s/refract", state);
    else
        snprintf(c->data_dir, sizeof c->data_dir, "%s/.local/state/refract",
                 home && home[0] ? home : "/tmp");
}

void config_print_usage(const char *argv0)
{
    printf("usage: %s [options]\n\nrefractd renders refractive volumes on the GPU and serves "
           "them over HTTP/JSON\n(proto/openapi.yaml). Sizes accept K, M and G suffixes.\n\n",
           argv0);
    for (size_t i = 0; i < OPTION_COUNT; i++) {
        char left[64];
        snprintf(left, sizeof left, "--%s%s%s", options[i].name, options[i].arg ? " " : "",
                 options[i].arg ? options[i].arg : "");
        printf("  %-34s %s\n", left, options[i].help);
    }
}

static bool parse_number(const char *text, bool with_suffix, long long *out)
{
    errno = 0;
    char *end = NULL;
    long long v = strtoll(text, &end, 10);
    if (end == text || errno != 0)
        return false;
    if (with_suffix && *end) {
        long long mult = *end == 'K' || *end == 'k'   ? 1ll << 10
                         : *end == 'M' || *end == 'm' ? 1ll << 20
                         : *end == 'G' || *end == 'g' ? 1ll << 30
                                                      : 0;
        if (mult == 0 || end[1] != '\0')
            return false;
        v *= mult;
    } else if (*end) {
        return false;
    }
    *out = v;
    return true;
}

static void copy_str(char *dst, size_t size, const char *src)
{
    snprintf(dst, size, "%s", src);
}

static void store_int(struct config *c, const char *name, long long v)
{
    struct scene_limits *l = &c->http.limits;
    if (!strcmp(name, "port"))
        c->http.port = (int)v;
    else if (!strcmp(name, "gpu-device"))
        c->gpu.context.device_index = (int)v;
    else if (!strcmp(name, "threads"))
        c->http.threads = (int)v;
    else if (!strcmp(name, "max-queued"))
        c->gpu.max_queued = (size_t)v;
    else if (!strcmp(name, "request-timeout-ms"))
        c->http.request_timeout_ms = (int)v;
    else if (!strcmp(name, "max-connections"))
        c->http.max_connections = (int)v;
    else if (!strcmp(name, "max-connections-per-ip"))
        c->http.max_connections_per_ip = (int)v;
    else if (!strcmp(name, "max-queued-per-client"))
        c->http.max_queued_per_client = (int)v;
    else if (!strcmp(name, "header-timeout"))
        c->http.header_timeout_s = (int)v;
    else if (!strcmp(name, "header-deadline"))
        c->http.header_deadline_s = (int)v;
    else if (!strcmp(name, "upload-min-rate"))
        c->http.upload_min_rate = v;
    else if (!strcmp(name, "connection-timeout"))
        c->http.connection_timeout_s = (int)v;
    else if (!strcmp(name, "render-tile-pixels"))
        c->http.render_tile_pixels = v;
    else if (!strcmp(name, "max-json-bytes"))
        c->http.max_json_bytes = (size_t)v;
    else if (!strcmp(name, "max-upload-bytes"))
        c->http.max_upload_bytes = (size_t)v;
    else if (!strcmp(name, "max-storage-bytes"))
        c->max_storage_bytes = (unsigned long long)v;
    else if (!strcmp(name, "max-rays"))
        c->http.max_rays = (int)v;
    else if (!strcmp(name, "max-resolution"))
        l->max_resolution = (int)v;
    else if (!strcmp(name, "max-voxels"))
        l->max_voxels = v;
    else if (!strcmp(name, "max-upload-voxels"))
        l->max_upload_voxels = v;
    else if (!strcmp(name, "max-objects"))
        l->max_objects = (int)v;
    else if (!strcmp(name, "max-layers"))
        l->max_layers = (int)v;
    else if (!strcmp(name, "max-profile-points"))
        l->max_profile_points = (int)v;
    else if (!strcmp(name, "max-text-length"))
        l->max_text_length = (int)v;
    else if (!strcmp(name, "max-image-dim"))
        l->max_image_dim = (int)v;
    else if (!strcmp(name, "max-steps"))
        l->max_steps = (int)v;
    else if (!strcmp(name, "max-samples-per-pixel"))
        l->max_samples_per_pixel = (int)v;
    else if (!strcmp(name, "max-reference-samples"))
        c->http.max_reference_samples = (int)v;
    else if (!strcmp(name, "max-reference-ms"))
        c->http.max_reference_ms = (int)v;
    else if (!strcmp(name, "max-mesh-triangles"))
        l->max_mesh_triangles = v;
    else if (!strcmp(name, "max-scenes"))
        c->max_scenes = (int)v;
    else if (!strcmp(name, "max-image-pixels"))
        c->http.max_image_pixels = v;
    else if (!strcmp(name, "max-env-pixels"))
        c->max_env_pixels = v;
    else if (!strcmp(name, "gpu-scene-budget"))
        c->gpu_scene_budget_bytes = (size_t)v;
    else if (!strcmp(name, "irradiance-gpu-budget"))
        c->irradiance.gpu_budget_bytes = (size_t)v;
    else if (!strcmp(name, "irradiance-host-budget"))
        c->irradiance.host_budget_bytes = (size_t)v;
    else if (!strcmp(name, "irradiance-disk-budget"))
        c->irradiance.disk_budget_bytes = (size_t)v;
    else if (!strcmp(name, "lightsim-chunk-steps"))
        c->irradiance.chunk_steps = (int)v;
    else if (!strcmp(name, "max-job-frames"))
        c->max_job_frames = (int)v;
    else if (!strcmp(name, "max-views"))
        c->views.max_views = (int)v;
    else if (!strcmp(name, "view-idle-timeout"))
        c->views.idle_timeout_s = (double)v;
    else if (!strcmp(name, "view-encoder-threads"))
        c->views.encoder_threads = (int)v;
    else if (!strcmp(name, "event-history"))
        c->event_history = (size_t)v;
}

static enum refract_code config_parse_file(struct config *c, const char *path, struct err *e);

/* --allow-host NAME: a host name, an IPv4 address, an [IPv6] address, or "*". */
static enum refract_code add_allow_host(struct config *c, const char *value, struct err *e)
{
    size_t n = c->http.allow_host_count;
    size_t len = strlen(value);
    if (len == 0 || len >= sizeof c->allow_host_names[0] ||
        strspn(value, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789.-_[]:*") !=
            len ||
        (strchr(value, '*') != NULL && strcmp(value, "*") != 0))
        return err_set(e, REFRACT_E_USAGE,
                       "--allow-host %.80s: expected a host name or address without port "
                       "(example.org, 192.0.2.7, [2001:db8::1]) or * for any",
                       value);
    if (value[0] != '[' && strchr(value, ':') != NULL)
        return err_set(e, REFRACT_E_USAGE,
                       "--allow-host %.80s: give the name without a port (any port is served); "
                       "write an IPv6 address in brackets ([2001:db8::1])",
                       value);
    if (n >= CONFIG_MAX_ALLOW_HOSTS)
        return err_set(e, REFRACT_E_USAGE, "--allow-host: at most %d names",
                       CONFIG_MAX_ALLOW_HOSTS);
    copy_str(c->allow_host_names[n], sizeof c->allow_host_names[n], value);
    c->allow_hosts[n] = c->allow_host_names[n];
    c->http.allow_hosts = c->allow_hosts;
    c->http.allow_host_count = n + 1;
    return REFRACT_E_OK;
}

/* Applies one option; value may be NULL for flags. */
static enum refract_code apply(struct config *c, const struct option_def *o, const char *value,
                               struct err *e)
{
    switch (o->kind) {
    case OPT_FLAG:
        if (!strcmp(o->name, "gl-debug"))
            c->gpu.context.debug = true;
        else if (!strcmp(o->name, "trusted-proxy"))
            c->trusted_proxy = true;
        else if (!strcmp(o->name, "help"))
            c->help = true;
        else
            c->version = true;
        return REFRACT_E_OK;
    case OPT_INT:
    case OPT_SIZE: {
        long long v = 0;
        if (!parse_number(value, o->kind == OPT_SIZE, &v) || v < o->min || v > o->max)
            return err_set(e, REFRACT_E_USAGE, "--%s %s: expected %s in %lld..%lld", o->name, value,
                           o->kind == OPT_SIZE ? "a size (K/M/G suffix allowed)" : "an integer",
                           o->min, o->max);
        store_int(c, o->name, v);
        return REFRACT_E_OK;
    }
    case OPT_REAL: {
        errno = 0;
        char *end = NULL;
        double v = strtod(value, &end);
        if (end == value || *end != '\0' || errno != 0 || !(v > 0) || v > REAL_MAX)
            return err_set(e, REFRACT_E_USAGE, "--%s %s: expected a number in (0, %g]", o->name,
                           value, REAL_MAX);
        if (!strcmp(o->name, "light-position-tolerance"))
            c->irradiance.position_tolerance = v;
        else
            c->irradiance.direction_tolerance = v;
        return REFRACT_E_OK;
    }
    case OPT_STRING:
        if (!strcmp(o->name, "bind")) {
            static char bind[64];
            copy_str(bind, sizeof bind, value);
            c->http.bind_address = bind;
        } else if (!strcmp(o->name, "data-dir")) {
            copy_str(c->data_dir, sizeof c->data_dir, value);
            c->data_dir_given = true;
        } else if (!strcmp(o->name, "batch")) {
            copy_str(c->batch, sizeof c->batch, value);
        } else if (!strcmp(o->name, "frames")) {
            copy_str(c->batch_frames, sizeof c->batch_frames, value);
        } else if (!strcmp(o->name, "task")) {
            copy_str(c->batch_task, sizeof c->batch_task, value);
        } else if (!strcmp(o->name, "out")) {
            copy_str(c->batch_out, sizeof c->batch_out, value);
        } else if (!strcmp(o->name, "scene-dir")) {
            copy_str(c->scene_dir, sizeof c->scene_dir, value);
        } else if (!strcmp(o->name, "shader-dir")) {
            copy_str(c->shader_dir, sizeof c->shader_dir, value);
        } else if (!strcmp(o->name, "port-file")) {
            copy_str(c->port_file, sizeof c->port_file, value);
        } else if (!strcmp(o->name, "token-file")) {
            copy_str(c->token_file, sizeof c->token_file, value);
        } else if (!strcmp(o->name, "tls-cert")) {
            copy_str(c->tls_cert, sizeof c->tls_cert, value);
        } else if (!strcmp(o->name, "tls-key")) {
            copy_str(c->tls_key, sizeof c->tls_key, value);
        } else if (!strcmp(o->name, "allow-host")) {
            return add_allow_host(c, value, e);
        }
        return REFRACT_E_OK;
    case OPT_GPU: {
        int pref = gpu_device_pref_parse(value);
        if (pref < 0)
            return err_set(e, REFRACT_E_USAGE, "--gpu %s: expected auto, hardware or software",
                           value);
        c->gpu.context.device = (enum gpu_device_pref)pref;
        return REFRACT_E_OK;
    }
    case OPT_LOG: {
        int level = log_level_parse(value);
        if (level < 0)
            return err_set(e, REFRACT_E_USAGE,
                           "--log-level %s: expected debug, info, warn or error", value);
        c->log_level = level;
        return REFRACT_E_OK;
    }
    case OPT_CONFIG:
        return config_parse_file(c, value, e);
    }
    return REFRACT_E_OK;
}

static const struct option_def *find_option(const char *name)
{
    for (size_t i = 0; i < OPTION_COUNT; i++) {
        if (strcmp(options[i].name, name) == 0)
            return &options[i];
    }
    return NULL;
}

static enum refract_code config_parse_file(struct config *c, const char *path, struct err *e)
{
    FILE *f = fopen(path, "r");
    if (f == NULL)
        return err_set(e, REFRACT_E_USAGE, "--config %s: %s", path, strerror(errno));
    char line[1024];
    int line_no = 0;
    enum refract_code rc = REFRACT_E_OK;
    while (rc == REFRACT_E_OK && fgets(line, sizeof line, f)) {
        line_no++;
        char *p = line + strspn(line, " \t");
        if (*p == '#' || *p == '\n' || *p == '\0')
            continue;
        p[strcspn(p, "\r\n")] = '\0';
        size_t end = strlen(p); /* trailing blanks are not part of the value */
        while (end > 0 && (p[end - 1] == ' ' || p[end - 1] == '\t'))
            p[--end] = '\0';
        char *value = p + strcspn(p, " \t");
        if (*value) {
            *value++ = '\0';
            value += strspn(value, " \t");
        }
        const struct option_def *o = find_option(p);
        if (o == NULL || o->kind == OPT_CONFIG)
            rc = err_set(e, REFRACT_E_USAGE,
                         "%s:%d: unknown key \"%s\" (refractd --help lists "
                         "the keys)",
                         path, line_no, p);
        else if (o->kind != OPT_FLAG && *value == '\0')
            rc = err_set(e, REFRACT_E_USAGE, "%s:%d: %s needs a value", path, line_no, p);
        else if ((rc = apply(c, o, value, e)) != REFRACT_E_OK) {
            char inner[sizeof e->msg];
            snprintf(inner, sizeof inner, "%s", e->msg);
            err_set(e, rc, "%s:%d: %s", path, line_no, inner);
        }
    }
    fclose(f);
    return rc;
}

enum refract_code config_parse_args(struct config *c, int argc, char **argv, struct err *e)
{
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (strncmp(arg, "--", 2) != 0)
            return err_set(e, REFRACT_E_USAGE, "unexpected argument \"%s\" (refractd --help)", arg);
        char name[64];
        const char *eq = strchr(arg + 2, '=');
        size_t len = eq ? (size_t)(eq - arg - 2) : strlen(arg + 2);
        if (len >= sizeof name)
            return err_set(e, REFRACT_E_USAGE, "unknown option %s (refractd --help)", arg);
        memcpy(name, arg + 2, len);
        name[len] = '\0';
        const struct option_def *o = find_option(name);
        if (o == NULL)
            return err_set(e, REFRACT_E_USAGE, "unknown option --%s (refractd --help)", name);
        const char *value = eq ? eq + 1 : NULL;
        if (o->kind != OPT_FLAG && value == NULL) {
            if (i + 1 >= argc)
                return err_set(e, REFRACT_E_USAGE, "--%s needs a value: %s", name, o->arg);
            value = argv[++i];
        }
        enum refract_code rc = apply(c, o, value, e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    if (!c->batch[0] && (c->batch_frames[0] || c->batch_task[0] || c->batch_out[0]))
        return err_set(e, REFRACT_E_USAGE,
                       "--frames, --task and --out belong to --batch JOB.json (docs/slurm.md)");
    if (c->batch[0] && !c->batch_out[0])
        return err_set(e, REFRACT_E_USAGE,
                       "--batch needs --out DIR: the directory that receives the frames");
    /* A misspelt REFRACT_GPU must not silently mean auto. */
    const char *env = getenv("REFRACT_GPU");
    if (env != NULL && env[0] != '\0' && gpu_device_pref_parse(env) < 0)
        return err_set(e, REFRACT_E_USAGE,
                       "REFRACT_GPU=%s: expected auto, hardware or software (or unset it)", env);
    return REFRACT_E_OK;
}

/* Reads a whole small file (at most max bytes) into a new NUL-terminated string. */
static char *read_small_file(const char *flag, const char *path, size_t max, struct err *e)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        err_set(e, REFRACT_E_USAGE, "--%s %s: %s", flag, path, strerror(errno));
        return NULL;
    }
    char *buf = malloc(max + 1);
    size_t got = buf ? fread(buf, 1, max + 1, f) : 0;
    bool failed = ferror(f) != 0;
    fclose(f);
    if (buf == NULL || failed || got > max) {
        err_set(e, REFRACT_E_USAGE, "--%s %s: %s", flag, path,
                buf == NULL ? "out of memory"
                : failed    ? "cannot read it"
                            : "larger than expected: is it the right file?");
        free(buf);
        return NULL;
    }
    buf[got] = '\0';
    return buf;
}

static bool is_loopback(const char *address)
{
    return strncmp(address, "127.", 4) == 0;
}

static enum refract_code load_token(struct config *c, struct err *e)
{
    char *text = read_small_file("token-file", c->token_file, 4096, e);
    if (text == NULL)
        return REFRACT_E_USAGE;
    size_t len = strcspn(text, "\r\n"); /* the first line */
    while (len > 0 && (text[len - 1] == ' ' || text[len - 1] == '\t'))
        len--;
    size_t start = strspn(text, " \t");
    enum refract_code rc = REFRACT_E_OK;
    if (start >= len || len - start < 16 || len - start >= sizeof c->token) {
        rc = err_set(e, REFRACT_E_USAGE,
                     "--token-file %s: the first line must hold a token of 16 to %zu "
                     "characters (make one with: head -c 32 /dev/urandom | base64 > FILE)",
                     c->token_file, sizeof c->token - 1);
    } else {
        for (size_t i = start; i < len && rc == REFRACT_E_OK; i++) {
            if (text[i] <= 0x20 || text[i] >= 0x7f)
                rc = err_set(e, REFRACT_E_USAGE,
                             "--token-file %s: the token may hold only visible ASCII characters "
                             "(no spaces; base64 or hex is fine)",
                             c->token_file);
        }
    }
    if (rc == REFRACT_E_OK) {
        memcpy(c->token, text + start, len - start);
        c->token[len - start] = '\0';
        c->http.token = c->token;
    }
    memset(text, 0, strlen(text));
    free(text);
    return rc;
}

enum refract_code config_load_secrets(struct config *c, struct err *e)
{
    if (c->token_file[0] && load_token(c, e) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if ((c->tls_cert[0] != '\0') != (c->tls_key[0] != '\0'))
        return err_set(e, REFRACT_E_USAGE,
                       "--tls-cert and --tls-key go together: give both (a PEM certificate and "
                       "its private key) or neither");
    if (c->tls_cert[0]) {
        c->tls_cert_pem = read_small_file("tls-cert", c->tls_cert, 1 << 20, e);
        if (c->tls_cert_pem == NULL)
            return REFRACT_E_USAGE;
        c->tls_key_pem = read_small_file("tls-key", c->tls_key, 1 << 20, e);
        if (c->tls_key_pem == NULL)
            return REFRACT_E_USAGE;
        c->http.tls_cert_pem = c->tls_cert_pem;
        c->http.tls_key_pem = c->tls_key_pem;
    }
    if (!is_loopback(c->http.bind_address) && c->token[0] == '\0' && !c->trusted_proxy)
        return err_set(e, REFRACT_E_USAGE,
                       "--bind %s is reachable from other machines, and without a token every "
                       "route (deletes and uploads included) would be open to them. Give "
                       "--token-file FILE (clients send the token as a bearer token), or "
                       "--trusted-proxy when a proxy in front of refractd authenticates its "
                       "clients; or bind 127.0.0.1",
                       c->http.bind_address);
    return REFRACT_E_OK;
}

void config_free(struct config *c)
{
    if (c->tls_key_pem)
        memset(c->tls_key_pem, 0, strlen(c->tls_key_pem));
    free(c->tls_cert_pem);
    free(c->tls_key_pem);
    c->tls_cert_pem = c->tls_key_pem = NULL;
    memset(c->token, 0, sizeof c->token);
}
