/*
 * lightsim_domain.c - the light grid of a scene and a light (docs/lightsim.md "Domain"):
 * the union of the objects' and the surfaces' world boxes (a mesh surface's from its
 * upload) and their footprint on the receiver as the light sees it (the whole receiver
 * square without a light), clipped below at the receiver plane, padded by two cubic
 * voxels on every side (below the receiver plane too: the receiver reads E at the plane,
 * and the deposit kernel there reaches two voxels below it).
 */
#include <math.h>

#include "../core/geom/geom.h"
#include "bindings.h"
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
    lightsim_domain_light(s, NULL, NULL, NULL, out);
}

void lightsim_domain_lookup(const struct scene *s, scene_volume_lookup_fn lookup, void *ctx,
                            struct light_grid *out)
{
    lightsim_domain_light(s, NULL, lookup, ctx, out);
}

/* The objects' and the surfaces' world box (finite sides only); lo > hi along an axis
 * that nothing finite reaches. */
static void objects_box(const struct scene *s, scene_volume_lookup_fn lookup, void *ctx, vec3 *lo,
                        vec3 *hi)
{
    *lo = (vec3){INFINITY, INFINITY, INFINITY};
    *hi = (vec3){-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < s->object_count; i++) {
        const struct scene_object *o = &s->objects[i];
        for (int c = 0; c < 8; c++) {
            vec3 p = {(c & 1) ? o->bounds_max.x : o->bounds_min.x,
                      (c & 2) ? o->bounds_max.y : o->bounds_min.y,
                      (c & 4) ? o->bounds_max.z : o->bounds_min.z};
            grow(lo, hi, xform_point_to_world(&o->world_from_object, p));
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
            if (isfinite(l) && l < vec3_get(*lo, a))
                vec3_set(lo, a, l);
            if (isfinite(h) && h > vec3_get(*hi, a))
                vec3_set(hi, a, h);
        }
    }
}

/* The footprint of the box [lo, hi] on the plane y = height as light l sees it
 * (docs/lightsim.md "Domain"): the x, z box of its corners projected from the light
 * (central projection from a point or spot light, parallel along a directional light's
 * direction), united with the box's own x, z extent and clipped to the square of half
 * side LIGHTSIM_FOOTPRINT_MAX times the box's longest extent about its centre; the
 * whole clip square when a corner is at or above a point light. A light that does not
 * shine down onto the plane (at or below it, or a directional light with direction.y >=
 * 0) leaves the box's own extent. fl, fh: x in .x, z in .z. */
static void footprint(vec3 lo, vec3 hi, double height, const struct scene_light *l, vec3 *fl,
                      vec3 *fh)
{
    *fl = lo;
    *fh = hi;
    double longest = fmax(hi.x - lo.x, fmax(hi.y - lo.y, hi.z - lo.z));
    double m = LIGHTSIM_FOOTPRINT_MAX * longest;
    vec3 c = vec3_scale(vec3_add(lo, hi), 0.5);
    bool point = l->kind != SCENE_LIGHT_DIRECTIONAL;
    if (point ? !(l->position.y > height) : !(l->direction.y < 0.0))
        return;
    bool unbounded = false;
    for (int k = 0; k < 8; k++) {
        vec3 p = {(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z};
        vec3 f;
        if (point) {
            vec3 q = l->position;
            if (p.y >= q.y) {
                unbounded = true;
                continue;
            }
            double t = (q.y - height) / (q.y - p.y);
            f = vec3_add(q, vec3_scale(vec3_sub(p, q), t));
        } else {
            f = vec3_madd(p, l->direction, (height - p.y) / l->direction.y);
        }
        fl->x = fmin(fl->x, f.x);
        fl->z = fmin(fl->z, f.z);
        fh->x = fmax(fh->x, f.x);
        fh->z = fmax(fh->z, f.z);
    }
    if (unbounded) {
        fl->x = c.x - m;
        fl->z = c.z - m;
        fh->x = c.x + m;
        fh->z = c.z + m;
    }
    fl->x = fmax(fl->x, c.x - m);
    fl->z = fmax(fl->z, c.z - m);
    fh->x = fmin(fh->x, c.x + m);
    fh->z = fmin(fh->z, c.z + m);
}

void lightsim_domain_light(const struct scene *s, const struct scene_light *l,
                           scene_volume_lookup_fn lookup, void *ctx, struct light_grid *out)
{
    vec3 lo, hi;
    objects_box(s, lookup, ctx, &lo, &hi);
    const struct scene_receiver *r = &s->receiver;
    if (r->enabled) {
        /* The receiver's part: the square, or with a light the footprint of the objects
         * on it, clipped to the square (outside it the receiver is lit by the light's
         * closed form, light_direct). */
        double sq_lo[2] = {r->center[0] - r->half_size, r->center[1] - r->half_size};
        double sq_hi[2] = {r->center[0] + r->half_size, r->center[1] + r->half_size};
        bool have = lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z;
        double f_lo[2], f_hi[2];
        if (l != NULL && have) {
            vec3 fl, fh;
            footprint(lo, hi, r->height, l, &fl, &fh);
            f_lo[0] = fmax(fl.x, sq_lo[0]);
            f_lo[1] = fmax(fl.z, sq_lo[1]);
            f_hi[0] = fmin(fh.x, sq_hi[0]);
            f_hi[1] = fmin(fh.z, sq_hi[1]);
        } else if (isfinite(r->half_size)) { /* without a light: the whole square */
            f_lo[0] = sq_lo[0];
            f_lo[1] = sq_lo[1];
            f_hi[0] = sq_hi[0];
            f_hi[1] = sq_hi[1];
        } else { /* the whole plane and no light: the objects' extent */
            f_lo[0] = lo.x;
            f_lo[1] = lo.z;
            f_hi[0] = hi.x;
            f_hi[1] = hi.z;
        }
        if (f_lo[0] <= f_hi[0] && f_lo[1] <= f_hi[1]) {
            grow(&lo, &hi, (vec3){f_lo[0], r->height, f_lo[1]});
            grow(&lo, &hi, (vec3){f_hi[0], r->height, f_hi[1]});
        }
        /* Nothing below the plane is seen; the pad below keeps the deposits that the
         * receiver's sample at y = height reads (docs/lightsim.md "Domain"). */
        lo.y = r->height;
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
        /* With a receiver, x and z get LIGHTSIM_RECEIVER_MARGIN voxels more each side: the
         * receiver reads the volume only LIGHT_RECEIVER_INSET voxels inside the faces. */
        int pad = 2 + (r->enabled && a != 1 ? LIGHTSIM_RECEIVER_MARGIN : 0);
        double ext = vec3_get(hi, a) - vec3_get(lo, a);
        /* 1e-9: the longest axis gives exactly resolution - 4 despite rounding */
        int n = (int)ceil(ext / voxel - 1e-9) + 2 * pad;
        out->dims[a] = n > 2 ? n : 2;
        vec3_set(&out->bmin, a, vec3_get(lo, a) - pad * voxel);
    }
}

int lightsim_deposit_every(const struct scene_lightsim *set)
{
    /* 1e-9: step 0.5 (or 1/3) gives exactly 2 (or 3) despite rounding */
    double k = set->step_voxels > 0.0 ? floor(1.0 / set->step_voxels + 1e-9) : 1.0;
    return k >= 1.0 ? (int)fmin(k, 1000.0) : 1;
}
