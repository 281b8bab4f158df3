/*
 * deadline.c - the reaper of requests that do not arrive in time (deadline.h).
 */
#include "deadline.h"

#include <pthread.h>
#include <stdlib.h>
#include <sys/socket.h>
#include <time.h>

#include "../core/log.h"
#include "../gpu/queue.h"

struct http_deadlines {
    pthread_mutex_t lock;
    pthread_cond_t wake; /* CLOCK_MONOTONIC: stop */
    pthread_t thread;
    bool stop;
    int seconds;
    long long min_rate; /* upload bytes per second; 0 = none */
    int tick_ms;        /* how often the reaper looks: a tenth of the deadline, 50 ms..1 s */
    struct http_deadline_entry *head;
};

/* Under the lock: closes the due connections. Returns how many; *first_ip names one. */
static int reap_locked(struct http_deadlines *d, int64_t now, const char **first_ip)
{
    int n = 0;
    for (struct http_deadline_entry *en = d->head; en != NULL; en = en->next) {
        if (en->due_ms == 0 || now < en->due_ms)
            continue;
        /* The entry is listed, so libmicrohttpd has not closed its socket yet (deadline.h,
         * RACES): fd is still this connection's. */
        shutdown(en->fd, SHUT_RDWR);
        en->due_ms = 0;
        if (n++ == 0)
            *first_ip = en->ip;
    }
    return n;
}

static void *reaper_main(void *arg)
{
    struct http_deadlines *d = arg;
    pthread_mutex_lock(&d->lock);
    while (!d->stop) {
        const char *ip = NULL;
        int n = reap_locked(d, gpu_now_ms(), &ip);
        if (n > 0)
            /* One line per sweep, not one per connection: an attacker's thousand
             * connections must not flood the log. */
            log_info("http",
                     "closed %d connection%s (from %s%s) whose request was not in after "
                     "--header-deadline %d s (an upload: whose body arrived slower than "
                     "--upload-min-rate %lld bytes/s)",
                     n, n == 1 ? "" : "s", ip ? ip : "unknown", n == 1 ? "" : " and others",
                     d->seconds, d->min_rate);
        struct timespec ts;
        clock_gettime(CLOCK_MONOTONIC, &ts);
        ts.tv_nsec += (long)d->tick_ms * 1000000L;
        ts.tv_sec += ts.tv_nsec / 1000000000L;
        ts.tv_nsec %= 1000000000L;
        pthread_cond_timedwait(&d->wake, &d->lock, &ts);
    }
    pthread_mutex_unlock(&d->lock);
    return NULL;
}

struct http_deadlines *http_deadlines_create(int seconds, long long min_rate, struct err *e)
{
    if (seconds <= 0)
        return NULL;
    struct http_deadlines *d = calloc(1, sizeof *d);
    if (d == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for --header-deadline");
        return NULL;
    }
    d->seconds = seconds;
    d->min_rate = min_rate > 0 ? min_rate : 0;
    int tick = seconds * 100;
    d->tick_ms = tick < 50 ? 50 : tick > 1000 ? 1000 : tick;
    pthread_mutex_init(&d->lock, NULL);
    pthread_condattr_t attr;
    pthread_condattr_init(&attr);
    pthread_condattr_setclock(&attr, CLOCK_MONOTONIC);
    pthread_cond_init(&d->wake, &attr);
    pthread_condattr_destroy(&attr);
    if (pthread_create(&d->thread, NULL, reaper_main, d) != 0) {
        pthread_cond_destroy(&d->wake);
        pthread_mutex_destroy(&d->lock);
        free(d);
        err_set(e, REFRACT_E_INTERNAL, "could not start the --header-deadline thread");
        return NULL;
    }
    return d;
}

void http_deadlines_destroy(struct http_deadlines *d)
{
    if (d == NULL)
        return;
    pthread_mutex_lock(&d->lock);
    d->stop = true;
    pthread_cond_broadcast(&d->wake);
    pthread_mutex_unlock(&d->lock);
    pthread_join(d->thread, NULL);
    pthread_cond_destroy(&d->wake);
    pthread_mutex_destroy(&d->lock);
    free(d);
}

void http_deadlines_add(struct http_deadlines *d, struct http_deadline_entry *en, int fd,
                        const char *ip)
{
    if (d == NULL || fd < 0)
        return;
    pthread_mutex_lock(&d->lock);
    en->fd = fd;
    en->ip = ip;
    en->base_ms = gpu_now_ms();
    en->due_ms = en->base_ms + (int64_t)d->seconds * 1000;
    en->upload = false;
    en->prev = NULL;
    en->next = d->head;
    if (d->head)
        d->head->prev = en;
    d->head = en;
    en->listed = true;
    pthread_mutex_unlock(&d->lock);
}

void http_deadlines_arm(struct http_deadlines *d, struct http_deadline_entry *en)
{
    if (d == NULL)
        return;
    pthread_mutex_lock(&d->lock);
    if (en->listed) {
        en->base_ms = gpu_now_ms();
        en->due_ms = en->base_ms + (int64_t)d->seconds * 1000;
        en->upload = false;
        en->bytes = 0;
    }
    pthread_mutex_unlock(&d->lock);
}

/* Under the lock: an upload's due time, base + deadline + bytes / rate. */
static void upload_due_locked(const struct http_deadlines *d, struct http_deadline_entry *en)
{
    en->due_ms = en->base_ms + (int64_t)d->seconds * 1000 + en->bytes * 1000 / d->min_rate;
}

void http_deadlines_upload(struct http_deadlines *d, struct http_deadline_entry *en)
{
    if (d == NULL)
        return;
    pthread_mutex_lock(&d->lock);
    en->upload = d->min_rate > 0;
    en->bytes = 0;
    if (!en->upload)
        en->due_ms = 0;
    else if (en->due_ms != 0) /* still armed: not reaped meanwhile */
        upload_due_locked(d, en);
    pthread_mutex_unlock(&d->lock);
}

void http_deadlines_received(struct http_deadlines *d, struct http_deadline_entry *en, size_t bytes)
{
    if (d == NULL)
        return;
    pthread_mutex_lock(&d->lock);
    if (en->upload && en->due_ms != 0) {
        en->bytes += (long long)bytes;
        upload_due_locked(d, en);
    }
    pthread_mutex_unlock(&d->lock);
}

void http_deadlines_disarm(struct http_deadlines *d, struct http_deadline_entry *en)
{
    if (d == NULL)
        return;
    pthread_mutex_lock(&d->lock);
    en->due_ms = 0;
    en->upload = false;
    pthread_mutex_unlock(&d->lock);
}

void http_deadlines_remove(struct http_deadlines *d, struct http_deadline_entry *en)
{
    if (d == NULL)
        return;
    pthread_mutex_lock(&d->lock);
    if (en->listed) {
        if (en->prev)
            en->prev->next = en->next;
        else
            d->head = en->next;
        if (en->next)
            en->next->prev = en->prev;
        en->prev = en->next = NULL;
        en->listed = false;
    }
    en->due_ms = 0;
    en->upload = false;
    pthread_mutex_unlock(&d->lock);
}
