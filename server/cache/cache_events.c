/*
 * cache_events.c - what the irradiance cache tells the event hub (events.h):
 * irradiance.progress, irradiance.ready and irradiance.failed for each (scene, light) slot
 * that wants a volume (irradiance_cache.h, "Events").
 *
 * Notes are queued under the cache's lock, where the state changes, and published by
 * irr_events_flush once the lock is released: a listener (an SSE stream, a view session)
 * never runs under the cache's lock, so it cannot deadlock against the GPU thread's
 * gathers. publish_lock, taken before the cache lock and held while publishing, keeps the
 * notes of concurrent flushes in the order they were made (never a progress after its
 * ready). Without a hub nothing is queued.
 */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "../events/events.h"
#include "cache_internal.h"

#define PROGRESS_EVERY_MS 250.0 /* docs/views.md: at most every 250 ms ... */
#define PROGRESS_EVERY 0.05     /* ... or 5 % per light */

/* Appends a note for slot sl about en (fields by type). */
static void note_locked(struct irradiance_cache *c, const struct irr_slot *sl,
                        const struct irr_entry *en, const char *type)
{
    struct irr_note *n = calloc(1, sizeof *n);
    if (n == NULL)
        return; /* an event lost to memory; the status API still tells */
    n->type = type;
    snprintf(n->scene, sizeof n->scene, "%s", sl->scene);
    snprintf(n->light, sizeof n->light, "%s", sl->light);
    n->key = en->key;
    n->state = en->phase == IRR_QUEUED ? "queued" : "computing";
    n->progress = en->phase == IRR_READY ? 1.0 : en->progress;
    n->compute_ms = en->compute_ms;
    n->loaded_from_disk = en->loaded_from_disk;
    n->photons = en->kind == IRR_KIND_PHOTONS;
    n->refining = en->refining;
    n->photons_emitted = en->has_host && en->host.photons ? en->host.photons->emitted : 0;
    snprintf(n->message, sizeof n->message, "%s", en->message);
    if (c->notes_tail)
        c->notes_tail->next = n;
    else
        c->notes_head = n;
    c->notes_tail = n;
}

void irr_note_progress_locked(struct irradiance_cache *c, struct irr_entry *en)
{
    if (c->desc.events == NULL)
        return;
    double now = gpu_time_ms();
    bool changed = en->noted_phase != (int)en->phase;
    if (!changed && now - en->noted_ms < PROGRESS_EVERY_MS &&
        en->progress - en->noted_progress < PROGRESS_EVERY)
        return;
    en->noted_phase = (int)en->phase;
    en->noted_progress = en->progress;
    en->noted_ms = now;
    for (size_t i = 0; i < c->slot_count; i++) {
        if (c->slots[i].current == en->key)
            note_locked(c, &c->slots[i], en, EVENT_IRRADIANCE_PROGRESS);
    }
}

void irr_note_ready_locked(struct irradiance_cache *c, struct irr_entry *en)
{
    for (size_t i = 0; i < c->slot_count; i++) {
        struct irr_slot *sl = &c->slots[i];
        if (sl->current != en->key || sl->announced)
            continue;
        sl->announced = true; /* once per change of the slot's key: renders ask again */
        if (c->desc.events)
            note_locked(c, sl, en, EVENT_IRRADIANCE_READY);
    }
}

void irr_note_failed_locked(struct irradiance_cache *c, const struct irr_entry *en)
{
    if (c->desc.events == NULL)
        return;
    for (size_t i = 0; i < c->slot_count; i++) {
        if (c->slots[i].current == en->key)
            note_locked(c, &c->slots[i], en, EVENT_IRRADIANCE_FAILED);
    }
}

static cJSON *note_json(const struct irr_note *n)
{
    cJSON *o = cJSON_CreateObject();
    if (o == NULL)
        return NULL;
    char key[17];
    snprintf(key, sizeof key, "%016" PRIx64, n->key);
    cJSON_AddStringToObject(o, "scene", n->scene);
    cJSON_AddStringToObject(o, "light", n->light);
    if (strcmp(n->type, EVENT_IRRADIANCE_PROGRESS) == 0) {
        cJSON_AddStringToObject(o, "state", n->state);
        cJSON_AddNumberToObject(o, "progress", n->progress);
    }
    cJSON_AddStringToObject(o, "key", key);
    if (strcmp(n->type, EVENT_IRRADIANCE_READY) == 0) {
        cJSON_AddNumberToObject(o, "compute_ms", n->compute_ms);
        cJSON_AddBoolToObject(o, "loaded_from_disk", n->loaded_from_disk);
        if (n->photons) { /* a photon map's pass (docs/photons.md "The cache") */
            cJSON_AddNumberToObject(o, "photons", (double)n->photons_emitted);
            cJSON_AddBoolToObject(o, "refining", n->refining);
        }
    } else if (strcmp(n->type, EVENT_IRRADIANCE_FAILED) == 0) {
        cJSON_AddStringToObject(o, "message", n->message);
    }
    return o;
}

void irr_events_flush(struct irradiance_cache *c)
{
    if (c->desc.events == NULL)
        return;
    pthread_mutex_lock(&c->publish_lock);
    pthread_mutex_lock(&c->lock);
    struct irr_note *n = c->notes_head;
    c->notes_head = c->notes_tail = NULL;
    pthread_mutex_unlock(&c->lock);
    while (n) {
        struct irr_note *next = n->next;
        event_publish_json(c->desc.events, n->scene, n->type, note_json(n));
        free(n);
        n = next;
    }
    pthread_mutex_unlock(&c->publish_lock);
}

void irr_notes_free(struct irradiance_cache *c)
{
    while (c->notes_head) {
        struct irr_note *next = c->notes_head->next;
        free(c->notes_head);
        c->notes_head = next;
    }
    c->notes_tail = NULL;
}
