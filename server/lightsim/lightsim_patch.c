/*
 * lightsim_patch.c - patch geometry: derived quantities, split, box tests. See
 * lightsim_patch.h and docs/lightsim.md "Patches".
 */
#include "lightsim_patch.h"

#include <math.h>
#include <stddef.h>

void ls_patch_derive(const struct ls_patch *p, struct ls_derived *out)
{
    vec3 c = {0, 0, 0}, ws = {0, 0, 0};
    for (int k = 0; k < 4; k++) {
        c = vec3_add(c, p->x[k]);
        ws = vec3_add(ws, p->w[k]);
    }
    out->c = vec3_scale(c, 0.25);
    out->d = vec3_normalize(ws);
    out->D = vec3_cross(vec3_sub(p->x[2], p->x[0]), vec3_sub(p->x[3], p->x[1]));
    out->area = 0.5 * vec3_length(out->D);
    double e = 0.0;
    for (int k = 0; k < 4; k++) {
        double len = vec3_length(vec3_sub(p->x[(k + 1) % 4], p->x[k]));
        e = len > e ? len : e;
    }
    out->e_max = e;
}

bool ls_patch_oriented(const struct ls_derived *g)
{
    return vec3_dot(g->D, g->d) > 0.0;
}

/* Mean position of n corners, and the mean ray vector rescaled to the mean length of
 * the vectors it came from, so a new particle keeps its parents' optical speed. */
static void mean_particle(const struct ls_patch *p, const int *idx, int n, vec3 *x, vec3 *w)
{
    vec3 xs = {0, 0, 0}, ws = {0, 0, 0};
    double len = 0.0;
    for (int k = 0; k < n; k++) {
        xs = vec3_add(xs, p->x[idx[k]]);
        ws = vec3_add(ws, p->w[idx[k]]);
        len += vec3_length(p->w[idx[k]]);
    }
    *x = vec3_scale(xs, 1.0 / n);
    *w = vec3_scale(vec3_normalize(ws), len / n);
}

/* Inside set of a new corner at x (docs/lightsim.md "Surfaces": a patch whose corners
 * lie in different media is split like any other, each new corner taking the set of the
 * point where it is). */
static uint32_t new_corner_set(const struct ls_patch *p, bool same, ls_inside_fn inside,
                               const void *ctx, vec3 x, int near)
{
    if (same || inside == NULL)
        return p->inside[near];
    return inside(ctx, x);
}

void ls_patch_split(const struct ls_patch *p, ls_inside_fn inside, const void *ctx,
                    struct ls_patch child[4])
{
    static const int edges[4][2] = {{0, 1}, {1, 2}, {2, 3}, {3, 0}};
    static const int all[4] = {0, 1, 2, 3};
    vec3 mx[4], mw[4], cx, cw;
    for (int k = 0; k < 4; k++)
        mean_particle(p, edges[k], 2, &mx[k], &mw[k]);
    mean_particle(p, all, 4, &cx, &cw);
    /* Children [p00, m0, mc, m3], [m0, p10, m1, mc], [mc, m1, p11, m2], [m3, mc, m2, p01]:
     * child k has parent corner k at position k. */
    const vec3 cxs[4][4] = {{p->x[0], mx[0], cx, mx[3]},
                            {mx[0], p->x[1], mx[1], cx},
                            {cx, mx[1], p->x[2], mx[2]},
                            {mx[3], cx, mx[2], p->x[3]}};
    const vec3 cws[4][4] = {{p->w[0], mw[0], cw, mw[3]},
                            {mw[0], p->w[1], mw[1], cw},
                            {cw, mw[1], p->w[2], mw[2]},
                            {mw[3], cw, mw[2], p->w[3]}};
    bool same = p->inside[0] == p->inside[1] && p->inside[0] == p->inside[2] &&
                p->inside[0] == p->inside[3];
    uint32_t ms[4], cs = new_corner_set(p, same, inside, ctx, cx, 0);
    for (int k = 0; k < 4; k++)
        ms[k] = new_corner_set(p, same, inside, ctx, mx[k], k);
    const uint32_t csets[4][4] = {{p->inside[0], ms[0], cs, ms[3]},
                                  {ms[0], p->inside[1], ms[1], cs},
                                  {cs, ms[1], p->inside[2], ms[2]},
                                  {ms[3], cs, ms[2], p->inside[3]}};
    double areas[4], sum = 0.0;
    for (int k = 0; k < 4; k++) {
        child[k] = *p;
        child[k].level = p->level + 1;
        /* the parent flushed its pending deposit before splitting */
        child[k].pend[0] = child[k].pend[1] = child[k].pend[2] = 0.0;
        child[k].pend_steps = 0;
        for (int q = 0; q < 4; q++) {
            child[k].x[q] = cxs[k][q];
            child[k].w[q] = cws[k][q];
            child[k].inside[q] = csets[k][q];
            child[k].last[q] = q == k ? p->last[k] : -1; /* parent corner k stays at q = k */
        }
        struct ls_derived g;
        ls_patch_derive(&child[k], &g);
        areas[k] = g.area;
        sum += g.area;
    }
    for (int k = 0; k < 4; k++) {
        double share = sum > 0.0 ? areas[k] / sum : 0.25; /* degenerate quad: equal shares */
        for (int ch = 0; ch < 3; ch++)
            child[k].P[ch] = p->P[ch] * share;
    }
}

bool ls_box_contains(vec3 lo, vec3 hi, vec3 p)
{
    return p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z;
}

bool ls_halfline_meets_box(vec3 o, vec3 d, vec3 lo, vec3 hi)
{
    double t0 = 0.0, t1 = INFINITY;
    for (int a = 0; a < 3; a++) {
        double oa = vec3_get(o, a), da = vec3_get(d, a);
        double la = vec3_get(lo, a), ha = vec3_get(hi, a);
        if (da == 0.0) {
            if (oa < la || oa > ha)
                return false;
            continue;
        }
        double ta = (la - oa) / da, tb = (ha - oa) / da;
        if (ta > tb) {
            double tmp = ta;
            ta = tb;
            tb = tmp;
        }
        t0 = ta > t0 ? ta : t0;
        t1 = tb < t1 ? tb : t1;
        if (t0 > t1)
            return false;
    }
    return true;
}
