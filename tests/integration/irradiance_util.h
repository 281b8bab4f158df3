/*
 * irradiance_util.h - what the irradiance and lights tests share, header-only like
 * expect.h: raw HTTP with libcurl that also returns the X-Refract-Irradiance header (the
 * client library does not expose it), the irradiance status, waiting for it, and a small
 * scene that needs light simulation: an index-matched box over a receiver, lit straight
 * down, on a 16-voxel light grid (docs/lightsim.md), so a volume computes in a fraction of
 * a second on llvmpipe.
 */
#ifndef REFRACT_TEST_IRRADIANCE_UTIL_H
#define REFRACT_TEST_IRRADIANCE_UTIL_H

#include <cjson/cJSON.h>
#include <curl/curl.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <time.h>

#include "daemon.h"
#include "test.h"

/* A check usable as an expression: counts like CHECK_MSG and returns cond. */
static inline bool irr_check(bool cond, const char *file, int line, const char *what)
{
    if (cond) {
        test_passed_count++;
    } else {
        test_failed_count++;
        fprintf(stderr, "%s:%d: CHECK failed: %s\n", file, line, what);
    }
    return cond;
}
#define IRR_CHECK(cond, what) irr_check((cond), __FILE__, __LINE__, (what))

/* The beam scene with lights `lights_json` (a JSON array). Caller frees. */
static inline char *beam_scene(const char *lights_json)
{
    static const char fmt[] =
        "{\"name\": \"beam\", \"camera\": {\"eye\": [0, 0.5, 4], \"look_at\": [0, -1, 0],"
        " \"up\": [0, 1, 0], \"fov_y_deg\": 50, \"width\": 24, \"height\": 16},"
        " \"environment\": {\"intensity\": 0},"
        " \"objects\": [{\"bounds\": {\"min\": [-0.5, -0.5, -0.5], \"max\": [0.5, 0.5, 0.5]},"
        " \"resolution\": 8, \"ior\": 1.0}],"
        " \"receiver\": {\"height\": -1, \"half_size\": 1, \"albedo\": 0.8},"
        " \"lights\": %s, \"lightsim\": {\"resolution\": 16, \"initial_patches\": 8}}";
    size_t n = sizeof fmt + strlen(lights_json);
    char *s = malloc(n);
    snprintf(s, n, fmt, lights_json);
    return s;
}

struct irr_answer {
    long status;
    char *body; /* NUL-terminated; owned */
    size_t len;
    char irradiance[32]; /* X-Refract-Irradiance, "" when absent */
    double seconds;      /* request to answer */
};

static inline size_t irr_body_cb(char *p, size_t size, size_t n, void *ud)
{
    struct irr_answer *a = ud;
    size_t add = size * n;
    char *grown = realloc(a->body, a->len + add + 1);
    if (grown == NULL)
        return 0;
    a->body = grown;
    memcpy(a->body + a->len, p, add);
    a->len += add;
    a->body[a->len] = '\0';
    return add;
}

static inline size_t irr_header_cb(char *p, size_t size, size_t n, void *ud)
{
    struct irr_answer *a = ud;
    size_t len = size * n;
    static const char name[] = "X-Refract-Irradiance:";
    if (len > sizeof name && strncasecmp(p, name, sizeof name - 1) == 0) {
        const char *v = p + sizeof name - 1;
        while (*v == ' ')
            v++;
        size_t k = 0;
        while (v + k < p + len && v[k] != '\r' && v[k] != '\n' && k + 1 < sizeof a->irradiance)
            k++;
        memcpy(a->irradiance, v, k);
        a->irradiance[k] = '\0';
    }
    return len;
}

/* One request; a->status is -1 when no answer came. Free a->body. */
static inline struct irr_answer irr_http(const struct test_daemon *d, const char *method,
                                         const char *path, const char *json)
{
    struct irr_answer a = {.status = -1};
    CURL *curl = curl_easy_init();
    char url[512];
    snprintf(url, sizeof url, "%s%s", d->url, path);
    struct curl_slist *hdr = curl_slist_append(NULL, "Content-Type: application/json");
    curl_easy_setopt(curl, CURLOPT_URL, url);
    curl_easy_setopt(curl, CURLOPT_CUSTOMREQUEST, method);
    if (json) {
        curl_easy_setopt(curl, CURLOPT_POSTFIELDS, json);
        curl_easy_setopt(curl, CURLOPT_POSTFIELDSIZE, (long)strlen(json));
        curl_easy_setopt(curl, CURLOPT_HTTPHEADER, hdr);
    }
    curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, irr_body_cb);
    curl_easy_setopt(curl, CURLOPT_WRITEDATA, &a);
    curl_easy_setopt(curl, CURLOPT_HEADERFUNCTION, irr_header_cb);
    curl_easy_setopt(curl, CURLOPT_HEADERDATA, &a);
    curl_easy_setopt(curl, CURLOPT_TIMEOUT, 60L);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    if (curl_easy_perform(curl) == CURLE_OK)
        curl_easy_getinfo(curl, CURLINFO_RESPONSE_CODE, &a.status);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    a.seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    curl_slist_free_all(hdr);
    curl_easy_cleanup(curl);
    return a;
}

/* GET /v1/scenes/{id}/irradiance, parsed (caller deletes), or NULL. */
static inline cJSON *irr_status(const struct test_daemon *d, const char *id)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/irradiance", id);
    struct irr_answer a = irr_http(d, "GET", path, NULL);
    cJSON *root = a.status == 200 ? cJSON_Parse(a.body) : NULL;
    free(a.body);
    return root;
}

/* The status entry of light `name` in a status object. */
static inline const cJSON *irr_light(const cJSON *status, const char *name)
{
    const cJSON *l = NULL;
    cJSON_ArrayForEach(l, cJSON_GetObjectItemCaseSensitive(status, "lights"))
    {
        const cJSON *n = cJSON_GetObjectItemCaseSensitive(l, "name");
        if (cJSON_IsString(n) && strcmp(n->valuestring, name) == 0)
            return l;
    }
    return NULL;
}

static inline const char *irr_str(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsString(v) ? v->valuestring : "";
}

static inline double irr_num(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
    return cJSON_IsNumber(v) ? v->valuedouble : -1.0;
}

/* A counter of the status's "cache" object. */
static inline double irr_counter(const cJSON *status, const char *key)
{
    return irr_num(cJSON_GetObjectItemCaseSensitive(status, "cache"), key);
}

/* Polls until every light is "ready" and no photon map is still refining (or a light
 * failed); returns the last status (caller deletes) after failing the test on a timeout or
 * a failure. */
static inline cJSON *irr_wait_ready(const struct test_daemon *d, const char *id, double timeout_s)
{
    struct timespec t0, now;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    for (;;) {
        cJSON *st = irr_status(d, id);
        bool ready = st != NULL, failed = false;
        const cJSON *l = NULL;
        cJSON_ArrayForEach(l, cJSON_GetObjectItemCaseSensitive(st, "lights"))
        {
            /* A photon map is "ready" from its first pass: wait for its last. */
            const cJSON *map = cJSON_GetObjectItemCaseSensitive(l, "photon_map");
            ready = ready && strcmp(irr_str(l, "state"), "ready") == 0 &&
                    !cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(map, "refining"));
            failed = failed || strcmp(irr_str(l, "state"), "failed") == 0;
        }
        clock_gettime(CLOCK_MONOTONIC, &now);
        double waited =
            (double)(now.tv_sec - t0.tv_sec) + 1e-9 * (double)(now.tv_nsec - t0.tv_nsec);
        if (ready || failed || waited > timeout_s) {
            char *text = st ? cJSON_PrintUnformatted(st) : NULL;
            CHECK_MSG(ready, "irradiance of scene %s not ready after %.1f s: %s", id, waited,
                      text ? text : "(no status)");
            free(text);
            return st;
        }
        cJSON_Delete(st);
        struct timespec pause = {0, 20 * 1000 * 1000};
        nanosleep(&pause, NULL);
    }
}

/* irr_wait_ready, then polls until light `name` says it was read back from disk: after a
 * restart an entry of the disk index is "ready" as soon as it is known, and its file is
 * read a moment later (under ASan and load that moment was seen in a status poll). Returns
 * the last status (caller deletes), failing the test on a timeout. */
static inline cJSON *irr_wait_loaded(const struct test_daemon *d, const char *id, const char *name,
                                     double timeout_s)
{
    cJSON *st = irr_wait_ready(d, id, timeout_s);
    for (int i = 0; i < (int)(timeout_s / 0.02); i++) {
        if (cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(irr_light(st, name), "loaded_from_disk")))
            return st;
        cJSON_Delete(st);
        struct timespec pause = {0, 20 * 1000 * 1000};
        nanosleep(&pause, NULL);
        st = irr_status(d, id);
    }
    CHECK_MSG(false, "light %s of scene %s was not read back from disk in %.0f s", name, id,
              timeout_s);
    return st;
}

#endif
