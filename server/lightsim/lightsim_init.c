/*
 * lightsim_init.c - initial wavefronts: a square of patches across the domain for a
 * directional light, a cube sphere of radius point_radius for a point light, its cone for
 * a spot (docs/lightsim.md "Initial wavefront", tevs2007 sect. 6.2.1).
 */
#include "lightsim_init.h"

#include <math.h>
#include <stdlib.h>

#include "../core/interface.h"
#include "lightsim_sample.h"
#include "lightsim_surfaces.h"

/* Cube faces: outward axis f and in-face axes (s, t) with s x t = f. */
static const vec3 FACE[6][3] = {
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
    {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
    {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
};

struct aim {
    vec3 lo, hi; /* the domain box */
};

/* The surface state of a new patch (docs/lightsim.md "Surfaces"): each corner's inside
 * set where it starts, nothing crossed, no pending event. */
static void start_surfaces(const struct lightsim_fields *f, struct ls_patch *p)
{
    for (int k = 0; k < 4; k++) {
        p->inside[k] = f->surface_count > 0 ? ls_surfaces_inside(f, p->x[k]) : 0u;
        p->last[k] = -1;
    }
    p->ev_surface = -1;
    p->ev_mask = 0;
    p->ev_reflect = false;
}

/* Keeps a patch whose centre half-line meets the domain box grown by e_max. */
static bool aimed(const struct aim *a, const struct ls_patch *p)
{
    struct ls_derived g;
    ls_patch_derive(p, &g);
    vec3 grow = {g.e_max, g.e_max, g.e_max};
    return ls_halfline_meets_box(g.c, g.d, vec3_sub(a->lo, grow), vec3_add(a->hi, grow));
}

static void set_power(struct ls_patch *p, double scale)
{
    struct ls_derived g;
    ls_patch_derive(p, &g);
    for (int c = 0; c < 3; c++)
        p->P[c] = g.area * scale;
}

static size_t directional(const struct lightsim_fields *f, const struct scene_light *l, int N0,
                          const struct aim *a, struct ls_patch *out)
{
    vec3 d = vec3_normalize(l->direction);
    vec3 axis = fabs(d.y) > 0.9 ? (vec3){1, 0, 0} : (vec3){0, 1, 0};
    vec3 u = vec3_normalize(vec3_cross(d, axis));
    vec3 v = vec3_cross(d, u);
    vec3 C = vec3_scale(vec3_add(a->lo, a->hi), 0.5);
    double rho = 0.5 * vec3_length(vec3_sub(a->hi, a->lo));
    vec3 S = vec3_madd(C, d, -(rho + f->grid.voxel));
    vec3 w = vec3_scale(d, f->ambient_ior);
    size_t n = 0;
    for (int j = 0; j < N0; j++) {
        for (int i = 0; i < N0; i++) {
            struct ls_patch p = {.level = 0};
            static const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
            for (int k = 0; k < 4; k++) {
                double su = -rho + 2.0 * rho * (i + di[k]) / N0;
                double sv = -rho + 2.0 * rho * (j + dj[k]) / N0;
                p.x[k] = vec3_madd(vec3_madd(S, u, su), v, sv);
                p.w[k] = w;
            }
            set_power(&p, 1.0); /* unit irradiance times the area */
            if (aimed(a, &p)) {
                start_surfaces(f, &p);
                out[n++] = p;
            }
        }
    }
    return n;
}

static size_t point(const struct lightsim_fields *f, const struct scene_light *l,
                    const struct scene_lightsim *set, int N0, const struct aim *a,
                    struct ls_patch *out)
{
    double eps = set->point_radius;
    double nq;
    vec3 gq;
    ls_sample_ior(f, l->position, &nq, &gq);
    if (f->surface_count > 0) /* a light inside a surface starts in its medium */
        nq = ls_medium_ior(f, interface_medium(ls_surfaces_inside(f, l->position)), l->position);
    bool spot = l->kind == SCENE_LIGHT_SPOT;
    vec3 axis = vec3_normalize(l->direction);
    double cos_cone = cos(l->spot_angle_deg * M_PI / 180.0);
    size_t n = 0;
    for (int face = 0; face < 6; face++) {
        vec3 fa = FACE[face][0], s = FACE[face][1], t = FACE[face][2];
        for (int j = 0; j < N0; j++) {
            for (int i = 0; i < N0; i++) {
                struct ls_patch p = {.level = 0};
                static const int di[4] = {0, 1, 1, 0}, dj[4] = {0, 0, 1, 1};
                for (int k = 0; k < 4; k++) {
                    double a_s = -1.0 + 2.0 * (i + di[k]) / N0;
                    double a_t = -1.0 + 2.0 * (j + dj[k]) / N0;
                    vec3 dir = vec3_normalize(vec3_madd(vec3_madd(fa, s, a_s), t, a_t));
                    p.x[k] = vec3_madd(l->position, dir, eps);
                    p.w[k] = vec3_scale(dir, nq);
                }
                /* unit intensity times the patch's solid angle A / eps^2 */
                set_power(&p, 1.0 / (eps * eps));
                if (spot) {
                    struct ls_derived g;
                    ls_patch_derive(&p, &g);
                    if (vec3_dot(g.d, axis) < cos_cone)
                        continue;
                }
                if (aimed(a, &p)) {
                    start_surfaces(f, &p);
                    out[n++] = p;
                }
            }
        }
    }
    return n;
}

enum refract_code ls_initial_wavefront(const struct lightsim_fields *f, const struct scene_light *l,
                                       const struct scene_lightsim *set, struct ls_patch **out,
                                       size_t *count, struct err *e)
{
    int N0 = set->initial_patches > 0 ? set->initial_patches : 1;
    size_t cap = (size_t)N0 * N0 * (l->kind == SCENE_LIGHT_DIRECTIONAL ? 1 : 6);
    *out = malloc(cap * sizeof **out);
    *count = 0;
    if (*out == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "out of memory for %zu initial patches; lower lightsim.initial_patches",
                       cap);
    struct aim a;
    ls_grid_box(&f->grid, &a.lo, &a.hi);
    *count = l->kind == SCENE_LIGHT_DIRECTIONAL ? directional(f, l, N0, &a, *out)
                                                : point(f, l, set, N0, &a, *out);
    return REFRACT_E_OK;
}

void ls_step_budget(const struct lightsim_fields *f, double dt, long long *max_steps,
                    double *t_sweep)
{
    vec3 lo, hi;
    ls_grid_box(&f->grid, &lo, &hi);
    double rho = 0.5 * vec3_length(vec3_sub(hi, lo));
    double n_max = f->ambient_ior;
    size_t v = (size_t)f->grid.dims[0] * f->grid.dims[1] * f->grid.dims[2];
    for (size_t i = 0; i < v; i++)
        n_max = fmax(n_max, f->ior_grad[4 * i + 3]);
    for (int k = 0; k < f->surface_count; k++)
        n_max = fmax(n_max, f->surfaces[k].ior);
    *max_steps = (long long)ceil(4.0 * n_max * rho * 2.0 / dt) + 16;
    *t_sweep = 2.0 * (rho + f->grid.voxel) * n_max;
}
