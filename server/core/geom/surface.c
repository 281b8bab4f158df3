/*
 * surface.c - a placed surface of any kind (geom.h): the world ray is carried into the
 * surface's object space (positions through M^-1, directions through R^T, lengths by
 * 1 / scale), intersected there by the kind's own file, and the hit carried back.
 * Twin: shaders/geom/surface.glsl.
 */
#include <math.h>

#include "geom.h"

static bool intersect_object(const struct geom_surface *g, vec3 o, vec3 d, double tmin, double tmax,
                             int64_t skip_prim, struct geom_hit *h)
{
    switch (g->kind) {
    case GEOM_SPHERE:
        return sphere_intersect(g->center, g->radius, o, d, tmin, tmax, h);
    case GEOM_BOX:
        return box_intersect(g->center, g->size, o, d, tmin, tmax, h);
    case GEOM_ROUNDED_BOX:
        return rounded_box_intersect(g->center, g->size, g->radius, o, d, tmin, tmax, h);
    case GEOM_CYLINDER:
        return cylinder_intersect(g->center, g->radius, g->height, g->axis, o, d, tmin, tmax, h);
    case GEOM_PLANE:
        return plane_intersect(g->center, g->normal, o, d, tmin, tmax, h);
    case GEOM_LATHE:
        return lathe_intersect(g->base, g->axis, g->profile, g->profile_count, o, d, tmin, tmax, h);
    case GEOM_MESH:
        return g->mesh_ops != NULL &&
               g->mesh_ops->intersect(g->mesh, o, d, tmin, tmax, skip_prim, h);
    }
    return false;
}

bool geom_surface_intersect(const struct geom_surface *g, vec3 o, vec3 d, double tmin, double tmax,
                            int64_t skip_prim, struct geom_hit *h)
{
    double s = g->xf.scale;
    vec3 oo = xform_point_to_object(&g->xf, o);
    vec3 dd = xform_dir_to_object(&g->xf, d);
    if (!intersect_object(g, oo, dd, tmin / s, tmax / s, skip_prim, h))
        return false;
    h->t *= s;
    h->normal = xform_dir_to_world(&g->xf, h->normal);
    h->shading = xform_dir_to_world(&g->xf, h->shading);
    return true;
}

bool geom_surface_inside(const struct geom_surface *g, vec3 p)
{
    vec3 q = xform_point_to_object(&g->xf, p);
    switch (g->kind) {
    case GEOM_SPHERE:
        return sphere_inside(g->center, g->radius, q);
    case GEOM_BOX:
        return box_inside(g->center, g->size, q);
    case GEOM_ROUNDED_BOX:
        return rounded_box_inside(g->center, g->size, g->radius, q);
    case GEOM_CYLINDER:
        return cylinder_inside(g->center, g->radius, g->height, g->axis, q);
    case GEOM_PLANE:
        return plane_inside(g->center, g->normal, q);
    case GEOM_LATHE:
        return lathe_inside(g->base, g->axis, g->profile, g->profile_count, q);
    case GEOM_MESH:
        return g->mesh_ops != NULL && g->mesh_ops->inside(g->mesh, q);
    }
    return false;
}

void geom_world_box(const struct xform *xf, vec3 lo, vec3 hi, vec3 *wlo, vec3 *whi)
{
    *wlo = vec3_make(INFINITY, INFINITY, INFINITY);
    *whi = vec3_make(-INFINITY, -INFINITY, -INFINITY);
    for (int c = 0; c < 8; c++) {
        vec3 p = {(c & 1) ? hi.x : lo.x, (c & 2) ? hi.y : lo.y, (c & 4) ? hi.z : lo.z};
        vec3 w = xform_point_to_world(xf, p);
        for (int a = 0; a < 3; a++) {
            vec3_set(wlo, a, fmin(vec3_get(*wlo, a), vec3_get(w, a)));
            vec3_set(whi, a, fmax(vec3_get(*whi, a), vec3_get(w, a)));
        }
    }
}

bool geom_surface_bounds(const struct geom_surface *g, vec3 *lo, vec3 *hi)
{
    vec3 a, b;
    switch (g->kind) {
    case GEOM_SPHERE:
        sphere_bounds(g->center, g->radius, &a, &b);
        break;
    case GEOM_BOX:
    case GEOM_ROUNDED_BOX:
        box_bounds(g->center, g->size, &a, &b);
        break;
    case GEOM_CYLINDER:
        cylinder_bounds(g->center, g->radius, g->height, g->axis, &a, &b);
        break;
    case GEOM_PLANE: {
        /* A half-space stays axis-aligned in world space only if its world normal is. */
        vec3 c = xform_point_to_world(&g->xf, g->center);
        vec3 n = xform_dir_to_world(&g->xf, g->normal);
        for (int k = 0; k < 3; k++)
            if (fabs(vec3_get(n, k)) < 1e-12)
                vec3_set(&n, k, 0.0);
        plane_bounds(c, n, lo, hi);
        return true;
    }
    case GEOM_LATHE:
        lathe_bounds(g->base, g->axis, g->profile, g->profile_count, &a, &b);
        break;
    case GEOM_MESH:
        a = g->mesh_lo;
        b = g->mesh_hi;
        break;
    default:
        return false;
    }
    geom_world_box(&g->xf, a, b, lo, hi);
    return true;
}

double geom_surface_size(const struct geom_surface *g)
{
    vec3 lo, hi;
    if (g->kind == GEOM_PLANE)
        return g->xf.scale * fmax(1.0, vec3_length(g->center));
    geom_surface_bounds(g, &lo, &hi);
    return vec3_length(vec3_sub(hi, lo));
}
