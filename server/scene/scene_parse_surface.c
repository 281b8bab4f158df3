/*
 * scene_parse_surface.c - the scene document's "surfaces" (docs/scenes.md "Surfaces"):
 * exact surfaces bounding constant media, with nesting priorities.
 *
 * Each surface is a shape of the kinds that have an exact intersection (sphere, box,
 * rounded_box, cylinder, lathe, mesh: the same keys as the voxel shapes; plane: a point and a
 * normal), an optional transform, a priority and a medium. Rules, each refused with the
 * JSON path when broken:
 *   - priority defaults to the surface's position in the list, so a later surface wins
 *     where solids overlap (as later layers override earlier ones in a field);
 *   - two surfaces of equal priority must not overlap (their world boxes are disjoint;
 *     for meshes, whose boxes come with the upload, equal priorities are refused);
 *   - a medium is constants (ior, attenuation, emission) or names a voxel object
 *     ("object"), whose fields then fill the solid (a GRIN lens bounded by its exact
 *     sphere): the object's bounds cover the solid, it fills only that surface and is seen
 *     nowhere else ("bound"), it has no opaque embeddings, and the scene does not ask for
 *     the light simulator, whose wavefront does not bend inside surfaces yet;
 *   - voxel objects lie in the ambient medium: an object's world box must not overlap a
 *     surface's, except the surface the object fills.
 * The light simulator traces every kind (docs/lightsim.md "Surfaces"); a receiver must
 * not cut a mesh either, which only the light fields can check (the mesh's extent comes
 * with its upload).
 * The surfaces are stored sorted by priority, highest first (core/interface.h).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/geom/geom.h"
#include "json_read.h"
#include "scene_parse_internal.h"

static const cJSON *member(const cJSON *obj, const char *key)
{
    return cJSON_IsObject(obj) ? cJSON_GetObjectItemCaseSensitive(obj, key) : NULL;
}

/* Names of "shape" for surfaces, as enum scene_shape_kind values. */
static const char *const surface_shape_names[] = {"sphere", "box",  "cylinder",    "plane",
                                                  "lathe",  "mesh", "rounded_box", NULL};
static const enum scene_shape_kind surface_shape_kinds[] = {
    SCENE_SHAPE_SPHERE, SCENE_SHAPE_BOX,  SCENE_SHAPE_CYLINDER,   SCENE_SHAPE_PLANE,
    SCENE_SHAPE_LATHE,  SCENE_SHAPE_MESH, SCENE_SHAPE_ROUNDED_BOX};

static enum refract_code parse_rgb(const cJSON *o, const char *path, const char *key, double *out,
                                   struct err *e)
{
    vec3 v;
    enum refract_code rc = jr_vec3(o, path, key, false, vec3_make(0, 0, 0), 0.0, 1e6, &v, e);
    out[0] = v.x;
    out[1] = v.y;
    out[2] = v.z;
    return rc;
}

/* medium.object: the name of a voxel object whose fields fill the solid. */
static enum refract_code parse_medium_object(const cJSON *mo, const char *p, const struct scene *s,
                                             struct scene_medium *m, struct err *e)
{
    char got[80];
    const cJSON *name = member(mo, "object");
    static const char *const constants[] = {"ior", "attenuation", "emission", "scattering",
                                            "anisotropy"};
    for (size_t i = 0; i < 5; i++)
        if (member(mo, constants[i]) != NULL)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s.%s: not allowed with \"object\": the object's fields give the "
                           "medium's ior, attenuation and emission; remove \"%s\" or "
                           "\"object\"",
                           p, constants[i], constants[i]);
    if (!cJSON_IsString(name))
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s.object: expected the name of an object in \"objects\", got %s", p,
                       jr_describe(name, got, sizeof got));
    for (size_t k = 0; k < s->object_count; k++)
        if (strcmp(s->objects[k].name, name->valuestring) == 0) {
            m->has_object = true;
            m->object = (int)k;
            m->ior = 1.0;
            return REFRACT_E_OK;
        }
    char names[256] = "";
    size_t len = 0;
    for (size_t k = 0; k < s->object_count && len + 2 < sizeof names; k++)
        len += (size_t)snprintf(names + len, sizeof names - len, "%s\"%s\"", k ? ", " : "",
                                s->objects[k].name);
    return err_set(e, REFRACT_E_INVALID_FIELD, "%s.object: no object named \"%s\"; %s%s", p,
                   name->valuestring,
                   s->object_count ? "the objects are "
                                   : "the scene has no objects: add one to "
                                     "\"objects\"",
                   names);
}

static enum refract_code parse_medium(const cJSON *o, const char *path, const struct scene *s,
                                      struct scene_medium *m, struct err *e)
{
    static const char *const keys[] = {"ior",        "attenuation", "emission", "object",
                                       "scattering", "anisotropy",  NULL};
    char p[256];
    jr_path(p, sizeof p, path, "medium");
    const cJSON *mo = member(o, "medium");
    if (mo == NULL)
        return err_set(e, REFRACT_E_MISSING_FIELD,
                       "%s: missing required field \"medium\" (what fills the surface, e.g. "
                       "{\"ior\": 1.5} or {\"object\": \"lens\"})",
                       path);
    enum refract_code rc = jr_check_object(mo, p, keys, e);
    if (rc == REFRACT_E_OK && member(mo, "object") != NULL)
        return parse_medium_object(mo, p, s, m, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(mo, p, "ior", true, 1.0, 1.0, 5.0, &m->ior, e);
    if (rc == REFRACT_E_OK)
        rc = parse_rgb(mo, p, "attenuation", m->attenuation, e);
    if (rc == REFRACT_E_OK)
        rc = parse_rgb(mo, p, "emission", m->emission, e);
    if (rc == REFRACT_E_OK) /* extinction and in-scattering (scene.h) */
        rc = parse_rgb(mo, p, "scattering", m->scattering, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(mo, p, "anisotropy", false, 0.0, -0.99, 0.99, &m->anisotropy, e);
    return rc;
}

static enum refract_code parse_shape(const cJSON *o, const char *path,
                                     const struct scene_limits *lim, struct scene_surface *sf,
                                     struct err *e)
{
    const cJSON *shape = member(o, "shape");
    char got[80];
    if (cJSON_IsString(shape)) {
        const char *voxel_only[] = {"text", "bumpy_sphere"};
        for (size_t i = 0; i < 2; i++)
            if (strcmp(shape->valuestring, voxel_only[i]) == 0)
                return err_set(
                    e, REFRACT_E_INVALID_FIELD,
                    "%s.shape: \"%s\" has no exact surface; surfaces are sphere, box, "
                    "rounded_box, cylinder, plane, lathe or mesh (upload a mesh of it), or use "
                    "the shape in a voxel object's field",
                    path, shape->valuestring);
    }
    int which;
    enum refract_code rc = jr_enum(o, path, "shape", true, 0, surface_shape_names, &which, e);
    if (rc != REFRACT_E_OK)
        return rc;
    enum scene_shape_kind kind = surface_shape_kinds[which];
    const char *allowed[16];
    size_t n = 0;
    const char *common[] = {"name", "shape", "transform", "priority", "medium", "brdf"};
    for (size_t i = 0; i < 6; i++)
        allowed[n++] = common[i];
    if (kind == SCENE_SHAPE_PLANE) {
        allowed[n++] = "point";
        allowed[n++] = "normal";
    } else {
        const char *const *keys = scene_shape_keys(kind);
        for (size_t i = 0; keys[i] != NULL; i++)
            allowed[n++] = keys[i];
    }
    allowed[n] = NULL;
    rc = jr_check_object(o, path, allowed, e);
    if (rc != REFRACT_E_OK)
        return rc;
    sf->shape.kind = kind;
    if (kind == SCENE_SHAPE_PLANE) {
        rc = jr_vec3(o, path, "point", false, vec3_make(0, 0, 0), -SCENE_COORD_MAX, SCENE_COORD_MAX,
                     &sf->shape.center, e);
        if (rc == REFRACT_E_OK)
            rc = jr_direction(o, path, "normal", true, vec3_make(0, 1, 0), &sf->shape.normal, e);
        (void)got;
        return rc;
    }
    return scene_parse_geometry(o, path, lim, &sf->shape, e);
}

static enum refract_code parse_surface(const cJSON *o, const char *path, int index,
                                       const struct scene_limits *lim, const struct scene *s,
                                       struct scene_surface *sf, struct err *e)
{
    char got[80];
    if (!cJSON_IsObject(o))
        return err_set(e, REFRACT_E_INVALID_FIELD, "%s: expected an object, got %s", path,
                       jr_describe(o, got, sizeof got));
    char def_name[32];
    snprintf(def_name, sizeof def_name, "surface%d", index);
    sf->document_index = index;
    enum refract_code rc = parse_shape(o, path, lim, sf, e);
    if (rc == REFRACT_E_OK)
        rc = jr_string(o, path, "name", false, def_name, SCENE_NAME_MAX - 1, sf->name,
                       sizeof sf->name, e);
    if (rc == REFRACT_E_OK)
        rc = scene_parse_transform(o, path, &sf->world_from_object, e);
    if (rc == REFRACT_E_OK)
        rc = jr_int(o, path, "priority", false, index, 0, 1000000, &sf->priority, e);
    if (rc == REFRACT_E_OK)
        rc = parse_medium(o, path, s, &sf->medium, e);
    if (rc == REFRACT_E_OK)
        rc = scene_parse_brdf(o, path, &sf->brdf, e);
    return rc;
}

bool scene_surface_world_bounds(const struct scene_surface *sf, vec3 *lo, vec3 *hi)
{
    const struct scene_shape *sh = &sf->shape;
    if (sh->kind == SCENE_SHAPE_MESH)
        return false;
    if (sh->kind == SCENE_SHAPE_PLANE) {
        vec3 c = xform_point_to_world(&sf->world_from_object, sh->center);
        vec3 n = xform_dir_to_world(&sf->world_from_object, sh->normal);
        *lo = vec3_make(-INFINITY, -INFINITY, -INFINITY);
        *hi = vec3_make(INFINITY, INFINITY, INFINITY);
        for (int a = 0; a < 3; a++) {
            int b = (a + 1) % 3, k = (a + 2) % 3;
            if (fabs(vec3_get(n, b)) > 1e-12 || fabs(vec3_get(n, k)) > 1e-12)
                continue;
            if (vec3_get(n, a) > 0.0)
                vec3_set(hi, a, vec3_get(c, a));
            else
                vec3_set(lo, a, vec3_get(c, a));
        }
        return true;
    }
    vec3 a, b;
    if (!scene_shape_bounds(sh, &a, &b))
        return false;
    geom_world_box(&sf->world_from_object, a, b, lo, hi);
    return true;
}

static bool boxes_overlap(vec3 alo, vec3 ahi, vec3 blo, vec3 bhi)
{
    for (int k = 0; k < 3; k++)
        if (vec3_get(ahi, k) <= vec3_get(blo, k) || vec3_get(bhi, k) <= vec3_get(alo, k))
            return false;
    return true;
}

static int by_priority(const void *a, const void *b)
{
    const struct scene_surface *x = a, *y = b;
    if (x->priority != y->priority)
        return x->priority > y->priority ? -1 : 1;
    return x->document_index - y->document_index;
}

/* Does the object's world box contain the world box lo..hi (touching counts: a lens's
 * bounds +-1 around its sphere of radius 1)? Tolerance: rounding of the transforms. */
static bool box_covers(const struct scene_object *o, vec3 lo, vec3 hi)
{
    vec3 olo, ohi;
    geom_world_box(&o->world_from_object, o->bounds_min, o->bounds_max, &olo, &ohi);
    for (int k = 0; k < 3; k++) {
        double tol = 1e-9 * fmax(1.0, fmax(fabs(vec3_get(olo, k)), fabs(vec3_get(ohi, k))));
        if (!(vec3_get(lo, k) >= vec3_get(olo, k) - tol &&
              vec3_get(hi, k) <= vec3_get(ohi, k) + tol))
            return false;
    }
    return true;
}

/* The medium "object" form: each bound object fills exactly one surface whose solid its
 * bounds cover, and has no opaque embeddings (not modelled inside surfaces). Marks the
 * objects bound (after the sort, so bound_surface is the priority index). */
static enum refract_code bind_objects(struct scene *s, struct err *e)
{
    for (size_t i = 0; i < s->surface_count; i++) {
        const struct scene_surface *sf = &s->surfaces[i];
        if (!sf->medium.has_object)
            continue;
        struct scene_object *o = &s->objects[sf->medium.object];
        int d = sf->document_index;
        if (o->bound)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "surfaces[%d].medium.object: objects[%d] (\"%s\") already fills "
                           "surfaces[%d] (\"%s\"); an object fills one surface: give this "
                           "surface its own object",
                           d, sf->medium.object, o->name,
                           s->surfaces[o->bound_surface].document_index,
                           s->surfaces[o->bound_surface].name);
        vec3 lo, hi;
        if (sf->shape.kind == SCENE_SHAPE_MESH)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "surfaces[%d].medium.object: a mesh surface cannot be filled by an "
                           "object yet (its extent is known only with the upload, so the "
                           "object's cover cannot be checked); use a sphere, box, cylinder or "
                           "lathe surface, or constant \"ior\"",
                           d);
        if (!scene_surface_world_bounds(sf, &lo, &hi) || !isfinite(lo.x + lo.y + lo.z) ||
            !isfinite(hi.x + hi.y + hi.z))
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "surfaces[%d].medium.object: the %s's solid is unbounded, so no "
                           "object's bounds can cover it; bound the field by a sphere, box, "
                           "cylinder or lathe",
                           d, sf->shape.kind == SCENE_SHAPE_PLANE ? "plane" : "surface");
        if (!box_covers(o, lo, hi))
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "surfaces[%d].medium.object: objects[%d] (\"%s\")'s bounds do not "
                           "cover the surface's solid, which spans [%g, %g, %g]..[%g, %g, %g] "
                           "in world space; make the object's bounds (after its transform) "
                           "contain that box (touching it is fine)",
                           d, sf->medium.object, o->name, lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
        if (o->fields[SCENE_CH_OPAQUE].count > 0)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "objects[%d].opaque: objects[%d] (\"%s\") fills surfaces[%d], and "
                           "opaque embeddings are not modelled inside a surface; remove "
                           "\"opaque\" or the surface's \"object\"",
                           sf->medium.object, sf->medium.object, o->name, d);
        o->bound = true;
        o->bound_surface = (int)i;
    }
    return REFRACT_E_OK;
}

/* Voxels added on each side of a bound object's grid. */
#define BOUND_PAD_VOXELS 2

/* A bound object's grid grows by BOUND_PAD_VOXELS on each side, with the same voxel size
 * (so the voxel centres, and every sample inside the old bounds, stay where they were):
 * where its bounds touch its surface (a lens in bounds +-1 around its sphere of radius 1),
 * the trilinear samples of the last half voxel would otherwise be clamped at the bounds
 * face, and the continued field (scene_field_bound.c) needs voxels beyond the surface to
 * live in. The object is seen only inside its surface, so the larger bounds are invisible.
 * An axis already at the resolution limit keeps its grid (the march then takes n at the
 * face from |w|, docs/tracing.md "The rim"). After the rules, which see the document's
 * bounds; not counted against max_voxels (at most (1 + 4 / res)^3 more). */
static void pad_bound_objects(struct scene *s, const struct scene_limits *lim)
{
    for (size_t k = 0; k < s->object_count; k++) {
        struct scene_object *o = &s->objects[k];
        if (!o->bound)
            continue;
        vec3 vs = scene_object_voxel_size(o);
        for (int a = 0; a < 3; a++) {
            if (o->resolution[a] + 2 * BOUND_PAD_VOXELS > lim->max_resolution)
                continue;
            double pad = BOUND_PAD_VOXELS * vec3_get(vs, a);
            vec3_set(&o->bounds_min, a, vec3_get(o->bounds_min, a) - pad);
            vec3_set(&o->bounds_max, a, vec3_get(o->bounds_max, a) + pad);
            o->resolution[a] += 2 * BOUND_PAD_VOXELS;
        }
    }
}

static enum refract_code check_rules(const struct scene *s, struct err *e)
{
    for (size_t i = 0; i < s->surface_count; i++) {
        const struct scene_surface *a = &s->surfaces[i];
        vec3 alo, ahi;
        bool abox = scene_surface_world_bounds(a, &alo, &ahi);
        for (size_t j = i + 1; j < s->surface_count; j++) {
            const struct scene_surface *b = &s->surfaces[j];
            if (a->priority != b->priority)
                continue;
            vec3 blo, bhi;
            bool bbox = scene_surface_world_bounds(b, &blo, &bhi);
            if (!abox || !bbox || boxes_overlap(alo, ahi, blo, bhi))
                return err_set(e, REFRACT_E_INVALID_FIELD,
                               "surfaces[%d].priority: %d, the same as surfaces[%d] (\"%s\"), "
                               "and their solids may overlap%s; nesting priority decides which "
                               "medium fills an overlap, so give them different priorities "
                               "(the higher wins)",
                               b->document_index, b->priority, a->document_index, a->name,
                               (!abox || !bbox) ? " (a mesh's extent is known only with its upload)"
                                                : "");
        }
        if (!abox)
            continue;
        for (size_t k = 0; k < s->object_count; k++) {
            const struct scene_object *o = &s->objects[k];
            if (o->bound && o->bound_surface == (int)i)
                continue; /* it fills this surface */
            vec3 olo, ohi;
            geom_world_box(&o->world_from_object, o->bounds_min, o->bounds_max, &olo, &ohi);
            if (boxes_overlap(alo, ahi, olo, ohi))
                return err_set(e, REFRACT_E_INVALID_FIELD,
                               "surfaces[%d]: its solid may overlap objects[%zu] (\"%s\")'s "
                               "bounds; voxel objects must lie in the ambient medium outside "
                               "every surface but the one they fill: move one of them, or "
                               "let the object fill the surface (\"medium\": {\"object\": "
                               "\"%s\"})",
                               a->document_index, k, o->name, o->name);
        }
    }
    for (size_t k = 0; k < s->object_count; k++)
        if (scene_channel_used(&s->objects[k], SCENE_CH_SCATTERING)) {
            char path[48];
            snprintf(path, sizeof path, "objects[%zu].scattering", k);
            enum refract_code rc = scene_check_lightsim_surfaces(s, path, e);
            if (rc != REFRACT_E_OK)
                return rc;
        }
    for (size_t k = 0; k < s->surface_count; k++)
        if (scene_surface_scatters(&s->surfaces[k])) { /* it needs the light simulator too */
            char path[64];
            snprintf(path, sizeof path, "surfaces[%d].medium.scattering",
                     s->surfaces[k].document_index);
            enum refract_code rc = scene_check_lightsim_surfaces(s, path, e);
            if (rc != REFRACT_E_OK)
                return rc;
        }
    return REFRACT_E_OK;
}

/* What keeps photons from a scene (docs/photons.md "Not yet"), as the refusal of an
 * explicit "photons" (REFRACT_E_INVALID_FIELD in e) and *reason, a short sentence for the
 * "auto" rule; REFRACT_E_OK when photons can trace it. *optical tells whether some surface
 * changes light at all. */
static enum refract_code photon_obstacle(const struct scene *s, const char **reason,
                                         bool *optical_any, struct err *e)
{
    static const char use[] = "set receiver.caustics to \"volume\" (docs/photons.md \"Not yet\")";
    *optical_any = false;
    if (s->object_count > 0) {
        *reason = "a volume object: its index varies continuously, so the light simulator's "
                  "wavefront volume";
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "receiver.caustics: \"photons\" traces exact surfaces only, and "
                       "objects[0] (\"%s\") is a volume object; remove it or %s",
                       s->objects[0].name, use);
    }
    for (size_t k = 0; k < s->surface_count; k++) {
        const struct scene_surface *sf = &s->surfaces[k];
        const struct scene_medium *m = &sf->medium;
        if (m->has_object) {
            *reason = "a surface filled by a field (GRIN): the light simulator's wavefront "
                      "volume";
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "receiver.caustics: \"photons\" does not trace through a field "
                           "yet, and surfaces[%d].medium names the object \"%s\"; %s",
                           sf->document_index, s->objects[m->object].name, use);
        }
        if (scene_surface_scatters(sf)) {
            *reason = "a scattering medium: the light simulator's volume (photons do not "
                      "scatter yet)";
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "receiver.caustics: \"photons\" does not scatter photons in media "
                           "yet, and surfaces[%d].medium.scattering is not 0; %s",
                           sf->document_index, use);
        }
        bool optical = m->ior != s->ambient_ior || m->attenuation[0] > 0.0 ||
                       m->attenuation[1] > 0.0 || m->attenuation[2] > 0.0;
        *optical_any = *optical_any || optical;
        if (sf->shape.kind == SCENE_SHAPE_PLANE && optical) {
            *reason = "an infinite optical plane: the light simulator's volume (photons need "
                      "bounded surfaces)";
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "receiver.caustics: \"photons\" needs bounded surfaces, and "
                           "surfaces[%d] (\"%s\") is an infinite plane; use a box or %s",
                           sf->document_index, sf->name, use);
        }
    }
    *reason = *optical_any ? "exact surfaces of constant media: photons traced through them"
                           : "no surface changes light on its way to the receiver: direct "
                             "light only";
    return REFRACT_E_OK;
}

enum refract_code scene_check_photon_surfaces(const struct scene *s, struct err *e)
{
    const char *reason;
    bool optical;
    return photon_obstacle(s, &reason, &optical, e);
}

void scene_resolve_caustics(struct scene *s)
{
    struct scene_receiver *r = &s->receiver;
    if (!r->enabled || r->caustics != SCENE_CAUSTICS_AUTO)
        return;
    const char *reason;
    bool optical;
    struct err ignored = {0};
    if (photon_obstacle(s, &reason, &optical, &ignored) != REFRACT_E_OK)
        r->caustics = SCENE_CAUSTICS_VOLUME;
    else
        r->caustics = optical ? SCENE_CAUSTICS_PHOTONS : SCENE_CAUSTICS_NONE;
    if (r->caustics == SCENE_CAUSTICS_VOLUME &&
        scene_check_lightsim_surfaces(s, "receiver", &ignored) != REFRACT_E_OK) {
        /* Neither traces through a field-filled surface yet (issue 12): rather than refuse
         * the scene, its receiver gets direct light and shadows. */
        r->caustics = SCENE_CAUSTICS_NONE;
        reason = "a surface filled by a field (GRIN): neither photons nor the light "
                 "simulator trace through it yet, so direct light and shadows only";
    }
    r->caustics_reason = reason;
}

enum refract_code scene_check_lightsim_surfaces(const struct scene *s, const char *path,
                                                struct err *e)
{
    for (size_t k = 0; k < s->surface_count; k++)
        if (s->surfaces[k].medium.has_object)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s: needs the light simulator, whose wavefront does not bend by a "
                           "field inside a surface yet, and surfaces[%d].medium names the "
                           "object \"%s\" (docs/lightsim.md \"Surfaces\"); remove one of "
                           "them",
                           path, s->surfaces[k].document_index,
                           s->objects[s->surfaces[k].medium.object].name);
    return REFRACT_E_OK;
}

enum refract_code scene_parse_surfaces(const cJSON *arr, const struct scene_limits *lim,
                                       struct scene *s, struct err *e)
{
    char got[80];
    if (arr == NULL)
        return REFRACT_E_OK;
    int n = cJSON_IsArray(arr) ? cJSON_GetArraySize(arr) : -1;
    if (n < 0 || (n == 0 && s->object_count == 0))
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "surfaces: expected an array of 1..%d surfaces, got %s", SCENE_MAX_SURFACES,
                       jr_describe(arr, got, sizeof got));
    if (n > SCENE_MAX_SURFACES) {
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "surfaces: %d surfaces exceed the limit of %d per scene (a fixed limit: "
                       "a ray carries the set of solids it is inside as 32 bits); merge "
                       "surfaces into meshes",
                       n, SCENE_MAX_SURFACES);
    }
    if (n == 0)
        return REFRACT_E_OK;
    s->surfaces = calloc((size_t)n, sizeof *s->surfaces);
    if (s->surfaces == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "surfaces: out of memory");
    int i = 0;
    for (const cJSON *it = arr->child; it != NULL; it = it->next, i++) {
        char p[64];
        s->surface_count = (size_t)i + 1; /* so scene_destroy frees what this one owns */
        enum refract_code rc = parse_surface(it, jr_path_index(p, sizeof p, "surfaces", i), i, lim,
                                             s, &s->surfaces[i], e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    qsort(s->surfaces, s->surface_count, sizeof *s->surfaces, by_priority);
    enum refract_code rc = bind_objects(s, e);
    if (rc == REFRACT_E_OK)
        rc = check_rules(s, e);
    if (rc == REFRACT_E_OK)
        pad_bound_objects(s, lim);
    return rc;
}
