/*
 * reftrace_march.h - internal to the reference tracer: the state of docs/tracing.md
 * "The march" and the small helpers that reftrace.c (objects, surfaces) and
 * reftrace_bound.c (fields inside surfaces) share. Not a public interface.
 */
#ifndef REFRACT_REFTRACE_MARCH_H
#define REFRACT_REFTRACE_MARCH_H

#include <math.h>
#include <stdint.h>

#include "reftrace.h"

/* The state of docs/tracing.md "The march". */
/* The view ray's first internal reflection in a walter scene's scattering medium
 * (docs/walter.md "The view ray's reflection"): traced as a second ray after the first
 * one, its radiance weighted by w. */
struct march_deferred {
    bool set;
    vec3 x, d, w;
    uint32_t inside;
    int surface;
    int64_t prim;
};

struct march {
    const struct reftrace_settings *set;
    struct march_deferred *defer; /* NULL: no deferral (the deferred ray itself, traces) */
    vec3 x, d;                    /* world position and unit direction */
    double t_f;                   /* Fresnel throughput */
    vec3 alpha;                   /* optical depth per channel (tevs2007 eq. 5.9) */
    vec3 L;                       /* radiance gathered along the view ray */
    double opl;                   /* optical path length, world units */
    int steps;                    /* integration steps over the whole ray */
    bool running;
    enum ray_status status;
    bool crossed; /* met at least one object */
};

static inline vec3 exp_neg(vec3 a)
{
    return (vec3){exp(-a.x), exp(-a.y), exp(-a.z)};
}

/* frisvad2010's basic radiance: light that starts in a medium of index n reaches the
 * viewer in the ambient medium times (n_amb / n)^2 (docs/tracing.md "Basic radiance"). */
static inline double basic_radiance(const struct march *m, double n)
{
    double r = m->set->ambient_ior / n;
    return r * r;
}

static inline double throughput(const struct march *m)
{
    vec3 t = exp_neg(m->alpha);
    return m->t_f * fmax(t.x, fmax(t.y, t.z));
}

static inline void stop(struct march *m, enum ray_status status)
{
    m->status = status;
    m->running = false;
}

/* T_f * max(exp(-alpha)) below this: absorbed (docs/tracing.md constants). */
#define REFTRACE_ABSORBED_EPS 1e-6

/* The absorbed cut-off: render.min_throughput, REFTRACE_ABSORBED_EPS for 0, never for < 0. */
static inline double reftrace_absorbed_cut(const struct reftrace_settings *set)
{
    return set->min_throughput > 0.0   ? set->min_throughput
           : set->min_throughput < 0.0 ? 0.0
                                       : REFTRACE_ABSORBED_EPS;
}

/* The nearest surface crossing of the world ray x + t d (unit d), t < t_max; -1 when none.
 * last/last_prim: the surface (and mesh triangle) the ray left at its previous event,
 * searched from a small offset on (reftrace.c). */
int reftrace_next_surface(const struct reftrace_settings *set, vec3 x, vec3 d, double t_max,
                          int last, int64_t last_prim, struct geom_hit *hit);

/* What reftrace_bound_march leaves for the surface event. */
struct reftrace_bound_exit {
    struct geom_hit hit;
    double gap; /* the cut's residual (reftrace_event.step_gap), world units */
    double n_w; /* n on the inside at the event: the field's sample there, or |w| within half
                   a voxel of the object's bounds (docs/tracing.md "The rim") */
};

/* Marches through the field that fills surface `med` (set->surfaces[med].field) from m->x
 * along m->d with the scene's stepper, each step's chord tested against the surfaces and
 * the step cut where it crosses one (reftrace_bound.c). Returns the surface crossed, with
 * *out filled, m->x on the surface, m->d the direction there and the integrals accumulated;
 * or -1 when the ray stopped (m->running false). */
int reftrace_bound_march(struct march *m, int med, int last, int64_t last_prim,
                         struct reftrace_bound_exit *out);

/* n of the medium of surface `medium` at world point x: the constant, the bound field's
 * sample there, or the ambient index for -1. */
double reftrace_medium_ior(const struct reftrace_settings *set, int medium, vec3 x);

#endif
