/*
 * clients.c - the clients table (clients.h): a chained hash of entries keyed by address,
 * each with its connection and GPU-request counts, freed when both reach zero.
 *
 * INVARIANT: `total` is the sum of the entries' `connections`; an entry with both counts
 * zero is not in the table.
 */
#include "clients.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <pthread.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define BUCKETS 1024 /* a power of two */

struct entry {
    struct http_client_key key;
    int connections, queued;
    struct entry *next;
};

struct http_clients {
    pthread_mutex_t lock;
    struct entry *buckets[BUCKETS];
    int total;
};

struct http_clients *http_clients_create(struct err *e)
{
    struct http_clients *c = calloc(1, sizeof *c);
    if (c == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the clients table");
        return NULL;
    }
    pthread_mutex_init(&c->lock, NULL);
    return c;
}

void http_clients_destroy(struct http_clients *c)
{
    if (c == NULL)
        return;
    for (size_t b = 0; b < BUCKETS; b++) {
        struct entry *n = c->buckets[b];
        while (n) {
            struct entry *next = n->next;
            free(n);
            n = next;
        }
    }
    pthread_mutex_destroy(&c->lock);
    free(c);
}

void http_client_key_from(const struct sockaddr *addr, struct http_client_key *out)
{
    memset(out, 0, sizeof *out);
    static const unsigned char v4_mapped[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0xff, 0xff};
    if (addr != NULL && addr->sa_family == AF_INET) {
        const struct sockaddr_in *a = (const struct sockaddr_in *)addr;
        out->family = AF_INET;
        memcpy(out->addr, &a->sin_addr, 4);
    } else if (addr != NULL && addr->sa_family == AF_INET6) {
        const struct sockaddr_in6 *a = (const struct sockaddr_in6 *)addr;
        if (memcmp(a->sin6_addr.s6_addr, v4_mapped, sizeof v4_mapped) == 0) {
            out->family = AF_INET;
            memcpy(out->addr, a->sin6_addr.s6_addr + 12, 4);
        } else {
            out->family = AF_INET6;
            memcpy(out->addr, a->sin6_addr.s6_addr, 16);
        }
    }
    if (out->family == 0 || inet_ntop(out->family, out->addr, out->ip, sizeof out->ip) == NULL)
        snprintf(out->ip, sizeof out->ip, "unknown");
}

/* FNV-1a over the family and the address bytes. */
static size_t bucket_of(const struct http_client_key *k)
{
    uint32_t h = 2166136261u ^ (uint32_t)k->family;
    for (size_t i = 0; i < sizeof k->addr; i++)
        h = (h ^ k->addr[i]) * 16777619u;
    return h & (BUCKETS - 1);
}

static bool same(const struct http_client_key *a, const struct http_client_key *b)
{
    return a->family == b->family && memcmp(a->addr, b->addr, sizeof a->addr) == 0;
}

/* The entry of k, made when `make` (NULL when out of memory or not there). Lock held. */
static struct entry *find(struct http_clients *c, const struct http_client_key *k, bool make)
{
    struct entry **head = &c->buckets[bucket_of(k)];
    for (struct entry *n = *head; n; n = n->next) {
        if (same(&n->key, k))
            return n;
    }
    if (!make)
        return NULL;
    struct entry *n = calloc(1, sizeof *n);
    if (n == NULL)
        return NULL;
    n->key = *k;
    n->next = *head;
    *head = n;
    return n;
}

/* Frees n when it holds nothing any more. Lock held. */
static void drop_if_empty(struct http_clients *c, struct entry *n)
{
    if (n->connections > 0 || n->queued > 0)
        return;
    for (struct entry **p = &c->buckets[bucket_of(&n->key)]; *p; p = &(*p)->next) {
        if (*p == n) {
            *p = n->next;
            free(n);
            return;
        }
    }
}

void http_clients_connect(struct http_clients *c, const struct http_client_key *k,
                          int *client_connections, int *total)
{
    pthread_mutex_lock(&c->lock);
    struct entry *n = find(c, k, true);
    c->total++;
    /* Out of memory for an entry: the connection still counts in the total; the client's
     * own count reads 1 so that the per-IP limit never refuses it for want of memory. */
    *client_connections = n ? ++n->connections : 1;
    *total = c->total;
    pthread_mutex_unlock(&c->lock);
}

void http_clients_disconnect(struct http_clients *c, const struct http_client_key *k)
{
    pthread_mutex_lock(&c->lock);
    if (c->total > 0)
        c->total--;
    struct entry *n = find(c, k, false);
    if (n != NULL && n->connections > 0) {
        n->connections--;
        drop_if_empty(c, n);
    }
    pthread_mutex_unlock(&c->lock);
}

bool http_clients_queue(struct http_clients *c, const struct http_client_key *k, int max,
                        int *queued)
{
    pthread_mutex_lock(&c->lock);
    struct entry *n = find(c, k, true);
    bool ok = n != NULL && (max <= 0 || n->queued < max);
    if (ok)
        n->queued++;
    *queued = n ? n->queued : 0;
    pthread_mutex_unlock(&c->lock);
    return ok;
}

void http_clients_dequeue(struct http_clients *c, const struct http_client_key *k)
{
    pthread_mutex_lock(&c->lock);
    struct entry *n = find(c, k, false);
    if (n != NULL && n->queued > 0) {
        n->queued--;
        drop_if_empty(c, n);
    }
    pthread_mutex_unlock(&c->lock);
}
