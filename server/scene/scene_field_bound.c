/*
 * scene_field_bound.c - the field of an object bound to a surface (docs/scenes.md
 * "Surfaces", medium "object") made right up to the surface.
 *
 * A bound object is seen only inside its surface, but the march samples its voxels
 * trilinearly (and the precomputation smooths n and takes central differences), so a
 * sample within a voxel or two of the surface mixes voxels whose centres lie outside the
 * solid. What the layers hold there (a Luneburg profile's n = 1 beyond its radius, a
 * shape's outside value) is not the medium's and bends the rays on their last step.
 * So the voxels outside the solid within a band of the surface are replaced by the
 * inside field continued across it: linear extrapolation along each axis from the two
 * nearest known voxels (2 v1 - v2), averaged over the axes that have them, a copy of the
 * known neighbours where no axis has two; layer by layer outwards, each layer from the
 * ones before. Linear continuation keeps grad n across the surface (the Luneburg lens's
 * -r/n), so the gradient's central difference at the last inside voxels is the field's.
 *
 * Not here: anything for free objects (their field is exactly what the layers say).
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../core/geom/geom.h"
#include "scene.h"

/* Layers of voxels continued beyond the surface: the trilinear footprint (1), the
 * gradient's central difference (1) and the smoothing kernel's reach (3 sigma). */
static int band_voxels(const struct scene_object *obj)
{
    int b = 2 + (int)ceil(3.0 * obj->smoothing_sigma_voxels);
    return b > 16 ? 16 : b;
}

/* known[v]: 1 where the voxel centre lies inside the solid. */
static void mark_inside(const struct scene_object *obj, const struct geom_surface *g,
                        uint8_t *known)
{
    vec3 vs = scene_object_voxel_size(obj);
    const int *n = obj->resolution;
    size_t v = 0;
    for (int k = 0; k < n[2]; k++)
        for (int j = 0; j < n[1]; j++)
            for (int i = 0; i < n[0]; i++, v++) {
                vec3 p = vec3_make(obj->bounds_min.x + (i + 0.5) * vs.x,
                                   obj->bounds_min.y + (j + 0.5) * vs.y,
                                   obj->bounds_min.z + (k + 0.5) * vs.z);
                known[v] = geom_surface_inside(g, xform_point_to_world(&obj->world_from_object, p));
            }
}

/* The continued value of voxel (i, j, k) from the known voxels; false when it has no
 * known neighbour. */
static bool continue_voxel(const int *n, const uint8_t *known, const float *out, int comps, int i,
                           int j, int k, float *value)
{
    static const int dirs[6][3] = {{1, 0, 0},  {-1, 0, 0}, {0, 1, 0},
                                   {0, -1, 0}, {0, 0, 1},  {0, 0, -1}};
    double lin[4] = {0, 0, 0, 0}, near[4] = {0, 0, 0, 0};
    int n_lin = 0, n_near = 0;
    for (int d = 0; d < 6; d++) {
        int i1 = i + dirs[d][0], j1 = j + dirs[d][1], k1 = k + dirs[d][2];
        if (i1 < 0 || j1 < 0 || k1 < 0 || i1 >= n[0] || j1 >= n[1] || k1 >= n[2])
            continue;
        size_t v1 = ((size_t)k1 * n[1] + j1) * n[0] + i1;
        if (!known[v1])
            continue;
        n_near++;
        for (int c = 0; c < comps; c++)
            near[c] += out[v1 * comps + c];
        int i2 = i1 + dirs[d][0], j2 = j1 + dirs[d][1], k2 = k1 + dirs[d][2];
        if (i2 < 0 || j2 < 0 || k2 < 0 || i2 >= n[0] || j2 >= n[1] || k2 >= n[2])
            continue;
        size_t v2 = ((size_t)k2 * n[1] + j2) * n[0] + i2;
        if (!known[v2])
            continue;
        n_lin++;
        for (int c = 0; c < comps; c++)
            lin[c] += 2.0 * out[v1 * comps + c] - out[v2 * comps + c];
    }
    if (n_near == 0)
        return false;
    for (int c = 0; c < comps; c++)
        value[c] = (float)(n_lin > 0 ? lin[c] / n_lin : near[c] / n_near);
    return true;
}

enum refract_code scene_field_extend_bound(const struct scene *s, const struct scene_object *obj,
                                           enum scene_channel ch, scene_volume_lookup_fn lookup,
                                           void *ctx, float *out, struct err *e)
{
    if (!obj->bound || obj->bound_surface < 0 || (size_t)obj->bound_surface >= s->surface_count)
        return REFRACT_E_OK;
    struct geom_surface g;
    if (!scene_surface_geom_lookup(&s->surfaces[obj->bound_surface], lookup, ctx, &g))
        return REFRACT_E_OK; /* a missing mesh: the render reports it */
    const int *n = obj->resolution;
    size_t count = (size_t)n[0] * n[1] * n[2];
    int comps = scene_channel_components(ch);
    uint8_t *known = malloc(count);
    uint8_t *next = malloc(count);
    if (known == NULL || next == NULL) {
        free(known);
        free(next);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "objects: out of memory continuing the field "
                       "of \"%s\" beyond its surface",
                       obj->name);
    }
    mark_inside(obj, &g, known);
    /* Attenuation, emission, scattering are >= 0; anisotropy within (-1, 1); n >= 0.2
     * (scene_field.c's ranges): the linear continuation must not leave them. */
    double lo = ch == SCENE_CH_ANISOTROPY ? -0.99 : ch == SCENE_CH_IOR ? 0.2 : 0.0;
    double hi = ch == SCENE_CH_ANISOTROPY ? 0.99 : 1e6;
    for (int layer = 0; layer < band_voxels(obj); layer++) {
        memcpy(next, known, count);
        size_t v = 0;
        for (int k = 0; k < n[2]; k++)
            for (int j = 0; j < n[1]; j++)
                for (int i = 0; i < n[0]; i++, v++) {
                    float value[4];
                    if (known[v] || !continue_voxel(n, known, out, comps, i, j, k, value))
                        continue;
                    for (int c = 0; c < comps; c++)
                        out[v * comps + c] = (float)fmin(fmax(value[c], lo), hi);
                    next[v] = 1;
                }
        memcpy(known, next, count);
    }
    free(known);
    free(next);
    return REFRACT_E_OK;
}
