/*
 * refract_lights.c - the calls of refract.h for lights and irradiance volumes:
 * PUT /v1/scenes/{id}/lights[/{name}], the scene's lights, GET .../irradiance and the
 * volume as OpenEXR. Built like refract_calls.c: check the arguments, build the path
 * with escaped segments, exchange through refract_call_reply(), and read an
 * irradiance status reply into struct refract_irradiance (refract_status.c).
 */
#include <stdlib.h>
#include <string.h>

#include "refract_internal.h"
#include "refract_status.h"
#include "refract_url.h"

int refract_irradiance_parse(refract_client *c, const char *json, struct refract_irradiance *out)
{
    char why[256] = "";

    if (out != NULL)
        memset(out, 0, sizeof(*out));
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (json == NULL || out == NULL)
        return refract_fail(c, REFRACT_E_USAGE,
                            "refract_irradiance_parse: json and out must "
                            "not be NULL");
    if (!refract_status_from_json(json, strlen(json), out, why, sizeof(why)))
        return refract_fail(c, REFRACT_E_PROTOCOL,
                            "refractd's irradiance status could not be read: %s", why);
    out->json = malloc(strlen(json) + 1);
    if (out->json == NULL) {
        refract_irradiance_free(out);
        return refract_out_of_memory(c, "copying the irradiance status");
    }
    strcpy(out->json, json);
    return REFRACT_E_OK;
}

static bool read_status(const char *json, size_t len, void *out, char *why, size_t why_size)
{
    return refract_status_from_json(json, len, out, why, why_size);
}

/* The exchange of method path with body (NULL: none); the reply is an irradiance status,
 * read into out (NULL: dropped). */
static int call_status(refract_client *c, const char *method, const char *path, const char *body,
                       struct refract_irradiance *out)
{
    long http_status = 0;
    int code = refract_call_reply(c, method, path, body, "an irradiance status", read_status, out,
                                  out != NULL ? &out->json : NULL, &http_status);

    if (code == REFRACT_E_OK && out != NULL)
        out->http_status = http_status;
    return code;
}

int refract_light_put(refract_client *c, const char *scene_id, const char *name,
                      const char *light_json, struct refract_irradiance *status_out)
{
    const char *call = "refract_light_put";
    char *esc_name = NULL;
    char *suffix = NULL;
    char *path = NULL;
    int code;

    if (status_out != NULL)
        memset(status_out, 0, sizeof(*status_out));
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    code = refract_check_segment(c, call, "scene id", scene_id);
    if (code == REFRACT_E_OK)
        code = refract_check_segment(c, call, "light name", name);
    if (code == REFRACT_E_OK && light_json == NULL)
        code = refract_fail(c, REFRACT_E_USAGE, "%s: light_json is NULL", call);
    if (code != REFRACT_E_OK)
        return code;
    esc_name = refract_url_escape_dup(name);
    suffix = esc_name != NULL ? refract_path_printf("/lights/%s", esc_name) : NULL;
    path = suffix != NULL ? refract_scene_path(scene_id, suffix) : NULL;
    code = path != NULL ? call_status(c, "PUT", path, light_json, status_out)
                        : refract_out_of_memory(c, "building the request path");
    free(path);
    free(suffix);
    free(esc_name);
    return code;
}

int refract_lights_put(refract_client *c, const char *scene_id, const char *lights_json,
                       struct refract_irradiance *status_out)
{
    char *path;
    int code;

    if (status_out != NULL)
        memset(status_out, 0, sizeof(*status_out));
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    code = refract_check_segment(c, "refract_lights_put", "scene id", scene_id);
    if (code == REFRACT_E_OK && lights_json == NULL)
        code = refract_fail(c, REFRACT_E_USAGE, "refract_lights_put: lights_json is NULL");
    if (code != REFRACT_E_OK)
        return code;
    path = refract_scene_path(scene_id, "/lights");
    if (path == NULL)
        return refract_out_of_memory(c, "building the request path");
    code = call_status(c, "PUT", path, lights_json, status_out);
    free(path);
    return code;
}

int refract_lights_get(refract_client *c, const char *scene_id, char **json_out)
{
    if (refract_begin(c, json_out) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (json_out == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_lights_get: json_out is NULL");
    return refract_scene_call_json(c, "refract_lights_get", "GET", scene_id, "/lights", NULL, 0,
                                   NULL, json_out);
}

int refract_irradiance_status(refract_client *c, const char *scene_id,
                              struct refract_irradiance *out)
{
    char *path;
    int code;

    if (out != NULL)
        memset(out, 0, sizeof(*out));
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (out == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "refract_irradiance_status: out is NULL");
    code = refract_scene_route(c, "refract_irradiance_status", scene_id, "/irradiance", &path);
    if (code != REFRACT_E_OK)
        return code;
    code = call_status(c, "GET", path, NULL, out);
    free(path);
    return code;
}

int refract_irradiance_get_exr(refract_client *c, const char *scene_id, const char *light,
                               struct refract_image *out)
{
    static const unsigned char exr_magic[4] = {0x76, 0x2F, 0x31, 0x01};
    const char *call = "refract_irradiance_get_exr";
    struct refract_response r;
    char *esc_light = NULL;
    char *suffix = NULL;
    char *path = NULL;
    int code;

    if (out != NULL) {
        memset(out, 0, sizeof(*out)); /* the contract allows an uninitialised out */
        out->render_ms = -1.0;
    }
    if (refract_begin(c, NULL) != REFRACT_E_OK)
        return REFRACT_E_USAGE;
    if (out == NULL)
        return refract_fail(c, REFRACT_E_USAGE, "%s: out is NULL", call);
    code = refract_check_segment(c, call, "scene id", scene_id);
    if (code == REFRACT_E_OK)
        code = refract_check_segment(c, call, "light name", light);
    if (code != REFRACT_E_OK)
        return code;
    esc_light = refract_url_escape_dup(light);
    suffix = esc_light != NULL ? refract_path_printf("/irradiance/%s.exr", esc_light) : NULL;
    path = suffix != NULL ? refract_scene_path(scene_id, suffix) : NULL;
    if (path == NULL)
        code = refract_out_of_memory(c, "building the request path");
    if (code == REFRACT_E_OK)
        code = refract_http_exchange(c, "GET", path, NULL, 0, NULL, &r);
    if (code == REFRACT_E_OK) {
        code = refract_http_check(c, "GET", path, &r);
        if (code == REFRACT_E_OK && (r.body_len < 4 || memcmp(r.body, exr_magic, 4) != 0))
            code = refract_fail(c, REFRACT_E_PROTOCOL,
                                "GET %s: expected an OpenEXR file, got HTTP "
                                "%ld with Content-Type \"%s\" and %zu bytes",
                                path, r.status, r.content_type, r.body_len);
        if (code == REFRACT_E_OK) {
            out->bytes = r.body; /* ownership moves to the caller */
            out->len = r.body_len;
            r.body = NULL;
            refract_copy_string(out->content_type, sizeof(out->content_type), "image/x-exr");
            refract_copy_string(out->irradiance, sizeof(out->irradiance), r.irradiance);
        }
        refract_response_free(&r);
    }
    free(path);
    free(suffix);
    free(esc_light);
    return code;
}
