/*
 * lightsim_corner.c - a corner's move among exact surfaces; see lightsim_corner.h and
 * docs/lightsim.md "Surfaces".
 *
 * Why a corner at a time: a patch is four rays (tevs2007 sect. 4.2.3), and the thesis'
 * voxel method lets each of them bend through the smoothed interface on its own; its
 * area, and so the irradiance, follows from where the corners end up. Exact surfaces keep
 * that: each corner refracts where its own straight leg meets the surface. What the
 * voxel method cannot do, following the reflected wavefront, needs the four corners
 * together: the event's R is decided once for the patch, when its first corner crosses,
 * from every corner's crossing point (each corner's line is straight up to the surface
 * in a constant medium, so those points are known in advance), and the reflected twin
 * takes that share of the power while its pending corners reflect as they arrive.
 */
#include "lightsim_corner.h"

#include <math.h>

#include "../core/interface.h"
#include "lightsim_sample.h"
#include "lightsim_surfaces.h"

/* dx/dt = w / n^2, dw/dt = grad n / n (tevs2007 eqs. 4.12/4.13). */
static void ray_rhs(const struct lightsim_fields *f, vec3 x, vec3 w, vec3 *dx, vec3 *dw)
{
    double n;
    vec3 g;
    ls_sample_ior(f, x, &n, &g);
    *dx = vec3_scale(w, 1.0 / (n * n));
    *dw = vec3_scale(g, 1.0 / n);
}

void ls_propagate(const struct lightsim_fields *f, double dt, vec3 *x, vec3 *w)
{
    vec3 k1x, k1w, k2x, k2w;
    ray_rhs(f, *x, *w, &k1x, &k1w);
    vec3 xm = vec3_madd(*x, k1x, dt / 2), wm = vec3_madd(*w, k1w, dt / 2);
    ray_rhs(f, xm, wm, &k2x, &k2w);
    *x = vec3_madd(*x, k2x, dt);
    *w = vec3_madd(*w, k2w, dt);
}

/* The transmitted limit of total internal reflection: at the critical angle the refracted
 * ray runs along the surface, so a corner of the transmitted patch whose own ray is
 * totally reflected (it carries no transmitted power: R = 1 in the patch's share) keeps
 * the patch continuous by grazing the surface. */
static vec3 grazing(vec3 d, vec3 N)
{
    vec3 t = vec3_sub(d, vec3_scale(N, vec3_dot(d, N)));
    double len = vec3_length(t);
    return len > 1e-12 ? vec3_scale(t, 1.0 / len) : d;
}

/* Corner j's reflectance where its straight line meets surface s (0 and false when it
 * does not, within the domain's diagonal, or meets it where the index does not change). */
static bool predict(const struct ls_step_ctx *c, const struct ls_patch *p, int j, int s,
                    double *R)
{
    const struct lightsim_fields *f = c->f;
    vec3 d = vec3_normalize(p->w[j]);
    struct geom_hit h;
    *R = 0.0;
    if (!ls_surface_hit(f, s, p->x[j], d, p->last[j], c->reach, &h))
        return false;
    uint32_t next = p->inside[j] ^ (1u << s);
    int from = interface_medium(p->inside[j]), to = interface_medium(next);
    vec3 x = vec3_madd(p->x[j], d, h.t);
    double n_i = ls_medium_ior(f, from, x), n_t = ls_medium_ior(f, to, x);
    if (from == to || fabs(n_i - n_t) <= LS_INDEX_EPS)
        return false;
    *R = interface_cross(d, h.shading, n_i, n_t).R;
    return true;
}

/* Corner k crosses surface s at x (hit h) going along *d: docs/lightsim.md "Surfaces". */
static void cross(const struct ls_step_ctx *c, struct ls_patch *p, int k, int s,
                  const struct geom_hit *h, vec3 x, vec3 *d, bool may_spawn, struct ls_spawn *sp)
{
    const struct lightsim_fields *f = c->f;
    uint32_t next = p->inside[k] ^ (1u << s);
    int from = interface_medium(p->inside[k]), to = interface_medium(next);
    p->last[k] = s;
    double n_i = ls_medium_ior(f, from, x), n_t = ls_medium_ior(f, to, x);
    if (from == to || fabs(n_i - n_t) <= LS_INDEX_EPS) {
        p->inside[k] = next; /* inside a higher-priority solid, or index-matched */
        return;
    }
    struct interface_event ev = interface_cross(*d, h->shading, n_i, n_t);
    int bit = 1 << k;
    bool pending = p->ev_surface == s && (p->ev_mask & bit);
    if (!pending && p->ev_mask == 0 && may_spawn && !sp->spawned) {
        /* The event begins: R from every corner that will cross s. */
        double sum = ev.R, R;
        int mask = bit;
        for (int j = 0; j < 4; j++)
            if (j != k && predict(c, p, j, s, &R)) {
                sum += R;
                mask |= 1 << j;
            }
        sp->spawned = true;
        sp->surface = s;
        sp->mask = mask;
        sp->R_mean = 0.25 * sum;
        p->ev_surface = s;
        p->ev_mask = mask;
        p->ev_reflect = false;
        for (int ch = 0; ch < 3; ch++) {
            sp->P[ch] = p->P[ch];
            p->P[ch] *= 1.0 - sp->R_mean;
        }
        pending = true;
    }
    if (pending) {
        p->ev_mask &= ~bit;
        if (p->ev_reflect) {
            *d = ev.reflected; /* the twin: stays in its medium */
            return;
        }
        *d = ev.tir ? grazing(*d, h->shading) : ev.refracted;
        p->inside[k] = next;
        return;
    }
    /* Outside an event (another one is pending, or a twin's first step): the corner
     * refracts on its own and the patch loses its quarter's reflected power, which is not
     * followed; under total internal reflection it reflects and loses nothing. */
    p->ev_mask &= ~bit; /* a pending corner diverted by another surface no longer waits */
    if (ev.tir) {
        *d = ev.reflected;
        return;
    }
    for (int ch = 0; ch < 3; ch++) {
        double loss = 0.25 * ev.R * p->P[ch];
        c->st->flux_reflected[ch] += loss;
        p->P[ch] -= loss;
    }
    *d = ev.refracted;
    p->inside[k] = next;
}

void ls_corner_move(const struct ls_step_ctx *c, struct ls_patch *p, int k, bool may_spawn,
                    struct ls_spawn *sp, double tau[3])
{
    const struct lightsim_fields *f = c->f;
    if (f->surface_count == 0) {
        ls_propagate(f, c->dt, &p->x[k], &p->w[k]);
        return;
    }
    double left = c->dt; /* time still to travel */
    vec3 x = p->x[k], w = p->w[k];
    for (int leg = 0; leg < LS_MAX_LEGS && left > 0.0; leg++) {
        int m = interface_medium(p->inside[k]);
        struct geom_hit h;
        vec3 d = w;
        if (m >= 0) {
            /* a constant medium: a straight leg at speed 1/n (|w| = n) */
            const struct reftrace_surface *sf = &f->surfaces[m];
            double n = sf->ior, L = left / n;
            d = vec3_normalize(w);
            int s = ls_next_surface(f, x, d, p->last[k], L, &h);
            double t = s >= 0 ? h.t : L;
            x = vec3_madd(x, d, t);
            for (int ch = 0; ch < 3; ch++)
                tau[ch] += reftrace_surface_extinction(sf, ch) * t; /* Beer-Lambert over
                                      sigma_a + sigma_s: the scattered part leaves the beam */
            if (s < 0) {
                w = vec3_scale(d, n);
                break;
            }
            left = fmax(0.0, left - t * n);
            cross(c, p, k, s, &h, x, &d, may_spawn, sp);
        } else {
            /* the voxel field: the ray equation, cut where its chord meets a surface */
            vec3 x1 = x, w1 = w;
            ls_propagate(f, left, &x1, &w1);
            vec3 chord = vec3_sub(x1, x);
            double len = vec3_length(chord);
            int s = -1;
            if (len > 0.0) {
                d = vec3_scale(chord, 1.0 / len);
                s = ls_next_surface(f, x, d, p->last[k], len, &h);
            }
            if (s < 0) {
                x = x1;
                w = w1;
                break;
            }
            x = vec3_madd(x, d, h.t);
            left -= left * (h.t / len);
            cross(c, p, k, s, &h, x, &d, may_spawn, sp);
        }
        w = vec3_scale(d, ls_medium_ior(f, interface_medium(p->inside[k]), x));
    }
    p->x[k] = x;
    p->w[k] = w;
}
