/*
 * view_registry.c - the table of view sessions: open, find, end, list; the registry's
 * threads' start and stop; and the event hub listener that marks sessions dirty when
 * their scene or its irradiance changes (view.h, DESIGN).
 *
 * The table is an array of at most max_views pointers searched linearly: with the default
 * of 64 sessions a lookup is a few hundred nanoseconds, far below one frame.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <time.h>

#include "../core/log.h"
#include "../events/events.h"
#include "view_internal.h"

static void apply_defaults(struct view_registry_desc *d)
{
    if (d->max_views <= 0)
        d->max_views = 64;
    if (d->idle_timeout_s <= 0)
        d->idle_timeout_s = 120;
    if (d->encoder_threads <= 0)
        d->encoder_threads = 2;
    if (d->request_timeout_ms <= 0)
        d->request_timeout_ms = 120000;
}

const struct view_registry_desc *view_registry_settings(const struct view_registry *r)
{
    return &r->desc;
}

void view_registry_kick(struct view_registry *r)
{
    pthread_mutex_lock(&r->mu);
    pthread_cond_signal(&r->wake);
    pthread_mutex_unlock(&r->mu);
}

struct view_session *view_registry_unlist_locked(struct view_registry *r, struct view_session *s)
{
    for (int i = 0; i < r->count; i++) {
        if (r->sessions[i] != s)
            continue;
        memmove(&r->sessions[i], &r->sessions[i + 1],
                (size_t)(r->count - i - 1) * sizeof r->sessions[0]);
        r->count--;
        return s;
    }
    return NULL;
}

static struct view_session *find_locked(struct view_registry *r, const char *id)
{
    for (int i = 0; i < r->count; i++) {
        if (strcmp(r->sessions[i]->id, id) == 0)
            return r->sessions[i];
    }
    return NULL;
}

/* Ends and unlists every session for which `match` holds (caller holds r->mu); *ended
 * receives the table's references, to be released after unlocking. */
static size_t end_matching_locked(struct view_registry *r, const char *scene,
                                  struct view_session **ended)
{
    size_t n = 0;
    for (int i = r->count - 1; i >= 0; i--) {
        struct view_session *s = r->sessions[i];
        if (scene != NULL && strcmp(s->scene, scene) != 0)
            continue;
        ended[n++] = view_registry_unlist_locked(r, s);
    }
    return n;
}

static void end_all(struct view_session **ended, size_t n)
{
    for (size_t i = 0; i < n; i++) {
        view_session_mark_ended(ended[i]);
        view_session_release(ended[i]);
    }
}

/* The hub's listener (publisher's thread, listener lock held: quick, no event_* calls). */
static void on_event(void *ctx, const struct event *ev)
{
    struct view_registry *r = ctx;
    bool deleted = strcmp(ev->type, EVENT_SCENE_DELETED) == 0;
    /* scene.created too: a document stored again under the same id replaces the scene. */
    bool changed = strcmp(ev->type, EVENT_SCENE_UPDATED) == 0 ||
                   strcmp(ev->type, EVENT_SCENE_CREATED) == 0 ||
                   strcmp(ev->type, EVENT_IRRADIANCE_READY) == 0;
    if ((!deleted && !changed) || ev->scene[0] == '\0')
        return;
    pthread_mutex_lock(&r->mu);
    if (deleted) {
        struct view_session **ended = calloc((size_t)r->desc.max_views, sizeof *ended);
        size_t n = ended ? end_matching_locked(r, ev->scene, ended) : 0;
        pthread_mutex_unlock(&r->mu);
        if (n > 0)
            log_info("view", "scene %s deleted: %zu view session(s) ended", ev->scene, n);
        end_all(ended, n);
        free(ended);
        return;
    }
    bool irradiance = strcmp(ev->type, EVENT_IRRADIANCE_READY) == 0;
    for (int i = 0; i < r->count; i++) {
        struct view_session *s = r->sessions[i];
        if (strcmp(s->scene, ev->scene) != 0)
            continue;
        pthread_mutex_lock(&s->mu);
        /* A reference view's path tracer reads no volume or photon map: their news would
         * only restart its image. */
        if (!(irradiance && s->settings.reference))
            view_session_changed_locked(s);
        pthread_mutex_unlock(&s->mu);
    }
    pthread_cond_signal(&r->wake);
    pthread_mutex_unlock(&r->mu);
}

struct view_registry *view_registry_create(const struct view_registry_desc *desc, struct err *e)
{
    struct view_registry *r = calloc(1, sizeof *r);
    if (r == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory making the view registry");
        return NULL;
    }
    r->desc = *desc;
    apply_defaults(&r->desc);
    r->sessions = calloc((size_t)r->desc.max_views, sizeof *r->sessions);
    pthread_mutex_init(&r->mu, NULL);
    pthread_condattr_t attr;
    pthread_condattr_init(&attr);
    pthread_condattr_setclock(&attr, CLOCK_MONOTONIC); /* gpu_now_ms() is monotonic */
    pthread_cond_init(&r->wake, &attr);
    pthread_condattr_destroy(&attr);
    pthread_cond_init(&r->idle, NULL);
    if (r->sessions == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for %d view sessions (--max-views)",
                r->desc.max_views);
        view_registry_destroy(r);
        return NULL;
    }
    r->encoder = view_encoder_create(r, r->desc.encoder_threads, e);
    if (r->encoder == NULL) {
        view_registry_destroy(r);
        return NULL;
    }
    int rc = pthread_create(&r->scheduler, NULL, view_scheduler_main, r);
    if (rc != 0) {
        err_set(e, REFRACT_E_INTERNAL, "cannot start the view scheduler thread: %s", strerror(rc));
        view_registry_destroy(r);
        return NULL;
    }
    r->scheduler_started = true;
    if (r->desc.events) {
        r->event_token = event_listen(r->desc.events, on_event, r);
        if (r->event_token == 0)
            log_warn("view", "the event hub's listener table is full: view sessions will not "
                             "follow scene and irradiance changes");
    }
    return r;
}

void view_registry_stop(struct view_registry *r)
{
    if (r == NULL || r->stopped)
        return;
    if (r->event_token > 0)
        event_unlisten(r->desc.events, r->event_token); /* no listener runs after this */
    r->event_token = 0;
    pthread_mutex_lock(&r->mu);
    r->stopping = true;
    struct view_session **ended = calloc((size_t)r->desc.max_views, sizeof *ended);
    size_t n = ended ? end_matching_locked(r, NULL, ended) : 0;
    pthread_cond_signal(&r->wake);
    pthread_mutex_unlock(&r->mu);
    end_all(ended, n); /* their streams finish and end */
    free(ended);
    if (r->scheduler_started)
        pthread_join(r->scheduler, NULL);
    r->scheduler_started = false;
    /* Frames in flight finish on the still-running GPU thread and the encoders. */
    pthread_mutex_lock(&r->mu);
    while (r->in_flight > 0)
        pthread_cond_wait(&r->idle, &r->mu);
    pthread_mutex_unlock(&r->mu);
    view_encoder_destroy(r->encoder);
    r->encoder = NULL;
    r->stopped = true;
}

void view_registry_destroy(struct view_registry *r)
{
    if (r == NULL)
        return;
    view_registry_stop(r);
    pthread_mutex_destroy(&r->mu);
    pthread_cond_destroy(&r->wake);
    pthread_cond_destroy(&r->idle);
    free(r->sessions);
    free(r);
}

/* "v" + 16 random lowercase hex digits, unique in the table (caller holds r->mu). */
static bool make_id_locked(struct view_registry *r, char *id)
{
    for (int attempt = 0; attempt < 8; attempt++) {
        uint64_t bits = 0;
        if (getrandom(&bits, sizeof bits, 0) != (ssize_t)sizeof bits)
            return false;
        snprintf(id, VIEW_ID_LEN + 1, "v%016llx", (unsigned long long)bits);
        if (find_locked(r, id) == NULL)
            return true;
    }
    return false;
}

enum refract_code view_session_open(struct view_registry *r, struct store_scene *v,
                                    const struct view_settings *st, struct view_session **out,
                                    struct err *e)
{
    *out = NULL;
    struct view_session *s = view_session_new(r, v->id, st, gpu_now_ms());
    if (s == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory opening a view session");
    pthread_mutex_lock(&r->mu);
    enum refract_code rc = REFRACT_E_OK;
    if (r->stopping)
        rc = err_set(e, REFRACT_E_SHUTTING_DOWN, "refractd is stopping; no new view sessions");
    else if (r->count >= r->desc.max_views)
        rc = err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                     "%d view sessions are open, the limit (refractd --max-views raises it); "
                     "end one with DELETE /v1/views/{vid} or let an idle one expire",
                     r->desc.max_views);
    else if (!make_id_locked(r, s->id))
        rc = err_set(e, REFRACT_E_INTERNAL, "cannot make a random view id: %s", strerror(errno));
    if (rc == REFRACT_E_OK) {
        r->sessions[r->count++] = s; /* the table's reference */
        view_session_retain(s);      /* the caller's */
        *out = s;
        pthread_cond_signal(&r->wake);
    }
    pthread_mutex_unlock(&r->mu);
    if (rc != REFRACT_E_OK)
        view_session_release(s);
    return rc;
}

struct view_session *view_session_find(struct view_registry *r, const char *id)
{
    pthread_mutex_lock(&r->mu);
    struct view_session *s = find_locked(r, id);
    if (s) {
        view_session_retain(s);
        pthread_mutex_lock(&s->mu);
        s->last_activity_ms = gpu_now_ms();
        pthread_mutex_unlock(&s->mu);
    }
    pthread_mutex_unlock(&r->mu);
    return s;
}

bool view_session_end(struct view_registry *r, const char *id)
{
    pthread_mutex_lock(&r->mu);
    struct view_session *s = find_locked(r, id);
    if (s)
        view_registry_unlist_locked(r, s);
    pthread_mutex_unlock(&r->mu);
    if (s == NULL)
        return false;
    view_session_mark_ended(s);
    view_session_release(s);
    return true;
}

size_t view_session_list(struct view_registry *r, struct view_session ***out)
{
    pthread_mutex_lock(&r->mu);
    size_t n = (size_t)r->count;
    struct view_session **list = calloc(n ? n : 1, sizeof *list);
    if (list == NULL)
        n = 0;
    for (size_t i = 0; i < n; i++) {
        list[i] = r->sessions[i];
        view_session_retain(list[i]);
    }
    pthread_mutex_unlock(&r->mu);
    *out = list;
    return n;
}

void view_session_list_free(struct view_session **list, size_t count)
{
    for (size_t i = 0; i < count; i++)
        view_session_release(list[i]);
    free(list);
}
