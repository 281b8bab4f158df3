/*
 * cli_light.c - the flags of `refract light set` turned into a light object (see
 * cli_light.h).
 *
 * `light set` changes what it is told and keeps the rest, so moving a light is one flag
 * (`--position 1,2,0`) and its colour and intensity stay. That takes the scene's current
 * light, which the command reads first; this file only does the merging.
 */
#include "cli_light.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "cli_args.h"
#include "../refract_say.h"

/* The light types and the members that belong to each (the scene schema's words). */
static const struct {
    const char *type;
    bool direction, position, angle;
} light_types[] = {
    {"directional", true, false, false},
    {"point", false, true, false},
    {"spot", true, true, true},
};

#define LIGHT_TYPE_COUNT (sizeof(light_types) / sizeof(light_types[0]))

static int type_index(const char *type)
{
    for (size_t i = 0; i < LIGHT_TYPE_COUNT; i++) {
        if (type != NULL && strcmp(light_types[i].type, type) == 0)
            return (int)i;
    }
    return -1;
}

static bool parse_vec(const char *option, const char *text, double out[3], char *why,
                      size_t why_size)
{
    char inner[200];

    if (cli_parse_vec3(text, out, inner, sizeof(inner)))
        return true;
    return refract_say(why, why_size, "%s: %s", option, inner);
}

static bool parse_number(const char *option, const char *text, double *out, char *why,
                         size_t why_size)
{
    char inner[200];

    if (cli_parse_double(text, out, inner, sizeof(inner)))
        return true;
    return refract_say(why, why_size, "%s: %s", option, inner);
}

bool cli_light_spec_parse(const struct cli_light_flags *flags, struct cli_light_spec *spec,
                          char *why, size_t why_size)
{
    memset(spec, 0, sizeof(*spec));
    if (flags->type != NULL) {
        for (size_t i = 0; i < LIGHT_TYPE_COUNT && spec->type == NULL; i++) {
            if (strcasecmp(flags->type, light_types[i].type) == 0)
                spec->type = light_types[i].type;
        }
        if (spec->type == NULL)
            return refract_say(why, why_size,
                               "--type: expected directional, point or spot, got '%s'",
                               flags->type);
    }
    spec->has_direction = flags->direction != NULL;
    if (spec->has_direction &&
        !parse_vec("--direction", flags->direction, spec->direction, why, why_size))
        return false;
    if (spec->has_direction && spec->direction[0] == 0 && spec->direction[1] == 0 &&
        spec->direction[2] == 0)
        return refract_say(why, why_size,
                           "--direction: 0,0,0 points nowhere; give the way the light "
                           "travels, such as 0,-1,0 for straight down");
    spec->has_position = flags->position != NULL;
    if (spec->has_position &&
        !parse_vec("--position", flags->position, spec->position, why, why_size))
        return false;
    spec->has_angle = flags->angle != NULL;
    if (spec->has_angle && !parse_number("--angle", flags->angle, &spec->angle_deg, why, why_size))
        return false;
    spec->has_color = flags->color != NULL;
    if (spec->has_color && !parse_vec("--color", flags->color, spec->color, why, why_size))
        return false;
    spec->has_intensity = flags->intensity != NULL;
    if (spec->has_intensity &&
        !parse_number("--intensity", flags->intensity, &spec->intensity, why, why_size))
        return false;
    return true;
}

bool cli_light_spec_fits(const struct cli_light_spec *spec, const char *type, char *why,
                         size_t why_size)
{
    int t = type_index(type);

    if (type == NULL)
        return true;
    if (t < 0)
        return refract_say(why, why_size,
                           "the light's type is '%s', which this refract does not know; "
                           "give --type directional, point or spot",
                           type);
    if (spec->has_position && !light_types[t].position)
        return refract_say(why, why_size,
                           "--position does not apply to a %s light, which has only a "
                           "direction; give --type point or spot to place the light",
                           type);
    if (spec->has_direction && !light_types[t].direction)
        return refract_say(why, why_size,
                           "--direction does not apply to a %s light, which shines every "
                           "way; give --type spot for a cone or --type directional",
                           type);
    if (spec->has_angle && !light_types[t].angle)
        return refract_say(why, why_size,
                           "--angle does not apply to a %s light; only a spot light has a "
                           "cone (give --type spot)",
                           type);
    return true;
}

/* Sets obj[key] = item (consumed), replacing a member of that name. */
static bool set_member(cJSON *obj, const char *key, cJSON *item)
{
    bool ok;

    if (item == NULL)
        return false;
    if (cJSON_GetObjectItemCaseSensitive(obj, key) != NULL)
        ok = cJSON_ReplaceItemInObjectCaseSensitive(obj, key, item);
    else
        ok = cJSON_AddItemToObject(obj, key, item);
    if (!ok)
        cJSON_Delete(item);
    return ok;
}

/* Drops the members of a light that do not belong to type t. */
static void drop_foreign_members(cJSON *light, int t)
{
    if (!light_types[t].direction)
        cJSON_DeleteItemFromObjectCaseSensitive(light, "direction");
    if (!light_types[t].position)
        cJSON_DeleteItemFromObjectCaseSensitive(light, "position");
    if (!light_types[t].angle)
        cJSON_DeleteItemFromObjectCaseSensitive(light, "angle_deg");
}

static bool set_fields(cJSON *light, const char *name, const struct cli_light_spec *spec)
{
    bool ok = set_member(light, "name", cJSON_CreateString(name));

    if (ok && spec->type != NULL)
        ok = set_member(light, "type", cJSON_CreateString(spec->type));
    if (ok && spec->has_direction)
        ok = set_member(light, "direction", cJSON_CreateDoubleArray(spec->direction, 3));
    if (ok && spec->has_position)
        ok = set_member(light, "position", cJSON_CreateDoubleArray(spec->position, 3));
    if (ok && spec->has_angle)
        ok = set_member(light, "angle_deg", cJSON_CreateNumber(spec->angle_deg));
    if (ok && spec->has_color)
        ok = set_member(light, "color", cJSON_CreateDoubleArray(spec->color, 3));
    if (ok && spec->has_intensity)
        ok = set_member(light, "intensity", cJSON_CreateNumber(spec->intensity));
    return ok;
}

cJSON *cli_light_build(const cJSON *existing, const char *name, const struct cli_light_spec *spec,
                       char *why, size_t why_size)
{
    const cJSON *old_type = cJSON_GetObjectItemCaseSensitive(existing, "type");
    const char *type = spec->type;
    cJSON *light;

    if (why != NULL && why_size > 0)
        why[0] = '\0';
    if (type == NULL && cJSON_IsString(old_type))
        type = old_type->valuestring;
    if (!cli_light_spec_fits(spec, type, why, why_size))
        return NULL;
    light = cJSON_IsObject(existing) ? cJSON_Duplicate(existing, 1) : cJSON_CreateObject();
    if (light == NULL)
        return NULL;
    if (type_index(type) >= 0)
        drop_foreign_members(light, type_index(type));
    if (!set_fields(light, name, spec)) {
        cJSON_Delete(light);
        return NULL;
    }
    return light;
}

const cJSON *cli_light_find(const cJSON *doc, const char *name)
{
    const cJSON *lights = cJSON_GetObjectItemCaseSensitive(doc, "lights");
    const cJSON *light;
    int index = 0;

    cJSON_ArrayForEach(light, lights)
    {
        const cJSON *n = cJSON_GetObjectItemCaseSensitive(light, "name");
        char fallback[32];

        snprintf(fallback, sizeof(fallback), "light%d", index++);
        if (strcmp(cJSON_IsString(n) ? n->valuestring : fallback, name) == 0)
            return light;
    }
    return NULL;
}
