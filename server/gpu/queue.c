/*
 * queue.c - the GPU thread: context creation, program builds, the priority queue and
 * orderly shutdown. See queue.h for the design and the contracts.
 *
 * INVARIANT: `lists[p]` holds the queued items of priority p in FIFO order; `length`
 * counts them all; `stopping` is set once and never cleared; after it is set no item
 * enters the queue.
 */
#include "queue.h"

#include <pthread.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../core/log.h"
#include "../core/metrics.h"

struct work_list {
    struct gpu_work *head, *tail;
};

struct gpu {
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t wake;
    struct work_list lists[GPU_PRIORITY_COUNT];
    size_t length, max_queued;
    bool stopping;
    struct gpu_work *final_work;

    /* start-up handshake */
    bool init_done;
    struct err init_err;

    struct gpu_desc desc;
    struct gpu_context *context; /* GPU thread */
    struct gpu_context_info info;
    struct gpu_programs programs; /* GPU thread */
};

int64_t gpu_now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

double gpu_time_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1000.0 + (double)ts.tv_nsec / 1e6;
}

static void list_push(struct work_list *l, struct gpu_work *w)
{
    w->next = NULL;
    if (l->tail)
        l->tail->next = w;
    else
        l->head = w;
    l->tail = w;
}

static struct gpu_work *list_pop(struct work_list *l)
{
    struct gpu_work *w = l->head;
    if (w) {
        l->head = w->next;
        if (l->head == NULL)
            l->tail = NULL;
        w->next = NULL;
    }
    return w;
}

/* Pops the most urgent item, or NULL when empty. Called with the lock held. */
static struct gpu_work *pop_locked(struct gpu *g)
{
    for (int p = 0; p < GPU_PRIORITY_COUNT; p++) {
        struct gpu_work *w = list_pop(&g->lists[p]);
        if (w) {
            g->length--;
            return w;
        }
    }
    return NULL;
}

/* Puts w back at the end of its priority's line for its next turn; false when the
 * queue is stopping (then w is completed with SHUTTING_DOWN by the caller). */
static bool requeue(struct gpu *g, struct gpu_work *w)
{
    pthread_mutex_lock(&g->lock);
    bool ok = !g->stopping;
    if (ok) {
        w->turn_ms = gpu_now_ms();
        list_push(&g->lists[w->priority], w);
        g->length++;
    }
    pthread_mutex_unlock(&g->lock);
    return ok;
}

static void execute(struct gpu *g, struct gpu_work *w)
{
    err_clear(&w->err);
    w->again = false;
    const char *label = w->label ? w->label : "work";
    if (w->deadline_ms > 0 && gpu_now_ms() > w->deadline_ms) {
        err_set(&w->err, REFRACT_E_TIMEOUT,
                "%s waited %lld ms in the GPU queue and passed its deadline; the GPU is busy "
                "(queue length %zu), retry later or raise --request-timeout-ms",
                label, (long long)(gpu_now_ms() - w->queued_ms), gpu_queue_length(g));
    } else if (w->abandoned != NULL && w->abandoned(w)) {
        const char *why = w->abandoned_why ? w->abandoned_why : "its client closed the connection";
        log_info("gpu", "%s dropped: %s", label, why);
        err_set(&w->err, REFRACT_E_TIMEOUT, "%s dropped before it was done: %s", label, why);
    } else {
        double t0 = gpu_time_ms();
        w->run(w, g);
        /* GET /metrics: GPU busy time and queue wait by priority (core/metrics.h). */
        metrics_gpu_work((int)w->priority, (double)(gpu_now_ms() - w->turn_ms) * 1e-3,
                         (gpu_time_ms() - t0) * 1e-3);
    }
    if (w->again && w->err.code == REFRACT_E_OK) {
        if (requeue(g, w))
            return;
        err_set(&w->err, REFRACT_E_SHUTTING_DOWN, "refractd is shutting down");
    }
    if (w->done)
        w->done(w);
}

static void drain_on_shutdown(struct gpu *g)
{
    for (;;) {
        pthread_mutex_lock(&g->lock);
        struct gpu_work *w = pop_locked(g);
        pthread_mutex_unlock(&g->lock);
        if (w == NULL)
            return;
        if (w->priority == GPU_PRIORITY_MAINTENANCE && !w->skip_on_shutdown) {
            execute(g, w);
        } else {
            err_set(&w->err, REFRACT_E_SHUTTING_DOWN, "refractd is shutting down");
            if (w->done)
                w->done(w);
        }
    }
}

static bool thread_init(struct gpu *g)
{
    g->context = gpu_context_create(&g->desc.context, &g->init_err);
    if (g->context == NULL)
        return false;
    g->info = *gpu_context_info(g->context);
    if (gpu_programs_build(&g->programs, g->desc.shader_dir, &g->init_err) != REFRACT_E_OK) {
        gpu_context_destroy(g->context);
        g->context = NULL;
        return false;
    }
    return true;
}

static void *gpu_thread_main(void *arg)
{
    struct gpu *g = arg;
    bool ok = thread_init(g);
    pthread_mutex_lock(&g->lock);
    g->init_done = true;
    pthread_cond_broadcast(&g->wake);
    pthread_mutex_unlock(&g->lock);
    if (!ok)
        return NULL;

    for (;;) {
        pthread_mutex_lock(&g->lock);
        while (g->length == 0 && !g->stopping)
            pthread_cond_wait(&g->wake, &g->lock);
        if (g->stopping) {
            pthread_mutex_unlock(&g->lock);
            break;
        }
        struct gpu_work *w = pop_locked(g);
        pthread_mutex_unlock(&g->lock);
        execute(g, w);
    }
    drain_on_shutdown(g);
    if (g->final_work) {
        g->final_work->run(g->final_work, g);
        if (g->final_work->done)
            g->final_work->done(g->final_work);
    }
    gpu_programs_destroy(&g->programs);
    gpu_context_destroy(g->context);
    g->context = NULL;
    return NULL;
}

struct gpu *gpu_create(const struct gpu_desc *desc, struct err *e)
{
    struct gpu *g = calloc(1, sizeof *g);
    if (g == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory starting the GPU thread");
        return NULL;
    }
    g->desc = *desc;
    g->max_queued = desc->max_queued ? desc->max_queued : 256;
    pthread_mutex_init(&g->lock, NULL);
    pthread_cond_init(&g->wake, NULL);
    if (pthread_create(&g->thread, NULL, gpu_thread_main, g) != 0) {
        err_set(e, REFRACT_E_INTERNAL, "cannot start the GPU thread");
        pthread_mutex_destroy(&g->lock);
        pthread_cond_destroy(&g->wake);
        free(g);
        return NULL;
    }
    pthread_mutex_lock(&g->lock);
    while (!g->init_done)
        pthread_cond_wait(&g->wake, &g->lock);
    pthread_mutex_unlock(&g->lock);
    if (g->context == NULL) {
        pthread_join(g->thread, NULL);
        if (e)
            *e = g->init_err;
        pthread_mutex_destroy(&g->lock);
        pthread_cond_destroy(&g->wake);
        free(g);
        return NULL;
    }
    return g;
}

void gpu_stop(struct gpu *g, struct gpu_work *final)
{
    if (g == NULL)
        return;
    pthread_mutex_lock(&g->lock);
    if (g->stopping) { /* stopped (or stopping) already: the first call's final runs */
        pthread_mutex_unlock(&g->lock);
        return;
    }
    g->stopping = true;
    g->final_work = final;
    pthread_cond_broadcast(&g->wake);
    pthread_mutex_unlock(&g->lock);
    pthread_join(g->thread, NULL);
}

void gpu_destroy(struct gpu *g, struct gpu_work *final)
{
    if (g == NULL)
        return;
    gpu_stop(g, final);
    pthread_mutex_destroy(&g->lock);
    pthread_cond_destroy(&g->wake);
    free(g);
}

enum refract_code gpu_submit(struct gpu *g, struct gpu_work *w, struct err *e)
{
    pthread_mutex_lock(&g->lock);
    if (g->stopping) {
        pthread_mutex_unlock(&g->lock);
        return err_set(e, REFRACT_E_SHUTTING_DOWN, "refractd is shutting down");
    }
    if (g->length >= g->max_queued && w->priority != GPU_PRIORITY_MAINTENANCE) {
        size_t len = g->length;
        pthread_mutex_unlock(&g->lock);
        return err_set(e, REFRACT_E_BUSY,
                       "the GPU queue is full (%zu items, --max-queued); retry later", len);
    }
    w->queued_ms = gpu_now_ms();
    w->turn_ms = w->queued_ms;
    list_push(&g->lists[w->priority], w);
    g->length++;
    pthread_cond_signal(&g->wake);
    pthread_mutex_unlock(&g->lock);
    return REFRACT_E_OK;
}

struct sync_work {
    struct gpu_work proxy;
    struct gpu_work *user_work;
    pthread_mutex_t lock;
    pthread_cond_t cond;
    bool finished;
};

static void sync_run(struct gpu_work *w, struct gpu *g)
{
    struct sync_work *s = w->user;
    s->user_work->again = false;
    s->user_work->run(s->user_work, g);
    w->err = s->user_work->err;
    w->again = s->user_work->again; /* another turn (a frame's next tile) */
}

static bool sync_abandoned(struct gpu_work *w)
{
    struct sync_work *s = w->user;
    return s->user_work->abandoned != NULL && s->user_work->abandoned(s->user_work);
}

static void sync_done(struct gpu_work *w)
{
    struct sync_work *s = w->user;
    s->user_work->err = w->err;
    if (s->user_work->done)
        s->user_work->done(s->user_work);
    pthread_mutex_lock(&s->lock);
    s->finished = true;
    pthread_cond_signal(&s->cond);
    pthread_mutex_unlock(&s->lock);
}

enum refract_code gpu_run_sync(struct gpu *g, struct gpu_work *w)
{
    struct sync_work s = {
        .proxy = {.priority = w->priority,
                  .deadline_ms = w->deadline_ms,
                  .label = w->label,
                  .run = sync_run,
                  .done = sync_done,
                  .abandoned = w->abandoned ? sync_abandoned : NULL,
                  .abandoned_why = w->abandoned_why},
        .user_work = w,
    };
    s.proxy.user = &s;
    pthread_mutex_init(&s.lock, NULL);
    pthread_cond_init(&s.cond, NULL);
    enum refract_code rc = gpu_submit(g, &s.proxy, &w->err);
    if (rc == REFRACT_E_OK) {
        pthread_mutex_lock(&s.lock);
        while (!s.finished)
            pthread_cond_wait(&s.cond, &s.lock);
        pthread_mutex_unlock(&s.lock);
        rc = w->err.code;
    }
    pthread_mutex_destroy(&s.lock);
    pthread_cond_destroy(&s.cond);
    return rc;
}

const struct gpu_context_info *gpu_info(const struct gpu *g)
{
    return &g->info;
}

const struct gpu_programs *gpu_programs_get(const struct gpu *g)
{
    return &g->programs;
}

size_t gpu_queue_length(struct gpu *g)
{
    pthread_mutex_lock(&g->lock);
    size_t n = g->length;
    pthread_mutex_unlock(&g->lock);
    return n;
}
