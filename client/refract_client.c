/*
 * refract_client.c - the librefract handle: create, configure, destroy.
 *
 * A client owns one CURL easy handle for its whole life. Reusing it keeps libcurl's
 * connection cache, so consecutive calls to refractd share one keep-alive TCP connection.
 * The only process-wide state is libcurl's own, initialised once through pthread_once
 * (curl_global_init is not thread-safe in libcurl 7.88). This file does no I/O.
 */
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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
    /* REFRACT_TOKEN: an invalid one is ignored here; the first 401 says what to send. */
    (void)refract_set_token(c, getenv("REFRACT_TOKEN"));
    refract_clear_error(c);
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
    if (c->token != NULL)
        memset(c->token, 0, strlen(c->token));
    free(c->token);
    free(c->cacert);
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

int refract_set_token(refract_client *c, const char *token)
{
    char *copy = NULL;

    if (c == NULL)
        return REFRACT_E_USAGE;
    if (token != NULL && token[0] != '\0') {
        for (const char *p = token; *p != '\0'; p++) {
            if ((unsigned char)*p <= 0x20 || (unsigned char)*p >= 0x7f)
                return refract_fail(c, REFRACT_E_USAGE,
                                    "the bearer token holds a space or a character that is not "
                                    "visible ASCII (at position %zu); refractd's tokens are "
                                    "one line of visible ASCII",
                                    (size_t)(p - token));
        }
        copy = strdup(token);
        if (copy == NULL)
            return refract_out_of_memory(c, "storing the bearer token");
    }
    if (c->token != NULL)
        memset(c->token, 0, strlen(c->token));
    free(c->token);
    c->token = copy;
    return REFRACT_E_OK;
}

int refract_set_token_file(refract_client *c, const char *path)
{
    char line[4096];
    size_t len, start;
    FILE *f;
    int code;

    if (c == NULL)
        return REFRACT_E_USAGE;
    if (path == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_set_token_file: path is NULL");
    f = fopen(path, "r");
    if (f == NULL)
        return refract_fail(c, REFRACT_E_IO, "cannot read the token file %s: %s", path,
                            strerror(errno));
    if (fgets(line, sizeof(line), f) == NULL)
        line[0] = '\0';
    fclose(f);
    len = strcspn(line, "\r\n");
    while (len > 0 && (line[len - 1] == ' ' || line[len - 1] == '\t'))
        len--;
    line[len] = '\0';
    start = strspn(line, " \t");
    if (line[start] == '\0')
        return refract_fail(c, REFRACT_E_USAGE, "the token file %s has no token on its first line",
                            path);
    code = refract_set_token(c, line + start);
    memset(line, 0, sizeof(line));
    return code;
}

int refract_set_cacert(refract_client *c, const char *path)
{
    char *copy = NULL;

    if (c == NULL)
        return REFRACT_E_USAGE;
    if (path != NULL) {
        if (access(path, R_OK) != 0)
            return refract_fail(c, REFRACT_E_IO, "cannot read the CA certificate file %s: %s",
                                path, strerror(errno));
        copy = strdup(path);
        if (copy == NULL)
            return refract_out_of_memory(c, "storing the CA file's path");
    }
    free(c->cacert);
    c->cacert = copy;
    return REFRACT_E_OK;
}
