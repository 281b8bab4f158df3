/*
 * scene_parse.c - a scene document (docs/scenes.md, proto/scene.schema.json) to a
 * struct scene: the document, environment, camera, render settings and objects.
 *
 * Validation is complete here: after scene_parse returns OK the renderer may trust every
 * field (ranges, limits, a camera that can look somewhere). Any problem is returned as
 * a code plus a message that starts with the JSON path; nothing is ignored, so a typo
 * in a key is an UNKNOWN_FIELD error rather than a silent default. Channels (ior,
 * attenuation, emission, opaque, scattering, anisotropy) are read by scene_parse_field.c;
 * lights, receiver, lightsim settings and BRDFs by scene_parse_light.c.
 *
 * Ownership: the cJSON tree lives only inside scene_parse; the scene is built in a
 * zeroed allocation so that scene_destroy can free a half-built one on any error path.
 */
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json_read.h"
#include "scene_parse_internal.h"

#define DESCRIPTION_MAX 1024

struct scene_limits scene_limits_default(void)
{
    return (struct scene_limits){
        .max_resolution = 512,
        .max_voxels = 64ll * 1024 * 1024,
        .max_objects = 8,
        .max_layers = 64,
        .max_profile_points = 1024,
        .max_text_length = 64,
        .max_image_dim = 4096,
        .max_steps = 100000,
        .max_mesh_triangles = 2000000,
        .max_samples_per_pixel = 64,
        .max_upload_voxels = 32ll * 1024 * 1024,
    };
}

enum refract_code scene_limit_error(struct err *e, const char *path, const char *given,
                                    const char *limit_name, long long value, const char *flag)
{
    return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                   "%s: %s exceeds the limit %s = %lld; start refractd with %s to raise it", path,
                   given, limit_name, value, flag);
}

enum refract_code scene_read_limited_int(const cJSON *item, const char *path, int def, int min,
                                         int limit, const char *limit_name, const char *flag,
                                         int *out, struct err *e)
{
    if (item == NULL) {
        *out = def;
        return REFRACT_E_OK;
    }
    double v = cJSON_IsNumber(item) ? item->valuedouble : NAN;
    if (!isfinite(v) || v != floor(v) || v < min) {
        char got[80];
        return err_set(e, REFRACT_E_INVALID_FIELD, "%s: expected an integer in %d..%d, got %s",
                       path, min, limit, jr_describe(item, got, sizeof got));
    }
    if (v > limit) {
        char given[40];
        snprintf(given, sizeof given, "%.0f", v);
        return scene_limit_error(e, path, given, limit_name, limit, flag);
    }
    *out = (int)v;
    return REFRACT_E_OK;
}

enum refract_code scene_read_samples_per_pixel(const cJSON *item, const char *path, int def,
                                               const struct scene_limits *lim, int *out,
                                               struct err *e)
{
    enum refract_code rc =
        scene_read_limited_int(item, path, def, 1, lim->max_samples_per_pixel,
                               "max_samples_per_pixel", "--max-samples-per-pixel", out, e);
    if (rc != REFRACT_E_OK)
        return rc;
    /* k x k strata of equal size: a box filter that weights the pixel evenly. */
    int k = (int)floor(sqrt((double)*out) + 0.5);
    if (k * k != *out)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: %d is not a square number; the pixel is split into k x k equal "
                       "strata, so use 1, 4, 9, 16, 25, ... (%d or %d)",
                       path, *out, (k - (k * k > *out)) * (k - (k * k > *out)),
                       (k + (k * k < *out)) * (k + (k * k < *out)));
    return REFRACT_E_OK;
}

/* The item at key, or NULL; case-sensitive, and NULL when obj is not an object. */
static const cJSON *member(const cJSON *obj, const char *key)
{
    return cJSON_IsObject(obj) ? cJSON_GetObjectItemCaseSensitive(obj, key) : NULL;
}

/* Checks an optional sub-object: absent -> *present = false and OK. */
static enum refract_code sub_object(const cJSON *parent, const char *key,
                                    const char *const *allowed, const cJSON **out, struct err *e)
{
    *out = member(parent, key);
    if (*out == NULL)
        return REFRACT_E_OK;
    return jr_check_object(*out, key, allowed, e);
}

static enum refract_code parse_environment(const cJSON *root, struct scene_environment *env,
                                           struct err *e)
{
    static const char *const keys[] = {"type", "intensity", "rotation_deg", NULL};
    static const char *const types[] = {"procedural", "image", NULL};
    const cJSON *o;
    enum refract_code rc = sub_object(root, "environment", keys, &o, e);
    int kind = SCENE_ENV_PROCEDURAL;
    if (rc == REFRACT_E_OK)
        rc = jr_enum(o, "environment", "type", false, SCENE_ENV_PROCEDURAL, types, &kind, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, "environment", "intensity", false, 1.0, 0.0, 1e6, &env->intensity, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, "environment", "rotation_deg", false, 0.0, -360.0, 360.0,
                       &env->rotation_deg, e);
    env->kind = (enum scene_env_kind)kind;
    return rc;
}

static const char *fmt_vec3(vec3 v, char *buf, size_t size)
{
    snprintf(buf, size, "[%g, %g, %g]", v.x, v.y, v.z);
    return buf;
}

/* The camera must be able to look somewhere: look_at != eye and up not along the view. */
static enum refract_code check_camera(const struct scene_camera *c, struct err *e)
{
    char a[100], b[100];
    vec3 view = vec3_sub(c->look_at, c->eye);
    /* The same rule as a render request's camera (http/request_parse.c): a scene whose
     * eye and look_at are closer than 1e-9 was accepted here, then refused by every
     * render that did not override its camera. */
    if (vec3_length(view) < 1e-9)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "camera.look_at: equals camera.eye (%s) or lies within 1e-9 of it; the "
                       "camera needs a point to look at that differs from where it stands",
                       fmt_vec3(c->eye, a, sizeof a));
    vec3 f = vec3_normalize(view);
    if (vec3_length(vec3_cross(f, vec3_normalize(c->up))) < 1e-9)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "camera.up: %s is parallel to the viewing direction look_at - eye = %s; "
                       "choose an up vector that is not (looking straight down, [0, 0, -1] "
                       "works)",
                       fmt_vec3(c->up, a, sizeof a), fmt_vec3(view, b, sizeof b));
    return REFRACT_E_OK;
}

static enum refract_code parse_camera(const cJSON *root, const struct scene_limits *lim,
                                      struct scene_camera *cam, struct err *e)
{
    static const char *const keys[] = {"eye",   "look_at", "up", "fov_y_deg",
                                       "width", "height",  NULL};
    const double m = SCENE_COORD_MAX;
    const cJSON *o;
    enum refract_code rc = sub_object(root, "camera", keys, &o, e);
    if (rc == REFRACT_E_OK)
        rc = jr_vec3(o, "camera", "eye", false, vec3_make(0, 0, 4), -m, m, &cam->eye, e);
    if (rc == REFRACT_E_OK)
        rc = jr_vec3(o, "camera", "look_at", false, vec3_make(0, 0, 0), -m, m, &cam->look_at, e);
    if (rc == REFRACT_E_OK)
        rc = jr_direction(o, "camera", "up", false, vec3_make(0, 1, 0), &cam->up, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number_gt(o, "camera", "fov_y_deg", false, 40.0, 0.1, 179.0, &cam->fov_y_deg, e);
    int def_w = lim->max_image_dim < 640 ? lim->max_image_dim : 640;
    int def_h = lim->max_image_dim < 480 ? lim->max_image_dim : 480;
    if (rc == REFRACT_E_OK)
        rc =
            scene_read_limited_int(member(o, "width"), "camera.width", def_w, 1, lim->max_image_dim,
                                   "max_image_dim", "--max-image-dim", &cam->width, e);
    if (rc == REFRACT_E_OK)
        rc = scene_read_limited_int(member(o, "height"), "camera.height", def_h, 1,
                                    lim->max_image_dim, "max_image_dim", "--max-image-dim",
                                    &cam->height, e);
    if (rc == REFRACT_E_OK)
        rc = check_camera(cam, e);
    return rc;
}

static enum refract_code parse_render(const cJSON *root, const struct scene_limits *lim,
                                      struct scene_render_settings *r, struct err *e)
{
    static const char *const keys[] = {"stepper",
                                       "step",
                                       "tolerance",
                                       "max_steps",
                                       "exposure",
                                       "boundary_threshold",
                                       "tonemap",
                                       "ior_texture",
                                       "ior_filter",
                                       "empty_space_skipping",
                                       "min_throughput",
                                       "samples_per_pixel",
                                       SCENE_STEPPER_OLD_KEY,
                                       NULL};
    /* Order as enum scene_stepper / scene_ior_texture / scene_ior_filter. */
    const cJSON *o;
    int stepper = SCENE_STEPPER_RK4, tonemap = SCENE_TONEMAP_CLAMP;
    int ior_texture = SCENE_IOR_FLOAT32, ior_filter = SCENE_FILTER_TRILINEAR;
    int def_steps = lim->max_steps < 20000 ? lim->max_steps : 20000;
    enum refract_code rc = sub_object(root, "render", keys, &o, e);
    const char *stepper_key = "stepper";
    if (rc == REFRACT_E_OK)
        rc = jr_renamed(o, "render", "stepper", SCENE_STEPPER_OLD_KEY, &stepper_key, e);
    if (rc == REFRACT_E_OK)
        rc = jr_enum(o, "render", stepper_key, false, SCENE_STEPPER_RK4, scene_stepper_words,
                     &stepper, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, "render", "step", false, 0.5, 0.01, 8.0, &r->step_voxels, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, "render", "tolerance", false, 1e-3, 1e-6, 1.0, &r->tolerance_voxels, e);
    if (rc == REFRACT_E_OK)
        rc = jr_enum(o, "render", "ior_texture", false, SCENE_IOR_FLOAT32, scene_ior_texture_words,
                     &ior_texture, e);
    if (rc == REFRACT_E_OK)
        rc = scene_read_limited_int(member(o, "max_steps"), "render.max_steps", def_steps, 1,
                                    lim->max_steps, "max_steps", "--max-steps", &r->max_steps, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, "render", "exposure", false, 0.0, -20.0, 20.0, &r->exposure_ev, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number_gt(o, "render", "boundary_threshold", false, 0.02, 0.0, 10.0,
                          &r->boundary_threshold, e);
    if (rc == REFRACT_E_OK)
        rc = jr_enum(o, "render", "tonemap", false, SCENE_TONEMAP_CLAMP, scene_tonemap_words,
                     &tonemap, e);
    if (rc == REFRACT_E_OK)
        rc = jr_bool(o, "render", "empty_space_skipping", false, true, &r->empty_space_skipping, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, "render", "min_throughput", false, 1e-6, 0.0, 0.5, &r->min_throughput, e);
    if (rc == REFRACT_E_OK)
        rc = jr_enum(o, "render", "ior_filter", false, SCENE_FILTER_TRILINEAR,
                     scene_ior_filter_words, &ior_filter, e);
    if (rc == REFRACT_E_OK)
        rc = scene_read_samples_per_pixel(member(o, "samples_per_pixel"), "render.samples_per_pixel",
                                          1, lim, &r->samples_per_pixel, e);
    r->ior_filter = (enum scene_ior_filter)ior_filter;
    r->stepper = (enum scene_stepper)stepper;
    r->tonemap = (enum scene_tonemap)tonemap;
    r->ior_texture = (enum scene_ior_texture)ior_texture;
    return rc;
}

static enum refract_code parse_bounds(const cJSON *obj, const char *path, struct scene_object *o,
                                      struct err *e)
{
    static const char *const keys[] = {"min", "max", NULL};
    static const char axis_names[3] = {'x', 'y', 'z'};
    char p[256];
    const cJSON *b = member(obj, "bounds");
    if (b == NULL)
        return err_set(e, REFRACT_E_MISSING_FIELD, "%s: missing required field \"bounds\"", path);
    jr_path(p, sizeof p, path, "bounds");
    const double m = SCENE_COORD_MAX;
    enum refract_code rc = jr_check_object(b, p, keys, e);
    if (rc == REFRACT_E_OK)
        rc = jr_vec3(b, p, "min", true, vec3_make(0, 0, 0), -m, m, &o->bounds_min, e);
    if (rc == REFRACT_E_OK)
        rc = jr_vec3(b, p, "max", true, vec3_make(0, 0, 0), -m, m, &o->bounds_max, e);
    for (int a = 0; rc == REFRACT_E_OK && a < 3; a++) {
        double lo = vec3_get(o->bounds_min, a), hi = vec3_get(o->bounds_max, a);
        /* The GPU marches in single precision in object space: an extent that rounds to
         * zero in float (1e-300) made every voxel size 0 and every traced value NaN, and
         * one below ~1e-4 of its coordinates makes voxels that float positions cannot
         * tell apart (tests/integration/test_hard_inputs.c). Tiny objects are made with
         * transform.scale instead. */
        double least =
            fmax(SCENE_BOUNDS_MIN_EXTENT, SCENE_BOUNDS_MIN_RELATIVE * fmax(fabs(lo), fabs(hi)));
        if (!(hi > lo))
            rc = err_set(e, REFRACT_E_INVALID_FIELD,
                         "%s: max must be greater than min on every axis; on %c, min = %g and "
                         "max = %g",
                         p, axis_names[a], lo, hi);
        else if (hi - lo < least)
            rc = err_set(e, REFRACT_E_INVALID_FIELD,
                         "%s: too thin on %c: max - min = %g, at least %g needed here (1e-6, "
                         "and 1e-4 of the largest |coordinate|, so that single-precision "
                         "positions can tell the voxels apart); make the bounds larger and "
                         "shrink the object with transform.scale",
                         p, axis_names[a], hi - lo, least);
    }
    return rc;
}

static enum refract_code parse_resolution(const cJSON *obj, const char *path,
                                          const struct scene_limits *lim, int res[3], struct err *e)
{
    char p[256], got[80];
    jr_path(p, sizeof p, path, "resolution");
    const cJSON *r = member(obj, "resolution");
    int def = lim->max_resolution < 128 ? lim->max_resolution : 128;
    if (r == NULL || cJSON_IsNumber(r)) {
        enum refract_code rc = scene_read_limited_int(
            r, p, def, 2, lim->max_resolution, "max_resolution", "--max-resolution", &res[0], e);
        res[1] = res[2] = res[0];
        return rc;
    }
    if (!cJSON_IsArray(r) || cJSON_GetArraySize(r) != 3)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected an integer or an array of 3 integers in 2..%d, got %s", p,
                       lim->max_resolution, jr_describe(r, got, sizeof got));
    for (int a = 0; a < 3; a++) {
        char pa[256];
        enum refract_code rc = scene_read_limited_int(
            cJSON_GetArrayItem(r, a), jr_path_index(pa, sizeof pa, p, a), def, 2,
            lim->max_resolution, "max_resolution", "--max-resolution", &res[a], e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    return REFRACT_E_OK;
}

enum refract_code scene_parse_transform(const cJSON *obj, const char *path, struct xform *x,
                                        struct err *e)
{
    static const char *const keys[] = {"translate", "rotate", "scale", NULL};
    static const char *const rot_keys[] = {"axis", "angle_deg", NULL};
    const double m = SCENE_COORD_MAX;
    char p[256], pr[256];
    jr_path(p, sizeof p, path, "transform");
    jr_path(pr, sizeof pr, p, "rotate");
    const cJSON *t = member(obj, "transform");
    vec3 translate = {0, 0, 0}, axis = {0, 1, 0};
    double angle = 0.0, scale = 1.0;
    enum refract_code rc = REFRACT_E_OK;
    if (t != NULL) {
        rc = jr_check_object(t, p, keys, e);
        if (rc == REFRACT_E_OK)
            rc = jr_vec3(t, p, "translate", false, translate, -m, m, &translate, e);
        if (rc == REFRACT_E_OK)
            /* Not below 1e-6: a scale that rounds to zero in single precision (1e-30,
             * 1e-300) gave the GPU an infinite object_from_world and NaN traces. */
            rc = jr_number(t, p, "scale", false, 1.0, SCENE_SCALE_MIN, m, &scale, e);
        const cJSON *r = member(t, "rotate");
        if (rc == REFRACT_E_OK && r != NULL) {
            rc = jr_check_object(r, pr, rot_keys, e);
            if (rc == REFRACT_E_OK)
                rc = jr_direction(r, pr, "axis", true, axis, &axis, e);
            if (rc == REFRACT_E_OK)
                rc = jr_number(r, pr, "angle_deg", true, 0.0, -3600.0, 3600.0, &angle, e);
        }
    }
    *x = xform_make(translate, axis, angle, scale);
    return rc;
}

/* How many channels other than `except` the object uses. */
static int channels_used_except(const struct scene_object *o, enum scene_channel except)
{
    int n = 0;
    for (int ch = 0; ch < SCENE_CH_COUNT; ch++)
        n += ch != (int)except && o->fields[ch].count > 0;
    return n;
}

static enum refract_code parse_channels(const cJSON *obj, const char *path,
                                        const struct scene_parse_ctx *ctx, struct scene_object *o,
                                        struct err *e)
{
    for (int ch = 0; ch < SCENE_CH_COUNT; ch++) {
        const char *key = scene_channel_name((enum scene_channel)ch);
        const cJSON *item = member(obj, key);
        if (item == NULL)
            continue;
        char p[256];
        enum refract_code rc = scene_parse_field(item, jr_path(p, sizeof p, path, key),
                                                 (enum scene_channel)ch, ctx, &o->fields[ch], e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    /* Anisotropy only shapes scattering, so alone it would describe nothing. A smoke
     * object may consist of scattering only. */
    if (channels_used_except(o, SCENE_CH_ANISOTROPY) == 0)
        return err_set(e, REFRACT_E_MISSING_FIELD,
                       "%s: an object needs at least one of ior, attenuation, emission, opaque, "
                       "scattering, particles",
                       path);
    if (!scene_channel_used(o, SCENE_CH_SCATTERING) && scene_channel_used(o, SCENE_CH_ANISOTROPY))
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s.anisotropy: has no effect without scattering; add a \"scattering\" "
                       "field or remove \"anisotropy\"",
                       path);
    return REFRACT_E_OK;
}

static enum refract_code parse_object(const cJSON *obj, const char *path, int index,
                                      const struct scene_parse_ctx *outer, struct scene_object *o,
                                      struct err *e)
{
    static const char *const keys[] = {
        "name",       "bounds",      "resolution", "transform", "smoothing_sigma",
        "ior",        "attenuation", "emission",   "opaque",    "opaque_ior",
        "scattering", "anisotropy",  "brdf",       "particles", NULL};
    char def_name[32];
    snprintf(def_name, sizeof def_name, "object%d", index);
    enum refract_code rc = jr_check_object(obj, path, keys, e);
    if (rc == REFRACT_E_OK)
        rc = jr_string(obj, path, "name", false, def_name, SCENE_NAME_MAX - 1, o->name,
                       sizeof o->name, e);
    if (rc == REFRACT_E_OK)
        rc = parse_bounds(obj, path, o, e);
    if (rc == REFRACT_E_OK)
        rc = parse_resolution(obj, path, outer->limits, o->resolution, e);
    if (rc == REFRACT_E_OK)
        rc = scene_parse_transform(obj, path, &o->world_from_object, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(obj, path, "smoothing_sigma", false, 1.0, 0.0, 8.0,
                       &o->smoothing_sigma_voxels, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(obj, path, "opaque_ior", false, 1.5, 1.0, 4.0, &o->opaque_ior, e);
    if (rc == REFRACT_E_OK)
        rc = scene_parse_brdf(obj, path, &o->brdf, e);
    if (rc != REFRACT_E_OK)
        return rc;
    struct scene_parse_ctx ctx = *outer;
    ctx.bounds_min = o->bounds_min;
    ctx.bounds_max = o->bounds_max;
    /* "particles" fills attenuation, scattering and anisotropy (and refuses them beside
     * it), so parse_channels then sees the channels as set. */
    rc = scene_parse_particles(obj, path, &ctx, o, e);
    if (rc != REFRACT_E_OK)
        return rc;
    return parse_channels(obj, path, &ctx, o, e);
}

static enum refract_code parse_objects(const cJSON *root, const struct scene_parse_ctx *ctx,
                                       struct scene *s, struct err *e)
{
    const struct scene_limits *lim = ctx->limits;
    const cJSON *arr = member(root, "objects");
    char got[80];
    bool has_surfaces = member(root, "surfaces") != NULL;
    if (arr == NULL && has_surfaces)
        return REFRACT_E_OK; /* a scene of exact surfaces only */
    if (arr == NULL)
        return err_set(e, REFRACT_E_MISSING_FIELD,
                       "(root): missing required field \"objects\" (or \"surfaces\")");
    int n = cJSON_IsArray(arr) ? cJSON_GetArraySize(arr) : 0;
    if (n == 0 && has_surfaces && cJSON_IsArray(arr))
        return REFRACT_E_OK;
    if (n == 0)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "objects: expected an array of 1..%d objects, got %s", lim->max_objects,
                       jr_describe(arr, got, sizeof got));
    if (n > lim->max_objects) {
        char given[40];
        snprintf(given, sizeof given, "%d objects", n);
        return scene_limit_error(e, "objects", given, "max_objects", lim->max_objects,
                                 "--max-objects");
    }
    s->objects = calloc((size_t)n, sizeof *s->objects);
    if (s->objects == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "objects: out of memory for %d objects", n);
    s->object_count = (size_t)n;
    int64_t voxels = 0;
    int i = 0;
    for (const cJSON *it = arr->child; it != NULL; it = it->next, i++) {
        char p[64];
        struct scene_object *o = &s->objects[i];
        enum refract_code rc =
            parse_object(it, jr_path_index(p, sizeof p, "objects", i), i, ctx, o, e);
        if (rc != REFRACT_E_OK)
            return rc;
        voxels += (int64_t)o->resolution[0] * o->resolution[1] * o->resolution[2];
        if (voxels > lim->max_voxels) {
            char given[80];
            snprintf(given, sizeof given, "%lld voxels over objects[0..%d]", (long long)voxels, i);
            return scene_limit_error(e, p, given, "max_voxels", (long long)lim->max_voxels,
                                     "--max-voxels");
        }
    }
    return REFRACT_E_OK;
}

static enum refract_code parse_description(const cJSON *root, struct err *e)
{
    const cJSON *d = member(root, "description");
    char got[80];
    if (d == NULL)
        return REFRACT_E_OK;
    if (!cJSON_IsString(d))
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "description: expected a string of at most %d bytes, got %s",
                       DESCRIPTION_MAX, jr_describe(d, got, sizeof got));
    size_t n = strlen(d->valuestring);
    if (n > DESCRIPTION_MAX)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "description: expected a string of at most %d bytes, got %zu bytes",
                       DESCRIPTION_MAX, n);
    return REFRACT_E_OK;
}

static enum refract_code parse_document(const cJSON *root, const struct scene_limits *lim,
                                        struct scene *s, struct err *e)
{
    static const char *const keys[] = {"name",     "description", "ambient_ior", "environment",
                                       "camera",   "render",      "objects",     "lights",
                                       "receiver", "lightsim",    "surfaces",    NULL};
    enum refract_code rc = jr_check_object(root, "", keys, e);
    if (rc == REFRACT_E_OK)
        rc = jr_string(root, "", "name", false, "untitled", SCENE_NAME_MAX - 1, s->name,
                       sizeof s->name, e);
    if (rc == REFRACT_E_OK)
        rc = parse_description(root, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(root, "", "ambient_ior", false, 1.0, 1.0, 4.0, &s->ambient_ior, e);
    if (rc == REFRACT_E_OK)
        rc = parse_environment(root, &s->environment, e);
    if (rc == REFRACT_E_OK)
        rc = parse_camera(root, lim, &s->camera, e);
    if (rc == REFRACT_E_OK)
        rc = parse_render(root, lim, &s->render, e);
    if (rc == REFRACT_E_OK)
        rc = scene_parse_lights(member(root, "lights"), s, e);
    if (rc == REFRACT_E_OK)
        rc = scene_parse_lightsim(member(root, "lightsim"), &s->lightsim, e);
    if (rc != REFRACT_E_OK)
        return rc;
    struct scene_parse_ctx ctx = {.limits = lim, .ambient_ior = s->ambient_ior};
    rc = parse_objects(root, &ctx, s, e);
    if (rc == REFRACT_E_OK)
        rc = scene_parse_surfaces(member(root, "surfaces"), lim, s, e);
    /* After the objects: the receiver's default size depends on where they are. */
    if (rc == REFRACT_E_OK)
        rc = scene_parse_receiver(member(root, "receiver"), s, e);
    if (rc == REFRACT_E_OK)
        scene_resolve_caustics(s);
    if (rc == REFRACT_E_OK && s->receiver.enabled && s->receiver.caustics == SCENE_CAUSTICS_PHOTONS)
        rc = scene_check_photon_surfaces(s, e);
    else if (rc == REFRACT_E_OK && s->receiver.enabled &&
             s->receiver.caustics == SCENE_CAUSTICS_VOLUME)
        rc = scene_check_lightsim_surfaces(s, "receiver", e);
    return rc;
}

enum refract_code scene_parse(const char *json, size_t len, const struct scene_limits *limits,
                              struct scene **out, struct err *e)
{
    *out = NULL;
    struct scene_limits lim = limits ? *limits : scene_limits_default();
    cJSON *root;
    enum refract_code rc = jr_parse(json, len, &root, e);
    if (rc != REFRACT_E_OK)
        return rc;
    struct scene *s = calloc(1, sizeof *s);
    if (s == NULL) {
        cJSON_Delete(root);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "(root): out of memory for the scene");
    }
    rc = parse_document(root, &lim, s, e);
    cJSON_Delete(root);
    if (rc != REFRACT_E_OK) {
        scene_destroy(s);
        return rc;
    }
    *out = s;
    return REFRACT_E_OK;
}

void scene_destroy(struct scene *s)
{
    if (s == NULL)
        return;
    for (size_t i = 0; i < s->object_count; i++) {
        for (int ch = 0; ch < SCENE_CH_COUNT; ch++)
            scene_field_fini(&s->objects[i].fields[ch]);
    }
    free(s->objects);
    for (size_t i = 0; i < s->surface_count; i++)
        free(s->surfaces[i].shape.profile);
    free(s->surfaces);
    free(s);
}
