/*
 * events.h - the daemon's event hub: a record of what changed (a scene document, an
 * upload, the lights, an irradiance volume's progress, a job's progress), for the
 * Server-Sent Events endpoints (GET /v1/events, GET /v1/scenes/{id}/events; docs/api.md
 * "Events") and for the view sessions, which push a new frame when something they show
 * changed (docs/views.md).
 *
 * DESIGN. Events go into one bounded ring (the last `capacity` events, oldest out first),
 * each with an id that grows by one per event over the daemon's life. A reader keeps the id
 * of the last event it has seen and asks for what came after it (event_read): readers never
 * make the hub hold more, so a slow or stalled SSE client costs nothing but its cursor, and
 * a reader that fell behind the ring learns how many events it missed. Listeners
 * (event_listen) are told about each event as it is published, on the publisher's thread:
 * that is how a sleeping stream is woken without polling.
 *
 * Thread: every function, any thread (the hub locks internally). Listener callbacks run
 * on the publishing thread with the listener lock held (not the ring lock): they must be
 * quick, must not block, and must not call event_publish, event_listen or event_unlisten.
 * Ownership: the hub copies what it is given; event_read copies out.
 */
#ifndef REFRACT_EVENTS_H
#define REFRACT_EVENTS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"

#define EVENT_SCENE_MAX 64 /* = STORE_ID_MAX */
#define EVENT_TYPE_MAX 32
#define EVENT_DATA_MAX 1024 /* one JSON object, serialised */

/* Event types (the SSE `event:` field). */
#define EVENT_SCENE_CREATED "scene.created" /* {"scene", "generation"} */
#define EVENT_SCENE_UPDATED "scene.updated" /* {"scene", "generation", "what"} */
#define EVENT_SCENE_DELETED "scene.deleted" /* {"scene"} */
#define EVENT_IRRADIANCE_PROGRESS                                                                  \
    "irradiance.progress" /* {"scene", "light", "state", "progress", "key"} */
#define EVENT_IRRADIANCE_READY                                                                     \
    "irradiance.ready" /* {"scene", "light", "key", "compute_ms", "loaded_from_disk"} */
#define EVENT_IRRADIANCE_FAILED "irradiance.failed" /* {"scene", "light", "key", "message"} */
#define EVENT_JOB_PROGRESS                                                                         \
    "job.progress" /* issue 5: {"job", "scene", "done", "total", "eta_s", "state"} */

struct event {
    uint64_t id;                 /* 1, 2, 3, ... */
    int64_t time_ms;             /* wall clock, milliseconds since the Unix epoch */
    char scene[EVENT_SCENE_MAX]; /* the scene it is about; "" = none (e.g. a job) */
    char type[EVENT_TYPE_MAX];   /* one of the EVENT_* names */
    char data[EVENT_DATA_MAX];   /* a JSON object */
};

struct event_hub;

/* A new hub keeping the last `capacity` events (0 = 1024). NULL with e filled when out of
 * memory. */
struct event_hub *event_hub_create(size_t capacity, struct err *e);
/* Frees the hub. Every listener must have been removed. NULL is a no-op. */
void event_hub_destroy(struct event_hub *h);

/* Records an event and tells the listeners. scene may be NULL or "". json_data is one JSON
 * object of at most EVENT_DATA_MAX - 1 bytes; a longer one is replaced by
 * {"truncated": true} (and logged: a bug in the publisher). Returns the event's id, or 0
 * when h is NULL (publishing into no hub is allowed, so modules work without one). */
uint64_t event_publish(struct event_hub *h, const char *scene, const char *type,
                       const char *json_data);

struct cJSON;
/* The same with a cJSON object, which it consumes (NULL json: out of memory, returns 0). */
uint64_t event_publish_json(struct event_hub *h, const char *scene, const char *type,
                            struct cJSON *json);

/* Copies into out (max entries) the events with id > after, oldest first, that are about
 * `scene` (NULL or "": every event; an event with scene "" is sent to every scene's
 * readers only when include_unscoped). Returns how many it copied. *lost (may be NULL) is
 * set to how many events after `after` had already left the ring (the reader fell
 * behind); *cursor is set to the id to pass as `after` next time (it moves past events
 * that were filtered out, so a filtered reader does not rescan them). */
size_t event_read(struct event_hub *h, uint64_t after, const char *scene, bool include_unscoped,
                  struct event *out, size_t max, uint64_t *lost, uint64_t *cursor);

/* The id of the newest event (0 = none yet). */
uint64_t event_last_id(struct event_hub *h);

/* Listeners: fn(ctx, ev) is called for every event published after event_listen returns.
 * Returns a token > 0 for event_unlisten, or 0 when the table is full (64 listeners).
 * event_unlisten returns only when fn is not running and will not be called again. */
typedef void (*event_listener_fn)(void *ctx, const struct event *ev);
int event_listen(struct event_hub *h, event_listener_fn fn, void *ctx);
void event_unlisten(struct event_hub *h, int token);

#endif
