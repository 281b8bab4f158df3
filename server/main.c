/*
 * main.c - refractd's start-up and orderly shutdown, and nothing else.
 *
 * Start-up: flags -> the GPU thread (EGL context, shaders compiled: a bad shader stops
 * start-up here) -> the renderer on that thread -> the data directory -> the irradiance
 * cache (indexes <data>/irradiance) -> demo scenes ->
 * the HTTP server -> background builds of every scene's GPU data. Then the main thread
 * waits for SIGINT or SIGTERM.
 *
 * Shutdown order:
 *   1. answer new requests 503 shutting_down (quiesce); stop the view registry (view_registry_stop:
 *      it stops following events, ends every view session, so their frame streams end,
 *      waits for the frames in flight, which need the GPU thread still running, and joins
 *      its scheduler and encoder threads); end every open stream (frame streams, event
 *      streams: a suspended stream connection would never complete);
 *   2. stop the GPU thread (gpu_stop): pending requests complete with "shutting_down",
 *      which resumes every suspended connection; the renderer frees its GL objects on the
 *      GPU thread, then the context is destroyed. The gpu struct stays valid: resumed
 *      handlers still read its renderer string, late submits get "shutting_down";
 *   3. wait (briefly) until the resumed requests have been answered, stop the HTTP daemon;
 *   4. free the gpu struct; free the view registry (no stream holds a session any more);
 *      stop the irradiance cache's worker (it finishes writing computed volumes to the
 *      data directory); close the store; free the event hub.
 *
 * Batch mode (--batch, docs/slurm.md) starts the same way up to the irradiance cache and
 * the --scene-dir scenes, renders its frames on the main thread (job_batch_run; SIGINT and
 * SIGTERM stop it before the next tile) and shuts down from step 2, with no HTTP,
 * views or job runner. Without --data-dir it uses a private temporary data directory,
 * removed at exit.
 */
#include <dirent.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cache/irradiance_cache.h"
#include "cache/irradiance_index.h"
#include "config.h"
#include "core/log.h"
#include "events/events.h"
#include "http/http.h"
#include "lightsim/gpu/lightsim_gpu.h"
#include "render/render.h"
#include "store/store.h"
#include "jobs/jobs.h"
#include "view/view.h"

struct render_create_work {
    struct gpu_work work;
    struct render_desc desc;
    struct render *render;
};

static void render_create_run(struct gpu_work *w, struct gpu *gpu)
{
    struct render_create_work *rc = w->user;
    /* The light simulator's programs too, so a shader error stops start-up. */
    if (lightsim_gpu_init(gpu, &w->err) != REFRACT_E_OK)
        return;
    rc->render = render_create(gpu, &rc->desc, &w->err);
}

/* The GPU thread's final item: the irradiance cache's runs and textures, then the
 * renderer's GL objects. */
struct final_work {
    struct render *render;
    struct irradiance_cache *irradiance;
};

static void final_run(struct gpu_work *w, struct gpu *gpu)
{
    (void)gpu;
    struct final_work *f = w->user;
    irradiance_cache_release_gpu(f->irradiance);
    lightsim_gpu_shutdown();
    render_destroy(f->render);
}

/* Stops the GPU thread (final: its last item, or NULL when it has stopped already), then the
 * irradiance cache's worker, then frees the queue: the worker may be building light fields
 * on the CPU when the signal comes and submit to the queue afterwards (gpu_submit refuses
 * once stopped, but reads the queue: freeing it first was a use after free, seen under
 * ASan when refractd was stopped during a 91 x 128 x 116 build). */
static void stop_gpu(struct gpu *gpu, struct gpu_work *final, struct irradiance_cache *irradiance)
{
    gpu_stop(gpu, final);
    irradiance_cache_stop(irradiance);
    gpu_destroy(gpu, NULL);
}

/* Loads *.json of dir as scenes named by their file stem. */
static void load_scene_dir(struct store *store, const char *dir)
{
    DIR *d = opendir(dir);
    if (d == NULL) {
        log_error("main", "--scene-dir %s: cannot open it", dir);
        return;
    }
    struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        size_t n = strlen(ent->d_name);
        if (n < 6 || strcmp(ent->d_name + n - 5, ".json") != 0 || n - 5 >= STORE_ID_MAX)
            continue;
        char id[STORE_ID_MAX] = {0}, path[1024];
        memcpy(id, ent->d_name, n - 5);
        if (!store_name_valid(id, false))
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, ent->d_name);
        FILE *f = fopen(path, "rb");
        if (f == NULL)
            continue;
        char *buf = NULL;
        size_t len = 0, cap = 0, got;
        char chunk[8192];
        while ((got = fread(chunk, 1, sizeof chunk, f)) > 0) {
            if (len + got > cap) {
                cap = (len + got) * 2;
                char *grown = realloc(buf, cap);
                if (grown == NULL)
                    break;
                buf = grown;
            }
            memcpy(buf + len, chunk, got);
            len += got;
        }
        fclose(f);
        struct err e = {0};
        if (buf && store_scene_create(store, id, buf, len, NULL, &e) == REFRACT_E_OK)
            log_info("main", "loaded scene \"%s\" from %s", id, path);
        else
            log_error("main", "%s: %s", path, e.msg);
        free(buf);
    }
    closedir(d);
}

static void prepare_all(const struct http_app *app)
{
    struct store_scene **list = NULL;
    size_t n = store_scene_list(app->store, &list);
    for (size_t i = 0; i < n; i++)
        http_prepare_scene(app, list[i]);
    store_list_free(list, n);
}

static void write_port_file(const char *path, int port)
{
    FILE *f = fopen(path, "w");
    if (f == NULL) {
        log_error("main", "--port-file %s: cannot write it", path);
        return;
    }
    fprintf(f, "%d\n", port);
    fclose(f);
}

/* job_batch_run's stop: a SIGINT or SIGTERM is pending (they are blocked in every thread,
 * so they wait to be noticed here, between frames). */
static bool stop_signal_pending(void *user)
{
    (void)user;
    sigset_t pending;
    sigpending(&pending);
    return sigismember(&pending, SIGTERM) == 1 || sigismember(&pending, SIGINT) == 1;
}

/* --batch: one array task's frames (docs/slurm.md). The exit status is the error code
 * (0 = every frame of the range is in --out); stopped by a signal: 128 + SIGTERM, as a
 * killed process reports, so a scheduler requeues or fails the task. */
static int run_batch(const struct config *cfg, struct gpu *gpu, struct render *render,
                     struct store *store, struct irradiance_cache *irradiance)
{
    struct job_batch_desc desc = {.store = store,
                                  .gpu = gpu,
                                  .render = render,
                                  .irradiance = irradiance,
                                  .limits = {.max_frames = cfg->max_job_frames,
                                             .max_image_dim = cfg->http.limits.max_image_dim,
                                             .max_image_pixels = cfg->http.max_image_pixels,
                                             .max_reference_samples =
                                                 cfg->http.max_reference_samples},
                                  .tile_pixels = cfg->http.render_tile_pixels,
                                  .spec_path = cfg->batch,
                                  .frames = cfg->batch_frames[0] ? cfg->batch_frames : NULL,
                                  .task = cfg->batch_task[0] ? cfg->batch_task : NULL,
                                  .out_dir = cfg->batch_out,
                                  .stop = stop_signal_pending};
    struct job_batch_report rep;
    struct err e = {0};
    enum refract_code rc = job_batch_run(&desc, &rep, &e);
    if (rc != REFRACT_E_OK) {
        log_error("batch", "%s", e.msg);
        return (int)rc;
    }
    log_info("batch", "frames %d-%d of %d: %d rendered, %d already there%s", rep.first, rep.last,
             rep.frames_total, rep.rendered, rep.skipped,
             rep.stopped ? "; stopped by a signal before the end" : "");
    return rep.stopped ? 128 + SIGTERM : 0;
}

static int run(const struct config *cfg)
{
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, NULL); /* every thread inherits this */
    signal(SIGPIPE, SIG_IGN);

    struct err e = {0};
    struct gpu_desc gdesc = cfg->gpu;
    gdesc.shader_dir = cfg->shader_dir[0] ? cfg->shader_dir : NULL;
    struct gpu *gpu = gpu_create(&gdesc, &e);
    if (gpu == NULL) {
        log_error("main", "no GPU context: %s", e.msg);
        return 1;
    }
    struct render_create_work rcw = {.desc = {.scene_budget_bytes = cfg->gpu_scene_budget_bytes}};
    rcw.work = (struct gpu_work){
        .priority = GPU_PRIORITY_INTERACTIVE, .run = render_create_run, .user = &rcw};
    if (gpu_run_sync(gpu, &rcw.work) != REFRACT_E_OK) {
        log_error("main", "renderer: %s", rcw.work.err.msg);
        gpu_destroy(gpu, NULL);
        return 1;
    }
    struct store_desc sdesc = {.data_dir = cfg->data_dir,
                               .limits = cfg->http.limits,
                               .max_scenes = cfg->max_scenes,
                               .max_env_pixels = cfg->max_env_pixels,
                               .max_storage_bytes = cfg->max_storage_bytes};
    struct store *store = store_open(&sdesc, &e);
    struct final_work fw = {.render = rcw.render};
    struct gpu_work final = {.run = final_run, .user = &fw};
    if (store == NULL) {
        log_error("main", "%s", e.msg);
        gpu_destroy(gpu, &final);
        return 1;
    }
    struct event_hub *events = event_hub_create(cfg->event_history, &e);
    if (events == NULL) {
        log_error("main", "events: %s", e.msg);
        gpu_destroy(gpu, &final);
        store_close(store);
        return 1;
    }
    struct irradiance_cache_desc idesc = cfg->irradiance;
    idesc.data_dir = cfg->data_dir;
    idesc.events = events; /* irradiance.progress, .ready, .failed */
    struct irradiance_index irradiance_rows;
    store_irradiance_index(store, &irradiance_rows);
    idesc.index = &irradiance_rows; /* which volumes are on disk: refract.db */
    fw.irradiance = irradiance_cache_create(&idesc, gpu, &e);
    if (fw.irradiance == NULL) {
        log_error("main", "irradiance cache: %s", e.msg);
        gpu_destroy(gpu, &final);
        store_close(store);
        event_hub_destroy(events);
        return 1;
    }
    if (cfg->scene_dir[0])
        load_scene_dir(store, cfg->scene_dir);
    if (cfg->batch[0]) {
        int rc = run_batch(cfg, gpu, rcw.render, store, fw.irradiance);
        stop_gpu(gpu, &final, fw.irradiance);
        irradiance_cache_destroy(fw.irradiance);
        store_close(store);
        event_hub_destroy(events);
        return rc;
    }
    struct view_registry_desc vdesc = cfg->views;
    vdesc.store = store;
    vdesc.gpu = gpu;
    vdesc.render = rcw.render;
    vdesc.irradiance = fw.irradiance;
    vdesc.events = events;
    vdesc.request_timeout_ms = cfg->http.request_timeout_ms;
    vdesc.tile_pixels = cfg->http.render_tile_pixels;
    struct view_registry *views = view_registry_create(&vdesc, &e);
    if (views == NULL) {
        log_error("main", "view sessions: %s", e.msg);
        stop_gpu(gpu, &final, fw.irradiance);
        irradiance_cache_destroy(fw.irradiance);
        store_close(store);
        event_hub_destroy(events);
        return 1;
    }
    struct job_runner_desc jdesc = {.store = store,
                                    .gpu = gpu,
                                    .render = rcw.render,
                                    .irradiance = fw.irradiance,
                                    .events = events,
                                    .limits = {.max_frames = cfg->max_job_frames,
                                               .max_image_dim = cfg->http.limits.max_image_dim,
                                               .max_image_pixels = cfg->http.max_image_pixels,
                                               .max_reference_samples =
                                                   cfg->http.max_reference_samples},
                                    .tile_pixels = cfg->http.render_tile_pixels};
    struct job_runner *jobs = job_runner_create(&jdesc, &e);
    if (jobs == NULL) {
        log_error("main", "batch jobs: %s", e.msg);
        view_registry_destroy(views);
        stop_gpu(gpu, &final, fw.irradiance);
        irradiance_cache_destroy(fw.irradiance);
        store_close(store);
        event_hub_destroy(events);
        return 1;
    }
    struct http_app app = {.store = store,
                           .gpu = gpu,
                           .render = rcw.render,
                           .irradiance = fw.irradiance,
                           .events = events,
                           .views = views,
                           .jobs = jobs};
    struct http_server *http = http_server_start(&cfg->http, &app, &e);
    if (http == NULL) {
        log_error("main", "%s", e.msg);
        job_runner_destroy(jobs);     /* before the GPU thread stops: a frame may be in flight */
        view_registry_destroy(views); /* before the GPU thread stops: frames may be in flight */
        stop_gpu(gpu, &final, fw.irradiance);
        irradiance_cache_destroy(fw.irradiance);
        store_close(store);
        event_hub_destroy(events);
        return 1;
    }
    int port = http_server_port(http);
    if (cfg->port_file[0])
        write_port_file(cfg->port_file, port);
    log_info("main", "refractd %s listening on %s://%s:%d (renderer: %s; data: %s; token: %s)",
             REFRACT_VERSION, cfg->tls_cert[0] ? "https" : "http", cfg->http.bind_address, port,
             gpu_info(gpu)->renderer, cfg->data_dir, cfg->token[0] ? "required" : "none");
    prepare_all(&app);

    int sig = 0;
    sigwait(&stop_signals, &sig);
    log_info("main", "signal %d: shutting down", sig);
    http_server_quiesce(http);
    http_reference_cancel_all();   /* reference renders answer at once (CPU, not the queue) */
    view_registry_stop(views);     /* sessions end, frames in flight finish on the GPU */
    job_runner_stop(jobs);         /* drops the frame in flight at a tile; jobs resume next start */
    http_server_end_streams(http); /* no stream may keep its connection suspended */
    gpu_stop(gpu, &final);         /* resumed requests still read gpu_info: free it after HTTP */
    if (!http_server_wait_idle(http, 3000))
        log_warn("main", "requests still in progress after 3 s; closing them");
    http_server_stop(http);
    stop_gpu(gpu, NULL, fw.irradiance); /* stopped above; now the cache's worker, then free */
    view_registry_destroy(views);
    job_runner_destroy(jobs);
    irradiance_cache_destroy(fw.irradiance); /* finishes writing volumes to disk */
    store_close(store);
    event_hub_destroy(events); /* last: the cache's worker publishes until it stops */
    log_info("main", "stopped");
    return 0;
}

/* A batch task's private data directory: $TMPDIR/refractd-batch-XXXXXX. A task killed
 * with SIGKILL leaves it behind; Slurm and Kubernetes give each job its own TMPDIR. */
static bool make_temp_data_dir(char *out, size_t size)
{
    const char *tmp = getenv("TMPDIR");
    snprintf(out, size, "%s/refractd-batch-XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
    return mkdtemp(out) != NULL;
}

/* rm -r of the temporary data directory (no symbolic link is followed). */
static void remove_tree(const char *path)
{
    struct stat st;
    if (lstat(path, &st) != 0)
        return;
    DIR *d = S_ISDIR(st.st_mode) ? opendir(path) : NULL;
    struct dirent *ent;
    while (d && (ent = readdir(d)) != NULL) {
        if (strcmp(ent->d_name, ".") == 0 || strcmp(ent->d_name, "..") == 0)
            continue;
        char child[1024];
        if (snprintf(child, sizeof child, "%s/%s", path, ent->d_name) < (int)sizeof child)
            remove_tree(child);
    }
    if (d)
        closedir(d);
    remove(path);
}

static bool is_loopback_bind(const char *address)
{
    return strncmp(address, "127.", 4) == 0;
}

int main(int argc, char **argv)
{
    struct config cfg;
    config_defaults(&cfg);
    struct err e = {0};
    if (config_parse_args(&cfg, argc, argv, &e) != REFRACT_E_OK) {
        fprintf(stderr, "refractd: %s\n", e.msg);
        return REFRACT_E_USAGE;
    }
    if (cfg.help) {
        config_print_usage(argv[0]);
        return 0;
    }
    if (cfg.version) {
        printf("refractd %s\n", REFRACT_VERSION);
        return 0;
    }
    log_set_level((enum log_level)cfg.log_level);
    if (config_load_secrets(&cfg, &e) != REFRACT_E_OK) {
        fprintf(stderr, "refractd: %s\n", e.msg);
        config_free(&cfg);
        return REFRACT_E_USAGE;
    }
    if (!is_loopback_bind(cfg.http.bind_address) && cfg.token[0] && !cfg.tls_cert[0] &&
        !cfg.trusted_proxy)
        log_warn("main",
                 "--bind %s without --tls-cert: the bearer token crosses the network in clear "
                 "text; give --tls-cert and --tls-key, or put a TLS proxy in front",
                 cfg.http.bind_address);
    bool temp_data = cfg.batch[0] && !cfg.data_dir_given;
    if (temp_data && !make_temp_data_dir(cfg.data_dir, sizeof cfg.data_dir)) {
        fprintf(stderr,
                "refractd: --batch: cannot create a temporary data directory in %s; "
                "set TMPDIR or give --data-dir\n",
                getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
        config_free(&cfg);
        return REFRACT_E_IO;
    }
    int rc = run(&cfg);
    if (temp_data)
        remove_tree(cfg.data_dir);
    config_free(&cfg);
    return rc;
}
