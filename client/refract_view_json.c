/*
 * refract_view_json.c - the JSON of view sessions: a create body from struct
 * refract_view_options, and a view status read into struct refract_view (see
 * refract_view_json.h).
 *
 * The options struct is the small way in: every zero field is left out of the body, so
 * refractd's defaults apply (docs/views.md), and a new field on the server's side needs
 * no change here. The status reader is lenient in the same way as refract_status.c: a
 * refractd that adds members, or one that leaves some out, still reads.
 */
#include "refract_view_json.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "refract_say.h"

static bool add_vec3(cJSON *obj, const char *key, const double v[3])
{
    return cJSON_AddItemToObject(obj, key, cJSON_CreateDoubleArray(v, 3));
}

/* The "camera" member of the body, or NULL when opts set none of its fields. */
static cJSON *camera_json(const struct refract_view_options *o, bool *ok)
{
    cJSON *cam;

    *ok = true;
    if (!o->has_eye && !o->has_look_at && !o->has_up && o->fov_y_deg == 0)
        return NULL;
    cam = cJSON_CreateObject();
    if (cam == NULL || (o->has_eye && !add_vec3(cam, "eye", o->eye)) ||
        (o->has_look_at && !add_vec3(cam, "look_at", o->look_at)) ||
        (o->has_up && !add_vec3(cam, "up", o->up)) ||
        (o->fov_y_deg != 0 && cJSON_AddNumberToObject(cam, "fov_y_deg", o->fov_y_deg) == NULL))
        *ok = false;
    return cam;
}

static bool fill_body(cJSON *body, const struct refract_view_options *o)
{
    bool ok;
    cJSON *cam = camera_json(o, &ok);

    if (cam != NULL && !cJSON_AddItemToObject(body, "camera", cam)) {
        cJSON_Delete(cam);
        return false;
    }
    if (!ok)
        return false;
    if (o->width != 0 && cJSON_AddNumberToObject(body, "width", o->width) == NULL)
        return false;
    if (o->height != 0 && cJSON_AddNumberToObject(body, "height", o->height) == NULL)
        return false;
    if (o->has_exposure && cJSON_AddNumberToObject(body, "exposure", o->exposure) == NULL)
        return false;
    if (o->quality != NULL && cJSON_AddStringToObject(body, "quality", o->quality) == NULL)
        return false;
    if (o->jpeg_quality != 0 &&
        cJSON_AddNumberToObject(body, "jpeg_quality", o->jpeg_quality) == NULL)
        return false;
    if (o->max_fps != 0 && cJSON_AddNumberToObject(body, "max_fps", o->max_fps) == NULL)
        return false;
    if (o->progressive != 0 &&
        cJSON_AddBoolToObject(body, "progressive", o->progressive > 0) == NULL)
        return false;
    return true;
}

char *refract_view_options_json(const struct refract_view_options *opts)
{
    cJSON *body = cJSON_CreateObject();
    char *text = NULL;

    if (body != NULL && (opts == NULL || fill_body(body, opts)))
        text = cJSON_PrintUnformatted(body);
    cJSON_Delete(body);
    if (text == NULL)
        return NULL;
    /* cJSON_PrintUnformatted allocates with cJSON's hooks, which are malloc unless an
     * application installed others; refract_free() is free(), so hand back a malloc copy. */
    {
        size_t n = strlen(text) + 1;
        char *copy = malloc(n);

        if (copy != NULL)
            memcpy(copy, text, n);
        cJSON_free(text);
        return copy;
    }
}

static void json_string_into(char *dst, size_t dst_size, const cJSON *obj, const char *key)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);

    snprintf(dst, dst_size, "%s", cJSON_IsString(item) ? item->valuestring : "");
}

static double json_number_or(const cJSON *obj, const char *key)
{
    const cJSON *item = cJSON_GetObjectItemCaseSensitive(obj, key);

    return cJSON_IsNumber(item) ? item->valuedouble : -1.0;
}

static long long json_count_or(const cJSON *obj, const char *key)
{
    double v = json_number_or(obj, key);

    return v >= 0 && v < 9.0e18 ? (long long)v : -1;
}

static int json_int_or(const cJSON *obj, const char *key)
{
    double v = json_number_or(obj, key);

    return v >= 0 && v < 2.0e9 ? (int)v : -1;
}

static void read_frame(const cJSON *frame, struct refract_view_frame *f)
{
    f->seq = json_count_or(frame, "seq");
    json_string_into(f->kind, sizeof(f->kind), frame, "kind");
    f->width = json_int_or(frame, "width");
    f->height = json_int_or(frame, "height");
    f->render_ms = json_number_or(frame, "render_ms");
    f->encode_ms = json_number_or(frame, "encode_ms");
    f->bytes = json_count_or(frame, "bytes");
    f->age_ms = json_number_or(frame, "age_ms");
    json_string_into(f->irradiance, sizeof(f->irradiance), frame, "irradiance");
    f->scene_generation = json_count_or(frame, "scene_generation");
}

bool refract_view_from_json(const char *json, size_t len, struct refract_view *out, char *why,
                            size_t why_size)
{
    cJSON *root = json != NULL ? cJSON_ParseWithLengthOpts(json, len, NULL, 0) : NULL;
    const cJSON *id = cJSON_GetObjectItemCaseSensitive(root, "id");
    const cJSON *frame = cJSON_GetObjectItemCaseSensitive(root, "frame");

    memset(out, 0, sizeof(*out));
    if (!cJSON_IsObject(root)) {
        cJSON_Delete(root);
        return refract_say(why, why_size, "expected a JSON object {\"id\", \"scene\", ...}");
    }
    if (!cJSON_IsString(id) || id->valuestring[0] == '\0' ||
        strlen(id->valuestring) >= sizeof(out->id)) {
        cJSON_Delete(root);
        return refract_say(why, why_size, "id: expected a view id string of 1 to %zu characters",
                           sizeof(out->id) - 1);
    }
    json_string_into(out->id, sizeof(out->id), root, "id");
    json_string_into(out->scene, sizeof(out->scene), root, "scene");
    out->width = json_int_or(root, "width");
    out->height = json_int_or(root, "height");
    json_string_into(out->quality, sizeof(out->quality), root, "quality");
    json_string_into(out->state, sizeof(out->state), root, "state");
    out->streams = json_int_or(root, "streams");
    out->max_fps = json_number_or(root, "max_fps");
    out->expires_in_s = json_number_or(root, "expires_in_s");
    json_string_into(out->renderer, sizeof(out->renderer), root, "renderer");
    json_string_into(out->stream, sizeof(out->stream), root, "stream");
    json_string_into(out->viewer, sizeof(out->viewer), root, "viewer");
    if (cJSON_IsObject(frame)) {
        out->has_frame = 1;
        read_frame(frame, &out->frame);
    }
    cJSON_Delete(root);
    return true;
}
