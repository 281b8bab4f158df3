/*
 * expect.h - the bad-input tests' checks, header-only like test.h (its pass/fail counters
 * are per test program): send one request, expect exactly this error (status, JSON
 * error.code, words of the message) or this status, and count the cases per section.
 *
 *     section("POST /v1/scenes");
 *     EXPECT_ERROR(d, "POST", "/v1/scenes", "{", 400, "invalid_json", "at byte 1");
 *     free(EXPECT_STATUS(d, "GET", "/v1/health", NULL, 200));
 */
#ifndef REFRACT_TEST_EXPECT_H
#define REFRACT_TEST_EXPECT_H

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "daemon.h"
#include "test.h"

static const char *section_name = "";
static int section_cases;

/* Starts a group of cases; prints how many cases the previous group had. */
static inline void section(const char *name)
{
    if (section_name[0] != '\0')
        printf("  %-34s %3d cases\n", section_name, section_cases);
    section_name = name;
    section_cases = 0;
}

static inline size_t text_len(const char *s)
{
    return s ? strlen(s) : 0;
}

/* Writes into why (empty when it matches) how the answer differs from the expected error:
 * the status, application/json, {"error": {"code", "message"}}, the code, each needle. */
static inline void error_mismatch(const struct refract_response *r, long status, const char *code,
                                  const char *const *needles, char *why, size_t size)
{
    why[0] = '\0';
    cJSON *root = cJSON_ParseWithLength(r->body, r->body_len);
    const cJSON *err = cJSON_GetObjectItemCaseSensitive(root, "error");
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(err, "code");
    const cJSON *m = cJSON_GetObjectItemCaseSensitive(err, "message");
    if (r->status != status)
        snprintf(why, size, "HTTP status %ld, expected %ld", r->status, status);
    else if (strncmp(r->content_type, "application/json", 16) != 0)
        snprintf(why, size, "Content-Type \"%s\", expected application/json", r->content_type);
    else if (!cJSON_IsString(c) || !cJSON_IsString(m) || m->valuestring[0] == '\0')
        snprintf(why, size, "not an {\"error\": {\"code\", \"message\"}} body");
    else if (strcmp(c->valuestring, code) != 0)
        snprintf(why, size, "error.code \"%s\", expected \"%s\"", c->valuestring, code);
    for (size_t i = 0; why[0] == '\0' && needles[i] != NULL; i++) {
        if (strstr(m->valuestring, needles[i]) == NULL)
            snprintf(why, size, "the message lacks \"%s\"", needles[i]);
    }
    cJSON_Delete(root);
}

/* Sends one request and checks that the answer is the error (status, code, needles). */
static inline void expect_error_at(const char *file, int line, struct test_daemon *d,
                                   const char *method, const char *path, const void *body,
                                   size_t len, const char *content_type, long status,
                                   const char *code, const char *const *needles)
{
    struct refract_response r;
    char why[300];
    section_cases++;
    int rc = refract_request(d->client, method, path, body, len, content_type, &r);
    if (rc != REFRACT_E_OK)
        snprintf(why, sizeof why, "no HTTP answer (%s)", refract_errmsg(d->client));
    else
        error_mismatch(&r, status, code, needles, why, sizeof why);
    if (why[0] == '\0') {
        test_passed_count++;
    } else {
        test_failed_count++;
        fprintf(stderr, "%s:%d: %s %s [%s]: expected %ld %s", file, line, method, path,
                section_name, status, code);
        for (size_t i = 0; needles[i] != NULL; i++)
            fprintf(stderr, " \"%s\"", needles[i]);
        fprintf(stderr, "\n    %s; got %ld %s\n", why, rc == REFRACT_E_OK ? r.status : -1L,
                rc == REFRACT_E_OK ? r.body : "");
    }
    if (rc == REFRACT_E_OK)
        refract_response_free(&r);
}

/* A JSON body (or none when json is NULL) expected to give the error. */
#define EXPECT_ERROR(d, method, path, json, status, code, ...)                                     \
    expect_error_at(__FILE__, __LINE__, (d), (method), (path), (json), text_len(json),             \
                    (json) ? "application/json" : NULL, (status), (code),                          \
                    (const char *const[]){__VA_ARGS__, NULL})

/* Raw bytes with a Content-Type expected to give the error. */
#define EXPECT_RAW_ERROR(d, method, path, bytes, len, ctype, status, code, ...)                    \
    expect_error_at(__FILE__, __LINE__, (d), (method), (path), (bytes), (len), (ctype), (status),  \
                    (code), (const char *const[]){__VA_ARGS__, NULL})

/* Sends a JSON request and checks its status; returns the body (new string, caller frees)
 * or NULL. */
static inline char *expect_status_at(const char *file, int line, struct test_daemon *d,
                                     const char *method, const char *path, const char *json,
                                     long status)
{
    char *body = NULL;
    long got = test_request(d, method, path, json, &body);
    if (got == status) {
        test_passed_count++;
        return body;
    }
    test_failed_count++;
    fprintf(stderr, "%s:%d: %s %s: expected HTTP %ld, got %ld: %s\n", file, line, method, path,
            status, got, body ? body : "(no answer)");
    free(body);
    return NULL;
}
#define EXPECT_STATUS(d, method, path, json, status)                                               \
    expect_status_at(__FILE__, __LINE__, (d), (method), (path), (json), (status))

/* A table row: a JSON body sent to one route and the error it must get. `line` is the
 * row's __LINE__, so a failure points at the row. */
struct json_error_case {
    int line;
    const char *json;
    long status;
    const char *code;
    const char *needles[3];
};

/* Sends every case's body to method path (Content-Type application/json); failures name
 * file:line of the row. */
static inline void expect_json_error_cases_at(const char *file, struct test_daemon *d,
                                              const char *method, const char *path,
                                              const struct json_error_case *cases, size_t count)
{
    for (size_t i = 0; i < count; i++) {
        const struct json_error_case *c = &cases[i];
        const char *needles[4] = {c->needles[0], c->needles[1], c->needles[2], NULL};
        expect_error_at(file, c->line, d, method, path, c->json, strlen(c->json),
                        "application/json", c->status, c->code, needles);
    }
}
#define EXPECT_JSON_ERROR_CASES(d, method, path, cases)                                            \
    expect_json_error_cases_at(__FILE__, (d), (method), (path), (cases),                           \
                               sizeof(cases) / sizeof((cases)[0]))

#endif
