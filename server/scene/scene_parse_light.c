/*
 * scene_parse_light.c - the parts of a scene document that describe light transport
 * rather than the volume objects (docs/scenes.md, "Lights, receiver and light
 * simulation"): "lights", "receiver", "lightsim", and each object's "brdf".
 *
 * Same rules as scene_parse.c: every key is checked, unknown keys are errors, messages
 * start with the JSON path. A light's allowed keys depend on its "type" (as a shape's do
 * on "shape"), so a "position" on a directional light is an unknown field rather than a
 * value silently ignored. Every default is filled in here, so that a scene that spells
 * a default out and one that leaves it away parse to the same structs (the transport
 * hash relies on that, scene_transport.c).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../core/geom/geom.h"
#include "json_read.h"
#include "scene_parse_internal.h"

static const cJSON *member(const cJSON *obj, const char *key)
{
    return cJSON_IsObject(obj) ? cJSON_GetObjectItemCaseSensitive(obj, key) : NULL;
}

/* A colour under key: a number (grey) or [r, g, b], each in 0..max; absent -> def grey. */
static enum refract_code read_rgb(const cJSON *obj, const char *path, const char *key, double def,
                                  double max, double out[3], struct err *e)
{
    const cJSON *item = member(obj, key);
    char p[256], got[80];
    jr_path(p, sizeof p, path, key);
    if (item == NULL) {
        out[0] = out[1] = out[2] = def;
        return REFRACT_E_OK;
    }
    if (cJSON_IsNumber(item)) {
        enum refract_code rc = jr_check_number(item, p, 0.0, false, max, &out[0], e);
        out[1] = out[2] = out[0];
        return rc;
    }
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 3)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected a number (grey) or [r, g, b], each in 0..%.15g, got %s", p,
                       max, jr_describe(item, got, sizeof got));
    for (int i = 0; i < 3; i++) {
        char pi[256];
        enum refract_code rc =
            jr_check_number(cJSON_GetArrayItem(item, i), jr_path_index(pi, sizeof pi, p, i), 0.0,
                            false, max, &out[i], e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    return REFRACT_E_OK;
}

/* ---- lights ---- */

static const char *const light_types[] = {"directional", "point", "spot", NULL};

/* Keys of each light type. */
static const char *const light_keys[][8] = {
    [SCENE_LIGHT_DIRECTIONAL] = {"name", "type", "direction", "color", "intensity", NULL},
    [SCENE_LIGHT_POINT] = {"name", "type", "position", "color", "intensity", "radius",
                           "camera_visible", NULL},
    [SCENE_LIGHT_SPOT] = {"name", "type", "position", "direction", "angle_deg", "color",
                          "intensity", NULL},
};

/* Light names appear in URLs (PUT /v1/scenes/{id}/lights/{name}), hence the alphabet. */
static bool valid_light_name(const char *s)
{
    size_t n = strlen(s);
    if (n == 0 || n >= SCENE_LIGHT_NAME_MAX)
        return false;
    for (size_t i = 0; i < n; i++) {
        char c = s[i];
        if (!((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-'))
            return false;
    }
    return true;
}

static enum refract_code parse_light_name(const cJSON *o, const char *path, int index,
                                          struct scene_light *l, struct err *e)
{
    const cJSON *name = member(o, "name");
    if (name == NULL) {
        snprintf(l->name, sizeof l->name, "light%d", index);
        return REFRACT_E_OK;
    }
    if (!cJSON_IsString(name) || !valid_light_name(name->valuestring)) {
        char p[256], got[80];
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected a light name of 1..%d characters from a-z 0-9 _ - (it is "
                       "used in URLs), got %s",
                       jr_path(p, sizeof p, path, "name"), SCENE_LIGHT_NAME_MAX - 1,
                       jr_describe(name, got, sizeof got));
    }
    snprintf(l->name, sizeof l->name, "%s", name->valuestring);
    return REFRACT_E_OK;
}

enum refract_code scene_parse_light(const cJSON *o, const char *path, int index,
                                    struct scene_light *l, struct err *e)
{
    const double m = SCENE_COORD_MAX;
    char got[80];
    if (!cJSON_IsObject(o))
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected a light object {\"type\": \"directional\" | \"point\" | "
                       "\"spot\", ...}, got %s",
                       path, jr_describe(o, got, sizeof got));
    int kind = 0;
    enum refract_code rc = jr_enum(o, path, "type", true, 0, light_types, &kind, e);
    if (rc == REFRACT_E_OK)
        rc = jr_check_object(o, path, light_keys[kind], e);
    if (rc != REFRACT_E_OK)
        return rc;
    memset(l, 0, sizeof *l);
    l->kind = (enum scene_light_kind)kind;
    rc = parse_light_name(o, path, index, l, e);
    bool aimed = l->kind != SCENE_LIGHT_POINT, placed = l->kind != SCENE_LIGHT_DIRECTIONAL;
    if (rc == REFRACT_E_OK && aimed)
        rc = jr_direction(o, path, "direction", true, vec3_make(0, -1, 0), &l->direction, e);
    if (rc == REFRACT_E_OK && placed)
        rc = jr_vec3(o, path, "position", true, vec3_make(0, 0, 0), -m, m, &l->position, e);
    if (rc == REFRACT_E_OK && l->kind == SCENE_LIGHT_SPOT)
        rc = jr_number(o, path, "angle_deg", false, 30.0, 1.0, 89.0, &l->spot_angle_deg, e);
    if (rc == REFRACT_E_OK)
        rc = read_rgb(o, path, "color", 1.0, 1e3, l->color, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, path, "intensity", false, 1.0, 0.0, 1e6, &l->intensity, e);
    l->camera_visible = true;
    if (rc == REFRACT_E_OK && l->kind == SCENE_LIGHT_POINT)
        rc = jr_number(o, path, "radius", false, 0.0, 0.0, m, &l->radius, e);
    if (rc == REFRACT_E_OK && l->kind == SCENE_LIGHT_POINT)
        rc = jr_bool(o, path, "camera_visible", false, true, &l->camera_visible, e);
    return rc;
}

enum refract_code scene_parse_lights(const cJSON *arr, struct scene *s, struct err *e)
{
    char got[80];
    s->light_count = 0;
    if (arr == NULL)
        return REFRACT_E_OK;
    int n = cJSON_IsArray(arr) ? cJSON_GetArraySize(arr) : -1;
    if (n < 0 || n > SCENE_MAX_LIGHTS)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "lights: expected an array of 0..%d light objects, got %s", SCENE_MAX_LIGHTS,
                       jr_describe(arr, got, sizeof got));
    int i = 0;
    for (const cJSON *it = arr->child; it != NULL; it = it->next, i++) {
        char p[64];
        jr_path_index(p, sizeof p, "lights", i);
        enum refract_code rc = scene_parse_light(it, p, i, &s->lights[i], e);
        if (rc != REFRACT_E_OK)
            return rc;
        for (int k = 0; k < i; k++) {
            if (strcmp(s->lights[k].name, s->lights[i].name) == 0)
                return err_set(e, REFRACT_E_INVALID_FIELD,
                               "%s.name: \"%s\" is already the name of lights[%d]; light names "
                               "must be unique (an unnamed light is \"light<index>\")",
                               p, s->lights[i].name, k);
        }
    }
    s->light_count = (size_t)n;
    return REFRACT_E_OK;
}

/* ---- receiver ---- */

/* Corner c (0..7; bit 0 picks max x, bit 1 max y, bit 2 max z) of o's bounds, in world
 * space. */
static vec3 world_corner(const struct scene_object *o, int c)
{
    vec3 p = {(c & 1) ? o->bounds_max.x : o->bounds_min.x,
              (c & 2) ? o->bounds_max.y : o->bounds_min.y,
              (c & 4) ? o->bounds_max.z : o->bounds_min.z};
    return xform_point_to_world(&o->world_from_object, p);
}

/* World box of surface k's solid; false for a mesh (its box comes with the upload).
 * Components of a plane's half-space are infinite. */
static bool surface_box(const struct scene *s, size_t k, vec3 *lo, vec3 *hi)
{
    struct geom_surface g;
    scene_surface_geom(&s->surfaces[k], &g);
    if (g.kind == GEOM_MESH)
        return false;
    geom_surface_bounds(&g, lo, hi);
    return true;
}

/* 1.5 times the largest |x| or |z| that any object's or surface's world bounding box
 * reaches (finite sides only: a plane's half-space adds nothing), so the plane catches the
 * shadow and caustic of everything above it. */
static double default_half_size(const struct scene *s)
{
    double reach = 0.0;
    for (size_t k = 0; k < s->surface_count; k++) {
        vec3 lo, hi;
        if (!surface_box(s, k, &lo, &hi))
            continue;
        const double v[4] = {lo.x, hi.x, lo.z, hi.z};
        for (int i = 0; i < 4; i++)
            if (isfinite(v[i]))
                reach = fmax(reach, fabs(v[i]));
    }
    for (size_t i = 0; i < s->object_count; i++) {
        const struct scene_object *o = &s->objects[i];
        for (int c = 0; c < 8; c++) {
            vec3 w = world_corner(o, c);
            reach = fmax(reach, fmax(fabs(w.x), fabs(w.z)));
        }
    }
    return 1.5 * reach;
}

/* The receiver must not cut through an object's bounds: the march sees the plane only
 * once a view ray has left every object (docs/tracing.md "Light"), so a plane above the
 * bottom of a box would be invisible inside that box and show the environment through a
 * square hole. The lowest world y of each object's bounding box is checked. */
static enum refract_code check_below_objects(const struct scene *s, double height, struct err *e)
{
    for (size_t i = 0; i < s->object_count; i++) {
        const struct scene_object *o = &s->objects[i];
        double low = INFINITY;
        for (int c = 0; c < 8; c++)
            low = fmin(low, world_corner(o, c).y);
        if (height > low + 1e-9)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "receiver.height: %g is above the bottom of object %zu (\"%s\")'s "
                           "bounds in world space (y = %g); view rays inside an object's bounds "
                           "do not see the receiver, so put the plane at or below y = %g, or let "
                           "the object's bounds end at the plane",
                           height, i, o->name, low, low);
    }
    /* Exact surfaces likewise: the plane would cut a solid whose bottom is finite (a
     * plane's half-space reaching down forever, e.g. water over a pool floor, may hold it). */
    for (size_t k = 0; k < s->surface_count; k++) {
        vec3 lo, hi;
        if (!surface_box(s, k, &lo, &hi) || !isfinite(lo.y))
            continue;
        if (height > lo.y + 1e-9)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "receiver.height: %g is above the bottom of surfaces[%d]'s solid "
                           "(y = %g); put the plane at or below y = %g",
                           height, s->surfaces[k].document_index, lo.y, lo.y);
    }
    return REFRACT_E_OK;
}

/* "center": [x, z], each a finite number in [-m, m]; absent: (0, 0). */
static enum refract_code read_center(const cJSON *o, double m, double out[2], struct err *e)
{
    out[0] = out[1] = 0.0;
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(o, "center");
    if (c == NULL)
        return REFRACT_E_OK;
    char what[64];
    if (!cJSON_IsArray(c) || cJSON_GetArraySize(c) != 2)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "receiver.center: expected an array of 2 numbers [x, z] (the world x "
                       "and z of the square's centre), got %s",
                       jr_describe(c, what, sizeof what));
    for (int i = 0; i < 2; i++) {
        char path[32];
        snprintf(path, sizeof path, "receiver.center[%d]", i);
        enum refract_code rc =
            jr_check_number(cJSON_GetArrayItem(c, i), path, -m, false, m, &out[i], e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    return REFRACT_E_OK;
}

enum refract_code scene_parse_receiver(const cJSON *o, struct scene *s, struct err *e)
{
    static const char *const keys[] = {"height",   "half_size", "center",        "albedo",
                                       "caustics", "photons",   "photons_max", "photon_radius",
                                       NULL};
    const double m = SCENE_COORD_MAX;
    struct scene_receiver *r = &s->receiver;
    memset(r, 0, sizeof *r);
    if (o == NULL)
        return REFRACT_E_OK;
    enum refract_code rc = jr_check_object(o, "receiver", keys, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, "receiver", "height", true, 0.0, -m, m, &r->height, e);
    if (rc == REFRACT_E_OK)
        rc = check_below_objects(s, r->height, e);
    if (rc == REFRACT_E_OK)
        rc = read_center(o, m, r->center, e);
    const cJSON *hs = cJSON_GetObjectItemCaseSensitive(o, "half_size");
    double def = default_half_size(s);
    if (rc != REFRACT_E_OK) {
    } else if (cJSON_IsString(hs)) {
        /* The whole plane (docs/scenes.md "receiver"). */
        if (strcmp(hs->valuestring, "infinite") != 0)
            rc = err_set(e, REFRACT_E_INVALID_FIELD,
                         "receiver.half_size: expected a number > 0 and <= %g or the string "
                         "\"infinite\", got \"%.32s\"",
                         m, hs->valuestring);
        else
            r->half_size = INFINITY;
    } else if (def > 0.0 && def <= m) {
        rc = jr_number_gt(o, "receiver", "half_size", false, def, 0.0, m, &r->half_size, e);
    } else {
        rc = jr_number_gt(o, "receiver", "half_size", true, 1.0, 0.0, m, &r->half_size, e);
    }
    if (rc == REFRACT_E_OK)
        rc = read_rgb(o, "receiver", "albedo", 0.8, 1.0, r->albedo, e);
    int caustics = SCENE_CAUSTICS_AUTO;
    if (rc == REFRACT_E_OK)
        rc = jr_enum(o, "receiver", "caustics", false, SCENE_CAUSTICS_AUTO, scene_caustics_words,
                     &caustics, e);
    r->caustics = (enum scene_caustics)caustics; /* auto: resolved after the surfaces */
    r->caustics_auto = caustics == SCENE_CAUSTICS_AUTO;
    r->caustics_reason = "given in the document";
    if (rc == REFRACT_E_OK)
        rc = jr_int(o, "receiver", "photons", false, 1048576, 1024, SCENE_MAX_PHOTONS, &r->photons,
                    e);
    if (rc == REFRACT_E_OK)
        rc = jr_int(o, "receiver", "photons_max", false, r->photons, r->photons, SCENE_MAX_PHOTONS,
                    &r->photons_max, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, "receiver", "photon_radius", false, 0.0, 0.0, m, &r->photon_radius, e);
    r->enabled = rc == REFRACT_E_OK;
    return rc;
}

/* ---- light simulation settings (docs/lightsim.md) ---- */

enum refract_code scene_parse_lightsim(const cJSON *o, struct scene_lightsim *ls, struct err *e)
{
    static const char *const keys[] = {
        "resolution",   "step",    "initial_patches", "max_level",   "split", "energy_threshold",
        "point_radius", "deposit", "cull_flipped",    "max_patches", NULL};
    static const char *const deposits[] = {"flux", "max", NULL};
    const char *p = "lightsim";
    /* Absent: every default below still applies (o == NULL reads as all keys absent). */
    enum refract_code rc = o != NULL ? jr_check_object(o, p, keys, e) : REFRACT_E_OK;
    int deposit = SCENE_DEPOSIT_FLUX;
    if (rc == REFRACT_E_OK)
        rc = jr_int(o, p, "resolution", false, 64, 8, 512, &ls->resolution, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, p, "step", false, 0.5, 0.05, 4.0, &ls->step_voxels, e);
    if (rc == REFRACT_E_OK)
        rc = jr_int(o, p, "initial_patches", false, 64, 2, 1024, &ls->initial_patches, e);
    if (rc == REFRACT_E_OK)
        rc = jr_int(o, p, "max_level", false, 6, 0, 12, &ls->max_level, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, p, "split", false, 1.0, 0.1, 8.0, &ls->split_voxels, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, p, "energy_threshold", false, 1e-4, 0.0, 1.0, &ls->energy_threshold, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number_gt(o, p, "point_radius", false, 0.01, 0.0, 1e3, &ls->point_radius, e);
    if (rc == REFRACT_E_OK)
        rc = jr_enum(o, p, "deposit", false, SCENE_DEPOSIT_FLUX, deposits, &deposit, e);
    if (rc == REFRACT_E_OK)
        rc = jr_bool(o, p, "cull_flipped", false, false, &ls->cull_flipped, e);
    if (rc == REFRACT_E_OK)
        rc = jr_int(o, p, "max_patches", false, 262144, 1024, 1048576, &ls->max_patches, e);
    ls->deposit = (enum scene_lightsim_deposit)deposit;
    return rc;
}

/* ---- BRDF of an object's boundaries ---- */

enum refract_code scene_parse_brdf(const cJSON *obj, const char *path, struct scene_brdf *b,
                                   struct err *e)
{
    static const char *const keys[] = {"type", "color", "roughness", "exponent", NULL};
    /* Index = enum scene_brdf_kind. */
    static const char *const types[] = {"none", "lambert", "phong", "ggx", NULL};
    char p[256];
    jr_path(p, sizeof p, path, "brdf");
    const cJSON *o = member(obj, "brdf");
    enum refract_code rc = o != NULL ? jr_check_object(o, p, keys, e) : REFRACT_E_OK;
    int kind = SCENE_BRDF_GGX;
    if (rc == REFRACT_E_OK)
        rc = jr_enum(o, p, "type", false, SCENE_BRDF_GGX, types, &kind, e);
    if (rc == REFRACT_E_OK)
        rc = read_rgb(o, p, "color", 1.0, 1.0, b->color, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, p, "roughness", false, 0.1, 0.01, 1.0, &b->roughness, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, p, "exponent", false, 200.0, 1.0, 10000.0, &b->exponent, e);
    b->kind = (enum scene_brdf_kind)kind;
    return rc;
}
