/*
 * scene_parse_field.c - one channel of one object: a FIELD is a VALUE, a LAYER object,
 * or an array of them (docs/scenes.md, "Fields and layers").
 *
 * A VALUE is a number (ior and anisotropy; grey for the RGB channels) or, for
 * attenuation, emission, opaque and scattering, an array of 3 numbers. An array of numbers
 * only is therefore one RGB VALUE in those channels, and any other array is a list of
 * layers. A LAYER object has exactly one of the keys "shape", "profile", "volume", which
 * decides the keys it may carry.
 *
 * Values are stored as 4 doubles: (n, 0, 0, 0) for ior, (g, 0, 0, 0) for anisotropy (both
 * evaluate to 1 float per voxel), (r, g, b, 0) for attenuation, emission and scattering and
 * (r, g, b, 1) for opaque, so that the layering rule is one blend for every channel.
 *
 * Lathe polygons are checked here (simple, non-degenerate), which is O(points^2); with
 * the default max_profile_points of 1024 that is half a million segment tests, a few
 * milliseconds, paid once per upload.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json_read.h"
#include "scene_parse_internal.h"

/* Range of one component of a VALUE, per channel. */
static const double value_max[SCENE_CH_COUNT] = {5.0, 1e5, 1e6, 1.0, 1e5, 0.99};
static const double value_min[SCENE_CH_COUNT] = {0.2, 0.0, 0.0, 0.0, 0.0, -0.99};

/* ior and anisotropy hold one number per voxel; the others RGB. */
static bool scalar_channel(enum scene_channel ch)
{
    return scene_channel_components(ch) == 1;
}

static const cJSON *member(const cJSON *obj, const char *key)
{
    return cJSON_IsObject(obj) ? cJSON_GetObjectItemCaseSensitive(obj, key) : NULL;
}

static bool is_number_array(const cJSON *item)
{
    if (!cJSON_IsArray(item) || item->child == NULL)
        return false;
    for (const cJSON *c = item->child; c != NULL; c = c->next) {
        if (!cJSON_IsNumber(c))
            return false;
    }
    return true;
}

static bool is_value(const cJSON *item, enum scene_channel ch)
{
    return cJSON_IsNumber(item) || (!scalar_channel(ch) && is_number_array(item));
}

static const char *value_rule(enum scene_channel ch, char *buf, size_t size)
{
    if (ch == SCENE_CH_IOR)
        snprintf(buf, size, "a refractive index in 0.2..5");
    else if (ch == SCENE_CH_ANISOTROPY)
        snprintf(buf, size, "a Henyey-Greenstein g in -0.99..0.99");
    else
        snprintf(buf, size, "a number or [r, g, b], each in 0..%.15g", value_max[ch]);
    return buf;
}

/* Reads a VALUE of channel ch into v[4] (see the file comment for the layout). */
static enum refract_code parse_value(const cJSON *item, const char *path, enum scene_channel ch,
                                     double v[4], struct err *e)
{
    double lo = value_min[ch], hi = value_max[ch];
    enum refract_code rc;
    v[1] = v[2] = v[3] = 0.0;
    if (cJSON_IsNumber(item)) {
        rc = jr_check_number(item, path, lo, false, hi, &v[0], e);
        if (!scalar_channel(ch))
            v[1] = v[2] = v[0];
    } else if (!scalar_channel(ch) && cJSON_IsArray(item) && cJSON_GetArraySize(item) == 3) {
        rc = REFRACT_E_OK;
        for (int i = 0; i < 3 && rc == REFRACT_E_OK; i++) {
            char p[256];
            rc = jr_check_number(cJSON_GetArrayItem(item, i), jr_path_index(p, sizeof p, path, i),
                                 lo, false, hi, &v[i], e);
        }
    } else {
        char rule[100], got[80];
        return err_set(e, REFRACT_E_INVALID_FIELD, "%s: expected %s, got %s", path,
                       value_rule(ch, rule, sizeof rule), jr_describe(item, got, sizeof got));
    }
    if (ch == SCENE_CH_OPAQUE)
        v[3] = 1.0; /* full coverage wherever the value applies */
    return rc;
}

/* A VALUE under key in a layer object; absent is MISSING_FIELD when required. */
static enum refract_code value_member(const cJSON *obj, const char *path, const char *key,
                                      enum scene_channel ch, double v[4], struct err *e)
{
    const cJSON *item = member(obj, key);
    if (item == NULL)
        return err_set(e, REFRACT_E_MISSING_FIELD, "%s: missing required field \"%s\"", path, key);
    char p[256];
    return parse_value(item, jr_path(p, sizeof p, path, key), ch, v, e);
}

/* ---- shapes ---- */

static const char *const shape_names[] = {
    "sphere", "box", "rounded_box", "cylinder", "lathe", "text", "bumpy_sphere", "mesh", NULL};
static const char *const axis_names[] = {"x", "y", "z", NULL};

/* Keys of each shape besides "shape", "inside" and "outside". */
static const char *const shape_keys[][6] = {
    [SCENE_SHAPE_SPHERE] = {"center", "radius", NULL},
    [SCENE_SHAPE_BOX] = {"center", "size", NULL},
    [SCENE_SHAPE_ROUNDED_BOX] = {"center", "size", "radius", NULL},
    [SCENE_SHAPE_CYLINDER] = {"center", "radius", "height", "axis", NULL},
    [SCENE_SHAPE_LATHE] = {"base", "axis", "profile", NULL},
    [SCENE_SHAPE_TEXT] = {"text", "center", "height", "depth", NULL},
    [SCENE_SHAPE_BUMPY_SPHERE] = {"center", "radius", "bump_amplitude", "bump_frequency", NULL},
    [SCENE_SHAPE_MESH] = {"mesh", "center", "scale", "rotate", NULL},
};

const char *const *scene_shape_keys(enum scene_shape_kind kind)
{
    return shape_keys[kind];
}

/* An array of 3 numbers, each > 0 and <= SCENE_COORD_MAX (box edge lengths). */
static enum refract_code positive_vec3(const cJSON *obj, const char *path, const char *key,
                                       vec3 *out, struct err *e)
{
    const cJSON *item = member(obj, key);
    char p[256], got[80];
    jr_path(p, sizeof p, path, key);
    if (item == NULL)
        return err_set(e, REFRACT_E_MISSING_FIELD, "%s: missing required field \"%s\"", path, key);
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 3)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected an array of 3 numbers > 0 and <= 1000000, got %s", p,
                       jr_describe(item, got, sizeof got));
    double v[3];
    for (int i = 0; i < 3; i++) {
        char pi[256];
        enum refract_code rc =
            jr_check_number(cJSON_GetArrayItem(item, i), jr_path_index(pi, sizeof pi, p, i), 0.0,
                            true, SCENE_COORD_MAX, &v[i], e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    *out = vec3_make(v[0], v[1], v[2]);
    return REFRACT_E_OK;
}

static double orient(const double a[2], const double b[2], const double c[2])
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

static bool on_segment(const double a[2], const double b[2], const double c[2])
{
    return fmin(a[0], b[0]) <= c[0] && c[0] <= fmax(a[0], b[0]) && fmin(a[1], b[1]) <= c[1] &&
           c[1] <= fmax(a[1], b[1]);
}

/* Closed segments ab and cd share at least one point. */
static bool segments_meet(const double a[2], const double b[2], const double c[2],
                          const double d[2])
{
    double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
        return true;
    return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) ||
           (o3 == 0 && on_segment(c, d, a)) || (o4 == 0 && on_segment(c, d, b));
}

/* The lathe polygon must be simple: no repeated consecutive points, no edge folding
 * back onto the previous one, no two non-adjacent edges touching, non-zero area. */
static enum refract_code check_polygon(double (*pt)[2], size_t n, const char *path, struct err *e)
{
    double area2 = 0.0;
    for (size_t i = 0; i < n; i++) {
        const double *a = pt[i], *b = pt[(i + 1) % n], *c = pt[(i + 2) % n];
        area2 += a[0] * b[1] - b[0] * a[1];
        if (a[0] == b[0] && a[1] == b[1])
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s: points %zu and %zu are the same [%g, %g]; remove one", path, i,
                           (i + 1) % n, a[0], a[1]);
        double dot = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]);
        if (orient(a, b, c) == 0 && dot < 0)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s: the edge after point %zu folds back onto the edge before it; "
                           "the polygon must be simple",
                           path, (i + 1) % n);
    }
    for (size_t i = 0; i < n; i++) {
        for (size_t j = i + 2; j < n; j++) {
            if (i == 0 && j == n - 1)
                continue; /* adjacent through the implicit closing edge */
            if (segments_meet(pt[i], pt[(i + 1) % n], pt[j], pt[(j + 1) % n]))
                return err_set(e, REFRACT_E_INVALID_FIELD,
                               "%s: edge %zu-%zu crosses or touches edge %zu-%zu; the polygon "
                               "must be simple (the closing edge from the last point to the "
                               "first is implicit)",
                               path, i, (i + 1) % n, j, (j + 1) % n);
        }
    }
    if (area2 == 0.0)
        return err_set(e, REFRACT_E_INVALID_FIELD, "%s: the polygon has zero area", path);
    return REFRACT_E_OK;
}

static enum refract_code parse_lathe_profile(const cJSON *obj, const char *path,
                                             const struct scene_limits *lim, struct scene_shape *s,
                                             struct err *e)
{
    const cJSON *arr = member(obj, "profile");
    char p[256], got[80];
    jr_path(p, sizeof p, path, "profile");
    if (arr == NULL)
        return err_set(e, REFRACT_E_MISSING_FIELD, "%s: missing required field \"profile\"", path);
    int n = cJSON_IsArray(arr) ? cJSON_GetArraySize(arr) : -1;
    if (n > lim->max_profile_points) {
        char given[40];
        snprintf(given, sizeof given, "%d points", n);
        return scene_limit_error(e, p, given, "max_profile_points", lim->max_profile_points,
                                 "--max-profile-points");
    }
    if (n < 3)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected an array of 3..%d [r, h] points, got %s", p,
                       lim->max_profile_points, jr_describe(arr, got, sizeof got));
    s->profile = calloc((size_t)n, sizeof *s->profile);
    if (s->profile == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "%s: out of memory for %d points", p, n);
    s->profile_count = (size_t)n;
    int i = 0;
    for (const cJSON *it = arr->child; it != NULL; it = it->next, i++) {
        char pi[256], pc[256];
        jr_path_index(pi, sizeof pi, p, i);
        if (!cJSON_IsArray(it) || cJSON_GetArraySize(it) != 2)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s: expected a point [r, h] (r >= 0: distance from the axis, h: "
                           "height along it), got %s",
                           pi, jr_describe(it, got, sizeof got));
        enum refract_code rc = jr_check_number(it->child, jr_path_index(pc, sizeof pc, pi, 0), 0.0,
                                               false, SCENE_COORD_MAX, &s->profile[i][0], e);
        if (rc == REFRACT_E_OK)
            rc = jr_check_number(it->child->next, jr_path_index(pc, sizeof pc, pi, 1),
                                 -SCENE_COORD_MAX, false, SCENE_COORD_MAX, &s->profile[i][1], e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    return check_polygon(s->profile, s->profile_count, p, e);
}

static enum refract_code parse_text(const cJSON *obj, const char *path,
                                    const struct scene_limits *lim, struct scene_shape *s,
                                    struct err *e)
{
    const cJSON *t = member(obj, "text");
    char p[256], got[80];
    jr_path(p, sizeof p, path, "text");
    if (t == NULL)
        return err_set(e, REFRACT_E_MISSING_FIELD, "%s: missing required field \"text\"", path);
    if (!cJSON_IsString(t) || t->valuestring[0] == '\0')
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected a string of 1..%d printable ASCII characters, got %s", p,
                       lim->max_text_length, jr_describe(t, got, sizeof got));
    size_t n = strlen(t->valuestring);
    if (n > (size_t)lim->max_text_length) {
        char given[40];
        snprintf(given, sizeof given, "%zu characters", n);
        return scene_limit_error(e, p, given, "max_text_length", lim->max_text_length,
                                 "--max-text-length");
    }
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)t->valuestring[i];
        if (c < 0x20 || c > 0x7e)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s: character %zu (byte 0x%02x) is not printable ASCII "
                           "(0x20..0x7E); the built-in font has glyphs for those only",
                           p, i, c);
    }
    s->text = malloc(n + 1);
    if (s->text == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "%s: out of memory", p);
    memcpy(s->text, t->valuestring, n + 1);
    return REFRACT_E_OK;
}

static bool valid_volume_name(const char *s);

/* A mesh shape: the upload's name and where its mesh space sits in the object,
 * p_object = center + scale * R(rotate) * p_mesh (the object transform's form). */
static enum refract_code parse_mesh_placement(const cJSON *o, const char *path,
                                              struct scene_shape *s, struct err *e)
{
    static const char *const rot_keys[] = {"axis", "angle_deg", NULL};
    const cJSON *name = member(o, "mesh");
    char p[256], got[80];
    if (name == NULL)
        return err_set(e, REFRACT_E_MISSING_FIELD,
                       "%s: missing required field \"mesh\" (the name given to POST "
                       "/v1/scenes/{id}/meshes?name=NAME)",
                       path);
    if (!cJSON_IsString(name) || !valid_volume_name(name->valuestring))
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected a mesh name of 1..%d characters from A-Z a-z 0-9 _ -, got %s",
                       jr_path(p, sizeof p, path, "mesh"), SCENE_VOLUME_NAME_MAX - 1,
                       jr_describe(name, got, sizeof got));
    snprintf(s->mesh, sizeof s->mesh, "%s", name->valuestring);
    double scale = 1.0, angle = 0.0;
    vec3 axis = {0, 1, 0};
    enum refract_code rc =
        jr_number_gt(o, path, "scale", false, 1.0, 0.0, SCENE_COORD_MAX, &scale, e);
    const cJSON *r = member(o, "rotate");
    jr_path(p, sizeof p, path, "rotate");
    if (rc == REFRACT_E_OK && r != NULL) {
        rc = jr_check_object(r, p, rot_keys, e);
        if (rc == REFRACT_E_OK)
            rc = jr_direction(r, p, "axis", true, axis, &axis, e);
        if (rc == REFRACT_E_OK)
            rc = jr_number(r, p, "angle_deg", true, 0.0, -3600.0, 3600.0, &angle, e);
    }
    s->object_from_mesh = xform_make(s->center, axis, angle, scale);
    return rc;
}

/* The geometry keys of a shape (everything except shape, inside, outside). */
enum refract_code scene_parse_geometry(const cJSON *o, const char *path,
                                       const struct scene_limits *lim, struct scene_shape *s,
                                       struct err *e)
{
    const double m = SCENE_COORD_MAX;
    const vec3 zero = {0, 0, 0};
    enum refract_code rc = REFRACT_E_OK;
    int axis = 1;
    if (s->kind != SCENE_SHAPE_LATHE)
        rc = jr_vec3(o, path, "center", false, zero, -m, m, &s->center, e);
    switch (s->kind) {
    case SCENE_SHAPE_PLANE:
        break; /* surfaces only: scene_parse_surface.c reads its point and normal */
    case SCENE_SHAPE_SPHERE:
        if (rc == REFRACT_E_OK)
            rc = jr_number_gt(o, path, "radius", true, 0.0, 0.0, m, &s->radius, e);
        break;
    case SCENE_SHAPE_BUMPY_SPHERE:
        if (rc == REFRACT_E_OK)
            rc = jr_number_gt(o, path, "radius", true, 0.0, 0.0, m, &s->radius, e);
        /* a <= R / 2 keeps r(theta, phi) >= R / 2 > 0: the surface stays star-shaped. */
        if (rc == REFRACT_E_OK)
            rc = jr_number(o, path, "bump_amplitude", false, 0.1 * s->radius, 0.0, 0.5 * s->radius,
                           &s->bump_amplitude, e);
        if (rc == REFRACT_E_OK)
            rc = jr_int(o, path, "bump_frequency", false, 6, 1, 32, &s->bump_frequency, e);
        break;
    case SCENE_SHAPE_BOX:
        if (rc == REFRACT_E_OK)
            rc = positive_vec3(o, path, "size", &s->size, e);
        break;
    case SCENE_SHAPE_ROUNDED_BOX:
        if (rc == REFRACT_E_OK)
            rc = positive_vec3(o, path, "size", &s->size, e);
        if (rc == REFRACT_E_OK)
            rc = jr_number(o, path, "radius", true, 0.0, 0.0, m, &s->radius, e);
        if (rc == REFRACT_E_OK) {
            double half = 0.5 * fmin(s->size.x, fmin(s->size.y, s->size.z));
            if (s->radius > half)
                rc = err_set(e, REFRACT_E_INVALID_FIELD,
                             "%s.radius: the corner radius %g is more than half the smallest "
                             "size (%g); use a radius in 0..%g",
                             path, s->radius, half, half);
        }
        break;
    case SCENE_SHAPE_CYLINDER:
        if (rc == REFRACT_E_OK)
            rc = jr_number_gt(o, path, "radius", true, 0.0, 0.0, m, &s->radius, e);
        if (rc == REFRACT_E_OK)
            rc = jr_number_gt(o, path, "height", true, 0.0, 0.0, m, &s->height, e);
        if (rc == REFRACT_E_OK)
            rc = jr_enum(o, path, "axis", false, 1, axis_names, &axis, e);
        break;
    case SCENE_SHAPE_LATHE:
        rc = jr_vec3(o, path, "base", false, zero, -m, m, &s->base, e);
        if (rc == REFRACT_E_OK)
            rc = jr_enum(o, path, "axis", false, 1, axis_names, &axis, e);
        if (rc == REFRACT_E_OK)
            rc = parse_lathe_profile(o, path, lim, s, e);
        break;
    case SCENE_SHAPE_TEXT:
        if (rc == REFRACT_E_OK)
            rc = parse_text(o, path, lim, s, e);
        if (rc == REFRACT_E_OK)
            rc = jr_number_gt(o, path, "height", true, 0.0, 0.0, m, &s->height, e);
        if (rc == REFRACT_E_OK)
            rc = jr_number_gt(o, path, "depth", true, 0.0, 0.0, m, &s->depth, e);
        break;
    case SCENE_SHAPE_MESH:
        if (rc == REFRACT_E_OK)
            rc = parse_mesh_placement(o, path, s, e);
        break;
    }
    s->axis = axis;
    return rc;
}

static enum refract_code parse_shape_layer(const cJSON *o, const char *path, enum scene_channel ch,
                                           const struct scene_parse_ctx *ctx, struct scene_layer *l,
                                           struct err *e)
{
    int kind;
    enum refract_code rc = jr_enum(o, path, "shape", true, 0, shape_names, &kind, e);
    if (rc != REFRACT_E_OK)
        return rc;
    if (ch == SCENE_CH_OPAQUE && member(o, "outside") != NULL)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s.outside: not allowed in opaque layers: an opaque shape covers only "
                       "its inside, and what lies outside keeps the previous layers' value; "
                       "remove \"outside\"",
                       path);
    const char *allowed[10];
    size_t n = 0;
    allowed[n++] = "shape";
    for (size_t i = 0; shape_keys[kind][i] != NULL; i++)
        allowed[n++] = shape_keys[kind][i];
    allowed[n++] = "inside";
    if (ch != SCENE_CH_OPAQUE)
        allowed[n++] = "outside";
    allowed[n] = NULL;
    rc = jr_check_object(o, path, allowed, e);
    if (rc != REFRACT_E_OK)
        return rc;
    l->kind = SCENE_LAYER_SHAPE;
    l->shape.kind = (enum scene_shape_kind)kind;
    rc = scene_parse_geometry(o, path, ctx->limits, &l->shape, e);
    if (rc == REFRACT_E_OK)
        rc = value_member(o, path, "inside", ch, l->inside, e);
    if (rc == REFRACT_E_OK && member(o, "outside") != NULL) {
        l->has_outside = true;
        rc = value_member(o, path, "outside", ch, l->outside, e);
    }
    return rc;
}

/* A bare shape (the "region" of a particle medium, scene_parse_particles.c): "shape" and
 * its geometry keys only. */
enum refract_code scene_parse_region(const cJSON *o, const char *path,
                                     const struct scene_parse_ctx *ctx, struct scene_shape *out,
                                     struct err *e)
{
    int kind;
    enum refract_code rc = jr_enum(o, path, "shape", true, 0, shape_names, &kind, e);
    if (rc != REFRACT_E_OK)
        return rc;
    const char *allowed[10];
    size_t n = 0;
    allowed[n++] = "shape";
    for (size_t i = 0; shape_keys[kind][i] != NULL; i++)
        allowed[n++] = shape_keys[kind][i];
    allowed[n] = NULL;
    rc = jr_check_object(o, path, allowed, e);
    if (rc != REFRACT_E_OK)
        return rc;
    out->kind = (enum scene_shape_kind)kind;
    return scene_parse_geometry(o, path, ctx->limits, out, e);
}

/* ---- GRIN profiles (ior only) ---- */

static const char *const profile_keys[][6] = {
    [GRIN_LUNEBURG] = {"profile", "center", "radius", NULL},
    [GRIN_MAXWELL_FISHEYE] = {"profile", "center", "radius", "n0", NULL},
    [GRIN_LINEAR] = {"profile", "center", "n0", "gradient", NULL},
    [GRIN_GAUSSIAN] = {"profile", "center", "n_peak", "n_out", "sigma", NULL},
};

/* n = n0 + gradient . (x - center) is affine, so its extremes over the bounds are at
 * corners; every corner must keep n within the ior range. */
static enum refract_code check_linear(const struct grin_profile *g, const char *path,
                                      const struct scene_parse_ctx *ctx, struct err *e)
{
    for (int c = 0; c < 8; c++) {
        vec3 p = {(c & 1) ? ctx->bounds_max.x : ctx->bounds_min.x,
                  (c & 2) ? ctx->bounds_max.y : ctx->bounds_min.y,
                  (c & 4) ? ctx->bounds_max.z : ctx->bounds_min.z};
        double n = grin_ior(g, p, NULL);
        if (!(n >= value_min[SCENE_CH_IOR] && n <= value_max[SCENE_CH_IOR]))
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s.gradient: the linear profile reaches n = %g at the bounds corner "
                           "[%g, %g, %g]; n must stay within 0.2..5 inside the object's bounds",
                           path, n, p.x, p.y, p.z);
    }
    return REFRACT_E_OK;
}

static enum refract_code parse_profile_layer(const cJSON *o, const char *path,
                                             enum scene_channel ch,
                                             const struct scene_parse_ctx *ctx,
                                             struct scene_layer *l, struct err *e)
{
    static const char *const names[] = {"luneburg", "maxwell_fisheye", "linear", "gaussian", NULL};
    if (ch != SCENE_CH_IOR)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: GRIN profiles apply only to ior; use a value, shape or volume layer "
                       "in %s",
                       path, scene_channel_name(ch));
    int kind;
    enum refract_code rc = jr_enum(o, path, "profile", true, 0, names, &kind, e);
    if (rc == REFRACT_E_OK)
        rc = jr_check_object(o, path, profile_keys[kind], e);
    if (rc != REFRACT_E_OK)
        return rc;
    const double m = SCENE_COORD_MAX;
    struct grin_profile *g = &l->profile;
    l->kind = SCENE_LAYER_PROFILE;
    g->kind = (enum grin_kind)kind;
    rc = jr_vec3(o, path, "center", false, vec3_make(0, 0, 0), -m, m, &g->center, e);
    switch (g->kind) {
    case GRIN_LUNEBURG:
    case GRIN_MAXWELL_FISHEYE:
        if (rc == REFRACT_E_OK)
            rc = jr_number_gt(o, path, "radius", true, 0.0, 0.0, m, &g->radius, e);
        if (rc == REFRACT_E_OK && g->kind == GRIN_MAXWELL_FISHEYE)
            rc = jr_number(o, path, "n0", false, 2.0, 0.2, 5.0, &g->n0, e);
        break;
    case GRIN_LINEAR:
        if (rc == REFRACT_E_OK)
            rc = jr_number(o, path, "n0", false, 1.0, 0.2, 5.0, &g->n0, e);
        if (rc == REFRACT_E_OK)
            rc = jr_vec3(o, path, "gradient", true, vec3_make(0, 0, 0), -m, m, &g->gradient, e);
        if (rc == REFRACT_E_OK)
            rc = check_linear(g, path, ctx, e);
        break;
    case GRIN_GAUSSIAN:
        if (rc == REFRACT_E_OK)
            rc = jr_number(o, path, "n_peak", true, 0.0, 0.2, 5.0, &g->n_peak, e);
        if (rc == REFRACT_E_OK)
            rc = jr_number(o, path, "n_out", false, ctx->ambient_ior, 0.2, 5.0, &g->n_out, e);
        if (rc == REFRACT_E_OK)
            rc = jr_number_gt(o, path, "sigma", true, 0.0, 0.0, m, &g->sigma, e);
        break;
    }
    return rc;
}

/* ---- uploaded volumes ---- */

static bool valid_volume_name(const char *s)
{
    size_t n = strlen(s);
    if (n == 0 || n >= SCENE_VOLUME_NAME_MAX)
        return false;
    for (size_t i = 0; i < n; i++) {
        char c = s[i];
        bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                  c == '_' || c == '-';
        if (!ok)
            return false;
    }
    return true;
}

static enum refract_code parse_volume_layer(const cJSON *o, const char *path, struct scene_layer *l,
                                            struct err *e)
{
    static const char *const keys[] = {"volume", "scale", "offset", NULL};
    enum refract_code rc = jr_check_object(o, path, keys, e);
    if (rc != REFRACT_E_OK)
        return rc;
    const cJSON *name = member(o, "volume");
    if (!cJSON_IsString(name) || !valid_volume_name(name->valuestring)) {
        char p[256], got[80];
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected a volume name of 1..%d characters from A-Z a-z 0-9 _ -, "
                       "got %s",
                       jr_path(p, sizeof p, path, "volume"), SCENE_VOLUME_NAME_MAX - 1,
                       jr_describe(name, got, sizeof got));
    }
    l->kind = SCENE_LAYER_VOLUME;
    snprintf(l->volume, sizeof l->volume, "%s", name->valuestring);
    rc = jr_number(o, path, "scale", false, 1.0, -SCENE_COORD_MAX, SCENE_COORD_MAX,
                   &l->volume_scale, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(o, path, "offset", false, 0.0, -SCENE_COORD_MAX, SCENE_COORD_MAX,
                       &l->volume_offset, e);
    return rc;
}

/* ---- layers and fields ---- */

/* The kind of a layer object is decided by its keys: "shape" makes a shape layer (and
 * a lathe's "profile" key is then its polygon), otherwise "profile" makes a GRIN
 * profile layer, otherwise "volume" a volume layer. Keys that belong to another kind
 * are then reported by jr_check_object as unknown, with the allowed list. */
static enum refract_code parse_layer_object(const cJSON *o, const char *path, enum scene_channel ch,
                                            const struct scene_parse_ctx *ctx,
                                            struct scene_layer *l, struct err *e)
{
    bool shape = member(o, "shape") != NULL, profile = member(o, "profile") != NULL;
    bool volume = member(o, "volume") != NULL;
    if (volume && (shape || profile))
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: a layer has exactly one of \"shape\", \"profile\", \"volume\"; "
                       "this one has both \"%s\" and \"volume\"",
                       path, shape ? "shape" : "profile");
    if (shape)
        return parse_shape_layer(o, path, ch, ctx, l, e);
    if (profile)
        return parse_profile_layer(o, path, ch, ctx, l, e);
    if (volume)
        return parse_volume_layer(o, path, l, e);
    return err_set(e, REFRACT_E_MISSING_FIELD,
                   "%s: a layer object needs one of \"shape\", \"profile\" or \"volume\" (or "
                   "write a plain value)",
                   path);
}

static enum refract_code parse_layer(const cJSON *item, const char *path, enum scene_channel ch,
                                     const struct scene_parse_ctx *ctx, struct scene_layer *l,
                                     struct err *e)
{
    if (cJSON_IsObject(item))
        return parse_layer_object(item, path, ch, ctx, l, e);
    if (is_value(item, ch)) {
        l->kind = SCENE_LAYER_CONSTANT;
        return parse_value(item, path, ch, l->inside, e);
    }
    char rule[100], got[80];
    return err_set(e, REFRACT_E_INVALID_FIELD,
                   "%s: expected a value (%s) or a layer object, got %s", path,
                   value_rule(ch, rule, sizeof rule), jr_describe(item, got, sizeof got));
}

enum refract_code scene_parse_field(const cJSON *item, const char *path, enum scene_channel ch,
                                    const struct scene_parse_ctx *ctx, struct scene_field *out,
                                    struct err *e)
{
    bool list = cJSON_IsArray(item) && !is_value(item, ch);
    int n = list ? cJSON_GetArraySize(item) : 1;
    if (list && n == 0) {
        char rule[100];
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected a value (%s), a layer object, or an array of 1..%d layers, "
                       "got an empty array",
                       path, value_rule(ch, rule, sizeof rule), ctx->limits->max_layers);
    }
    if (n > ctx->limits->max_layers) {
        char given[40];
        snprintf(given, sizeof given, "%d layers", n);
        return scene_limit_error(e, path, given, "max_layers", ctx->limits->max_layers,
                                 "--max-layers");
    }
    out->layers = calloc((size_t)n, sizeof *out->layers);
    if (out->layers == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "%s: out of memory for %d layers", path, n);
    out->count = (size_t)n;
    if (!list)
        return parse_layer(item, path, ch, ctx, &out->layers[0], e);
    int i = 0;
    for (const cJSON *it = item->child; it != NULL; it = it->next, i++) {
        char p[256];
        enum refract_code rc =
            parse_layer(it, jr_path_index(p, sizeof p, path, i), ch, ctx, &out->layers[i], e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    return REFRACT_E_OK;
}

void scene_field_fini(struct scene_field *f)
{
    for (size_t i = 0; i < f->count; i++) {
        free(f->layers[i].shape.profile);
        free(f->layers[i].shape.text);
    }
    free(f->layers);
    f->layers = NULL;
    f->count = 0;
}
