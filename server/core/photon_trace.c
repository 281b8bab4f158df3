/*
 * photon_trace.c - emitting and tracing caustic photons (photon.h, docs/photons.md
 * "Emission", "Tracing"). The interface event and the medium rule are the path tracer's
 * (interface.h); the surfaces are the fast renderer's (geom/geom.h).
 */
#include "photon.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "interface.h"

static const struct pathtrace_medium *medium_of(const struct pathtrace_scene *s, uint32_t inside)
{
    int k = interface_medium(inside);
    return k < 0 ? &s->ambient : &s->surfaces[k].medium;
}

bool photon_surface_optical(const struct pathtrace_scene *s, int k)
{
    const struct pathtrace_medium *m = &s->surfaces[k].medium;
    if (m->ior != s->ambient.ior)
        return true;
    for (int c = 0; c < 3; c++)
        if (m->sigma_a[c] != s->ambient.sigma_a[c] || m->sigma_s[c] != s->ambient.sigma_s[c])
            return true;
    return false;
}

bool photon_target(const struct pathtrace_scene *s, vec3 *center, double *radius, int *unbounded)
{
    vec3 lo = vec3_make(INFINITY, INFINITY, INFINITY), hi = vec3_scale(lo, -1.0);
    bool any = false;
    if (unbounded)
        *unbounded = -1;
    for (int k = 0; k < s->surface_count; k++) {
        if (!photon_surface_optical(s, k))
            continue;
        vec3 a, b;
        geom_surface_bounds(&s->surfaces[k].geom, &a, &b);
        if (!vec3_is_finite(a) || !vec3_is_finite(b)) {
            if (unbounded)
                *unbounded = k;
            return false;
        }
        for (int ax = 0; ax < 3; ax++) {
            vec3_set(&lo, ax, fmin(vec3_get(lo, ax), vec3_get(a, ax)));
            vec3_set(&hi, ax, fmax(vec3_get(hi, ax), vec3_get(b, ax)));
        }
        any = true;
    }
    if (!any)
        return false;
    *center = vec3_scale(vec3_add(lo, hi), 0.5);
    /* A hair larger, so that a photon grazing the sphere's silhouette is in the cone. */
    *radius = 0.5 * vec3_length(vec3_sub(hi, lo)) * (1.0 + 1e-6) + 1e-12;
    return true;
}

/* A photon on its way: ray, inside set, power, and whether it touched an optical surface. */
struct ph_state {
    vec3 o, d;
    uint32_t inside;
    double power[3];
    bool caustic;
    int last_surface;
    int64_t last_prim;
};

static double eps_at(vec3 p)
{
    return 1e-9 * (1.0 + fmax(fabs(p.x), fmax(fabs(p.y), fabs(p.z))));
}

/* The cone from p that holds the target sphere: its axis and cos of its half angle; the
 * whole sphere of directions (cos -1) when p is inside it. */
static void target_cone(vec3 p, vec3 c, double r, vec3 *axis, double *cos_max)
{
    vec3 v = vec3_sub(c, p);
    double dist = vec3_length(v);
    if (dist <= r) {
        *axis = vec3_make(0.0, -1.0, 0.0);
        *cos_max = -1.0;
        return;
    }
    *axis = vec3_scale(v, 1.0 / dist);
    double s = r / dist;
    *cos_max = sqrt(fmax(0.0, 1.0 - s * s));
}

/* A unit vector uniformly on the sphere. */
static vec3 sample_sphere(struct pathtrace_rng *rng)
{
    double z = 1.0 - 2.0 * pathtrace_rng_uniform(rng),
           phi = 2.0 * M_PI * pathtrace_rng_uniform(rng);
    double s = sqrt(fmax(0.0, 1.0 - z * z));
    return vec3_make(s * cos(phi), s * sin(phi), z);
}

/* Emits photon k of light l (n_l photons from it) towards the target sphere (c, r): its
 * ray and the power it stands for (W; 0: a wasted sample, e.g. outside a spot's cone or
 * leaving the lamp's back). docs/photons.md "Emission". */
static void emit(const struct pathtrace_light *l, long n_l, vec3 c, double r,
                 struct pathtrace_rng *rng, struct ph_state *st)
{
    vec3 axis;
    double cos_max, w = 0.0;
    switch (l->kind) {
    case PATHTRACE_LIGHT_POINT:
    case PATHTRACE_LIGHT_SPOT: {
        target_cone(l->position, c, r, &axis, &cos_max);
        st->o = l->position;
        st->d = pathtrace_sample_cone(axis, cos_max, rng);
        double solid = 2.0 * M_PI * (1.0 - cos_max);
        bool in_cone =
            l->kind == PATHTRACE_LIGHT_POINT || vec3_dot(st->d, l->direction) >= l->cos_spot;
        w = in_cone ? solid : 0.0; /* I(omega) dOmega / pdf = I solid */
        break;
    }
    case PATHTRACE_LIGHT_SPHERE: {
        vec3 n = sample_sphere(rng);
        vec3 y = vec3_madd(l->position, n, l->radius);
        target_cone(y, c, r, &axis, &cos_max);
        st->o = vec3_madd(y, n, 1e-9 * (1.0 + l->radius));
        st->d = pathtrace_sample_cone(axis, cos_max, rng);
        double solid = 2.0 * M_PI * (1.0 - cos_max);
        double area = 4.0 * M_PI * l->radius * l->radius;
        /* L_e cos dA dOmega / (pdf_A pdf_omega) = L_e cos area solid */
        w = fmax(0.0, vec3_dot(n, st->d)) * area * solid;
        break;
    }
    case PATHTRACE_LIGHT_DIRECTIONAL: {
        /* A disk of radius r normal to the beam, 2 r before the target's centre. */
        vec3 d = l->direction, t, b;
        vec3 up = fabs(d.y) < 0.9 ? vec3_make(0.0, 1.0, 0.0) : vec3_make(1.0, 0.0, 0.0);
        t = vec3_normalize(vec3_cross(up, d));
        b = vec3_cross(d, t);
        double u = sqrt(pathtrace_rng_uniform(rng)) * r,
               phi = 2.0 * M_PI * pathtrace_rng_uniform(rng);
        vec3 o = vec3_madd(c, d, -2.0 * r);
        o = vec3_madd(o, t, u * cos(phi));
        st->o = vec3_madd(o, b, u * sin(phi));
        st->d = d;
        w = M_PI * r * r; /* E dA / pdf_A */
        break;
    }
    }
    for (int ch = 0; ch < 3; ch++)
        st->power[ch] = l->value[ch] * w / (double)n_l;
}

static enum refract_code store(struct photon_list *out, vec3 p, const double power[3],
                               struct err *e)
{
    if (out->count == out->capacity) {
        size_t cap = out->capacity ? 2 * out->capacity : 4096;
        struct photon *n = realloc(out->items, cap * sizeof *n);
        if (n == NULL)
            return err_set(e, REFRACT_E_OUT_OF_MEMORY, "photons: out of memory storing %zu photons",
                           cap);
        out->items = n;
        out->capacity = cap;
    }
    struct photon *ph = &out->items[out->count++];
    ph->x = p.x;
    ph->z = p.z;
    for (int c = 0; c < 3; c++) {
        ph->power[c] = power[c];
        out->landed[c] += power[c];
    }
    return REFRACT_E_OK;
}

/* Follows one photon until it lands on the receiver (stored when it is a caustic photon),
 * leaves the scene or has made PHOTON_MAX_EVENTS events. */
static enum refract_code follow(const struct pathtrace_scene *s, struct ph_state *st,
                                struct pathtrace_rng *rng, struct photon_list *out, struct err *e)
{
    for (int events = 0; events < PHOTON_MAX_EVENTS; events++) {
        double tmin = eps_at(st->o), t_best = INFINITY;
        int hit = -1;
        struct geom_hit best = {0};
        for (int k = 0; k < s->surface_count; k++) {
            struct geom_hit gh;
            int64_t skip = k == st->last_surface ? st->last_prim : -1;
            if (geom_surface_intersect(&s->surfaces[k].geom, st->o, st->d, tmin, t_best, skip,
                                       &gh)) {
                t_best = gh.t;
                hit = k;
                best = gh;
            }
        }
        double t_recv;
        bool lands = pathtrace_receiver_hit(&s->receiver, st->o, st->d, tmin, t_best, &t_recv);
        double seg = lands ? t_recv : t_best;
        if (isfinite(seg)) {
            double tr[3] = {1.0, 1.0, 1.0};
            pathtrace_medium_transmittance(medium_of(s, st->inside), seg, tr);
            for (int c = 0; c < 3; c++)
                st->power[c] *= tr[c];
        }
        if (lands) {
            if (!st->caustic)
                return REFRACT_E_OK; /* direct light: the shadow ray's part */
            return store(out, vec3_madd(st->o, st->d, t_recv), st->power, e);
        }
        if (hit < 0)
            return REFRACT_E_OK; /* left the scene */
        vec3 p = vec3_madd(st->o, st->d, best.t);
        uint32_t next = st->inside ^ (1u << hit);
        double n_i = medium_of(s, st->inside)->ior, n_t = medium_of(s, next)->ior;
        if (photon_surface_optical(s, hit))
            st->caustic = true;
        st->o = p;
        st->last_surface = hit;
        st->last_prim = best.prim;
        if (n_i == n_t) {
            st->inside = next;
            continue;
        }
        struct interface_event ev = interface_cross(st->d, best.shading, n_i, n_t);
        if (ev.tir || pathtrace_rng_uniform(rng) < ev.R) {
            st->d = ev.reflected;
        } else {
            st->d = ev.refracted;
            st->inside = next;
        }
    }
    for (int c = 0; c < 3; c++)
        out->lost[c] += st->power[c];
    return REFRACT_E_OK;
}

enum refract_code photon_trace(const struct pathtrace_scene *s, long count, uint64_t seed,
                               long first, long stride, struct photon_list *out, struct err *e)
{
    vec3 c;
    double r;
    int unbounded;
    for (int k = 0; k < s->surface_count; k++)
        if (pathtrace_medium_scatters(&s->surfaces[k].medium))
            return err_set(e, REFRACT_E_CONFLICT,
                           "photons: surface %d's medium scatters; caustic photons do not "
                           "scatter in media yet (docs/photons.md \"Not yet\"): use the "
                           "light simulator's caustics (\"caustics\": \"volume\")",
                           k);
    if (!photon_target(s, &c, &r, &unbounded)) {
        if (unbounded >= 0)
            return err_set(e, REFRACT_E_CONFLICT,
                           "photons: surface %d is unbounded (an infinite plane); caustic "
                           "photons need bounded surfaces (docs/photons.md \"Not yet\"): use "
                           "\"caustics\": \"volume\"",
                           unbounded);
        return REFRACT_E_OK; /* nothing optical: no caustic */
    }
    if (s->light_count <= 0 || count <= 0 || !s->receiver.enabled)
        return REFRACT_E_OK;
    if (stride < 1)
        stride = 1;
    long per_light = count / s->light_count;
    if (per_light < 1)
        per_light = 1;
    for (int j = 0; j < s->light_count; j++) {
        for (long k = first; k < per_light; k += stride) {
            struct pathtrace_rng rng;
            pathtrace_rng_init(&rng, seed, (uint64_t)j, (uint64_t)k);
            struct ph_state st = {.last_surface = -1, .last_prim = -1};
            emit(&s->lights[j], per_light, c, r, &rng, &st);
            out->emitted++;
            if (st.power[0] <= 0.0 && st.power[1] <= 0.0 && st.power[2] <= 0.0)
                continue;
            st.inside = pathtrace_inside_set(s, st.o);
            enum refract_code rc = follow(s, &st, &rng, out, e);
            if (rc != REFRACT_E_OK)
                return rc;
        }
    }
    return REFRACT_E_OK;
}

enum refract_code photon_list_merge(struct photon_list *a, const struct photon_list *b,
                                    struct err *e)
{
    if (b->count > 0) {
        size_t need = a->count + b->count;
        if (need > a->capacity) {
            struct photon *n = realloc(a->items, need * sizeof *n);
            if (n == NULL)
                return err_set(e, REFRACT_E_OUT_OF_MEMORY, "photons: out of memory merging lists");
            a->items = n;
            a->capacity = need;
        }
        memcpy(a->items + a->count, b->items, b->count * sizeof *b->items);
        a->count = need;
    }
    a->emitted += b->emitted;
    for (int c = 0; c < 3; c++) {
        a->lost[c] += b->lost[c];
        a->landed[c] += b->landed[c];
    }
    return REFRACT_E_OK;
}

static void scale_items(struct photon_list *l, size_t from, size_t to, double f)
{
    for (size_t i = from; i < to; i++)
        for (int c = 0; c < 3; c++)
            l->items[i].power[c] *= f;
}

enum refract_code photon_list_accumulate(struct photon_list *acc, long acc_count,
                                         const struct photon_list *batch, long batch_count,
                                         struct err *e)
{
    double total = (double)acc_count + (double)batch_count;
    if (!(total > 0.0))
        return REFRACT_E_OK;
    double wa = (double)acc_count / total, wb = (double)batch_count / total;
    size_t first = acc->count;
    double lost[3], landed[3];
    for (int c = 0; c < 3; c++) {
        lost[c] = acc->lost[c] * wa + batch->lost[c] * wb;
        landed[c] = acc->landed[c] * wa + batch->landed[c] * wb;
    }
    enum refract_code rc = photon_list_merge(acc, batch, e);
    if (rc != REFRACT_E_OK)
        return rc;
    scale_items(acc, 0, first, wa);
    scale_items(acc, first, acc->count, wb);
    for (int c = 0; c < 3; c++) {
        acc->lost[c] = lost[c];
        acc->landed[c] = landed[c];
    }
    return REFRACT_E_OK;
}

void photon_list_free(struct photon_list *l)
{
    free(l->items);
    memset(l, 0, sizeof *l);
}

double photon_radius(const struct pathtrace_scene *s, long count, double radius_setting)
{
    if (radius_setting > 0.0)
        return radius_setting;
    vec3 c;
    double r;
    if (!photon_target(s, &c, &r, NULL))
        return 0.0;
    double n = count > 0 ? (double)count : 1.0;
    return PHOTON_RADIUS_SCENE * r * pow(n / (double)PHOTON_RADIUS_COUNT, -1.0 / 6.0);
}
