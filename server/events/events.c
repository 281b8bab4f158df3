/*
 * events.c - the event hub (events.h): a bounded ring of the newest events under one
 * mutex, and a fixed table of listeners under a second lock so that a listener's callback
 * never runs while the ring is locked (a reader woken by the callback may read at once).
 */
#include "events.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cjson/cJSON.h>

#include "../core/log.h"

#define EVENT_LISTENERS_MAX 64

struct event_listener {
    event_listener_fn fn;
    void *ctx;
    int token; /* 0 = free slot */
};

struct event_hub {
    pthread_mutex_t ring_lock;
    struct event *ring; /* event id k lives at ring[(k - 1) % capacity] */
    size_t capacity;
    uint64_t last_id; /* ids 1..last_id were published; the ring holds the newest ones */

    pthread_rwlock_t listener_lock; /* readers: publishers calling back; writer: (un)listen */
    struct event_listener listeners[EVENT_LISTENERS_MAX];
    int next_token;
};

struct event_hub *event_hub_create(size_t capacity, struct err *e)
{
    if (capacity == 0)
        capacity = 1024;
    struct event_hub *h = calloc(1, sizeof *h);
    if (h != NULL)
        h->ring = calloc(capacity, sizeof *h->ring);
    if (h == NULL || h->ring == NULL) {
        free(h);
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for an event history of %zu events",
                capacity);
        return NULL;
    }
    h->capacity = capacity;
    pthread_mutex_init(&h->ring_lock, NULL);
    pthread_rwlock_init(&h->listener_lock, NULL);
    return h;
}

void event_hub_destroy(struct event_hub *h)
{
    if (h == NULL)
        return;
    pthread_mutex_destroy(&h->ring_lock);
    pthread_rwlock_destroy(&h->listener_lock);
    free(h->ring);
    free(h);
}

static int64_t wall_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (int64_t)ts.tv_sec * 1000 + ts.tv_nsec / 1000000;
}

static void copy_text(char *dst, size_t size, const char *src)
{
    size_t n = src ? strlen(src) : 0;
    if (n >= size)
        n = size - 1;
    if (n > 0)
        memcpy(dst, src, n);
    dst[n] = '\0';
}

uint64_t event_publish(struct event_hub *h, const char *scene, const char *type,
                       const char *json_data)
{
    if (h == NULL)
        return 0;
    struct event ev = {.time_ms = wall_ms()};
    copy_text(ev.scene, sizeof ev.scene, scene);
    copy_text(ev.type, sizeof ev.type, type);
    if (json_data == NULL || strlen(json_data) >= sizeof ev.data) {
        /* A publisher's bug: its data should be a few fields. Readers still learn that
         * something of this type happened. */
        log_warn("events", "%s event data for scene '%s' too long; sent as truncated", ev.type,
                 ev.scene);
        copy_text(ev.data, sizeof ev.data, "{\"truncated\":true}");
    } else {
        copy_text(ev.data, sizeof ev.data, json_data);
    }

    pthread_mutex_lock(&h->ring_lock);
    ev.id = ++h->last_id;
    h->ring[(ev.id - 1) % h->capacity] = ev;
    pthread_mutex_unlock(&h->ring_lock);

    pthread_rwlock_rdlock(&h->listener_lock);
    for (int i = 0; i < EVENT_LISTENERS_MAX; i++)
        if (h->listeners[i].token != 0)
            h->listeners[i].fn(h->listeners[i].ctx, &ev);
    pthread_rwlock_unlock(&h->listener_lock);
    return ev.id;
}

uint64_t event_publish_json(struct event_hub *h, const char *scene, const char *type,
                            struct cJSON *json)
{
    if (json == NULL)
        return 0;
    char *text = cJSON_PrintUnformatted(json);
    cJSON_Delete(json);
    if (text == NULL)
        return 0;
    uint64_t id = event_publish(h, scene, type, text);
    cJSON_free(text);
    return id;
}

static bool wanted(const struct event *ev, const char *scene, bool include_unscoped)
{
    if (scene == NULL || scene[0] == '\0')
        return true;
    if (ev->scene[0] == '\0')
        return include_unscoped;
    return strcmp(ev->scene, scene) == 0;
}

size_t event_read(struct event_hub *h, uint64_t after, const char *scene, bool include_unscoped,
                  struct event *out, size_t max, uint64_t *lost, uint64_t *cursor)
{
    size_t n = 0;
    uint64_t missed = 0;
    pthread_mutex_lock(&h->ring_lock);
    uint64_t oldest = h->last_id >= h->capacity ? h->last_id - h->capacity + 1 : 1;
    uint64_t id = after + 1;
    if (id < oldest) {
        missed = oldest - id;
        id = oldest;
    }
    for (; id <= h->last_id && n < max; id++) {
        const struct event *ev = &h->ring[(id - 1) % h->capacity];
        if (wanted(ev, scene, include_unscoped))
            out[n++] = *ev;
    }
    pthread_mutex_unlock(&h->ring_lock);
    if (lost)
        *lost = missed;
    if (cursor)
        *cursor = id - 1;
    return n;
}

uint64_t event_last_id(struct event_hub *h)
{
    pthread_mutex_lock(&h->ring_lock);
    uint64_t id = h->last_id;
    pthread_mutex_unlock(&h->ring_lock);
    return id;
}

int event_listen(struct event_hub *h, event_listener_fn fn, void *ctx)
{
    int token = 0;
    pthread_rwlock_wrlock(&h->listener_lock);
    for (int i = 0; i < EVENT_LISTENERS_MAX; i++) {
        if (h->listeners[i].token == 0) {
            token = ++h->next_token;
            h->listeners[i] = (struct event_listener){.fn = fn, .ctx = ctx, .token = token};
            break;
        }
    }
    pthread_rwlock_unlock(&h->listener_lock);
    return token;
}

void event_unlisten(struct event_hub *h, int token)
{
    if (h == NULL || token == 0)
        return;
    /* The write lock waits for every publisher inside a callback: after it, fn is idle. */
    pthread_rwlock_wrlock(&h->listener_lock);
    for (int i = 0; i < EVENT_LISTENERS_MAX; i++)
        if (h->listeners[i].token == token)
            h->listeners[i] = (struct event_listener){0};
    pthread_rwlock_unlock(&h->listener_lock);
}
