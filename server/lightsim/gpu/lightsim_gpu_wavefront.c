/*
 * lightsim_gpu_wavefront.c - the initial wavefront on the host; see
 * lightsim_gpu_wavefront.h and docs/lightsim.md "Initial wavefront".
 */
#include "lightsim_gpu_wavefront.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static vec3 grid_max(const struct light_grid *g)
{
    return vec3_madd(g->bmin, vec3_make(g->dims[0], g->dims[1], g->dims[2]), g->voxel);
}

static bool inside(vec3 x, vec3 lo, vec3 hi)
{
    return x.x >= lo.x && x.y >= lo.y && x.z >= lo.z && x.x <= hi.x && x.y <= hi.y &&
           x.z <= hi.z;
}

void lightsim_fields_sample_ior(const struct lightsim_fields *f, vec3 x, double out[4])
{
    const struct light_grid *g = &f->grid;
    if (!inside(x, g->bmin, grid_max(g))) {
        out[0] = out[1] = out[2] = 0;
        out[3] = f->ambient_ior;
        return;
    }
    double v[3] = {(x.x - g->bmin.x) / g->voxel - 0.5, (x.y - g->bmin.y) / g->voxel - 0.5,
                   (x.z - g->bmin.z) / g->voxel - 0.5};
    int i0[3], i1[3];
    double t[3];
    for (int a = 0; a < 3; a++) {
        double c = fmin(fmax(v[a], 0.0), g->dims[a] - 1);
        int lo = (int)floor(c);
        int top = g->dims[a] >= 2 ? g->dims[a] - 2 : 0;
        if (lo > top)
            lo = top;
        i0[a] = lo;
        i1[a] = lo + 1 < g->dims[a] ? lo + 1 : g->dims[a] - 1;
        t[a] = c - lo;
    }
    for (int ch = 0; ch < 4; ch++)
        out[ch] = 0;
    for (int k = 0; k < 8; k++) {
        int ix = (k & 1) ? i1[0] : i0[0], iy = (k & 2) ? i1[1] : i0[1],
            iz = (k & 4) ? i1[2] : i0[2];
        double w = ((k & 1) ? t[0] : 1 - t[0]) * ((k & 2) ? t[1] : 1 - t[1]) *
                   ((k & 4) ? t[2] : 1 - t[2]);
        const double *s = &f->ior_grad[4 * (((size_t)iz * g->dims[1] + iy) * g->dims[0] + ix)];
        for (int ch = 0; ch < 4; ch++)
            out[ch] += w * s[ch];
    }
}

double lightsim_grid_rho(const struct light_grid *g, vec3 *centre)
{
    vec3 hi = grid_max(g);
    *centre = vec3_scale(vec3_add(g->bmin, hi), 0.5);
    return 0.5 * vec3_length(vec3_sub(hi, g->bmin));
}

double lightsim_fields_n_max(const struct lightsim_fields *f)
{
    double n = f->ambient_ior;
    size_t count = (size_t)f->grid.dims[0] * f->grid.dims[1] * f->grid.dims[2];
    for (size_t i = 0; i < count; i++)
        n = fmax(n, f->ior_grad[4 * i + 3]);
    return n;
}

/* Does the half-line x + t d, t >= 0, meet the box [lo, hi]? */
static bool ray_meets_box(vec3 x, vec3 d, vec3 lo, vec3 hi)
{
    double t0 = 0, t1 = INFINITY;
    for (int a = 0; a < 3; a++) {
        double xa = vec3_get(x, a), da = vec3_get(d, a);
        double la = vec3_get(lo, a), ha = vec3_get(hi, a);
        if (fabs(da) < 1e-30) {
            if (xa < la || xa > ha)
                return false;
            continue;
        }
        double ta = (la - xa) / da, tb = (ha - xa) / da;
        t0 = fmax(t0, fmin(ta, tb));
        t1 = fmin(t1, fmax(ta, tb));
    }
    return t0 <= t1;
}

struct builder {
    const struct lightsim_fields *f;
    const struct scene_lightsim *set;
    vec3 lo, hi;
    struct lightsim_wavefront *w;
    double sum_max_power;
};

/* Keeps the patch (corners x[], ray vectors r[], power P) if it is aimed at the domain. */
static void offer(struct builder *b, const vec3 x[4], const vec3 r[4], double power_scale,
                  const vec3 *spot_dir, double spot_cos)
{
    vec3 c = vec3_scale(vec3_add(vec3_add(x[0], x[1]), vec3_add(x[2], x[3])), 0.25);
    vec3 d = vec3_normalize(vec3_add(vec3_add(r[0], r[1]), vec3_add(r[2], r[3])));
    if (spot_dir != NULL && vec3_dot(d, *spot_dir) < spot_cos)
        return;
    double e_max = 0;
    for (int k = 0; k < 4; k++)
        e_max = fmax(e_max, vec3_length(vec3_sub(x[(k + 1) % 4], x[k])));
    vec3 grow = vec3_make(e_max, e_max, e_max);
    vec3 lo = vec3_sub(b->lo, grow), hi = vec3_add(b->hi, grow);
    if (!inside(c, lo, hi) && !ray_meets_box(c, d, lo, hi))
        return;
    vec3 D = vec3_cross(vec3_sub(x[2], x[0]), vec3_sub(x[3], x[1]));
    double P = 0.5 * vec3_length(D) * power_scale;
    struct lightsim_wavefront *w = b->w;
    w->kept++;
    b->sum_max_power += P;
    for (int ch = 0; ch < 3; ch++)
        w->flux_in[ch] += P;
    if (w->count >= b->set->max_patches) {
        for (int ch = 0; ch < 3; ch++)
            w->flux_dropped[ch] += P;
        return;
    }
    ls_patch *p = &w->patches[w->count++];
    memset(p, 0, sizeof *p);
    for (int k = 0; k < 4; k++) {
        p->x[k] = (vec4){(float)x[k].x, (float)x[k].y, (float)x[k].z, 0};
        p->w[k] = (vec4){(float)r[k].x, (float)r[k].y, (float)r[k].z, 0};
    }
    p->power = (vec4){(float)P, (float)P, (float)P, 0};
    p->state.w = inside(c, b->lo, b->hi) ? 1 : 0;
}

/* Corner (i, j) -> patch corners p00, p10, p11, p01 of patch (i, j). */
static const int corner_di[4] = {0, 1, 1, 0}, corner_dj[4] = {0, 0, 1, 1};

static void directional(struct builder *b, const struct scene_light *l, int n0)
{
    vec3 C;
    double rho = lightsim_grid_rho(&b->f->grid, &C);
    vec3 dir = vec3_normalize(l->direction);
    vec3 a = fabs(dir.y) > 0.9 ? vec3_make(1, 0, 0) : vec3_make(0, 1, 0);
    vec3 u = vec3_normalize(vec3_cross(dir, a));
    vec3 v = vec3_cross(dir, u);
    vec3 S = vec3_madd(C, dir, -(rho + b->f->grid.voxel));
    vec3 r = vec3_scale(dir, b->f->ambient_ior);
    for (int j = 0; j < n0; j++) {
        for (int i = 0; i < n0; i++) {
            vec3 x[4], w[4];
            for (int k = 0; k < 4; k++) {
                double s = -rho + 2 * rho * (i + corner_di[k]) / n0;
                double t = -rho + 2 * rho * (j + corner_dj[k]) / n0;
                x[k] = vec3_madd(vec3_madd(S, u, s), v, t);
                w[k] = r;
            }
            offer(b, x, w, 1.0, NULL, 0);
        }
    }
}

static void point(struct builder *b, const struct scene_light *l, int n0)
{
    /* Faces +x, -x, +y, -y, +z, -z with (s, t), s x t = f. */
    static const double axes[6][3][3] = {
        {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
    };
    double eps = b->set->point_radius;
    double nq[4];
    lightsim_fields_sample_ior(b->f, l->position, nq);
    bool spot = l->kind == SCENE_LIGHT_SPOT;
    vec3 spot_dir = vec3_normalize(l->direction);
    double spot_cos = cos(l->spot_angle_deg * M_PI / 180.0);
    for (int face = 0; face < 6; face++) {
        vec3 f = vec3_make(axes[face][0][0], axes[face][0][1], axes[face][0][2]);
        vec3 s = vec3_make(axes[face][1][0], axes[face][1][1], axes[face][1][2]);
        vec3 t = vec3_make(axes[face][2][0], axes[face][2][1], axes[face][2][2]);
        for (int j = 0; j < n0; j++) {
            for (int i = 0; i < n0; i++) {
                vec3 x[4], w[4];
                for (int k = 0; k < 4; k++) {
                    double a = -1 + 2.0 * (i + corner_di[k]) / n0;
                    double c = -1 + 2.0 * (j + corner_dj[k]) / n0;
                    vec3 d = vec3_normalize(vec3_madd(vec3_madd(f, s, a), t, c));
                    x[k] = vec3_madd(l->position, d, eps);
                    w[k] = vec3_scale(d, nq[3]);
                }
                offer(b, x, w, 1.0 / (eps * eps), spot ? &spot_dir : NULL, spot_cos);
            }
        }
    }
}

enum refract_code lightsim_wavefront_build(const struct lightsim_fields *f,
                                           const struct scene_light *l,
                                           const struct scene_lightsim *set,
                                           struct lightsim_wavefront *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    int n0 = set->initial_patches;
    size_t total = (size_t)n0 * n0 * (l->kind == SCENE_LIGHT_DIRECTIONAL ? 1 : 6);
    size_t cap = total < (size_t)set->max_patches ? total : (size_t)set->max_patches;
    out->patches = malloc((cap ? cap : 1) * sizeof *out->patches);
    if (out->patches == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "no host memory for the initial wavefront (%zu patches)", cap);
    struct builder b = {.f = f, .set = set, .lo = f->grid.bmin, .hi = grid_max(&f->grid), .w = out};
    if (l->kind == SCENE_LIGHT_DIRECTIONAL)
        directional(&b, l, n0);
    else
        point(&b, l, n0);
    out->mean_max_power = out->kept > 0 ? b.sum_max_power / out->kept : 0;
    return REFRACT_E_OK;
}

void lightsim_wavefront_free(struct lightsim_wavefront *w)
{
    free(w->patches);
    w->patches = NULL;
    w->count = 0;
}
