/*
 * job_spec.c - a batch job's specification (docs/api.md "Batch jobs") expanded into the
 * frames to render: an explicit "frames" list, or the "turntable" generator, which orbits
 * the scene camera's eye (and look_at and up) about an axis through a centre in N equal
 * steps, or the "light_path" generator, which moves one light through keyframes in N frames
 * (directions slerped, positions lerped) with the scene camera. Top-level "width",
 * "height", "format" and "exposure" are defaults for every frame.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "../scene/json_read.h"
#include "jobs.h"

const char *const job_format_names[] = {"png", "jpeg", "exr", NULL};

enum refract_code job_spec_scene(const cJSON *root, char out[STORE_ID_MAX],
                                 const cJSON **inline_doc, struct err *e)
{
    *inline_doc = NULL;
    out[0] = '\0';
    const cJSON *scene = cJSON_GetObjectItemCaseSensitive(root, "scene");
    if (cJSON_IsObject(scene)) {
        *inline_doc = scene;
        return REFRACT_E_OK;
    }
    if (scene != NULL && !cJSON_IsString(scene)) {
        char what[64];
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "scene: expected a scene id (a string) or a whole scene document (an"
                       " object, as POST /v1/scenes takes), got %s",
                       jr_describe(scene, what, sizeof what));
    }
    return jr_string(root, "", "scene", true, "", STORE_ID_MAX - 1, out, STORE_ID_MAX, e);
}

void job_spec_inline_error(struct err *e)
{
    static const char root[] = "(root)"; /* json_read.c's name of the document itself */
    char msg[ERR_MSG_MAX];
    snprintf(msg, sizeof msg, "%s", e->msg);
    size_t n = strspn(msg, "abcdefghijklmnopqrstuvwxyz_0123456789[].");
    const char *sep = n > 0 && msg[n] == ':' ? "." : ": ";
    const char *rest = msg;
    if (strncmp(msg, root, sizeof root - 1) == 0) {
        sep = "";
        rest = msg + sizeof root - 1;
    }
    snprintf(e->msg, sizeof e->msg, "scene%s%.*s", sep, (int)sizeof msg - 8, rest);
}

enum refract_code job_spec_inline_check(const struct scene *s, struct err *e)
{
    static const char fix[] =
        "an inline scene cannot use uploads (uploaded volumes and meshes belong to a scene"
        " id): create the scene with POST /v1/scenes, upload to it, and submit the job with"
        " \"scene\": \"<id>\"";
    for (size_t o = 0; o < s->object_count; o++) {
        for (int ch = 0; ch < SCENE_CH_COUNT; ch++) {
            const struct scene_field *f = &s->objects[o].fields[ch];
            for (size_t i = 0; i < f->count; i++) {
                const struct scene_layer *l = &f->layers[i];
                bool mesh = l->kind == SCENE_LAYER_SHAPE && l->shape.kind == SCENE_SHAPE_MESH;
                if (l->kind != SCENE_LAYER_VOLUME && !mesh)
                    continue;
                return err_set(e, REFRACT_E_INVALID_FIELD, "scene.objects[%zu].%s: %s \"%s\": %s",
                               o, scene_channel_name((enum scene_channel)ch),
                               mesh ? "uses the uploaded mesh" : "uses the uploaded volume",
                               mesh ? l->shape.mesh : l->volume, fix);
            }
        }
    }
    if (s->environment.kind == SCENE_ENV_IMAGE)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "scene.environment.type: \"image\" uses the uploaded environment image;"
                       " %s (or use \"procedural\")",
                       fix);
    return REFRACT_E_OK;
}

vec3 job_rotate_about(vec3 p, vec3 center, vec3 axis, double angle)
{
    /* Rodrigues: v' = v cos a + (k x v) sin a + k (k . v)(1 - cos a), v = p - center. */
    vec3 v = vec3_sub(p, center);
    double c = cos(angle), s = sin(angle);
    vec3 r = vec3_add(vec3_add(vec3_scale(v, c), vec3_scale(vec3_cross(axis, v), s)),
                      vec3_scale(axis, vec3_dot(axis, v) * (1.0 - c)));
    return vec3_add(center, r);
}

vec3 job_slerp(vec3 a, vec3 b, double t)
{
    double c = vec3_dot(a, b);
    c = c > 1 ? 1 : c < -1 ? -1 : c;
    if (c > 1 - 1e-12)
        return vec3_normalize(vec3_add(vec3_scale(a, 1 - t), vec3_scale(b, t)));
    if (c < -1 + 1e-9) {
        /* Opposite: any great circle will do; turn through a vector perpendicular to a. */
        vec3 helper = fabs(a.x) < 0.9 ? vec3_make(1, 0, 0) : vec3_make(0, 1, 0);
        vec3 mid = vec3_normalize(vec3_cross(a, helper));
        return t < 0.5 ? job_slerp(a, mid, 2 * t) : job_slerp(mid, b, 2 * t - 1);
    }
    /* slerp(a, b; t) = sin((1 - t) w) / sin w a + sin(t w) / sin w b, w = acos(a . b). */
    double w = acos(c), sw = sin(w);
    return vec3_normalize(
        vec3_add(vec3_scale(a, sin((1 - t) * w) / sw), vec3_scale(b, sin(t * w) / sw)));
}

/* Size, format and exposure of a frame (or the top-level defaults) read over def. */
static enum refract_code read_image(const cJSON *obj, const char *path,
                                    const struct job_limits *lim, const struct job_frame *def,
                                    struct job_frame *out, struct err *e)
{
    *out = *def;
    int format = (int)def->format;
    enum refract_code rc = jr_int(obj, path, "width", false, def->camera.width, 1,
                                  lim->max_image_dim, &out->camera.width, e);
    if (rc == REFRACT_E_OK)
        rc = jr_int(obj, path, "height", false, def->camera.height, 1, lim->max_image_dim,
                    &out->camera.height, e);
    if (rc == REFRACT_E_OK)
        rc = jr_enum(obj, path, "format", false, format, job_format_names, &format, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(obj, path, "exposure", false, def->exposure_ev, -20, 20, &out->exposure_ev,
                       e);
    if (rc != REFRACT_E_OK)
        return rc;
    out->format = (enum job_format)format;
    long long pixels = (long long)out->camera.width * out->camera.height;
    if (pixels > lim->max_image_pixels)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "%s: %dx%d is %lld pixels, over --max-image-pixels %lld; ask for a smaller"
                       " width or height",
                       path[0] ? path : "job", out->camera.width, out->camera.height, pixels,
                       lim->max_image_pixels);
    return REFRACT_E_OK;
}

static enum refract_code read_camera(const cJSON *obj, const char *path, struct scene_camera *cam,
                                     struct err *e)
{
    static const char *const keys[] = {"eye", "look_at", "up", "fov_y_deg", NULL};
    const cJSON *c = cJSON_GetObjectItemCaseSensitive(obj, "camera");
    if (c == NULL)
        return REFRACT_E_OK;
    char p[128];
    jr_path(p, sizeof p, path, "camera");
    enum refract_code rc = jr_check_object(c, p, keys, e);
    if (rc == REFRACT_E_OK)
        rc = jr_vec3(c, p, "eye", false, cam->eye, -1e6, 1e6, &cam->eye, e);
    if (rc == REFRACT_E_OK)
        rc = jr_vec3(c, p, "look_at", false, cam->look_at, -1e6, 1e6, &cam->look_at, e);
    if (rc == REFRACT_E_OK)
        rc = jr_direction(c, p, "up", false, cam->up, &cam->up, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(c, p, "fov_y_deg", false, cam->fov_y_deg, 1, 179, &cam->fov_y_deg, e);
    if (rc == REFRACT_E_OK && vec3_length(vec3_sub(cam->look_at, cam->eye)) < 1e-9)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: eye and look_at are the same point; move one of them", p);
    return rc;
}

static enum refract_code count_ok(long long n, const struct job_limits *lim, const char *path,
                                  struct err *e)
{
    if (n > lim->max_frames)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "%s: %lld frames, over --max-job-frames %d; split the job or raise the flag",
                       path, n, lim->max_frames);
    return REFRACT_E_OK;
}

/* A frame's "lights": [{"name", "direction" | "position"}, ...], each naming a light of the
 * scene at most once, with the field its kind has. */
static enum refract_code read_lights(const cJSON *item, const char *path, const struct scene *s,
                                     struct job_frame *f, struct err *e)
{
    static const char *const keys[] = {"name", "direction", "position", NULL};
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(item, "lights");
    if (list == NULL)
        return REFRACT_E_OK;
    char p[96], what[64];
    jr_path(p, sizeof p, path, "lights");
    if (!cJSON_IsArray(list) || cJSON_GetArraySize(list) > SCENE_MAX_LIGHTS)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected an array of at most %d light changes, got %s", p,
                       SCENE_MAX_LIGHTS, jr_describe(list, what, sizeof what));
    int k = 0;
    const cJSON *o;
    cJSON_ArrayForEach(o, list)
    {
        char q[128], name[SCENE_LIGHT_NAME_MAX];
        jr_path_index(q, sizeof q, p, k);
        enum refract_code rc = jr_check_object(o, q, keys, e);
        if (rc == REFRACT_E_OK)
            rc = jr_string(o, q, "name", true, "", SCENE_LIGHT_NAME_MAX - 1, name, sizeof name, e);
        if (rc != REFRACT_E_OK)
            return rc;
        const struct scene_light *light = NULL;
        for (size_t i = 0; i < s->light_count; i++) {
            if (strcmp(s->lights[i].name, name) == 0)
                light = &s->lights[i];
        }
        if (light == NULL)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s.name: the scene has no light \"%s\"; GET /v1/scenes/{id}/lights"
                           " lists them",
                           q, name);
        for (int j = 0; j < k; j++) {
            if (strcmp(f->lights[j].light, name) == 0)
                return err_set(e, REFRACT_E_INVALID_FIELD,
                               "%s.name: light \"%s\" is changed twice in one frame", q, name);
        }
        bool has_dir = cJSON_GetObjectItemCaseSensitive(o, "direction") != NULL;
        bool has_pos = cJSON_GetObjectItemCaseSensitive(o, "position") != NULL;
        if (has_dir == has_pos)
            return err_set(e, has_dir ? REFRACT_E_INVALID_FIELD : REFRACT_E_MISSING_FIELD,
                           "%s: a light change gives exactly one of \"direction\" or"
                           " \"position\"",
                           q);
        if (has_dir && light->kind == SCENE_LIGHT_POINT)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s.direction: light \"%s\" is a point light, which has no direction", q,
                           name);
        if (has_pos && light->kind == SCENE_LIGHT_DIRECTIONAL)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s.position: light \"%s\" is directional, which has no position", q,
                           name);
        struct job_light_override *ov = &f->lights[k];
        ov->field = has_dir ? JOB_LIGHT_DIRECTION : JOB_LIGHT_POSITION;
        snprintf(ov->light, sizeof ov->light, "%s", name);
        rc = has_dir ? jr_direction(o, q, "direction", true, light->direction, &ov->value, e)
                     : jr_vec3(o, q, "position", true, light->position, -1e6, 1e6, &ov->value, e);
        if (rc != REFRACT_E_OK)
            return rc;
        k++;
    }
    f->light_count = k;
    return REFRACT_E_OK;
}

static enum refract_code expand_list(const cJSON *list, const struct scene *s,
                                     const struct job_limits *lim, const struct job_frame *def,
                                     struct job_frame **frames, int *count, struct err *e)
{
    static const char *const keys[] = {"camera",   "width",  "height", "format",
                                       "exposure", "lights", NULL};
    if (!cJSON_IsArray(list) || cJSON_GetArraySize(list) == 0) {
        char what[64];
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "frames: expected a non-empty array of frame objects, got %s",
                       jr_describe(list, what, sizeof what));
    }
    int n = cJSON_GetArraySize(list);
    enum refract_code rc = count_ok(n, lim, "frames", e);
    if (rc != REFRACT_E_OK)
        return rc;
    *frames = calloc((size_t)n, sizeof **frames);
    if (*frames == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for %d frames", n);
    int i = 0;
    const cJSON *item;
    cJSON_ArrayForEach(item, list)
    {
        char p[64];
        jr_path_index(p, sizeof p, "frames", i);
        rc = jr_check_object(item, p, keys, e);
        if (rc == REFRACT_E_OK)
            rc = read_image(item, p, lim, def, &(*frames)[i], e);
        if (rc == REFRACT_E_OK)
            rc = read_camera(item, p, &(*frames)[i].camera, e);
        if (rc == REFRACT_E_OK)
            rc = read_lights(item, p, s, &(*frames)[i], e);
        if (rc != REFRACT_E_OK) {
            free(*frames);
            *frames = NULL;
            return rc;
        }
        i++;
    }
    *count = n;
    return REFRACT_E_OK;
}

static enum refract_code expand_turntable(const cJSON *t, const struct job_limits *lim,
                                          const struct job_frame *def, struct job_frame **frames,
                                          int *count, struct err *e)
{
    static const char *const keys[] = {"frames", "axis", "center", "degrees", NULL};
    int n = 0;
    vec3 axis = {0, 1, 0}, center = def->camera.look_at;
    double degrees = 360;
    enum refract_code rc = jr_check_object(t, "turntable", keys, e);
    if (rc == REFRACT_E_OK)
        rc = jr_int(t, "turntable", "frames", true, 0, 1, 1 << 30, &n, e);
    if (rc == REFRACT_E_OK)
        rc = count_ok(n, lim, "turntable.frames", e);
    if (rc == REFRACT_E_OK)
        rc = jr_direction(t, "turntable", "axis", false, axis, &axis, e);
    if (rc == REFRACT_E_OK)
        rc = jr_vec3(t, "turntable", "center", false, center, -1e6, 1e6, &center, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(t, "turntable", "degrees", false, degrees, -3600, 3600, &degrees, e);
    if (rc != REFRACT_E_OK)
        return rc;
    vec3 radial = vec3_sub(def->camera.eye, center);
    if (vec3_length(vec3_sub(radial, vec3_scale(axis, vec3_dot(radial, axis)))) < 1e-9)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "turntable: the camera's eye lies on the axis through center, so orbiting"
                       " does not move it; give another center or axis");
    *frames = calloc((size_t)n, sizeof **frames);
    if (*frames == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for %d frames", n);
    /* N frames over `degrees` without repeating the first: step = degrees / N. */
    double step = degrees * M_PI / 180.0 / n;
    for (int i = 0; i < n; i++) {
        struct job_frame *f = &(*frames)[i];
        *f = *def;
        double a = step * i;
        f->camera.eye = job_rotate_about(def->camera.eye, center, axis, a);
        f->camera.look_at = job_rotate_about(def->camera.look_at, center, axis, a);
        vec3 origin = {0, 0, 0};
        f->camera.up = job_rotate_about(def->camera.up, origin, axis, a);
    }
    *count = n;
    return REFRACT_E_OK;
}

static enum refract_code expand_light_path(const cJSON *lp, const struct scene *s,
                                           const struct job_limits *lim,
                                           const struct job_frame *def, struct job_frame **frames,
                                           int *count, struct err *e)
{
    static const char *const keys[] = {"light", "keyframes", "frames", NULL};
    static const char *const kf_keys[] = {"direction", "position", NULL};
    char name[SCENE_LIGHT_NAME_MAX];
    int n = 0;
    enum refract_code rc = jr_check_object(lp, "light_path", keys, e);
    if (rc == REFRACT_E_OK)
        rc = jr_string(lp, "light_path", "light", true, "", SCENE_LIGHT_NAME_MAX - 1, name,
                       sizeof name, e);
    if (rc == REFRACT_E_OK)
        rc = jr_int(lp, "light_path", "frames", true, 0, 1, 1 << 30, &n, e);
    if (rc == REFRACT_E_OK)
        rc = count_ok(n, lim, "light_path.frames", e);
    if (rc != REFRACT_E_OK)
        return rc;
    const struct scene_light *light = NULL;
    for (size_t i = 0; i < s->light_count; i++) {
        if (strcmp(s->lights[i].name, name) == 0)
            light = &s->lights[i];
    }
    if (light == NULL)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "light_path.light: the scene has no light \"%s\"; GET "
                       "/v1/scenes/{id}/lights lists them",
                       name);
    const cJSON *kfs = cJSON_GetObjectItemCaseSensitive(lp, "keyframes");
    int k = cJSON_IsArray(kfs) ? cJSON_GetArraySize(kfs) : 0;
    if (k < 2 || k > 1000) {
        char what[64];
        return err_set(e, kfs ? REFRACT_E_INVALID_FIELD : REFRACT_E_MISSING_FIELD,
                       "light_path.keyframes: expected an array of 2..1000 keyframes, got %s",
                       jr_describe(kfs, what, sizeof what));
    }
    vec3 *values = calloc((size_t)k, sizeof *values);
    if (values == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the keyframes");
    enum job_light_field field = JOB_LIGHT_NONE;
    for (int i = 0; i < k && rc == REFRACT_E_OK; i++) {
        const cJSON *kf = cJSON_GetArrayItem(kfs, i);
        char p[64];
        jr_path_index(p, sizeof p, "light_path.keyframes", i);
        rc = jr_check_object(kf, p, kf_keys, e);
        bool has_dir = kf && cJSON_GetObjectItemCaseSensitive(kf, "direction");
        bool has_pos = kf && cJSON_GetObjectItemCaseSensitive(kf, "position");
        enum job_light_field f = has_dir ? JOB_LIGHT_DIRECTION : JOB_LIGHT_POSITION;
        if (rc == REFRACT_E_OK && has_dir == has_pos)
            rc = err_set(e, has_dir ? REFRACT_E_INVALID_FIELD : REFRACT_E_MISSING_FIELD,
                         "%s: a keyframe has exactly one of \"direction\" or \"position\"", p);
        else if (rc == REFRACT_E_OK && field != JOB_LIGHT_NONE && f != field)
            rc = err_set(e, REFRACT_E_INVALID_FIELD,
                         "%s: every keyframe of a path gives the same field (the first gave %s)", p,
                         field == JOB_LIGHT_DIRECTION ? "direction" : "position");
        else if (rc == REFRACT_E_OK && f == JOB_LIGHT_DIRECTION && light->kind == SCENE_LIGHT_POINT)
            rc = err_set(e, REFRACT_E_INVALID_FIELD,
                         "%s.direction: light \"%s\" is a point light, which has no direction;"
                         " give positions",
                         p, name);
        else if (rc == REFRACT_E_OK && f == JOB_LIGHT_POSITION &&
                 light->kind == SCENE_LIGHT_DIRECTIONAL)
            rc = err_set(e, REFRACT_E_INVALID_FIELD,
                         "%s.position: light \"%s\" is directional, which has no position;"
                         " give directions",
                         p, name);
        if (rc == REFRACT_E_OK)
            rc = f == JOB_LIGHT_DIRECTION
                     ? jr_direction(kf, p, "direction", true, light->direction, &values[i], e)
                     : jr_vec3(kf, p, "position", true, light->position, -1e6, 1e6, &values[i], e);
        field = f;
    }
    if (rc == REFRACT_E_OK) {
        *frames = calloc((size_t)n, sizeof **frames);
        if (*frames == NULL)
            rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for %d frames", n);
    }
    /* Frame i is at t = i / (N - 1) along the keyframes, evenly spaced: the first frame at
     * the first keyframe, the last at the last. */
    for (int i = 0; rc == REFRACT_E_OK && i < n; i++) {
        double t = n > 1 ? (double)i / (n - 1) * (k - 1) : 0;
        int seg = (int)floor(t);
        seg = seg > k - 2 ? k - 2 : seg;
        double u = t - seg;
        struct job_frame *f = &(*frames)[i];
        *f = *def;
        f->light_count = 1;
        f->lights[0].field = field;
        snprintf(f->lights[0].light, sizeof f->lights[0].light, "%s", name);
        f->lights[0].value =
            field == JOB_LIGHT_DIRECTION
                ? job_slerp(values[seg], values[seg + 1], u)
                : vec3_add(vec3_scale(values[seg], 1 - u), vec3_scale(values[seg + 1], u));
    }
    free(values);
    if (rc == REFRACT_E_OK)
        *count = n;
    return rc;
}

enum refract_code job_spec_expand(const cJSON *root, const struct scene *s,
                                  const struct job_limits *lim, struct job_frame **frames,
                                  int *count, struct err *e)
{
    static const char *const keys[] = {"scene",    "frames", "turntable", "light_path",
                                       "width",    "height", "format",    "exposure",
                                       "mode",     "samples", "seed",     NULL};
    static const char *const modes[] = {"fast", "reference", NULL};
    *frames = NULL;
    *count = 0;
    enum refract_code rc = jr_check_object(root, "", keys, e);
    if (rc != REFRACT_E_OK)
        return rc;
    struct job_frame base = {
        .camera = s->camera, .format = JOB_FORMAT_PNG, .exposure_ev = s->render.exposure_ev};
    /* "mode": "reference": every frame by the path tracer (docs/api.md "Batch jobs"). */
    int mode = 0;
    rc = jr_enum(root, "", "mode", false, 0, modes, &mode, e);
    int max_samples = lim->max_reference_samples > 0 ? lim->max_reference_samples : 65536;
    int samples = 64 < max_samples ? 64 : max_samples;
    double seed = 1.0;
    if (rc == REFRACT_E_OK && mode == 0 &&
        (cJSON_GetObjectItemCaseSensitive(root, "samples") ||
         cJSON_GetObjectItemCaseSensitive(root, "seed")))
        rc = err_set(e, REFRACT_E_INVALID_FIELD,
                     "samples, seed: only with \"mode\": \"reference\" (the path tracer's paths "
                     "per pixel and its random streams); the fast renderer takes its samples "
                     "from the scene's render settings");
    if (rc == REFRACT_E_OK)
        rc = jr_int(root, "", "samples", false, samples, 1, max_samples, &samples, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(root, "", "seed", false, 1.0, 0.0, 4294967295.0, &seed, e);
    if (rc == REFRACT_E_OK && seed != floor(seed))
        rc = err_set(e, REFRACT_E_INVALID_FIELD,
                     "seed: expected an integer in 0..4294967295, got %g", seed);
    if (rc != REFRACT_E_OK)
        return rc;
    base.reference_samples = mode == 1 ? samples : 0;
    base.reference_seed = (uint64_t)seed;
    struct job_frame def;
    rc = read_image(root, "", lim, &base, &def, e);
    if (rc != REFRACT_E_OK)
        return rc;
    const cJSON *list = cJSON_GetObjectItemCaseSensitive(root, "frames");
    const cJSON *turn = cJSON_GetObjectItemCaseSensitive(root, "turntable");
    const cJSON *path = cJSON_GetObjectItemCaseSensitive(root, "light_path");
    int given = (list != NULL) + (turn != NULL) + (path != NULL);
    if (given != 1)
        return err_set(e, given ? REFRACT_E_INVALID_FIELD : REFRACT_E_MISSING_FIELD,
                       "a job needs exactly one of \"frames\" (a list of frames), \"turntable\""
                       " or \"light_path\" (generators)%s",
                       given ? "; it has more than one" : "");
    if (list)
        return expand_list(list, s, lim, &def, frames, count, e);
    if (path)
        return expand_light_path(path, s, lim, &def, frames, count, e);
    return expand_turntable(turn, lim, &def, frames, count, e);
}

bool job_format_sniff(const void *bytes, size_t len, enum job_format *out)
{
    const unsigned char *b = bytes;
    if (len >= 8 && memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0)
        *out = JOB_FORMAT_PNG;
    else if (len >= 3 && b[0] == 0xff && b[1] == 0xd8 && b[2] == 0xff)
        *out = JOB_FORMAT_JPEG;
    else if (len >= 4 && memcmp(b, "\x76\x2f\x31\x01", 4) == 0)
        *out = JOB_FORMAT_EXR;
    else
        return false;
    return true;
}

const char *job_format_content_type(enum job_format f)
{
    return f == JOB_FORMAT_EXR ? "image/x-exr" : f == JOB_FORMAT_JPEG ? "image/jpeg" : "image/png";
}

const char *job_format_extension(enum job_format f)
{
    return f == JOB_FORMAT_EXR ? "exr" : f == JOB_FORMAT_JPEG ? "jpg" : "png";
}
