/*
 * lightsim_sample.c - field sampling at world points; see lightsim_sample.h.
 */
#include "lightsim_sample.h"

#include "../core/smooth.h"
#include "lightsim_patch.h"

void ls_grid_box(const struct light_grid *g, vec3 *lo, vec3 *hi)
{
    *lo = g->bmin;
    *hi = vec3_add(g->bmin, vec3_scale((vec3){g->dims[0], g->dims[1], g->dims[2]}, g->voxel));
}

/* Voxel coordinates v = (x - bmin) / voxel - 0.5 (voxel centres at integers); false
 * outside the grid box. voxel_sample_trilinear clamps v to [0, dims - 1]. */
static bool voxel_coords(const struct light_grid *g, vec3 x, vec3 *v)
{
    vec3 lo, hi;
    ls_grid_box(g, &lo, &hi);
    if (!ls_box_contains(lo, hi, x))
        return false;
    *v = vec3_sub(vec3_scale(vec3_sub(x, g->bmin), 1.0 / g->voxel), (vec3){0.5, 0.5, 0.5});
    return true;
}

void ls_sample_ior(const struct lightsim_fields *f, vec3 x, double *n, vec3 *grad)
{
    vec3 v;
    if (!voxel_coords(&f->grid, x, &v)) {
        *n = f->ambient_ior;
        *grad = (vec3){0, 0, 0};
        return;
    }
    double s[4];
    voxel_sample_trilinear(f->ior_grad, 4, f->grid.dims, v, s);
    *grad = (vec3){s[0], s[1], s[2]};
    *n = s[3];
}

void ls_sample_all(const struct lightsim_fields *f, vec3 x, struct ls_sample *out)
{
    vec3 v;
    if (!voxel_coords(&f->grid, x, &v)) {
        *out = (struct ls_sample){.n = f->ambient_ior};
        return;
    }
    double s[4], t[4];
    voxel_sample_trilinear(f->ior_grad, 4, f->grid.dims, v, s);
    voxel_sample_trilinear(f->extinction, 4, f->grid.dims, v, t);
    out->grad = (vec3){s[0], s[1], s[2]};
    out->n = s[3];
    for (int c = 0; c < 3; c++)
        out->sigma[c] = t[c];
    out->coverage = t[3];
}
