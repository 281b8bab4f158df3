/*
 * refract_client.c - the librefract handle: create, configure, destroy.
 *
 * A client owns one CURL easy handle for its whole life. Reusing it keeps libcurl's
 * connection cache, so consecutive calls to refractd share one keep-alive TCP connection.
 * The only process-wide state is libcurl's own, initialised once through pthread_once
 * (curl_global_init is not thread-safe in libcurl 7.88). This file does no I/O.
 */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "refract_internal.h"
#include "refract_url.h"

static pthread_once_t global_once = PTHREAD_ONCE_INIT;
static CURLcode global_result = CURLE_FAILED_INIT;

static void global_init(void)
{
    global_result = curl_global_init(CURL_GLOBAL_DEFAULT);
}

refract_client *refract_client_create(const char *base_url)
{
    refract_client *c;

    if (pthread_once(&global_once, global_init) != 0 || global_result != CURLE_OK)
        return NULL;
    c = calloc(1, sizeof(*c));
    if (c == NULL)
        return NULL;
    c->base_url = refract_url_join(base_url != NULL ? base_url : REFRACT_DEFAULT_URL, "");
    c->curl = curl_easy_init();
    if (c->base_url == NULL || c->curl == NULL)
        goto err;
    c->timeout_ms = REFRACT_DEFAULT_TIMEOUT_MS;
    return c;

err:
    refract_client_destroy(c);
    return NULL;
}

void refract_client_destroy(refract_client *c)
{
    if (c == NULL)
        return;
    if (c->curl != NULL)
        curl_easy_cleanup(c->curl);
    free(c->base_url);
    free(c);
}

void refract_set_timeout_ms(refract_client *c, long timeout_ms)
{
    if (c == NULL)
        return;
    c->timeout_ms = timeout_ms > 0 ? timeout_ms : 0;
}

void refract_free(void *p)
{
    free(p);
}
