/*
 * test_events.c - the event hub (server/events/events.h): ids, the bounded ring and what a
 * reader that fell behind is told, scene filtering and the reader's cursor, listeners and
 * their removal, oversized data, and publishers on several threads.
 */
#include <pthread.h>
#include <stdio.h>
#include <string.h>

#include "../test.h"
#include "events/events.h"

static struct event_hub *make_hub(size_t capacity)
{
    struct err e = {0};
    struct event_hub *h = event_hub_create(capacity, &e);
    if (h == NULL)
        test_setup_failed("test_events", e.msg);
    return h;
}

static void ids_grow_by_one_and_readers_get_what_came_after(void)
{
    struct event_hub *h = make_hub(8);
    CHECK(event_last_id(h) == 0);
    CHECK(event_publish(h, "a", EVENT_SCENE_CREATED, "{\"n\":1}") == 1);
    CHECK(event_publish(h, "b", EVENT_SCENE_CREATED, "{\"n\":2}") == 2);
    CHECK(event_publish(h, "a", EVENT_SCENE_UPDATED, "{\"n\":3}") == 3);
    struct event out[8];
    uint64_t lost = 99, cursor = 0;
    size_t n = event_read(h, 1, NULL, false, out, 8, &lost, &cursor);
    CHECK_INT((int)n, 2);
    CHECK(lost == 0);
    CHECK(cursor == 3);
    CHECK(out[0].id == 2 && out[1].id == 3);
    CHECK_STR(out[0].scene, "b");
    CHECK_STR(out[1].type, EVENT_SCENE_UPDATED);
    CHECK_STR(out[1].data, "{\"n\":3}");
    CHECK(out[1].time_ms > 1700000000000LL); /* wall clock, ms since the epoch */
    /* Nothing new: nothing read, the cursor stays. */
    CHECK_INT((int)event_read(h, cursor, NULL, false, out, 8, &lost, &cursor), 0);
    CHECK(cursor == 3);
    event_hub_destroy(h);
}

static void a_reader_behind_the_ring_learns_how_many_it_missed(void)
{
    struct event_hub *h = make_hub(4);
    for (int i = 0; i < 10; i++)
        event_publish(h, "s", EVENT_SCENE_UPDATED, "{}");
    struct event out[8];
    uint64_t lost = 0, cursor = 0;
    size_t n = event_read(h, 0, NULL, false, out, 8, &lost, &cursor);
    /* Ids 1..10; the ring holds 7..10, so 1..6 are gone. */
    CHECK_INT((int)n, 4);
    CHECK(lost == 6);
    CHECK(out[0].id == 7 && out[3].id == 10);
    CHECK(cursor == 10);
    /* A reader exactly at the ring's start missed nothing. */
    n = event_read(h, 6, NULL, false, out, 8, &lost, &cursor);
    CHECK_INT((int)n, 4);
    CHECK(lost == 0);
    /* max limits the batch; the cursor stops after the last one copied. */
    n = event_read(h, 6, NULL, false, out, 2, &lost, &cursor);
    CHECK_INT((int)n, 2);
    CHECK(cursor == 8);
    event_hub_destroy(h);
}

static void scene_readers_see_their_scene_and_unscoped_events_only_when_asked(void)
{
    struct event_hub *h = make_hub(16);
    event_publish(h, "glass", EVENT_SCENE_CREATED, "{}"); /* 1 */
    event_publish(h, "water", EVENT_SCENE_CREATED, "{}"); /* 2 */
    event_publish(h, NULL, EVENT_JOB_PROGRESS, "{}");     /* 3 */
    event_publish(h, "glass", EVENT_SCENE_DELETED, "{}"); /* 4 */
    event_publish(h, "water", EVENT_SCENE_UPDATED, "{}"); /* 5 */
    struct event out[16];
    uint64_t cursor = 0;
    size_t n = event_read(h, 0, "glass", false, out, 16, NULL, &cursor);
    CHECK_INT((int)n, 2);
    CHECK(out[0].id == 1 && out[1].id == 4);
    /* The cursor passed the filtered-out events too. */
    CHECK(cursor == 5);
    n = event_read(h, 0, "glass", true, out, 16, NULL, &cursor);
    CHECK_INT((int)n, 3);
    CHECK(out[1].id == 3);
    CHECK_STR(out[1].scene, "");
    n = event_read(h, 0, "", false, out, 16, NULL, &cursor);
    CHECK_INT((int)n, 5);
    event_hub_destroy(h);
}

struct counting_listener {
    int calls;
    uint64_t last_id;
    char last_type[EVENT_TYPE_MAX];
};

static void count_event(void *ctx, const struct event *ev)
{
    struct counting_listener *c = ctx;
    c->calls++;
    c->last_id = ev->id;
    snprintf(c->last_type, sizeof c->last_type, "%s", ev->type);
}

static void listeners_hear_each_event_until_removed(void)
{
    struct event_hub *h = make_hub(4);
    struct counting_listener a = {0}, b = {0};
    int ta = event_listen(h, count_event, &a);
    int tb = event_listen(h, count_event, &b);
    CHECK(ta > 0 && tb > 0 && ta != tb);
    event_publish(h, "s", EVENT_IRRADIANCE_READY, "{}");
    CHECK_INT(a.calls, 1);
    CHECK_INT(b.calls, 1);
    CHECK(a.last_id == 1);
    CHECK_STR(a.last_type, EVENT_IRRADIANCE_READY);
    event_unlisten(h, ta);
    event_publish(h, "s", EVENT_IRRADIANCE_FAILED, "{}");
    CHECK_INT(a.calls, 1);
    CHECK_INT(b.calls, 2);
    event_unlisten(h, tb);
    event_unlisten(h, 0); /* no-op */
    /* The table holds 64 listeners; the 65th is refused with 0. */
    int tokens[65], refused = 0;
    for (int i = 0; i < 65; i++)
        if ((tokens[i] = event_listen(h, count_event, &a)) == 0)
            refused++;
    CHECK_INT(refused, 1);
    for (int i = 0; i < 65; i++)
        event_unlisten(h, tokens[i]);
    event_publish(h, "s", EVENT_SCENE_UPDATED, "{}");
    CHECK_INT(a.calls, 1);
    event_hub_destroy(h);
}

static void oversized_data_is_replaced_and_no_hub_is_allowed(void)
{
    struct event_hub *h = make_hub(4);
    char big[EVENT_DATA_MAX + 10];
    memset(big, 'x', sizeof big - 1);
    big[sizeof big - 1] = '\0';
    event_publish(h, "s", EVENT_SCENE_UPDATED, big);
    struct event out[1];
    CHECK_INT((int)event_read(h, 0, NULL, false, out, 1, NULL, NULL), 1);
    CHECK_STR(out[0].data, "{\"truncated\":true}");
    /* A scene id longer than the field is cut, never overflowing. */
    char long_id[200];
    memset(long_id, 'a', sizeof long_id - 1);
    long_id[sizeof long_id - 1] = '\0';
    event_publish(h, long_id, EVENT_SCENE_UPDATED, "{}");
    event_read(h, 1, NULL, false, out, 1, NULL, NULL);
    CHECK_INT((int)strlen(out[0].scene), EVENT_SCENE_MAX - 1);
    event_hub_destroy(h);
    CHECK(event_publish(NULL, "s", EVENT_SCENE_UPDATED, "{}") == 0);
}

#define PUBLISHERS 4
#define PER_PUBLISHER 2000

static void *publish_many(void *arg)
{
    struct event_hub *h = arg;
    for (int i = 0; i < PER_PUBLISHER; i++)
        event_publish(h, "s", EVENT_IRRADIANCE_PROGRESS, "{}");
    return NULL;
}

static void concurrent_publishers_get_distinct_ids_and_lose_nothing(void)
{
    struct event_hub *h = make_hub(PUBLISHERS * PER_PUBLISHER);
    pthread_t t[PUBLISHERS];
    for (int i = 0; i < PUBLISHERS; i++)
        pthread_create(&t[i], NULL, publish_many, h);
    for (int i = 0; i < PUBLISHERS; i++)
        pthread_join(t[i], NULL);
    CHECK(event_last_id(h) == PUBLISHERS * PER_PUBLISHER);
    static struct event out[PUBLISHERS * PER_PUBLISHER];
    uint64_t lost = 1;
    size_t n = event_read(h, 0, NULL, false, out, PUBLISHERS * PER_PUBLISHER, &lost, NULL);
    CHECK_INT((int)n, PUBLISHERS * PER_PUBLISHER);
    CHECK(lost == 0);
    int in_order = 1;
    for (size_t i = 0; i < n; i++)
        if (out[i].id != i + 1)
            in_order = 0;
    CHECK(in_order);
    event_hub_destroy(h);
}

int main(void)
{
    ids_grow_by_one_and_readers_get_what_came_after();
    a_reader_behind_the_ring_learns_how_many_it_missed();
    scene_readers_see_their_scene_and_unscoped_events_only_when_asked();
    listeners_hear_each_event_until_removed();
    oversized_data_is_replaced_and_no_hub_is_allowed();
    concurrent_publishers_get_distinct_ids_and_lose_nothing();
    return test_summary("test_events");
}
