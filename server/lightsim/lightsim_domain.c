/*
 * lightsim_domain.c - the light grid of a scene (docs/lightsim.md "Domain"): the union of
 * the objects' and the surfaces' world boxes (a mesh surface's from its upload) and the
 * receiver square, clipped below at the receiver plane, padded by two cubic voxels.
 */
#include <math.h>

#include "../core/geom/geom.h"
#include "lightsim.h"

static void grow(vec3 *lo, vec3 *hi, vec3 p)
{
    for (int a = 0; a < 3; a++) {
        double v = vec3_get(p, a);
        if (v < vec3_get(*lo, a))
            vec3_set(lo, a, v);
        if (v > vec3_get(*hi, a))
            vec3_set(hi, a, v);
    }
}

void lightsim_domain(const struct scene *s, struct light_grid *out)
{
    lightsim_domain_lookup(s, NULL, NULL, out);
}

void lightsim_domain_lookup(const struct scene *s, scene_volume_lookup_fn lookup, void *ctx,
                            struct light_grid *out)
{
    vec3 lo = {INFINITY, INFINITY, INFINITY}, hi = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < s->object_count; i++) {
        const struct scene_object *o = &s->objects[i];
        for (int c = 0; c < 8; c++) {
            vec3 p = {(c & 1) ? o->bounds_max.x : o->bounds_min.x,
                      (c & 2) ? o->bounds_max.y : o->bounds_min.y,
                      (c & 4) ? o->bounds_max.z : o->bounds_min.z};
            grow(&lo, &hi, xform_point_to_world(&o->world_from_object, p));
        }
    }
    /* Exact surfaces: their solids' world boxes; an infinite side (a plane's half-space)
     * adds nothing along that axis, so a water plane bounds the domain only where it is
     * finite (docs/lightsim.md "Domain"). */
    for (size_t k = 0; k < s->surface_count; k++) {
        struct geom_surface g;
        vec3 blo, bhi;
        if (!scene_surface_geom_lookup(&s->surfaces[k], lookup, ctx, &g))
            continue; /* a mesh not found: lightsim_fields_build refuses it */
        geom_surface_bounds(&g, &blo, &bhi);
        for (int a = 0; a < 3; a++) {
            double l = vec3_get(blo, a), h = vec3_get(bhi, a);
            if (isfinite(l) && l < vec3_get(lo, a))
                vec3_set(&lo, a, l);
            if (isfinite(h) && h > vec3_get(hi, a))
                vec3_set(&hi, a, h);
        }
    }
    const struct scene_receiver *r = &s->receiver;
    if (r->enabled) {
        grow(&lo, &hi, (vec3){-r->half_size, r->height, -r->half_size});
        grow(&lo, &hi, (vec3){r->half_size, r->height, r->half_size});
        lo.y = r->height; /* light below the receiver plane is never seen */
        if (hi.y < lo.y)
            hi.y = lo.y;
    }
    for (int a = 0; a < 3; a++)
        if (!(vec3_get(lo, a) <= vec3_get(hi, a))) { /* nothing finite along a */
            vec3_set(&lo, a, 0.0);
            vec3_set(&hi, a, 0.0);
        }
    double longest = 0.0;
    for (int a = 0; a < 3; a++) {
        double ext = vec3_get(hi, a) - vec3_get(lo, a);
        longest = ext > longest ? ext : longest;
    }
    int res = s->lightsim.resolution > 4 ? s->lightsim.resolution : 5;
    double voxel = longest > 0.0 ? longest / (res - 4) : 1.0;
    out->voxel = voxel;
    for (int a = 0; a < 3; a++) {
        bool clipped = a == 1 && r->enabled;
        double ext = vec3_get(hi, a) - vec3_get(lo, a);
        /* 1e-9: the longest axis gives exactly resolution - 4 despite rounding */
        int n = (int)ceil(ext / voxel - 1e-9) + (clipped ? 2 : 4);
        out->dims[a] = n > 2 ? n : 2;
        vec3_set(&out->bmin, a, vec3_get(lo, a) - (clipped ? 0.0 : 2.0 * voxel));
    }
}

int lightsim_deposit_every(const struct scene_lightsim *set)
{
    /* 1e-9: step 0.5 (or 1/3) gives exactly 2 (or 3) despite rounding */
    double k = set->step_voxels > 0.0 ? floor(1.0 / set->step_voxels + 1e-9) : 1.0;
    return k >= 1.0 ? (int)fmin(k, 1000.0) : 1;
}
