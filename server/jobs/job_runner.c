/*
 * job_runner.c - the jobs registry and its runner thread (jobs.h, DESIGN).
 *
 * Lock: `lock` guards the job list and the in-flight frame's completion flag. The runner
 * thread never holds it across a store call that could take long, a GPU submission or an
 * encode; the job list is looked up again by id after each unlocked step, because a DELETE
 * may have removed the job meanwhile.
 */
#include <errno.h>
#include <fcntl.h>
#include <inttypes.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "../cache/irradiance_cache.h"
#include "../core/log.h"
#include "../events/events.h"
#include "../gpu/queue.h"
#include "../render/render.h"
#include "../scene/json_read.h"
#include "../request/render_request.h"
#include "../request/render_tiles.h"
#include "jobs.h"

/* How long a frame whose lights are not simulated yet waits before it is tried again. */
#define JOB_RETRY_MS 200

struct job {
    struct job_status st;
    struct job_frame *frames; /* NULL once finished or for jobs loaded finished */
    /* An inline scene's private version (store_scene_private, id "job:<id>"): an owned
     * reference while the job is unfinished, else NULL. */
    struct store_scene *inline_scene;
    double run_start_ms; /* when this process started rendering it */
    int run_start_done;  /* frames_done then (for the ETA) */
};

struct job_runner {
    struct job_runner_desc d;
    pthread_mutex_t lock;
    pthread_cond_t cond;
    pthread_t thread;
    bool thread_started, stop;
    struct job **jobs;
    size_t count, cap;
    /* the frame in flight */
    struct gpu_work work;
    bool work_done;
    struct store_scene *version;
    struct render_view_request request;
    struct render_light lights[SCENE_MAX_LIGHTS];
    struct render_view_result result;
    const char *irradiance;
    struct render_tiles tiles;    /* the frame's tile loop (GPU thread) */
    char frame_job[STORE_ID_MAX]; /* whose frame it is */
    int frame_n;                  /* and which */
};

static bool finished_state(const char *state)
{
    return !strcmp(state, "done") || !strcmp(state, "failed") || !strcmp(state, "cancelled");
}

static struct job *find_locked(struct job_runner *r, const char *id, size_t *index)
{
    for (size_t i = 0; i < r->count; i++) {
        if (strcmp(r->jobs[i]->st.id, id) == 0) {
            if (index)
                *index = i;
            return r->jobs[i];
        }
    }
    return NULL;
}

static bool add_locked(struct job_runner *r, struct job *j)
{
    if (r->count == r->cap) {
        size_t cap = r->cap ? r->cap * 2 : 16;
        void *grown = realloc(r->jobs, cap * sizeof *r->jobs);
        if (grown == NULL)
            return false;
        r->jobs = grown;
        r->cap = cap;
    }
    r->jobs[r->count++] = j;
    return true;
}

static void job_free(struct job *j)
{
    if (j) {
        free(j->frames);
        store_scene_release(j->inline_scene);
        free(j);
    }
}

static double eta_locked(const struct job *j)
{
    int done_here = j->st.frames_done - j->run_start_done;
    if (strcmp(j->st.state, "running") != 0 || done_here <= 0)
        return -1;
    double per_frame_ms = (gpu_time_ms() - j->run_start_ms) / done_here;
    return per_frame_ms * (j->st.frames_total - j->st.frames_done) / 1000.0;
}

static void status_locked(const struct job *j, struct job_status *out)
{
    *out = j->st;
    out->eta_s = finished_state(j->st.state) ? 0 : eta_locked(j);
}

static void publish(struct job_runner *r, const struct job_status *st)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "job", st->id);
    if (st->inline_scene)
        cJSON_AddNullToObject(o, "scene");
    else
        cJSON_AddStringToObject(o, "scene", st->scene);
    cJSON_AddNumberToObject(o, "done", st->frames_done);
    cJSON_AddNumberToObject(o, "total", st->frames_total);
    if (st->eta_s >= 0)
        cJSON_AddNumberToObject(o, "eta_s", st->eta_s);
    else
        cJSON_AddNullToObject(o, "eta_s");
    cJSON_AddStringToObject(o, "state", st->state);
    event_publish_json(r->d.events, st->scene, EVENT_JOB_PROGRESS, o);
}

struct forget_work {
    struct gpu_work work;
    struct render *render;
    char id[STORE_ID_MAX + 8];
};

static void forget_run(struct gpu_work *w, struct gpu *gpu)
{
    (void)gpu;
    struct forget_work *f = w->user;
    render_scene_forget(f->render, f->id);
}

static void forget_done(struct gpu_work *w)
{
    free(w->user);
}

/* Frees the renderer's GPU copy of an inline scene ("job:<id>"), which no other work
 * uses once its job has ended (LRU eviction would free it too, but later). */
static void forget_render_scene(struct job_runner *r, const char *slot_id)
{
    struct forget_work *f = calloc(1, sizeof *f);
    if (f == NULL)
        return;
    f->render = r->d.render;
    snprintf(f->id, sizeof f->id, "%s", slot_id);
    f->work = (struct gpu_work){.priority = GPU_PRIORITY_MAINTENANCE,
                                .label = "inline scene free",
                                .run = forget_run,
                                .done = forget_done,
                                .user = f};
    struct err e = {0};
    if (gpu_submit(r->d.gpu, &f->work, &e) != REFRACT_E_OK)
        free(f);
}

/* Sets a job's state in memory and in the database, and tells the event stream. */
static void set_state(struct job_runner *r, const char *id, const char *state, const char *msg)
{
    struct job_status st;
    pthread_mutex_lock(&r->lock);
    struct job *j = find_locked(r, id, NULL);
    if (j == NULL) {
        pthread_mutex_unlock(&r->lock);
        return;
    }
    snprintf(j->st.state, sizeof j->st.state, "%s", state);
    snprintf(j->st.message, sizeof j->st.message, "%s", msg ? msg : "");
    int64_t now = (int64_t)time(NULL);
    if (!strcmp(state, "running") && j->st.started_unix == 0)
        j->st.started_unix = now;
    struct store_scene *inline_scene = NULL;
    if (finished_state(state)) {
        j->st.finished_unix = now;
        free(j->frames);
        j->frames = NULL;
        inline_scene = j->inline_scene;
        j->inline_scene = NULL;
    }
    status_locked(j, &st);
    pthread_mutex_unlock(&r->lock);
    struct err e = {0};
    if (finished_state(state)) {
        char slot_id[STORE_ID_MAX + 8];
        snprintf(slot_id, sizeof slot_id, "job:%s", id);
        irradiance_cache_forget_scene(r->d.irradiance, slot_id);
        if (inline_scene)
            forget_render_scene(r, slot_id);
        store_scene_release(inline_scene);
    }
    if (store_job_state_set(r->d.store, id, state, msg, &e) != REFRACT_E_OK)
        log_warn("jobs", "job %s: %s", id, e.msg);
    publish(r, &st);
}

/* ---- one frame ------------------------------------------------------------------------- */

/* One tile per turn; another turn until every row is drawn. Between two turns the GPU
 * thread runs what is queued above batch work, so a render asked for meanwhile waits for
 * one tile of the frame at most. */
static void frame_run(struct gpu_work *w, struct gpu *gpu)
{
    (void)gpu;
    struct job_runner *r = w->user;
    bool more = false;
    if (render_tiles_step(&r->tiles, r->d.render, r->d.irradiance, r->d.store, r->version,
                          &r->request, r->lights, &r->result, &r->irradiance, &more,
                          &w->err) == REFRACT_E_OK)
        w->again = more;
}

/* Before each tile: nobody wants the frame any more when its job was cancelled or deleted,
 * or refractd is stopping (job_runner_stop waits for the frame in flight: one tile, not a
 * whole large frame). The frame is dropped; a stopped job resumes at that frame at its next start. */
static bool frame_abandoned(struct gpu_work *w)
{
    struct job_runner *r = w->user;
    pthread_mutex_lock(&r->lock);
    const struct job *j = find_locked(r, r->frame_job, NULL);
    bool gone =
        r->stop || j == NULL || finished_state(j->st.state) || j->st.frames_done != r->frame_n;
    pthread_mutex_unlock(&r->lock);
    return gone;
}

static void frame_done(struct gpu_work *w)
{
    struct job_runner *r = w->user;
    pthread_mutex_lock(&r->lock);
    r->work_done = true;
    pthread_cond_broadcast(&r->cond);
    pthread_mutex_unlock(&r->lock);
}

enum frame_outcome { FRAME_DONE, FRAME_RETRY, FRAME_FAILED, FRAME_STOPPED };

/* While frame n renders, ask for the irradiance of frame n + 1's light pose, so a light
 * sweep's simulations overlap its renders. */
static void prefetch(struct job_runner *r, struct store_scene *base, const struct job_frame *next,
                     const char *slot_id)
{
    if (next == NULL || next->light_count == 0)
        return;
    struct store_scene *nv = NULL;
    struct err e = {0};
    if (job_frame_version(r->d.store, base, next, &nv, &e) != REFRACT_E_OK)
        return; /* the frame itself will report it */
    struct irradiance_source isrc;
    job_frame_source(nv, next, slot_id, &isrc);
    irradiance_cache_request(r->d.irradiance, &isrc, false);
    store_scene_release(nv);
}

/* Encodes r->result (frees it) and commits it as frame n of job id, unless `out` says
 * otherwise or the job was cancelled meanwhile. Runner thread, lock not held. */
static enum frame_outcome commit_frame(struct job_runner *r, const char *id, int n,
                                       const struct job_frame *f, enum scene_tonemap tonemap,
                                       enum frame_outcome out, bool inline_scene,
                                       const char *slot_id, char *msg, size_t size)
{
    struct err e = {0};
    enum refract_code rc;
    void *bytes = NULL;
    size_t len = 0;
    if (out == FRAME_DONE &&
        job_frame_encode(&r->result, f, tonemap, &bytes, &len, &e) != REFRACT_E_OK) {
        snprintf(msg, size, "frame %d: %.400s", n, e.msg);
        out = FRAME_FAILED;
    }
    free(r->result.rgba);
    r->result.rgba = NULL;
    if (out != FRAME_DONE)
        return out;
    /* A job cancelled while its frame rendered keeps what it had. */
    pthread_mutex_lock(&r->lock);
    struct job *j = find_locked(r, id, NULL);
    bool live = j && !finished_state(j->st.state) && j->st.frames_done == n;
    pthread_mutex_unlock(&r->lock);
    if (!live) {
        free(bytes);
        if (inline_scene) /* cancelled meanwhile: the frame just built its GPU copy again */
            forget_render_scene(r, slot_id);
        return FRAME_STOPPED;
    }
    rc = store_job_frame_commit(r->d.store, id, n, bytes, len, &e);
    free(bytes);
    if (rc != REFRACT_E_OK) {
        snprintf(msg, size, "frame %d: %.400s", n, e.msg);
        return FRAME_FAILED;
    }
    return FRAME_DONE;
}

/* Renders, encodes and commits frame n of job id (next: frame n + 1 or NULL) of scene
 * scene_id, or of the inline scene's version inline_v (consumed; NULL for a scene id).
 * Runner thread, lock not held. */
static enum frame_outcome run_frame(struct job_runner *r, const char *id, const char *scene_id,
                                    struct store_scene *inline_v, int n, const struct job_frame *f,
                                    const struct job_frame *next, char *msg, size_t size)
{
    struct store_scene *base = inline_v ? inline_v : store_scene_get(r->d.store, scene_id);
    if (base == NULL) {
        snprintf(msg, size, "scene \"%s\" was deleted while the job ran", scene_id);
        return FRAME_FAILED;
    }
    char slot_id[STORE_ID_MAX + 8];
    snprintf(slot_id, sizeof slot_id, "job:%s", id);
    struct store_scene *v = NULL;
    struct err ve = {0};
    if (job_frame_version(r->d.store, base, f, &v, &ve) != REFRACT_E_OK) {
        store_scene_release(base);
        snprintf(msg, size, "frame %d: %.400s", n, ve.msg);
        return FRAME_FAILED;
    }
    if (f->reference_samples > 0) { /* the path tracer on CPU threads: no volume needed */
        memset(&r->result, 0, sizeof r->result);
        struct err re = {0};
        enum refract_code rrc = job_frame_reference(v, f, &r->result, &re);
        enum scene_tonemap tonemap = v->scene->render.tonemap;
        store_scene_release(v);
        store_scene_release(base);
        if (rrc == REFRACT_E_BUSY)
            return FRAME_RETRY; /* another reference render holds the CPUs */
        if (rrc == REFRACT_E_SHUTTING_DOWN)
            return FRAME_STOPPED;
        if (rrc != REFRACT_E_OK) {
            snprintf(msg, size, "frame %d: %.400s", n, re.msg);
            free(r->result.rgba);
            r->result.rgba = NULL;
            return FRAME_FAILED;
        }
        return commit_frame(r, id, n, f, tonemap, FRAME_DONE, inline_v != NULL, slot_id, msg,
                            size);
    }
    struct irradiance_source isrc;
    job_frame_source(v, f, slot_id, &isrc);
    if (!irradiance_cache_request(r->d.irradiance, &isrc, false)) {
        bool failed = job_frame_lights_failed(r->d.irradiance, &isrc, msg, size);
        store_scene_release(v);
        store_scene_release(base);
        return failed ? FRAME_FAILED : FRAME_RETRY; /* not lit yet: wait, never on the GPU */
    }
    r->version = v;
    memset(&r->request, 0, sizeof r->request);
    memset(&r->result, 0, sizeof r->result);
    r->request.camera = f->camera;
    r->request.settings = v->scene->render;
    r->irradiance = NULL;
    render_tiles_init(&r->tiles, r->d.tile_pixels, f->camera.width, f->camera.height);
    memset(&r->work, 0, sizeof r->work);
    r->work.priority = GPU_PRIORITY_BATCH;
    r->work.label = "job frame";
    r->work.run = frame_run;
    r->work.done = frame_done;
    r->work.abandoned = frame_abandoned;
    r->work.abandoned_why = "its job was cancelled, or refractd is stopping";
    snprintf(r->frame_job, sizeof r->frame_job, "%s", id);
    r->frame_n = n;
    r->work.user = r;
    r->work_done = false;
    struct err e = {0};
    enum refract_code rc = gpu_submit(r->d.gpu, &r->work, &e);
    if (rc != REFRACT_E_OK) {
        store_scene_release(v);
        store_scene_release(base);
        r->version = NULL;
        return rc == REFRACT_E_SHUTTING_DOWN ? FRAME_STOPPED : FRAME_RETRY; /* BUSY */
    }
    prefetch(r, base, next, slot_id);
    store_scene_release(base);
    pthread_mutex_lock(&r->lock);
    while (!r->work_done)
        pthread_cond_wait(&r->cond, &r->lock);
    pthread_mutex_unlock(&r->lock);
    enum scene_tonemap tonemap = v->scene->render.tonemap;
    store_scene_release(v);
    r->version = NULL;
    enum frame_outcome out = FRAME_DONE;
    rc = r->work.err.code;
    if (rc == REFRACT_E_SHUTTING_DOWN) {
        out = FRAME_STOPPED;
    } else if (rc == REFRACT_E_TIMEOUT || rc == REFRACT_E_BUSY) {
        out = FRAME_RETRY;
    } else if (rc != REFRACT_E_OK) {
        snprintf(msg, size, "frame %d: %.400s", n, r->work.err.msg);
        out = FRAME_FAILED;
    } else if (r->irradiance &&
               (!strcmp(r->irradiance, "missing") || !strcmp(r->irradiance, "stale"))) {
        out = FRAME_RETRY; /* the volume went away between request and gather */
    }
    return commit_frame(r, id, n, f, tonemap, out, inline_v != NULL, slot_id, msg, size);
}

/* The oldest job with frames left, as a snapshot (lock held). */
static bool next_locked(struct job_runner *r, char *id, char *scene, struct store_scene **inline_v,
                        int *n, struct job_frame *f, struct job_frame *next, bool *has_next,
                        bool *first)
{
    for (size_t i = 0; i < r->count; i++) {
        struct job *j = r->jobs[i];
        if (finished_state(j->st.state) || j->frames == NULL ||
            j->st.frames_done >= j->st.frames_total)
            continue;
        snprintf(id, STORE_ID_MAX, "%s", j->st.id);
        snprintf(scene, STORE_ID_MAX, "%s", j->st.scene);
        *inline_v = j->inline_scene; /* a new reference for run_frame */
        if (*inline_v)
            atomic_fetch_add(&(*inline_v)->refs, 1);
        *n = j->st.frames_done;
        *f = j->frames[*n];
        *has_next = *n + 1 < j->st.frames_total;
        if (*has_next)
            *next = j->frames[*n + 1];
        *first = strcmp(j->st.state, "running") != 0;
        if (j->run_start_ms == 0) { /* the ETA counts from this run's first frame's start */
            j->run_start_ms = gpu_time_ms();
            j->run_start_done = *n;
        }
        return true;
    }
    return false;
}

static void timed_wait_locked(struct job_runner *r, int ms)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    ts.tv_nsec += (long)ms * 1000000L;
    ts.tv_sec += ts.tv_nsec / 1000000000L;
    ts.tv_nsec %= 1000000000L;
    pthread_cond_timedwait(&r->cond, &r->lock, &ts);
}

static void *runner_main(void *arg)
{
    struct job_runner *r = arg;
    pthread_mutex_lock(&r->lock);
    while (!r->stop) {
        char id[STORE_ID_MAX], scene[STORE_ID_MAX], msg[ERR_MSG_MAX] = "";
        struct job_frame f, next;
        struct store_scene *inline_v = NULL;
        int n = 0;
        bool first = false, has_next = false;
        if (!next_locked(r, id, scene, &inline_v, &n, &f, &next, &has_next, &first)) {
            pthread_cond_wait(&r->cond, &r->lock);
            continue;
        }
        pthread_mutex_unlock(&r->lock);
        if (first)
            set_state(r, id, "running", NULL);
        enum frame_outcome out =
            run_frame(r, id, scene, inline_v, n, &f, has_next ? &next : NULL, msg, sizeof msg);
        if (out == FRAME_FAILED) {
            log_warn("jobs", "job %s failed: %s", id, msg);
            set_state(r, id, "failed", msg);
        }
        pthread_mutex_lock(&r->lock);
        if (out == FRAME_RETRY) {
            timed_wait_locked(r, JOB_RETRY_MS);
            continue;
        }
        struct job *j = find_locked(r, id, NULL);
        if (out != FRAME_DONE || j == NULL)
            continue;
        j->st.frames_done = n + 1;
        j->st.updated_unix = (int64_t)time(NULL);
        struct job_status st;
        status_locked(j, &st);
        bool all = j->st.frames_done == j->st.frames_total;
        pthread_mutex_unlock(&r->lock);
        if (all)
            set_state(r, id, "done", NULL); /* publishes the last progress */
        else
            publish(r, &st);
        pthread_mutex_lock(&r->lock);
    }
    pthread_mutex_unlock(&r->lock);
    return NULL;
}

/* ---- the registry ---------------------------------------------------------------------- */

static void random_id(char out[JOB_ID_LEN + 1])
{
    unsigned char b[8] = {0};
    int fd = open("/dev/urandom", O_RDONLY | O_CLOEXEC);
    if (fd < 0 || read(fd, b, sizeof b) != (ssize_t)sizeof b) {
        uint64_t t = (uint64_t)gpu_now_ms() * 6364136223846793005ull + (uint64_t)getpid();
        memcpy(b, &t, sizeof b);
    }
    if (fd >= 0)
        close(fd);
    out[0] = 'j';
    for (int i = 0; i < 8; i++)
        snprintf(out + 1 + 2 * i, 3, "%02x", b[i]);
}

/* The private version of inline scene document doc for job id (store_scene_private under
 * "job:<id>", checked to use no uploads): *out is a new reference. */
static enum refract_code inline_version(struct job_runner *r, const char *id, const cJSON *doc,
                                        struct store_scene **out, struct err *e)
{
    char *json = cJSON_PrintUnformatted(doc);
    if (json == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory reading the inline scene");
    char slot_id[STORE_ID_MAX + 8];
    snprintf(slot_id, sizeof slot_id, "job:%s", id);
    enum refract_code rc = store_scene_private(r->d.store, slot_id, json, strlen(json), out, e);
    free(json);
    if (rc != REFRACT_E_OK) {
        job_spec_inline_error(e);
        return rc;
    }
    rc = job_spec_inline_check((*out)->scene, e);
    if (rc != REFRACT_E_OK) {
        store_scene_release(*out);
        *out = NULL;
    }
    return rc;
}

/* Expands a stored or received specification of job id against the scene's current
 * version, or against its inline scene: then *inline_out gets that scene's private
 * version (a new reference) and scene "". */
static enum refract_code expand(struct job_runner *r, const char *id, const char *spec, size_t len,
                                char scene[STORE_ID_MAX], struct store_scene **inline_out,
                                struct job_frame **frames, int *count, struct err *e)
{
    *inline_out = NULL;
    cJSON *root = NULL;
    const cJSON *doc = NULL;
    enum refract_code rc = jr_parse(spec, len, &root, e);
    if (rc == REFRACT_E_OK && !cJSON_IsObject(root))
        rc = err_set(e, REFRACT_E_INVALID_FIELD, "a job is a JSON object; see docs/api.md");
    if (rc == REFRACT_E_OK)
        rc = job_spec_scene(root, scene, &doc, e);
    struct store_scene *v = NULL;
    if (rc == REFRACT_E_OK && doc) {
        rc = inline_version(r, id, doc, &v, e);
    } else if (rc == REFRACT_E_OK) {
        v = store_scene_get(r->d.store, scene);
        if (v == NULL)
            rc = err_set(e, REFRACT_E_SCENE_NOT_FOUND,
                         "scene: no scene \"%s\"; create it with POST /v1/scenes first, or send"
                         " the whole scene document as \"scene\"",
                         scene);
    }
    if (rc == REFRACT_E_OK)
        rc = job_spec_expand(root, v->scene, &r->d.limits, frames, count, e);
    if (rc == REFRACT_E_OK && doc) {
        *inline_out = v;
        v = NULL;
    }
    if (v)
        store_scene_release(v);
    cJSON_Delete(root);
    return rc;
}

struct load_ctx {
    struct job_runner *r;
    struct job **list;
    char **specs;
    size_t count, cap;
};

static void load_row(const struct store_job_row *row, void *arg)
{
    struct load_ctx *c = arg;
    if (c->count == c->cap) {
        size_t cap = c->cap ? c->cap * 2 : 16;
        void *l = realloc(c->list, cap * sizeof *c->list);
        if (l)
            c->list = l;
        void *s = realloc(c->specs, cap * sizeof *c->specs);
        if (s)
            c->specs = s;
        if (l == NULL || s == NULL)
            return;
        c->cap = cap;
    }
    struct job *j = calloc(1, sizeof *j);
    char *spec = strdup(row->spec ? row->spec : "{}");
    if (j == NULL || spec == NULL) {
        free(j);
        free(spec);
        return;
    }
    snprintf(j->st.id, sizeof j->st.id, "%s", row->id);
    snprintf(j->st.scene, sizeof j->st.scene, "%s", row->scene);
    j->st.inline_scene = row->scene[0] == '\0';
    snprintf(j->st.state, sizeof j->st.state, "%s", row->state);
    snprintf(j->st.message, sizeof j->st.message, "%s", row->message);
    j->st.frames_total = row->frames_total;
    j->st.frames_done = row->frames_done;
    j->st.created_unix = row->created_unix;
    j->st.updated_unix = row->updated_unix;
    j->st.started_unix = row->started_unix;
    j->st.finished_unix = row->finished_unix;
    c->list[c->count] = j;
    c->specs[c->count++] = spec;
}

/* Start-up: every job of the database; unfinished ones get their frames again. */
static enum refract_code load(struct job_runner *r, struct err *e)
{
    struct load_ctx c = {.r = r};
    enum refract_code rc = store_job_each(r->d.store, load_row, &c, e);
    for (size_t i = 0; i < c.count; i++) {
        struct job *j = c.list[i];
        if (!finished_state(j->st.state)) {
            char scene[STORE_ID_MAX];
            int count = 0;
            struct err pe = {0};
            if (expand(r, j->st.id, c.specs[i], strlen(c.specs[i]), scene, &j->inline_scene,
                       &j->frames, &count, &pe) != REFRACT_E_OK ||
                count != j->st.frames_total) {
                char msg[ERR_MSG_MAX];
                snprintf(msg, sizeof msg, "could not resume after a restart: %.400s",
                         pe.code ? pe.msg : "the specification no longer gives the same frames");
                free(j->frames);
                j->frames = NULL;
                store_scene_release(j->inline_scene);
                j->inline_scene = NULL;
                snprintf(j->st.state, sizeof j->st.state, "failed");
                snprintf(j->st.message, sizeof j->st.message, "%s", msg);
                store_job_state_set(r->d.store, j->st.id, "failed", msg, &pe);
            } else {
                log_info("jobs", "job %s resumes at frame %d of %d", j->st.id, j->st.frames_done,
                         j->st.frames_total);
            }
        }
        free(c.specs[i]);
        if (!add_locked(r, j))
            job_free(j);
    }
    free(c.list);
    free(c.specs);
    return rc;
}

struct job_runner *job_runner_create(const struct job_runner_desc *desc, struct err *e)
{
    struct job_runner *r = calloc(1, sizeof *r);
    if (r == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the job runner");
        return NULL;
    }
    r->d = *desc;
    if (r->d.limits.max_frames <= 0)
        r->d.limits.max_frames = 10000;
    pthread_mutex_init(&r->lock, NULL);
    pthread_cond_init(&r->cond, NULL);
    if (load(r, e) != REFRACT_E_OK || pthread_create(&r->thread, NULL, runner_main, r) != 0) {
        if (e->code == REFRACT_E_OK)
            err_set(e, REFRACT_E_INTERNAL, "could not start the job runner thread");
        job_runner_destroy(r);
        return NULL;
    }
    r->thread_started = true;
    return r;
}

void job_runner_stop(struct job_runner *r)
{
    if (r == NULL)
        return;
    pthread_mutex_lock(&r->lock);
    bool join = r->thread_started && !r->stop;
    r->stop = true;
    pthread_cond_broadcast(&r->cond);
    pthread_mutex_unlock(&r->lock);
    if (join)
        pthread_join(r->thread, NULL);
}

void job_runner_destroy(struct job_runner *r)
{
    if (r == NULL)
        return;
    job_runner_stop(r);
    for (size_t i = 0; i < r->count; i++)
        job_free(r->jobs[i]);
    free(r->jobs);
    pthread_cond_destroy(&r->cond);
    pthread_mutex_destroy(&r->lock);
    free(r);
}

enum refract_code job_submit(struct job_runner *r, const char *body, size_t len,
                             struct job_status *out, struct err *e)
{
    struct job *j = calloc(1, sizeof *j);
    if (j == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a job");
    int count = 0;
    random_id(j->st.id); /* first: an inline scene's version is named after it */
    enum refract_code rc =
        expand(r, j->st.id, body, len, j->st.scene, &j->inline_scene, &j->frames, &count, e);
    if (rc != REFRACT_E_OK) {
        job_free(j);
        return rc;
    }
    j->st.inline_scene = j->inline_scene != NULL;
    snprintf(j->st.state, sizeof j->st.state, "queued");
    j->st.frames_total = count;
    j->st.created_unix = j->st.updated_unix = (int64_t)time(NULL);
    j->st.eta_s = -1;
    char *spec = malloc(len + 1);
    if (spec == NULL) {
        job_free(j);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a job");
    }
    memcpy(spec, body, len);
    spec[len] = '\0';
    struct store_job_row row = {
        .frames_total = count, .created_unix = j->st.created_unix, .spec = spec};
    snprintf(row.id, sizeof row.id, "%s", j->st.id);
    snprintf(row.scene, sizeof row.scene, "%s", j->st.scene);
    snprintf(row.state, sizeof row.state, "queued");
    pthread_mutex_lock(&r->lock);
    if (r->stop)
        rc = err_set(e, REFRACT_E_SHUTTING_DOWN, "refractd is stopping; submit the job again");
    else
        rc = store_job_insert(r->d.store, &row, e);
    if (rc == REFRACT_E_OK && !add_locked(r, j))
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a job");
    if (rc == REFRACT_E_OK) {
        status_locked(j, out);
        /* Published before the runner can see the job, so "queued" is always the job's
         * first event (lock order: the jobs lock, then the event hub's). */
        publish(r, out);
        pthread_cond_broadcast(&r->cond);
    }
    pthread_mutex_unlock(&r->lock);
    free(spec);
    if (rc != REFRACT_E_OK) {
        job_free(j);
        return rc;
    }
    return REFRACT_E_OK;
}

bool job_get(struct job_runner *r, const char *id, struct job_status *out)
{
    pthread_mutex_lock(&r->lock);
    struct job *j = find_locked(r, id, NULL);
    if (j)
        status_locked(j, out);
    pthread_mutex_unlock(&r->lock);
    return j != NULL;
}

size_t job_list(struct job_runner *r, const char *state, const char *scene, struct job_status **out)
{
    pthread_mutex_lock(&r->lock);
    *out = calloc(r->count ? r->count : 1, sizeof **out);
    size_t n = 0;
    for (size_t i = 0; *out && i < r->count; i++) {
        const struct job *j = r->jobs[i];
        if (state && state[0] && strcmp(state, j->st.state) != 0)
            continue;
        if (scene && scene[0] && strcmp(scene, j->st.scene) != 0)
            continue;
        status_locked(j, &(*out)[n++]);
    }
    pthread_mutex_unlock(&r->lock);
    return n;
}

enum refract_code job_cancel_or_delete(struct job_runner *r, const char *id, bool *deleted,
                                       struct job_status *out, struct err *e)
{
    pthread_mutex_lock(&r->lock);
    size_t index = 0;
    struct job *j = find_locked(r, id, &index);
    if (j == NULL) {
        pthread_mutex_unlock(&r->lock);
        return err_set(e, REFRACT_E_NOT_FOUND, "no job \"%s\"; GET /v1/jobs lists them", id);
    }
    *deleted = finished_state(j->st.state);
    if (*deleted) {
        status_locked(j, out);
        memmove(&r->jobs[index], &r->jobs[index + 1], (r->count - index - 1) * sizeof *r->jobs);
        r->count--; /* the list stays in creation order */
        pthread_mutex_unlock(&r->lock);
        job_free(j);
        return store_job_delete(r->d.store, id, e);
    }
    pthread_mutex_unlock(&r->lock);
    set_state(r, id, "cancelled", "cancelled by DELETE /v1/jobs/{id}");
    job_get(r, id, out);
    return REFRACT_E_OK;
}
