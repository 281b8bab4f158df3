/*
 * lightsim_step.c - one time step of one patch; see lightsim_step.h and docs/lightsim.md
 * "A time step". Every particle advances by the same time dt, so the wavefront stays
 * equitemporal (tevs2007 sect. 4.2.3) and the patch area stays meaningful.
 */
#include "lightsim_step.h"

#include <math.h>

#include "../core/fresnel.h"
#include "lightsim_corner.h"
#include "lightsim_sample.h"
#include "lightsim_surfaces.h"

static void add3(double dst[3], const double P[3], double factor)
{
    for (int ch = 0; ch < 3; ch++)
        dst[ch] += P[ch] * factor;
}

static double max3(const double P[3])
{
    return fmax(P[0], fmax(P[1], P[2]));
}

/* Step 3: the interface zone and its one Fresnel transmission event. */
static void interface(const struct ls_step_ctx *c, struct ls_patch *p, const struct ls_sample *s0,
                      const struct ls_sample *s1, vec3 c1, vec3 w1)
{
    const struct lightsim_fields *f = c->f;
    double gl = vec3_length(s1->grad);
    double g = gl * f->grid.voxel;
    if (!p->in_zone && g > f->boundary_threshold) {
        vec3 N = vec3_scale(s1->grad, 1.0 / gl);
        vec3 unused;
        ls_sample_ior(f, vec3_madd(c1, N, -f->probe_distance), &p->n_lo, &unused);
        ls_sample_ior(f, vec3_madd(c1, N, f->probe_distance), &p->n_hi, &unused);
        p->in_zone = true;
        p->crossed = false;
    }
    if (p->in_zone && !p->crossed) {
        double n_mid = 0.5 * (p->n_lo + p->n_hi);
        if ((s0->n >= n_mid) != (s1->n >= n_mid)) {
            vec3 N = gl > 0.0 ? vec3_scale(s1->grad, 1.0 / gl) : vec3_normalize(w1);
            bool rising = s1->n > s0->n;
            double n_i = rising ? p->n_lo : p->n_hi, n_t = rising ? p->n_hi : p->n_lo;
            /* The ray equation changes w = n d only along grad n, so w's tangential part
             * is the incident side's n_i sin(theta_i) wherever in the smoothed interface
             * the crossing is seen (Snell's invariant, tevs2007 sect. 5.2). */
            double w_t = vec3_length(vec3_cross(w1, N));
            /* w_t >= n_t: total internal reflection, the ray equation turns the wavefront
             * round. w_t >= n_i: the wavefront cannot have come from the n_i side (there
             * |w| = n_i); it is one that turned round inside the smoothed zone and comes
             * back (or creeps along it): no surface is crossed. */
            if (w_t < n_t && w_t < n_i) {
                double sin_i = fmin(1.0, w_t / n_i);
                double cos_i = sqrt(1.0 - sin_i * sin_i);
                double R = fresnel_unpolarized(cos_i, n_i, n_t);
                add3(c->st->flux_reflected, p->P, R);
                for (int ch = 0; ch < 3; ch++)
                    p->P[ch] *= 1.0 - R;
                p->crossed = true;
            }
        }
    }
    if (p->in_zone && g < 0.5 * f->boundary_threshold)
        p->in_zone = false;
}

/* Cubic B-spline weights of the 4 voxels i0 - 1 .. i0 + 2 about fraction f = v - i0.
 * They sum to 1 for every f, and their Fourier transform (sinc^4) suppresses the ripple
 * of a lattice of splats to <= 0.45 % for any spacing up to one voxel (the tent's sinc^2
 * leaves 12 %): docs/lightsim.md step 5. */
static void bspline_weights(double f, double w[4])
{
    double g = 1.0 - f;
    w[0] = g * g * g / 6.0;
    w[1] = 2.0 / 3.0 - f * f + 0.5 * f * f * f;
    w[2] = 2.0 / 3.0 - g * g + 0.5 * g * g * g;
    w[3] = f * f * f / 6.0;
}

/* Flux mode's direction: q_lum d' with trilinear weights over the 2 x 2 x 2 voxels about
 * m. Only its normalised mean is used, so the tent's ripple does not matter here. */
static void deposit_direction(const struct ls_step_ctx *c, double q_lum, vec3 m, vec3 d1)
{
    const struct light_grid *g = &c->f->grid;
    vec3 v = vec3_sub(vec3_scale(vec3_sub(m, g->bmin), 1.0 / g->voxel), (vec3){0.5, 0.5, 0.5});
    int i0[3];
    double w[3][2];
    for (int a = 0; a < 3; a++) {
        double va = vec3_get(v, a);
        double fl = floor(va);
        if (!(fl > -2.0 && fl < g->dims[a])) /* all 8 outside, or NaN */
            return;
        i0[a] = (int)fl;
        w[a][1] = va - fl;
        w[a][0] = 1.0 - w[a][1];
    }
    for (int kz = 0; kz < 2; kz++) {
        int z = i0[2] + kz;
        if (z < 0 || z >= g->dims[2])
            continue;
        for (int ky = 0; ky < 2; ky++) {
            int y = i0[1] + ky;
            if (y < 0 || y >= g->dims[1])
                continue;
            for (int kx = 0; kx < 2; kx++) {
                int x = i0[0] + kx;
                if (x < 0 || x >= g->dims[0])
                    continue;
                double wt = w[0][kx] * w[1][ky] * w[2][kz] * q_lum;
                size_t o =
                    3 * ((size_t)x + (size_t)g->dims[0] * ((size_t)y + (size_t)g->dims[1] * z));
                c->acc_d[o + 0] += wt * d1.x;
                c->acc_d[o + 1] += wt * d1.y;
                c->acc_d[o + 2] += wt * d1.z;
            }
        }
    }
}

/* Step 5, flux mode: q splatted about m with cubic B-spline weights, the direction
 * q_lum d' trilinearly. */
static void deposit_flux(const struct ls_step_ctx *c, const double q[3], vec3 m, vec3 d1)
{
    const struct light_grid *g = &c->f->grid;
    deposit_direction(c, (q[0] + q[1] + q[2]) / 3.0, m, d1);
    vec3 v = vec3_sub(vec3_scale(vec3_sub(m, g->bmin), 1.0 / g->voxel), (vec3){0.5, 0.5, 0.5});
    int i0[3];
    double w[3][4];
    for (int a = 0; a < 3; a++) {
        double va = vec3_get(v, a);
        double fl = floor(va);
        if (!(fl > -3.0 && fl < g->dims[a] + 1.0)) /* all 64 outside, or NaN */
            return;
        i0[a] = (int)fl - 1;
        bspline_weights(va - fl, w[a]);
    }
    for (int kz = 0; kz < 4; kz++) {
        int z = i0[2] + kz;
        if (z < 0 || z >= g->dims[2])
            continue;
        for (int ky = 0; ky < 4; ky++) {
            int y = i0[1] + ky;
            if (y < 0 || y >= g->dims[1])
                continue;
            for (int kx = 0; kx < 4; kx++) {
                int x = i0[0] + kx;
                if (x < 0 || x >= g->dims[0])
                    continue;
                double wt = w[0][kx] * w[1][ky] * w[2][kz];
                size_t o =
                    3 * ((size_t)x + (size_t)g->dims[0] * ((size_t)y + (size_t)g->dims[1] * z));
                for (int ch = 0; ch < 3; ch++)
                    c->acc_e[o + ch] += wt * q[ch];
            }
        }
    }
}

/* Step 5, flux mode: deposits the pending sum, q = sum(P ds) / voxel^3, at the midpoint
 * of the pending segment pend_from .. to, with direction d, and clears it. */
static void flush_pending(const struct ls_step_ctx *c, struct ls_patch *p, vec3 to, vec3 d)
{
    if (p->pend_steps == 0)
        return;
    double vol = c->f->grid.voxel * c->f->grid.voxel * c->f->grid.voxel;
    double q[3];
    for (int ch = 0; ch < 3; ch++) {
        q[ch] = p->pend[ch] / vol;
        p->pend[ch] = 0.0;
    }
    deposit_flux(c, q, vec3_scale(vec3_add(p->pend_from, to), 0.5), d);
    p->pend_steps = 0;
}

/* Step 5, max mode (tevs2007 sect. 6.2.3): the voxel containing m keeps the largest
 * patch irradiance; the direction is accumulated as in flux mode. */
static void deposit_max(const struct ls_step_ctx *c, const double P[3], const double q[3],
                        double area, vec3 m, vec3 d1)
{
    const struct light_grid *g = &c->f->grid;
    int idx[3];
    for (int a = 0; a < 3; a++) {
        double va = floor((vec3_get(m, a) - vec3_get(g->bmin, a)) / g->voxel);
        if (!(va >= 0.0 && va < g->dims[a]))
            return;
        idx[a] = (int)va;
    }
    size_t o = 3 * ((size_t)idx[0] + (size_t)g->dims[0] * (idx[1] + (size_t)g->dims[1] * idx[2]));
    double floor_area = 0.01 * g->voxel * 0.01 * g->voxel;
    double a = area > floor_area ? area : floor_area;
    for (int ch = 0; ch < 3; ch++) {
        double E = P[ch] / a;
        if (E > c->acc_e[o + ch])
            c->acc_e[o + ch] = E;
    }
    double q_lum = (q[0] + q[1] + q[2]) / 3.0;
    c->acc_d[o + 0] += q_lum * d1.x;
    c->acc_d[o + 1] += q_lum * d1.y;
    c->acc_d[o + 2] += q_lum * d1.z;
}

static uint32_t inside_at(const void *ctx, vec3 x)
{
    return ls_surfaces_inside(ctx, x);
}

/* Step 6: the patch's fate, in the order of docs/lightsim.md. A patch with a pending
 * surface event is neither flip-tested nor split (its corners are on both sides of the
 * event), nor is a twin in its first step (may_split). */
static enum ls_fate fate_of(const struct ls_step_ctx *c, struct ls_patch *p,
                            const struct ls_derived *g1, bool may_split, struct ls_patch child[4])
{
    struct lightsim_stats *st = c->st;
    if (!ls_box_contains(c->lo, c->hi, g1->c) &&
        !ls_halfline_meets_box(g1->c, g1->d, c->lo, c->hi)) {
        add3(st->flux_out, p->P, 1.0);
        return LS_DIES;
    }
    if (max3(p->P) < c->energy_floor) {
        add3(st->flux_culled, p->P, 1.0);
        st->culled_energy++;
        return LS_DIES;
    }
    if (c->set->cull_flipped && p->ev_mask == 0 && !ls_patch_oriented(g1)) {
        add3(st->flux_culled, p->P, 1.0);
        st->culled_flip++;
        return LS_DIES;
    }
    if (g1->e_max > c->set->split_voxels * c->f->grid.voxel) {
        if (!may_split || p->ev_mask != 0)
            return LS_LIVES;
        if (p->level < c->set->max_level) {
            ls_patch_split(p, c->f->surface_count > 0 ? inside_at : NULL, c->f, child);
            st->splits++;
            return LS_SPLITS;
        }
        add3(st->flux_culled, p->P, 1.0);
        st->culled_level++;
        return LS_DIES;
    }
    return LS_LIVES;
}

/* Steps 1-6 of one patch; may_spawn: a surface event may begin (not in a twin's first
 * step, which is also not split). */
static enum ls_fate step_one(const struct ls_step_ctx *c, struct ls_patch *p, bool may_spawn,
                             struct ls_spawn *sp, struct ls_patch child[4])
{
    const struct lightsim_fields *f = c->f;
    struct lightsim_stats *st = c->st;
    struct ls_derived g0, g1;
    ls_patch_derive(p, &g0);

    /* 1. propagate every corner (docs/lightsim.md "Surfaces" among exact surfaces) */
    double tau[4][3] = {{0}};
    for (int k = 0; k < 4; k++)
        ls_corner_move(c, p, k, may_spawn, sp, tau[k]);
    ls_patch_derive(p, &g1);

    /* 2. path and extinction (trapezoid of sigma_t along the centre's path; in the
     * surfaces' media Beer-Lambert along each corner's legs, averaged over the corners) */
    struct ls_sample s0, s1;
    ls_sample_all(f, g0.c, &s0);
    ls_sample_all(f, g1.c, &s1);
    double ds = vec3_length(vec3_sub(g1.c, g0.c));
    for (int ch = 0; ch < 3; ch++) {
        double T = exp(-0.5 * (s0.sigma[ch] + s1.sigma[ch]) * ds);
        if (f->surface_count > 0)
            T *= 0.25 * (exp(-tau[0][ch]) + exp(-tau[1][ch]) + exp(-tau[2][ch]) +
                         exp(-tau[3][ch]));
        st->flux_absorbed[ch] += p->P[ch] * (1.0 - T);
        p->P[ch] *= T;
    }

    /* 3. interface */
    vec3 w1 = vec3_scale(vec3_add(vec3_add(p->w[0], p->w[1]), vec3_add(p->w[2], p->w[3])), 0.25);
    interface(c, p, &s0, &s1, g1.c, w1);

    /* 4. opaque: the steps before this one (pending, they ended at c) are deposited */
    bool flux = c->set->deposit != SCENE_DEPOSIT_MAX;
    if (s1.coverage >= 0.5) {
        if (flux)
            flush_pending(c, p, g0.c, g0.d);
        add3(st->flux_absorbed, p->P, 1.0);
        return LS_DIES;
    }

    /* 5. deposit: max mode at every step's midpoint; flux mode accumulates P ds and
     * deposits every deposit_every steps and before the patch dies or splits */
    if (flux) {
        if (p->pend_steps == 0)
            p->pend_from = g0.c;
        add3(p->pend, p->P, ds);
        p->pend_steps++;
    } else {
        vec3 m = vec3_scale(vec3_add(g0.c, g1.c), 0.5);
        double vol = f->grid.voxel * f->grid.voxel * f->grid.voxel;
        double q[3];
        for (int ch = 0; ch < 3; ch++)
            q[ch] = p->P[ch] * ds / vol;
        deposit_max(c, p->P, q, g1.area, m, g1.d);
    }

    enum ls_fate fate = fate_of(c, p, &g1, may_spawn, child);
    if (flux && (fate != LS_LIVES || p->pend_steps >= c->deposit_every))
        flush_pending(c, p, g1.c, g1.d);
    return fate;
}

/* Swaps corners 1 and 3 (p10 and p01): the quad's winding, and so its orientation
 * sign(dot(D, d)), reverses, which a mirror image needs to come out positive. */
static void swap_winding(struct ls_patch *p)
{
    vec3 x = p->x[1], w = p->w[1];
    uint32_t in = p->inside[1];
    int last = p->last[1];
    p->x[1] = p->x[3];
    p->w[1] = p->w[3];
    p->inside[1] = p->inside[3];
    p->last[1] = p->last[3];
    p->x[3] = x;
    p->w[3] = w;
    p->inside[3] = in;
    p->last[3] = last;
    int m = p->ev_mask;
    p->ev_mask = (m & 5) | ((m & 2) << 2) | ((m & 8) >> 2);
}

enum ls_fate ls_patch_step(const struct ls_step_ctx *c, struct ls_patch *p,
                           struct ls_patch child[4], struct ls_patch *twin,
                           enum ls_fate *twin_fate)
{
    struct ls_patch before = *p;
    struct ls_spawn sp = {.spawned = false};
    enum ls_fate fate = step_one(c, p, true, &sp, child);
    *twin_fate = LS_DIES;
    if (sp.spawned) {
        /* The reflected twin (docs/lightsim.md "Surfaces"): the patch as it was before
         * this step, with the event's share of the power (of the power when it began: a
         * corner may have lost some earlier in the step) and every crossing corner
         * pending, stepped now so that the wavefront stays equitemporal. */
        *twin = before;
        for (int ch = 0; ch < 3; ch++) {
            twin->P[ch] = sp.P[ch] * sp.R_mean;
            twin->pend[ch] = 0.0;
        }
        twin->pend_steps = 0;
        twin->ev_surface = sp.surface;
        twin->ev_mask = sp.mask;
        twin->ev_reflect = true;
        swap_winding(twin);
        struct ls_spawn none = {.spawned = false};
        struct ls_patch unused[4];
        *twin_fate = step_one(c, twin, false, &none, unused);
    }
    return fate;
}
