/*
 * scene_field.c - evaluates an object's channel at its voxel centres (the layering rule
 * of docs/scenes.md), plus the small queries about channels, voxels and volumes.
 *
 * The output is written layer by layer into the caller's buffer, which doubles as the
 * "previous value" of the layering rule, so evaluation allocates nothing and can fail
 * only on an uploaded volume that is missing or unusable. Shape layers visit only the
 * voxels within one voxel of the shape's bounding box and, along each row, skip runs of
 * voxels whose coverage is already known to be 0 or 1: shape SDFs are exact, hence
 * 1-Lipschitz, so a voxel at distance t from one with sdf = d has sdf within d +- t
 * (shapes.c; the bumpy sphere, whose SDF is an estimate, is evaluated at every voxel of
 * its box). That keeps a 128^3 lathe or text layer well under a second on one core.
 *
 * Mesh shape layers are voxelized by the mesh module (mesh_voxelize: generalized
 * winding numbers for the side, the distance for the same one-voxel edge) into a
 * coverage grid, then blended like any shape; that is the one allocation here. The mesh
 * remembers its last grid (mesh_voxelize_memo), so the other channels of the object
 * and the light simulator's fields copy it instead of voxelizing again.
 *
 * An object bound to a surface (docs/scenes.md "Surfaces", medium "object") has its field
 * continued beyond the surface afterwards (scene_field_bound.c), which allocates a mask.
 *
 * Not here: smoothing and gradients of the ior (the GPU module does those, tracing.md).
 */
#include "scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../mesh/mesh.h"

static const char *const channel_names[SCENE_CH_COUNT] = {"ior",    "attenuation", "emission",
                                                          "opaque", "scattering",  "anisotropy"};

/* Valid range of every component a channel stores; volume layers are clamped to it. */
static const double channel_min[SCENE_CH_COUNT] = {0.2, 0.0, 0.0, 0.0, 0.0, -0.99};
static const double channel_max[SCENE_CH_COUNT] = {5.0, 1e5, 1e6, 1.0, 1e5, 0.99};

int scene_channel_components(enum scene_channel ch)
{
    return (ch == SCENE_CH_IOR || ch == SCENE_CH_ANISOTROPY) ? 1 : 4;
}

const char *scene_channel_name(enum scene_channel ch)
{
    return (ch >= 0 && ch < SCENE_CH_COUNT) ? channel_names[ch] : "unknown";
}

bool scene_channel_used(const struct scene_object *obj, enum scene_channel ch)
{
    return ch >= 0 && ch < SCENE_CH_COUNT && obj->fields[ch].count > 0;
}

bool scene_ior_constant(const struct scene_object *obj)
{
    const struct scene_field *f = &obj->fields[SCENE_CH_IOR];
    for (size_t i = 0; i < f->count; i++)
        if (f->layers[i].kind != SCENE_LAYER_CONSTANT)
            return false;
    return true;
}

vec3 scene_object_voxel_size(const struct scene_object *obj)
{
    vec3 ext = vec3_sub(obj->bounds_max, obj->bounds_min);
    return vec3_make(ext.x / obj->resolution[0], ext.y / obj->resolution[1],
                     ext.z / obj->resolution[2]);
}

double scene_object_min_voxel(const struct scene_object *obj)
{
    vec3 vs = scene_object_voxel_size(obj);
    return fmin(vs.x, fmin(vs.y, vs.z));
}

/* ---- missing volumes ---- */

/* The volume name of layer k of channel ch of object i, or NULL for other layers. */
static const char *volume_at(const struct scene *s, size_t i, int ch, size_t k)
{
    const struct scene_layer *l = &s->objects[i].fields[ch].layers[k];
    return l->kind == SCENE_LAYER_VOLUME ? l->volume : NULL;
}

/* The name layer k of channel ch of object i gives (a volume's, a mesh's), or NULL. */
typedef const char *(*layer_name_fn)(const struct scene *s, size_t i, int ch, size_t k);
/* True when the scene's lookup finds `name`. */
typedef bool (*name_found_fn)(scene_volume_lookup_fn lookup, void *ctx, const char *name);

/* True when a layer before (i, ch, k), in document order, gives the same name. */
static bool seen_before(const struct scene *s, layer_name_fn name_at, size_t i, int ch, size_t k,
                        const char *name)
{
    for (size_t oi = 0; oi <= i; oi++) {
        for (int oc = 0; oc < SCENE_CH_COUNT; oc++) {
            for (size_t ok = 0; ok < s->objects[oi].fields[oc].count; ok++) {
                if (oi == i && oc == ch && ok == k)
                    return false;
                const char *other = name_at(s, oi, oc, ok);
                if (other != NULL && strcmp(other, name) == 0)
                    return true;
            }
        }
    }
    return false;
}

/* Counts the distinct names the layers give (name_at) that found() does not find, and
 * writes them comma-separated into buf (cut at buf_size). */
static int missing_names(const struct scene *s, layer_name_fn name_at, name_found_fn found,
                         scene_volume_lookup_fn lookup, void *ctx, char *buf, size_t buf_size)
{
    /* Quadratic in the number of layers (at most objects * 4 * max_layers, 2048 by
     * default), which is cheap next to evaluating a single channel. */
    int missing = 0;
    size_t used = 0;
    if (buf != NULL && buf_size > 0)
        buf[0] = '\0';
    for (size_t i = 0; i < s->object_count; i++) {
        for (int ch = 0; ch < SCENE_CH_COUNT; ch++) {
            for (size_t k = 0; k < s->objects[i].fields[ch].count; k++) {
                const char *name = name_at(s, i, ch, k);
                if (name == NULL || seen_before(s, name_at, i, ch, k, name))
                    continue;
                if (found(lookup, ctx, name))
                    continue;
                if (buf != NULL && used < buf_size) {
                    int n = snprintf(buf + used, buf_size - used, "%s%s", missing ? "," : "", name);
                    used += n > 0 ? (size_t)n : 0;
                }
                missing++;
            }
        }
    }
    return missing;
}

static bool volume_found(scene_volume_lookup_fn lookup, void *ctx, const char *name)
{
    return lookup != NULL && lookup(ctx, name) != NULL;
}

int scene_missing_volumes(const struct scene *s, scene_volume_lookup_fn lookup, void *ctx,
                          char *buf, size_t buf_size)
{
    return missing_names(s, volume_at, volume_found, lookup, ctx, buf, buf_size);
}

/* ---- meshes ---- */

const struct mesh *scene_mesh_lookup(scene_volume_lookup_fn lookup, void *ctx, const char *name)
{
    char key[sizeof SCENE_MESH_LOOKUP_PREFIX + SCENE_VOLUME_NAME_MAX];
    if (lookup == NULL)
        return NULL;
    snprintf(key, sizeof key, "%s%s", SCENE_MESH_LOOKUP_PREFIX, name);
    const struct scene_volume *v = lookup(ctx, key);
    return v != NULL ? v->mesh : NULL;
}

/* The mesh name of a layer, or NULL when it is not a mesh shape. */
static const char *mesh_at(const struct scene *s, size_t i, int ch, size_t k)
{
    const struct scene_layer *l = &s->objects[i].fields[ch].layers[k];
    return l->kind == SCENE_LAYER_SHAPE && l->shape.kind == SCENE_SHAPE_MESH ? l->shape.mesh : NULL;
}

static bool mesh_found(scene_volume_lookup_fn lookup, void *ctx, const char *name)
{
    return scene_mesh_lookup(lookup, ctx, name) != NULL;
}

/* Whether a mesh layer of any object names the mesh (missing_names has listed it then). */
static bool layers_name_mesh(const struct scene *s, const char *name)
{
    for (size_t i = 0; i < s->object_count; i++)
        for (int ch = 0; ch < SCENE_CH_COUNT; ch++)
            for (size_t k = 0; k < s->objects[i].fields[ch].count; k++) {
                const char *m = mesh_at(s, i, ch, k);
                if (m != NULL && strcmp(m, name) == 0)
                    return true;
            }
    return false;
}

int scene_missing_meshes(const struct scene *s, scene_volume_lookup_fn lookup, void *ctx, char *buf,
                         size_t buf_size)
{
    int missing = missing_names(s, mesh_at, mesh_found, lookup, ctx, buf, buf_size);
    /* ... and the meshes of mesh surfaces, each name once. */
    size_t used = buf != NULL ? strlen(buf) : 0;
    for (size_t k = 0; k < s->surface_count; k++) {
        const struct scene_shape *sh = &s->surfaces[k].shape;
        if (sh->kind != SCENE_SHAPE_MESH || mesh_found(lookup, ctx, sh->mesh))
            continue;
        bool dup = false;
        for (size_t j = 0; j < k && !dup; j++)
            dup = s->surfaces[j].shape.kind == SCENE_SHAPE_MESH &&
                  strcmp(s->surfaces[j].shape.mesh, sh->mesh) == 0;
        if (dup || layers_name_mesh(s, sh->mesh))
            continue;
        if (buf != NULL && used < buf_size) {
            int n = snprintf(buf + used, buf_size - used, "%s%s", missing ? "," : "", sh->mesh);
            used += n > 0 ? (size_t)n : 0;
        }
        missing++;
    }
    return missing;
}

/* ---- evaluation ---- */

struct grid {
    int n[3];
    size_t count;
    int comps;
    vec3 bmin, vs;
    double h_min;
};

static vec3 voxel_centre(const struct grid *g, int i, int j, int k)
{
    return vec3_make(g->bmin.x + (i + 0.5) * g->vs.x, g->bmin.y + (j + 0.5) * g->vs.y,
                     g->bmin.z + (k + 0.5) * g->vs.z);
}

static void fill(const struct grid *g, float *out, const double v[4])
{
    for (size_t idx = 0; idx < g->count; idx++) {
        for (int c = 0; c < g->comps; c++)
            out[idx * (size_t)g->comps + (size_t)c] = (float)v[c];
    }
}

/* out = c * v + (1 - c) * out at one voxel. */
static void blend(float *out, int comps, const double v[4], double c)
{
    if (c <= 0.0)
        return;
    for (int k = 0; k < comps; k++)
        out[k] = (float)(c * v[k] + (1.0 - c) * out[k]);
}

/* Voxel index range [lo, hi] along an axis whose centres fall in [a, b]. */
static bool index_range(double a, double b, double bmin, double vs, int n, int *lo, int *hi)
{
    double fa = ceil((a - bmin) / vs - 0.5), fb = floor((b - bmin) / vs - 0.5);
    fa = fmax(fa, 0.0);
    fb = fmin(fb, (double)(n - 1));
    if (!(fa <= fb))
        return false;
    *lo = (int)fa;
    *hi = (int)fb;
    return true;
}

static void eval_shape(const struct grid *g, const struct scene_layer *l, float *out)
{
    if (l->has_outside)
        fill(g, out, l->outside);
    vec3 lo, hi;
    if (!scene_shape_bounds(&l->shape, &lo, &hi))
        return;
    /* Coverage is zero where sdf >= h_min / 2; growing the box by a whole voxel keeps a
     * margin for rounding. */
    double grow = g->h_min;
    int i0, i1, j0, j1, k0, k1;
    if (!index_range(lo.x - grow, hi.x + grow, g->bmin.x, g->vs.x, g->n[0], &i0, &i1) ||
        !index_range(lo.y - grow, hi.y + grow, g->bmin.y, g->vs.y, g->n[1], &j0, &j1) ||
        !index_range(lo.z - grow, hi.z + grow, g->bmin.z, g->vs.z, g->n[2], &k0, &k1))
        return;
    double half = 0.5 * g->h_min;
    /* Only a true distance bounds its neighbours' values (the bumpy sphere's estimate does
     * not, shapes.c). */
    bool exact = l->shape.kind != SCENE_SHAPE_BUMPY_SPHERE;
    for (int k = k0; k <= k1; k++) {
        for (int j = j0; j <= j1; j++) {
            size_t row = ((size_t)k * (size_t)g->n[1] + (size_t)j) * (size_t)g->n[0];
            for (int i = i0; i <= i1;) {
                double d = scene_shape_sdf(&l->shape, voxel_centre(g, i, j, k));
                double c = fmin(fmax(0.5 - d / g->h_min, 0.0), 1.0);
                /* Voxels up to `skip` further along x are within |d| - h/2 of this one,
                 * so their coverage is the same 0 or 1. */
                double skip = exact && fabs(d) > half ? floor((fabs(d) - half) / g->vs.x) : 0.0;
                int last = skip >= (double)(i1 - i) ? i1 : i + (int)skip;
                for (int t = i; t <= last; t++)
                    blend(out + (row + (size_t)t) * (size_t)g->comps, g->comps, l->inside, c);
                i = last + 1;
            }
        }
    }
}

/* A mesh layer: its inside fraction from the mesh module, blended like a shape's. */
static enum refract_code eval_mesh(const struct grid *g, const struct scene_object *obj,
                                   const struct scene_layer *l, const struct mesh *m,
                                   const char *path, float *out, struct err *e)
{
    if (m == NULL)
        return err_set(e, REFRACT_E_CONFLICT,
                       "%s: mesh \"%s\" has not been uploaded; upload it with POST "
                       "/v1/scenes/{id}/meshes?name=%s before rendering",
                       path, l->shape.mesh, l->shape.mesh);
    float *coverage = malloc(g->count * sizeof *coverage);
    if (coverage == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "%s: out of memory for the %d x %d x %d coverage of mesh \"%s\"", path,
                       g->n[0], g->n[1], g->n[2], l->shape.mesh);
    struct mesh_voxelize_desc d = {
        .resolution = {obj->resolution[0], obj->resolution[1], obj->resolution[2]},
        .bounds_min = g->bmin,
        .voxel_size = g->vs,
        .object_from_mesh = l->shape.object_from_mesh,
    };
    enum refract_code rc = mesh_voxelize_memo(m, &d, coverage, e);
    if (rc == REFRACT_E_OK) {
        if (l->has_outside)
            fill(g, out, l->outside);
        for (size_t idx = 0; idx < g->count; idx++)
            blend(out + idx * (size_t)g->comps, g->comps, l->inside, coverage[idx]);
    }
    free(coverage);
    return rc;
}

static void eval_profile(const struct grid *g, const struct scene_layer *l, float *out)
{
    size_t idx = 0;
    for (int k = 0; k < g->n[2]; k++) {
        for (int j = 0; j < g->n[1]; j++) {
            for (int i = 0; i < g->n[0]; i++, idx++)
                out[idx] = (float)grin_ior(&l->profile, voxel_centre(g, i, j, k), NULL);
        }
    }
}

/* Trilinear taps along one axis: the target voxel i's centre in source index space is
 * (i + 0.5) * src / dst - 0.5 (both grids span the object's bounds), clamped to edge. */
struct tap {
    int i0, i1;
    double f;
};

static struct tap make_tap(int i, int dst, int src)
{
    double u = (i + 0.5) * (double)src / (double)dst - 0.5;
    u = fmin(fmax(u, 0.0), (double)(src - 1));
    struct tap t = {.i0 = (int)floor(u)};
    t.i1 = t.i0 + 1 < src ? t.i0 + 1 : t.i0;
    t.f = u - t.i0;
    return t;
}

static double sample(const struct scene_volume *v, const struct tap *tx, const struct tap *ty,
                     const struct tap *tz, int comp)
{
    size_t sx = (size_t)v->dims[0], sy = (size_t)v->dims[1], nc = (size_t)v->components;
    double acc = 0.0;
    for (int c = 0; c < 8; c++) {
        size_t x = (size_t)((c & 1) ? tx->i1 : tx->i0);
        size_t y = (size_t)((c & 2) ? ty->i1 : ty->i0);
        size_t z = (size_t)((c & 4) ? tz->i1 : tz->i0);
        double w = ((c & 1) ? tx->f : 1.0 - tx->f) * ((c & 2) ? ty->f : 1.0 - ty->f) *
                   ((c & 4) ? tz->f : 1.0 - tz->f);
        if (w != 0.0)
            acc += w * v->data[((z * sy + y) * sx + x) * nc + (size_t)comp];
    }
    return acc;
}

static void volume_path(const struct scene *s, const struct scene_object *obj,
                        enum scene_channel ch, size_t layer, char *buf, size_t size)
{
    long idx =
        (obj >= s->objects && obj < s->objects + s->object_count) ? (long)(obj - s->objects) : -1;
    int n = idx >= 0 ? snprintf(buf, size, "objects[%ld].%s", idx, scene_channel_name(ch))
                     : snprintf(buf, size, "%s.%s", obj->name, scene_channel_name(ch));
    if (obj->fields[ch].count > 1 && n > 0 && (size_t)n < size)
        snprintf(buf + n, size - (size_t)n, "[%zu]", layer);
}

static enum refract_code check_volume(const struct scene_volume *v, const char *path,
                                      const char *name, enum scene_channel ch, struct err *e)
{
    if (v == NULL)
        return err_set(e, REFRACT_E_CONFLICT,
                       "%s: volume \"%s\" has not been uploaded; upload it with PUT "
                       "/v1/scenes/{id}/volumes/%s before rendering",
                       path, name, name);
    bool scalar = scene_channel_components(ch) == 1;
    bool comps_ok = v->components == 1 || (v->components == 3 && !scalar);
    if (!comps_ok)
        return err_set(e, REFRACT_E_CONFLICT,
                       "%s: volume \"%s\" has %d components but %s takes %s; upload it again "
                       "with PUT /v1/scenes/{id}/volumes/%s",
                       path, name, v->components, scene_channel_name(ch),
                       scalar ? "1" : "1 (grey) or 3 (RGB)", name);
    if (v->data == NULL || v->dims[0] < 1 || v->dims[1] < 1 || v->dims[2] < 1)
        return err_set(e, REFRACT_E_CONFLICT,
                       "%s: volume \"%s\" is empty (dims %d x %d x %d); upload it again with PUT "
                       "/v1/scenes/{id}/volumes/%s",
                       path, name, v->dims[0], v->dims[1], v->dims[2], name);
    return REFRACT_E_OK;
}

/* Taps are recomputed per voxel rather than tabulated: a few flops next to the eight
 * loads, and it keeps evaluation free of allocations. */
static void eval_volume(const struct grid *g, const struct scene_volume *v,
                        const struct scene_layer *l, enum scene_channel ch, float *out)
{
    double lo = channel_min[ch], hi = channel_max[ch];
    size_t idx = 0;
    for (int k = 0; k < g->n[2]; k++) {
        struct tap tz = make_tap(k, g->n[2], v->dims[2]);
        for (int j = 0; j < g->n[1]; j++) {
            struct tap ty = make_tap(j, g->n[1], v->dims[1]);
            for (int i = 0; i < g->n[0]; i++, idx++) {
                struct tap tx = make_tap(i, g->n[0], v->dims[0]);
                float *o = out + idx * (size_t)g->comps;
                for (int c = 0; c < 3 && c < g->comps; c++) {
                    int src = v->components == 1 ? 0 : c;
                    double x = l->volume_offset + l->volume_scale * sample(v, &tx, &ty, &tz, src);
                    /* fmax maps NaN to lo. */
                    o[c] = (float)fmin(fmax(x, lo), hi);
                }
                if (g->comps == 4)
                    o[3] = ch == SCENE_CH_OPAQUE ? 1.0f : 0.0f;
            }
        }
    }
}

enum refract_code scene_field_eval(const struct scene *s, const struct scene_object *obj,
                                   enum scene_channel ch, scene_volume_lookup_fn lookup, void *ctx,
                                   float *out, struct err *e)
{
    if (ch < 0 || ch >= SCENE_CH_COUNT)
        return err_set(e, REFRACT_E_INTERNAL, "scene_field_eval: no channel %d", (int)ch);
    struct grid g = {
        .n = {obj->resolution[0], obj->resolution[1], obj->resolution[2]},
        .comps = scene_channel_components(ch),
        .bmin = obj->bounds_min,
        .vs = scene_object_voxel_size(obj),
        .h_min = scene_object_min_voxel(obj),
    };
    g.count = (size_t)g.n[0] * (size_t)g.n[1] * (size_t)g.n[2];
    double base[4] = {ch == SCENE_CH_IOR ? s->ambient_ior : 0.0, 0.0, 0.0, 0.0};
    fill(&g, out, base);
    const struct scene_field *f = &obj->fields[ch];
    for (size_t i = 0; i < f->count; i++) {
        const struct scene_layer *l = &f->layers[i];
        switch (l->kind) {
        case SCENE_LAYER_CONSTANT:
            fill(&g, out, l->inside);
            break;
        case SCENE_LAYER_SHAPE:
            if (l->shape.kind == SCENE_SHAPE_MESH) {
                char path[256];
                volume_path(s, obj, ch, i, path, sizeof path);
                enum refract_code rc = eval_mesh(
                    &g, obj, l, scene_mesh_lookup(lookup, ctx, l->shape.mesh), path, out, e);
                if (rc != REFRACT_E_OK)
                    return rc;
                break;
            }
            eval_shape(&g, l, out);
            break;
        case SCENE_LAYER_PROFILE:
            eval_profile(&g, l, out);
            break;
        case SCENE_LAYER_VOLUME: {
            char path[256];
            volume_path(s, obj, ch, i, path, sizeof path);
            const struct scene_volume *v = lookup ? lookup(ctx, l->volume) : NULL;
            enum refract_code rc = check_volume(v, path, l->volume, ch, e);
            if (rc != REFRACT_E_OK)
                return rc;
            eval_volume(&g, v, l, ch, out);
            break;
        }
        }
    }
    /* A bound object's field continues its inside values beyond its surface. */
    return scene_field_extend_bound(s, obj, ch, lookup, ctx, out, e);
}
