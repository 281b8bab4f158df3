/*
 * refract_status.c - the irradiance status document read into struct refract_irradiance
 * (see refract_status.h), and the questions asked of it.
 *
 * Only "lights", and each light's "name" and "state", are required: they are what a
 * client cannot do without. Every other member is read when present and of the right
 * type, so a refractd that adds members, or one that leaves some out, still reads.
 */
#include "refract_status.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "refract_say.h"

static void copy_member(char *dst, size_t dst_size, const cJSON *obj, const char *key)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);
    const char *src = cJSON_IsString(item) ? item->valuestring : "";
    size_t n = strnlen(src, dst_size - 1);

    memcpy(dst, src, n);
    dst[n] = '\0';
}

static double number_member(const cJSON *obj, const char *key)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);

    return cJSON_IsNumber(item) ? item->valuedouble : -1.0;
}

/* A non-negative whole count (bytes, patches); -1 when absent, negative or too large. */
static long long count_member(const cJSON *obj, const char *key)
{
    double v = number_member(obj, key);

    return v >= 0 && v < 9.0e18 ? (long long)v : -1;
}

/* The code of a JSON code name ("gpu_out_of_memory"), 0 when the table has none. The
 * table is walked here rather than through refract_error.c so that this file stays free
 * of libcurl's headers. */
static int code_of(const char *json_code)
{
    static const struct {
        int code;
        const char *json;
    } rows[] = {
#define REFRACT_X_ROW(name, num, http, json, text) {num, json},
        REFRACT_ERROR_TABLE(REFRACT_X_ROW)
#undef REFRACT_X_ROW
    };

    for (size_t i = 0; i < sizeof(rows) / sizeof(rows[0]); i++) {
        if (strcmp(rows[i].json, json_code) == 0)
            return rows[i].code;
    }
    return 0;
}

static bool read_light(const cJSON *obj, size_t i, struct refract_light_status *l, char *why,
                       size_t why_size)
{
    const cJSON *name = cJSON_GetObjectItemCaseSensitive(obj, "name");
    const cJSON *state = cJSON_GetObjectItemCaseSensitive(obj, "state");
    const cJSON *code = cJSON_GetObjectItemCaseSensitive(obj, "code");

    if (!cJSON_IsObject(obj))
        return refract_say(why, why_size, "lights[%zu]: expected an object", i);
    if (!cJSON_IsString(name) || name->valuestring[0] == '\0')
        return refract_say(why, why_size, "lights[%zu].name: expected a non-empty string", i);
    if (!cJSON_IsString(state) || state->valuestring[0] == '\0')
        return refract_say(why, why_size, "lights[%zu].state: expected a non-empty string", i);
    copy_member(l->name, sizeof(l->name), obj, "name");
    copy_member(l->state, sizeof(l->state), obj, "state");
    copy_member(l->key, sizeof(l->key), obj, "key");
    copy_member(l->using_volume, sizeof(l->using_volume), obj, "using");
    copy_member(l->message, sizeof(l->message), obj, "message");
    l->progress = number_member(obj, "progress");
    l->patches_live = count_member(obj, "patches_live");
    l->gpu_bytes = count_member(obj, "gpu_bytes");
    l->host_bytes = count_member(obj, "host_bytes");
    l->compute_ms = number_member(obj, "compute_ms");
    l->code = cJSON_IsString(code) ? code_of(code->valuestring) : 0;
    const cJSON *map = cJSON_GetObjectItemCaseSensitive(obj, "photon_map");
    l->photon_map = cJSON_IsObject(map);
    l->refining = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(map, "refining"));
    l->photons = l->photon_map && count_member(map, "photons") > 0 ? count_member(map, "photons")
                                                                   : 0;
    return true;
}

bool refract_status_from_json(const char *json, size_t len, struct refract_irradiance *out,
                              char *why, size_t why_size)
{
    cJSON *root = json != NULL ? cJSON_ParseWithLengthOpts(json, len, NULL, 0) : NULL;
    const cJSON *lights = cJSON_GetObjectItemCaseSensitive(root, "lights");
    const cJSON *needed = cJSON_GetObjectItemCaseSensitive(root, "needed");
    size_t n = 0;
    bool ok = true;

    memset(out, 0, sizeof(*out));
    if (root == NULL || !cJSON_IsObject(root)) {
        cJSON_Delete(root);
        return refract_say(why, why_size, "expected a JSON object {\"scene\", \"lights\": [...]}");
    }
    if (!cJSON_IsArray(lights)) {
        cJSON_Delete(root);
        return refract_say(why, why_size, "lights: expected an array");
    }
    n = (size_t)cJSON_GetArraySize(lights);
    out->lights = n > 0 ? calloc(n, sizeof(*out->lights)) : NULL;
    if (n > 0 && out->lights == NULL) {
        cJSON_Delete(root);
        return refract_say(why, why_size, "out of memory reading %zu lights", n);
    }
    copy_member(out->scene, sizeof(out->scene), root, "scene");
    copy_member(out->transport_hash, sizeof(out->transport_hash), root, "transport_hash");
    out->needed = cJSON_IsBool(needed) ? cJSON_IsTrue(needed) : 1;
    for (size_t i = 0; i < n && ok; i++)
        ok = read_light(cJSON_GetArrayItem(lights, (int)i), i, &out->lights[i], why, why_size);
    cJSON_Delete(root);
    if (!ok) {
        free(out->lights);
        memset(out, 0, sizeof(*out));
        return false;
    }
    out->light_count = n;
    return true;
}

bool refract_state_is_settled(const char *state)
{
    return strcmp(state, "ready") == 0 || strcmp(state, "failed") == 0 ||
           strcmp(state, "not_needed") == 0;
}

int refract_irradiance_settled(const struct refract_irradiance *status)
{
    if (status == NULL)
        return 0;
    for (size_t i = 0; i < status->light_count; i++) {
        if (!refract_state_is_settled(status->lights[i].state) || status->lights[i].refining)
            return 0;
    }
    return 1;
}

void refract_irradiance_free(struct refract_irradiance *status)
{
    if (status == NULL)
        return;
    free(status->json);
    free(status->lights);
    memset(status, 0, sizeof(*status));
}
