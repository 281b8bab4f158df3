/*
 * clients.h - what each client (an IP address) holds of refractd: its open connections and
 * its requests waiting for or using the GPU, and the total of connections. These back the
 * fair-sharing limits (docs/api.md "Fair sharing"): --max-connections,
 * --max-connections-per-ip and --max-queued-per-client.
 *
 * A client is its IP address: behind a proxy every client is the proxy (set the per-IP
 * limits to what the proxy may use). Entries are made on a client's first connection and
 * freed when it holds nothing any more.
 * Thread: any; one mutex guards the table.
 */
#ifndef REFRACT_HTTP_CLIENTS_H
#define REFRACT_HTTP_CLIENTS_H

#include <stdbool.h>
#include <stddef.h>
#include <sys/socket.h>

#include "../core/err.h"

#define HTTP_CLIENT_IP_MAX 48 /* INET6_ADDRSTRLEN rounded up */

/* A client's identity: its address family and address bytes (16 for IPv6, 4 for IPv4),
 * and the text form for messages. */
struct http_client_key {
    int family;
    unsigned char addr[16];
    char ip[HTTP_CLIENT_IP_MAX];
};

struct http_clients;

/* A new, empty table, or NULL with e filled. */
struct http_clients *http_clients_create(struct err *e);
/* NULL is a no-op. Entries still held are freed too. */
void http_clients_destroy(struct http_clients *c);

/* The key of a peer address (AF_INET or AF_INET6; an IPv4-mapped IPv6 address is its IPv4
 * address). Another family, or NULL, gives the key "unknown" (one shared client). */
void http_client_key_from(const struct sockaddr *addr, struct http_client_key *out);

/* A connection opened: counts it. *client_connections is the client's count with it, and
 * *total the count of every client's, for the limits. */
void http_clients_connect(struct http_clients *c, const struct http_client_key *k,
                          int *client_connections, int *total);
/* A connection counted by http_clients_connect closed. */
void http_clients_disconnect(struct http_clients *c, const struct http_client_key *k);

/* Counts one more GPU request of the client unless it has `max` already (max <= 0: no
 * limit); returns whether it was counted. *queued is the client's count (with it, when
 * counted). */
bool http_clients_queue(struct http_clients *c, const struct http_client_key *k, int max,
                        int *queued);
/* A request counted by http_clients_queue is done (answered, or its client left). */
void http_clients_dequeue(struct http_clients *c, const struct http_client_key *k);

#endif
