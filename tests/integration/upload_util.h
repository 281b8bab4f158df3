/*
 * upload_util.h - what the upload tests share (header-only): a raw PUT of bytes, the
 * FNV-1a 64 checksum computed independently of refractd, the SHA-256 of a file by
 * coreutils' sha256sum (code refractd does not share), JSON field access, gzip.
 */
#ifndef REFRACT_TEST_UPLOAD_UTIL_H
#define REFRACT_TEST_UPLOAD_UTIL_H

#include <cjson/cJSON.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "daemon.h"

/* PUT bytes to path (with its query); returns the status or -1; *body a new string. */
static inline long upload_put(struct test_daemon *d, const char *path, const void *bytes,
                              size_t len, char **body)
{
    struct refract_response r;
    *body = NULL;
    if (refract_request(d->client, "PUT", path, bytes, len, "application/octet-stream", &r) !=
        REFRACT_E_OK)
        return -1;
    long status = r.status;
    *body = r.body;
    r.body = NULL;
    refract_response_free(&r);
    return status;
}

static inline uint64_t upload_fnv1a64(const void *data, size_t len)
{
    const unsigned char *p = data;
    uint64_t h = 14695981039346656037ull;
    for (size_t i = 0; i < len; i++) {
        h ^= p[i];
        h *= 1099511628211ull;
    }
    return h;
}

static inline void upload_fnv_hex(const float *values, size_t count, char out[17])
{
    snprintf(out, 17, "%016llx", (unsigned long long)upload_fnv1a64(values, count * sizeof(float)));
}

/* The SHA-256 of the file at path as 64 hex digits, from `sha256sum` (coreutils), or
 * "" when it cannot be run. */
static inline void upload_sha256sum(const char *path, char out[65])
{
    char cmd[600];
    out[0] = '\0';
    snprintf(cmd, sizeof cmd, "sha256sum '%s'", path);
    FILE *p = popen(cmd, "r");
    if (p == NULL)
        return;
    if (fscanf(p, "%64[0-9a-f]", out) != 1)
        out[0] = '\0';
    pclose(p);
}

/* The string field `key` of a JSON body ("" when absent), copied into out. */
static inline void upload_json_string(const char *body, const char *key, char *out, size_t size)
{
    out[0] = '\0';
    cJSON *root = cJSON_Parse(body ? body : "");
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, key);
    if (cJSON_IsString(v))
        snprintf(out, size, "%s", v->valuestring);
    cJSON_Delete(root);
}

static inline double upload_json_number(const char *body, const char *key)
{
    cJSON *root = cJSON_Parse(body ? body : "");
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, key);
    double x = cJSON_IsNumber(v) ? v->valuedouble : -1e300;
    cJSON_Delete(root);
    return x;
}

/* gzip (RFC 1952) of bytes: a new buffer the caller frees, *out_len its size. */
static inline unsigned char *upload_gzip(const void *bytes, size_t len, size_t *out_len)
{
    z_stream z = {0};
    if (deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
        return NULL;
    size_t cap = deflateBound(&z, (uLong)len) + 64;
    unsigned char *out = malloc(cap);
    z.next_in = (Bytef *)bytes;
    z.avail_in = (uInt)len;
    z.next_out = out;
    z.avail_out = (uInt)cap;
    int rc = deflate(&z, Z_FINISH);
    *out_len = z.total_out;
    deflateEnd(&z);
    if (rc != Z_STREAM_END) {
        free(out);
        return NULL;
    }
    return out;
}

#endif
