/*
 * request_parse.c - the render and trace request bodies (proto/openapi.yaml RenderRequest,
 * TraceRequest) into validated structs, with the same path-first messages as scene
 * documents (scene/json_read.h). Defaults come from the scene's camera and render blocks.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../scene/json_read.h"
#include "http_internal.h"

/* Order as enum scene_stepper. */
static const char *const format_names[] = {"png", "jpeg", "exr", NULL};

enum refract_code http_parse_body(const char *body, size_t len, cJSON **root, struct err *e)
{
    size_t i = 0;
    while (i < len && (body[i] == ' ' || body[i] == '\n' || body[i] == '\r' || body[i] == '\t'))
        i++;
    if (i == len) {
        *root = cJSON_CreateObject();
        return *root ? REFRACT_E_OK : err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory");
    }
    return jr_parse(body, len, root, e);
}

/* An integer in 1..INT_MAX that must not exceed a configurable limit: beyond it the
 * answer is LIMIT_EXCEEDED naming the flag, as for scene documents. */
static enum refract_code limited_int(const cJSON *root, const char *key, int def, int limit,
                                     const char *flag, int *out, struct err *e)
{
    enum refract_code rc = jr_int(root, "", key, false, def, 1, 2147483647, out, e);
    if (rc == REFRACT_E_OK && *out > limit)
        rc = err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                     "%s: %d exceeds the limit of %d (refractd %s raises it)", key, *out, limit,
                     flag);
    return rc;
}

enum refract_code http_parse_settings(const cJSON *root, const struct scene_render_settings *def,
                                      const struct http_config *cfg,
                                      struct scene_render_settings *st, struct err *e)
{
    *st = *def;
    int stepper = (int)st->stepper, ior_filter = (int)st->ior_filter;
    const char *stepper_key = "stepper";
    enum refract_code rc = jr_renamed(root, "", "stepper", SCENE_STEPPER_OLD_KEY, &stepper_key, e);
    if (rc == REFRACT_E_OK)
        rc = jr_enum(root, "", stepper_key, false, stepper, scene_stepper_words, &stepper, e);
    if (rc == REFRACT_E_OK)
        rc = jr_enum(root, "", "ior_filter", false, ior_filter, scene_ior_filter_words, &ior_filter,
                     e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(root, "", "step", false, st->step_voxels, 0.01, 8.0, &st->step_voxels, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(root, "", "tolerance", false, st->tolerance_voxels, 1e-6, 1.0,
                       &st->tolerance_voxels, e);
    if (rc == REFRACT_E_OK)
        rc = limited_int(root, "max_steps", st->max_steps, cfg->limits.max_steps, "--max-steps",
                         &st->max_steps, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(root, "", "boundary_threshold", false, st->boundary_threshold, 1e-6, 10.0,
                       &st->boundary_threshold, e);
    if (rc == REFRACT_E_OK)
        rc = scene_read_samples_per_pixel(cJSON_GetObjectItemCaseSensitive(root,
                                                                           "samples_per_pixel"),
                                          "samples_per_pixel", st->samples_per_pixel,
                                          &cfg->limits, &st->samples_per_pixel, e);
    st->stepper = (enum scene_stepper)stepper;
    st->ior_filter = (enum scene_ior_filter)ior_filter;
    return rc;
}

enum refract_code http_parse_camera(const cJSON *root, const struct scene_camera *def,
                                    const struct http_config *cfg, struct scene_camera *cam,
                                    struct err *e)
{
    static const char *const keys[] = {"eye", "look_at", "up", "fov_y_deg", NULL};
    *cam = *def;
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(root, "camera");
    enum refract_code rc = REFRACT_E_OK;
    if (c) {
        rc = jr_check_object(c, "camera", keys, e);
        if (rc == REFRACT_E_OK)
            rc = jr_vec3(c, "camera", "eye", false, cam->eye, -1e6, 1e6, &cam->eye, e);
        if (rc == REFRACT_E_OK)
            rc = jr_vec3(c, "camera", "look_at", false, cam->look_at, -1e6, 1e6, &cam->look_at, e);
        if (rc == REFRACT_E_OK)
            /* jr_direction, as the scene parser: a zero or underflowing up vector was
             * reported as "parallel to the view direction", which it is not. */
            rc = jr_direction(c, "camera", "up", false, cam->up, &cam->up, e);
        if (rc == REFRACT_E_OK)
            rc = jr_number_gt(c, "camera", "fov_y_deg", false, cam->fov_y_deg, 0.1, 179.0,
                              &cam->fov_y_deg, e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    rc = limited_int(root, "width", cam->width, cfg->limits.max_image_dim, "--max-image-dim",
                     &cam->width, e);
    if (rc == REFRACT_E_OK)
        rc = limited_int(root, "height", cam->height, cfg->limits.max_image_dim, "--max-image-dim",
                         &cam->height, e);
    if (rc != REFRACT_E_OK)
        return rc;
    long long pixels = (long long)cam->width * cam->height;
    if (pixels > cfg->max_image_pixels)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "width x height: %dx%d = %lld pixels exceed the limit of %lld (refractd "
                       "--max-image-pixels raises it)",
                       cam->width, cam->height, pixels, cfg->max_image_pixels);
    vec3 f = vec3_sub(cam->look_at, cam->eye);
    if (vec3_length(f) < 1e-9)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "camera: eye and look_at are the same point; the camera needs a view "
                       "direction");
    if (vec3_length(vec3_cross(vec3_normalize(f), vec3_normalize(cam->up))) < 1e-9)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "camera.up: parallel to the view direction (look_at - eye); choose an up "
                       "vector that is not, e.g. [0, 1, 0] for a horizontal view");
    return REFRACT_E_OK;
}

enum refract_code http_parse_image_options(const cJSON *root, double *exposure_ev,
                                           enum scene_tonemap *tonemap, int *jpeg_quality,
                                           struct err *e)
{
    int tm = (int)*tonemap;
    enum refract_code rc = jr_enum(root, "", "tonemap", false, tm, scene_tonemap_words, &tm, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(root, "", "exposure", false, *exposure_ev, -20.0, 20.0, exposure_ev, e);
    if (rc == REFRACT_E_OK)
        rc = jr_int(root, "", "jpeg_quality", false, *jpeg_quality, 1, 100, jpeg_quality, e);
    *tonemap = (enum scene_tonemap)tm;
    return rc;
}

enum refract_code http_parse_render_request(const char *body, size_t len, const struct scene *scene,
                                            const struct http_config *cfg,
                                            struct http_render_request *out, struct err *e)
{
    static const char *const keys[] = {"camera",
                                       "width",
                                       "height",
                                       "format",
                                       "exposure",
                                       "tonemap",
                                       "stepper",
                                       "step",
                                       "tolerance",
                                       "max_steps",
                                       "jpeg_quality",
                                       "boundary_threshold",
                                       "ior_filter",
                                       "samples_per_pixel",
                                       "mode",
                                       SCENE_STEPPER_OLD_KEY,
                                       NULL};
    /* "reference" is answered by h_render_reference.c before this parser runs */
    static const char *const modes[] = {"fast", "reference", NULL};
    memset(out, 0, sizeof *out);
    cJSON *root = NULL;
    enum refract_code rc = http_parse_body(body, len, &root, e);
    if (rc != REFRACT_E_OK)
        return rc;
    rc = jr_check_object(root, "", keys, e);
    int mode = 0;
    if (rc == REFRACT_E_OK)
        rc = jr_enum(root, "", "mode", false, 0, modes, &mode, e);
    if (rc == REFRACT_E_OK)
        rc = http_parse_camera(root, &scene->camera, cfg, &out->view.camera, e);
    if (rc == REFRACT_E_OK)
        rc = http_parse_settings(root, &scene->render, cfg, &out->view.settings, e);
    int format = HTTP_FORMAT_PNG;
    if (rc == REFRACT_E_OK)
        rc = jr_enum(root, "", "format", false, HTTP_FORMAT_PNG, format_names, &format, e);
    out->exposure_ev = scene->render.exposure_ev;
    out->tonemap = scene->render.tonemap;
    out->jpeg_quality = 90;
    if (rc == REFRACT_E_OK)
        rc =
            http_parse_image_options(root, &out->exposure_ev, &out->tonemap, &out->jpeg_quality, e);
    out->format = format;
    cJSON_Delete(root);
    return rc;
}

static enum refract_code parse_ray(const cJSON *item, int i, struct render_trace_ray *ray,
                                   struct err *e)
{
    static const char *const keys[] = {"origin", "direction", NULL};
    char path[48];
    jr_path_index(path, sizeof path, "rays", i);
    vec3 o = {0, 0, 0}, d = {0, 0, 1};
    enum refract_code rc = jr_check_object(item, path, keys, e);
    if (rc == REFRACT_E_OK)
        rc = jr_vec3(item, path, "origin", true, o, -1e6, 1e6, &o, e);
    if (rc == REFRACT_E_OK)
        rc = jr_direction(item, path, "direction", true, d, &d, e);
    if (rc != REFRACT_E_OK)
        return rc;
    ray->origin[0] = o.x;
    ray->origin[1] = o.y;
    ray->origin[2] = o.z;
    ray->direction[0] = d.x;
    ray->direction[1] = d.y;
    ray->direction[2] = d.z;
    return REFRACT_E_OK;
}

enum refract_code http_parse_trace_request(const char *body, size_t len, const struct scene *scene,
                                           const struct http_config *cfg,
                                           struct scene_render_settings *settings,
                                           struct render_trace_ray **rays, size_t *count,
                                           bool *events, struct err *e)
{
    static const char *const keys[] = {
        "rays",       "step",   "tolerance",           "stepper", "max_steps", "boundary_threshold",
        "ior_filter", "events", SCENE_STEPPER_OLD_KEY, NULL};
    *rays = NULL;
    *count = 0;
    cJSON *root = NULL;
    enum refract_code rc = jr_parse(body, len, &root, e);
    if (rc != REFRACT_E_OK)
        return rc;
    rc = jr_check_object(root, "", keys, e);
    if (rc == REFRACT_E_OK)
        rc = http_parse_settings(root, &scene->render, cfg, settings, e);
    if (rc == REFRACT_E_OK)
        rc = jr_bool(root, "", "events", false, false, events, e);
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(root, "rays");
    if (rc == REFRACT_E_OK && list == NULL)
        rc = err_set(e, REFRACT_E_MISSING_FIELD,
                     "rays: missing required field; send {\"rays\": [{\"origin\": [x, y, z], "
                     "\"direction\": [x, y, z]}]}");
    if (rc == REFRACT_E_OK && !cJSON_IsArray(list))
        rc = err_set(e, REFRACT_E_INVALID_FIELD, "rays: expected an array of rays");
    int n = rc == REFRACT_E_OK ? cJSON_GetArraySize(list) : 0;
    if (rc == REFRACT_E_OK && n == 0)
        rc = err_set(e, REFRACT_E_INVALID_FIELD, "rays: expected at least one ray, got none");
    if (rc == REFRACT_E_OK && n > cfg->max_rays)
        rc = err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                     "rays: %d rays exceed the limit of %d per request (refractd --max-rays); "
                     "split the request",
                     n, cfg->max_rays);
    struct render_trace_ray *out = NULL;
    if (rc == REFRACT_E_OK) {
        out = calloc((size_t)n, sizeof *out);
        if (out == NULL)
            rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for %d rays", n);
    }
    int i = 0;
    const cJSON *item;
    cJSON_ArrayForEach(item, list)
    {
        if (rc != REFRACT_E_OK)
            break;
        rc = parse_ray(item, i, &out[i], e);
        i++;
    }
    cJSON_Delete(root);
    if (rc != REFRACT_E_OK) {
        free(out);
        return rc;
    }
    *rays = out;
    *count = (size_t)n;
    return REFRACT_E_OK;
}

/* ---- query parameters ---- */

struct unknown_query {
    const char *const *allowed;
    const char *first_unknown;
};

static enum MHD_Result find_unknown_query(void *cls, enum MHD_ValueKind kind, const char *key,
                                          const char *value)
{
    (void)kind;
    (void)value;
    struct unknown_query *u = cls;
    for (const char *const *a = u->allowed; *a; a++)
        if (strcmp(*a, key) == 0)
            return MHD_YES;
    u->first_unknown = key;
    return MHD_NO;
}

const char *http_query_unknown(struct http_request *req, const char *const *allowed)
{
    struct unknown_query u = {allowed, NULL};
    MHD_get_connection_values(req->conn, MHD_GET_ARGUMENT_KIND, find_unknown_query, &u);
    return u.first_unknown;
}
