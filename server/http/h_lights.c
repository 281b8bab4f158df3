/*
 * h_lights.c - the lights of a scene: GET /v1/scenes/{id}/lights, PUT /v1/scenes/{id}/lights
 * (replace all) and PUT /v1/scenes/{id}/lights/{name} (add or replace one).
 *
 * A change edits the stored document's "lights" array with cJSON and stores the result
 * through store_scene_set_lights, which parses the whole document again: validation is the
 * scene parser's, complete, with its JSON paths ("lights[1].direction: ..."). The new
 * version keeps the scene's GPU data (data_generation); the irradiance cache is asked for
 * the new poses at once, and the answer says whether they were all cached (200) or some
 * recompute started (202), with the irradiance status as the body.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../cache/irradiance_cache.h"
#include "../events/events.h"
#include "../scene/json_read.h"
#include "http_internal.h"

static const char *kind_name(enum scene_light_kind k)
{
    return k == SCENE_LIGHT_POINT ? "point" : k == SCENE_LIGHT_SPOT ? "spot" : "directional";
}

static cJSON *vec_json(vec3 v)
{
    double a[3] = {v.x, v.y, v.z};
    return cJSON_CreateDoubleArray(a, 3);
}

/* A light with every default written out. */
static cJSON *light_json(const struct scene_light *l)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "name", l->name);
    cJSON_AddStringToObject(o, "type", kind_name(l->kind));
    if (l->kind != SCENE_LIGHT_POINT)
        cJSON_AddItemToObject(o, "direction", vec_json(l->direction));
    if (l->kind != SCENE_LIGHT_DIRECTIONAL)
        cJSON_AddItemToObject(o, "position", vec_json(l->position));
    if (l->kind == SCENE_LIGHT_SPOT)
        cJSON_AddNumberToObject(o, "angle_deg", l->spot_angle_deg);
    cJSON_AddItemToObject(o, "color", cJSON_CreateDoubleArray(l->color, 3));
    cJSON_AddNumberToObject(o, "intensity", l->intensity);
    if (l->kind == SCENE_LIGHT_POINT) {
        cJSON_AddNumberToObject(o, "radius", l->radius);
        cJSON_AddBoolToObject(o, "camera_visible", l->camera_visible);
    }
    return o;
}

enum MHD_Result http_handle_lights_get(struct http_request *req)
{
    enum MHD_Result answer = MHD_NO;
    struct store_scene *v = http_scene_or_404(req, &answer);
    if (v == NULL)
        return answer;
    cJSON *root = cJSON_CreateObject();
    cJSON_AddStringToObject(root, "scene", v->id);
    cJSON *arr = cJSON_AddArrayToObject(root, "lights");
    for (size_t i = 0; i < v->scene->light_count; i++)
        cJSON_AddItemToArray(arr, light_json(&v->scene->lights[i]));
    store_scene_release(v);
    return http_respond_json(req, MHD_HTTP_OK, root);
}

/* False when some number of the tree is not finite (1e400 parses as infinity, which the
 * re-serialised document would turn into null); path gets its JSON path. */
static bool all_finite(const cJSON *node, char *path, size_t size, size_t used)
{
    if (cJSON_IsNumber(node) && !isfinite(node->valuedouble))
        return false;
    int index = 0;
    for (const cJSON *c = node->child; c; c = c->next, index++) {
        int n = cJSON_IsArray(node) ? snprintf(path + used, size - used, "[%d]", index)
                                    : snprintf(path + used, size - used, "%s%s", used ? "." : "",
                                               c->string ? c->string : "");
        size_t next = n > 0 && (size_t)n < size - used ? used + (size_t)n : used;
        if (!all_finite(c, path, size, next))
            return false;
        path[used] = '\0';
    }
    return true;
}

/* Parses the request body as a JSON object (the scene reader's syntax errors: byte, line,
 * column), answering 400 when it is not one. */
static cJSON *body_object(struct http_request *req, const char *what, enum MHD_Result *answer)
{
    if (req->body_len == 0) {
        *answer = http_respond_error(req, REFRACT_E_INVALID_JSON,
                                     "the request body is empty; send %s", what);
        return NULL;
    }
    cJSON *body = NULL;
    struct err e = {0};
    if (jr_parse(req->body, req->body_len, &body, &e) != REFRACT_E_OK) {
        *answer = http_respond_err(req, &e);
        return NULL;
    }
    if (!cJSON_IsObject(body)) {
        cJSON_Delete(body);
        *answer = http_respond_error(req, REFRACT_E_INVALID_FIELD, "(root): expected an object: %s",
                                     what);
        return NULL;
    }
    char path[256];
    if (!all_finite(body, path, sizeof path, 0)) {
        cJSON_Delete(body);
        *answer = http_respond_error(req, REFRACT_E_INVALID_FIELD,
                                     "%s: the number is too large for a double; lights take "
                                     "finite numbers",
                                     path);
        return NULL;
    }
    return body;
}

/* Stores `doc` (the edited document, consumed) as the new version of the scene and
 * answers with the irradiance status: 200 when every light hit, 202 when a recompute
 * started. */
static enum MHD_Result store_and_answer(struct http_request *req, cJSON *doc)
{
    char *text = cJSON_PrintUnformatted(doc);
    cJSON_Delete(doc);
    if (text == NULL)
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory");
    struct store_scene *v = NULL;
    struct err e = {0};
    enum refract_code rc =
        store_scene_set_lights(req->app->store, req->params[0], text, strlen(text), &v, &e);
    free(text);
    if (rc != REFRACT_E_OK)
        return http_respond_err(req, &e);
    /* Before the cache request, so the lights change comes before its irradiance events. */
    http_publish_scene(req->app, EVENT_SCENE_UPDATED, v->id, v, "lights");
    struct irradiance_source src;
    render_request_irradiance_source(v, &src);
    bool all_hit = irradiance_cache_request(req->app->irradiance, &src, true);
    cJSON *root = http_irradiance_status(req->app, v);
    store_scene_release(v);
    return http_respond_json(req, all_hit ? MHD_HTTP_OK : MHD_HTTP_ACCEPTED, root);
}

/* The scene's stored document, parsed; answers 404/500 and returns NULL on failure. */
static cJSON *stored_document(struct http_request *req, enum MHD_Result *answer)
{
    struct store_scene *v = http_scene_or_404(req, answer);
    if (v == NULL)
        return NULL;
    cJSON *doc = cJSON_ParseWithLength(v->json, v->json_len);
    store_scene_release(v);
    if (doc == NULL)
        *answer = http_respond_error(req, REFRACT_E_INTERNAL,
                                     "the stored document of scene \"%s\" does not parse",
                                     req->params[0]);
    return doc;
}

enum MHD_Result http_handle_lights_put(struct http_request *req)
{
    static const char what[] = "{\"lights\": [{\"type\": \"directional\", \"direction\": [0, "
                               "-1, 0]}, ...]} (0 to 4 lights; docs/api.md)";
    enum MHD_Result answer = MHD_NO;
    cJSON *doc = stored_document(req, &answer);
    if (doc == NULL)
        return answer;
    cJSON *body = body_object(req, what, &answer);
    if (body == NULL) {
        cJSON_Delete(doc);
        return answer;
    }
    static const char *const allowed[] = {"lights", NULL};
    struct err e = {0};
    if (jr_check_object(body, "", allowed, &e) != REFRACT_E_OK) {
        cJSON_Delete(body);
        cJSON_Delete(doc);
        return http_respond_err(req, &e);
    }
    cJSON *lights = cJSON_DetachItemFromObjectCaseSensitive(body, "lights");
    cJSON_Delete(body);
    if (lights == NULL) {
        cJSON_Delete(doc);
        return http_respond_error(req, REFRACT_E_MISSING_FIELD, "lights: required; the body is %s",
                                  what);
    }
    if (!cJSON_IsArray(lights)) {
        cJSON_Delete(lights);
        cJSON_Delete(doc);
        return http_respond_error(req, REFRACT_E_INVALID_FIELD,
                                  "lights: must be an array of 0 to 4 light objects");
    }
    cJSON_DeleteItemFromObjectCaseSensitive(doc, "lights");
    cJSON_AddItemToObject(doc, "lights", lights);
    return store_and_answer(req, doc);
}

enum MHD_Result http_handle_light_put(struct http_request *req)
{
    static const char what[] = "one light object, e.g. {\"type\": \"point\", \"position\": [0, "
                               "2, 0]} (docs/api.md)";
    const char *name = req->params[1];
    enum MHD_Result answer = MHD_NO;
    cJSON *doc = stored_document(req, &answer);
    if (doc == NULL)
        return answer;
    cJSON *light = body_object(req, what, &answer);
    if (light == NULL) {
        cJSON_Delete(doc);
        return answer;
    }
    const cJSON *given = cJSON_GetObjectItemCaseSensitive(light, "name");
    if (given && (!cJSON_IsString(given) || strcmp(given->valuestring, name) != 0)) {
        cJSON_Delete(light);
        cJSON_Delete(doc);
        return http_respond_error(req, REFRACT_E_INVALID_FIELD,
                                  "name: must be the light's name in the URL (\"%s\") or left "
                                  "out",
                                  name);
    }
    if (given == NULL)
        cJSON_AddStringToObject(light, "name", name);
    cJSON *lights = cJSON_GetObjectItemCaseSensitive(doc, "lights");
    if (lights == NULL)
        lights = cJSON_AddArrayToObject(doc, "lights");
    if (!cJSON_IsArray(lights)) {
        cJSON_Delete(light);
        cJSON_Delete(doc);
        return http_respond_error(req, REFRACT_E_INTERNAL, "the stored lights are not an array");
    }
    /* Replace the light of that name (given, or defaulted "light<index>"), else append. */
    int index = 0, found = -1;
    const cJSON *l = NULL;
    cJSON_ArrayForEach(l, lights)
    {
        const cJSON *n = cJSON_GetObjectItemCaseSensitive(l, "name");
        char fallback[32];
        snprintf(fallback, sizeof fallback, "light%d", index);
        const char *have = cJSON_IsString(n) ? n->valuestring : fallback;
        if (found < 0 && strcmp(have, name) == 0)
            found = index;
        index++;
    }
    if (found >= 0)
        cJSON_ReplaceItemInArray(lights, found, light);
    else
        cJSON_AddItemToArray(lights, light);
    return store_and_answer(req, doc);
}
