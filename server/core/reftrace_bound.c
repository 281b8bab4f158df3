/*
 * reftrace_bound.c - the reference march through a field that fills an exact surface
 * (docs/tracing.md "Fields inside surfaces"; the medium "object" form of docs/scenes.md):
 * a GRIN lens bounded by its exact sphere.
 *
 * Inside such a surface the ray follows the ray equation (tevs2007 eqs. 4.8/4.9) through
 * the bound object's field with the scene's stepper, from the surface it entered by to the
 * next surface it meets. Each step's chord is tested against every surface; a step whose
 * chord crosses one is cut there: its length s is shortened (secant on where the chord
 * meets the surface, bisection when the secant leaves the bracket) until the chord's hit
 * lies within 1e-6 of the step from the step's end. The event point is that hit, exactly on
 * the surface, and the direction is the step's there. Where n is the same everywhere
 * (reftrace_object.ior_constant) a step is straight, its chord is the path and the first
 * cut is exact: only the integrals are stepped. The integrals (optical path, optical depth
 * over sigma_a + sigma_s, emission) use the trapezoid rule per step as in the voxel march.
 *
 * The GLSL twin is march_through_bound in shaders/ray_march.glsl.
 *
 * Not modelled inside a surface (model only what a scene needs; the scene parser refuses
 * what would need them): opaque embeddings, the sharp-boundary Fresnel zones of the voxel
 * march (a field in a surface is a GRIN medium; its sharp boundary is the surface), empty-
 * space skipping, in-scattering (the light simulator does not run for these scenes). The
 * adaptive Dormand-Prince reference steps the ray with its error control but integrates the
 * optical path by the trapezoid rule too.
 */
#include <math.h>

#include "reftrace_integrate.h"
#include "reftrace_march.h"

#define CUT_REL 1e-6       /* the cut's residual, relative to the step (world units) */
#define CUT_MAX_ITER 64    /* secant/bisection iterations of one cut */
#define CONTROL_SAFETY 0.9 /* the adaptive steppers' controllers, as reftrace.c */
#define CONTROL_SHRINK 0.2
#define CONTROL_GROW 5.0
#define BS23_FLOOR 1e-3      /* smallest BS23 step, in units of the largest */
#define DOPRI_FLOOR_REL 1e-9 /* smallest Dormand-Prince step, relative to the extent */

struct bound_frame {
    const struct reftrace_object *o;
    double scale;  /* world units per object unit */
    double h_max;  /* the configured step, object units */
    double extent; /* the bounds' largest edge, object units */
    double tol;    /* adaptive steppers: error per step, object units */
    double floor;  /* adaptive steppers: the smallest step, object units */
    bool adaptive; /* REFTRACE_BS23 or REFTRACE_ADAPTIVE */
};

static struct bound_frame frame_of(const struct reftrace_settings *set,
                                   const struct reftrace_object *o)
{
    vec3 vs = reftrace_voxel_size(o), ext = vec3_sub(o->bmax, o->bmin);
    double h_min = fmin(vs.x, fmin(vs.y, vs.z));
    struct bound_frame b = {
        .o = o,
        .scale = o->xf.scale,
        .h_max = set->step_voxels * h_min,
        .extent = fmax(ext.x, fmax(ext.y, ext.z)),
    };
    if (o->ior_constant)
        return b;
    if (set->stepper == REFTRACE_BS23) {
        b.adaptive = true;
        b.tol = set->tolerance_voxels * h_min;
        b.floor = BS23_FLOOR * b.h_max;
    } else if (set->stepper == REFTRACE_ADAPTIVE) {
        b.adaptive = true;
        b.tol = set->tolerance;
        b.floor = DOPRI_FLOOR_REL * b.extent;
    }
    return b;
}

/* One step of length h from (p, w) to (*p1, *w1), object space: straight where n is
 * constant, else the scene's stepper. Returns the adaptive steppers' error estimate
 * (object units; reftrace_integrate.h), 0 for the fixed ones. */
static double raw_step(const struct reftrace_settings *set, const struct bound_frame *b, double h,
                       vec3 p, vec3 w, vec3 *p1, vec3 *w1)
{
    *p1 = p;
    *w1 = w;
    if (b->o->ior_constant) {
        *p1 = vec3_madd(p, vec3_normalize(w), h);
        return 0.0;
    }
    switch (set->stepper) {
    case REFTRACE_EULER:
        reftrace_step_euler(b->o, h, p1, w1);
        return 0.0;
    case REFTRACE_RK2:
        reftrace_step_rk2(b->o, h, p1, w1);
        return 0.0;
    case REFTRACE_BS23:
        return reftrace_step_bs23(b->o, h, b->extent, p1, w1);
    case REFTRACE_ADAPTIVE: {
        struct reftrace_ode y0 = {.p = p, .w = w}, y1;
        double e[3];
        reftrace_step_dopri(b->o, b->scale, h, &y0, &y1, e);
        *p1 = y1.p;
        *w1 = y1.w;
        return e[0] + b->extent / fmax(vec3_length(w), 1e-300) * e[1];
    }
    case REFTRACE_RK4:
        break;
    }
    reftrace_step_rk4(b->o, h, p1, w1);
    return 0.0;
}

/* The adaptive steppers' next step, h (tol / err)^(1 / (order + 1)), bounded. */
static double next_step(const struct reftrace_settings *set, const struct bound_frame *b, double h,
                        double err)
{
    double expo = set->stepper == REFTRACE_BS23 ? 1.0 / 3.0 : 0.2;
    double fac = err > 0.0 ? CONTROL_SAFETY * pow(b->tol / err, expo) : CONTROL_GROW;
    fac = fmin(fmax(fac, CONTROL_SHRINK), CONTROL_GROW);
    return fmin(fmax(h * fac, b->floor), b->h_max);
}

/* The first surface the chord from world x0 to x1 crosses: its index (-1: none), the hit,
 * the hit point and the chord's length. */
static int chord_hit(const struct reftrace_settings *set, vec3 x0, vec3 x1, int last,
                     int64_t last_prim, struct geom_hit *hit, vec3 *x_hit, double *len)
{
    vec3 c = vec3_sub(x1, x0);
    *len = vec3_length(c);
    if (!(*len > 0.0))
        return -1;
    vec3 d = vec3_scale(c, 1.0 / *len);
    int k = reftrace_next_surface(set, x0, d, *len, last, last_prim, hit);
    if (k >= 0)
        *x_hit = vec3_madd(x0, d, hit->t);
    return k;
}

/* Trapezoid accumulation over the step p0 -> p1 (object space), as reftrace.c's
 * finish_step: optical path, optical depth (tevs2007 eq. 5.9), emission at the step's end
 * in basic radiance (eq. 5.10, frisvad2010). */
static void accumulate(struct march *m, const struct bound_frame *b, vec3 p0,
                       const struct reftrace_field *f0, vec3 p1, const struct reftrace_field *f1)
{
    double ds = vec3_length(vec3_sub(p1, p0)) * b->scale;
    m->opl += 0.5 * (f0->n + f1->n) * ds;
    vec3 sigma_t0 = vec3_add(f0->sigma_a, f0->sigma_s);
    vec3 sigma_t1 = vec3_add(f1->sigma_a, f1->sigma_s);
    m->alpha = vec3_madd(m->alpha, vec3_add(sigma_t0, sigma_t1), 0.5 * ds);
    vec3 t = vec3_scale(exp_neg(m->alpha), m->t_f * ds * basic_radiance(m, f1->n));
    m->L = vec3_add(m->L, vec3_mul(t, f1->emission));
}

/* The cut: the step from (p, w) of length h, whose chord crossed a surface (*hit at
 * chord length len, point *x_hit), shortened until the chord's hit lies within CUT_REL h of
 * the step's end. Writes the step's end direction to *w_end and returns the surface; *hit
 * and *x_hit are the last hit, *gap its distance from the step's end (world units). */
static int cut_step(struct march *m, const struct bound_frame *b, vec3 p, vec3 w, double h,
                    vec3 w_h, int k, double len, int last, int64_t last_prim, struct geom_hit *hit,
                    vec3 *x_hit, vec3 *w_end, double *gap)
{
    const struct reftrace_object *o = b->o;
    double lo = 0.0, hi = h, tol = CUT_REL * h * b->scale;
    double c_hi = hit->t / len, gap_hi = len - hit->t;
    bool bisect = false;
    *w_end = w_h;
    for (int it = 0; it < CUT_MAX_ITER && gap_hi > tol && hi - lo > 1e-15 * h; it++) {
        /* The secant: the path's length to the surface is about the chord's fraction c of
         * the step. Bisection after a secant that kept less than half the bracket. */
        double s = bisect ? 0.5 * (lo + hi) : hi * c_hi;
        if (!(s > lo && s < hi))
            s = 0.5 * (lo + hi);
        vec3 p1, w1;
        raw_step(m->set, b, s, p, w, &p1, &w1);
        struct geom_hit hs;
        vec3 xs;
        double ls;
        int ks = chord_hit(m->set, m->x, xform_point_to_world(&o->xf, p1), last, last_prim, &hs,
                           &xs, &ls);
        double before = hi - lo;
        if (ks >= 0) {
            hi = s;
            k = ks;
            *hit = hs;
            *x_hit = xs;
            c_hi = hs.t / ls;
            gap_hi = ls - hs.t;
            *w_end = w1;
        } else {
            lo = s;
        }
        bisect = hi - lo > 0.5 * before;
    }
    *gap = gap_hi;
    return k;
}

static vec3 p_end_of(const struct reftrace_object *o, vec3 x_world)
{
    return xform_point_to_object(&o->xf, x_world);
}

/* n on the inside at the exit point p (object space): the field's sample, except within
 * half a voxel of the bounds, where the trilinear sample is clamped (a lens whose bounds
 * touch its sphere has its focus there) and the index the ray carries, |w| (= n along an
 * exact ray, tevs2007 eq. 4.8), is the better value (docs/tracing.md "The rim"). */
static double exit_index(const struct bound_frame *b, vec3 p, vec3 w)
{
    vec3 vs = reftrace_voxel_size(b->o);
    for (int a = 0; a < 3; a++) {
        double half = 0.5 * vec3_get(vs, a);
        if (vec3_get(p, a) < vec3_get(b->o->bmin, a) + half ||
            vec3_get(p, a) > vec3_get(b->o->bmax, a) - half)
            return vec3_length(w);
    }
    vec3 grad_unused;
    return reftrace_sample_ior(b->o, p, &grad_unused);
}

int reftrace_bound_march(struct march *m, int med, int last, int64_t last_prim,
                         struct reftrace_bound_exit *out)
{
    struct geom_hit *hit = &out->hit;
    const struct reftrace_settings *set = m->set;
    const struct reftrace_object *o = set->surfaces[med].field;
    struct bound_frame b = frame_of(set, o);
    vec3 p = xform_point_to_object(&o->xf, m->x);
    struct reftrace_field f0, f1;
    reftrace_sample_field(o, p, &f0);
    vec3 w = vec3_scale(xform_dir_to_object(&o->xf, m->d), f0.n); /* w = n dx/ds */
    double h = b.h_max, cut = reftrace_absorbed_cut(set);
    m->crossed = true;
    for (;;) {
        if (m->steps >= set->max_steps) {
            stop(m, RAY_MAX_STEPS);
            m->d = xform_dir_to_world(&o->xf, vec3_normalize(w));
            return -1;
        }
        vec3 p1, w1;
        double hs = h, err = raw_step(set, &b, hs, p, w, &p1, &w1);
        m->steps++; /* a rejected attempt counts against the budget too (as reftrace.c) */
        if (b.adaptive) {
            h = next_step(set, &b, hs, err);
            if (err > b.tol && hs > b.floor * 1.0001)
                continue;
        }
        double len;
        vec3 x_hit;
        int k = chord_hit(set, m->x, xform_point_to_world(&o->xf, p1), last, last_prim, hit, &x_hit,
                          &len);
        if (k >= 0) {
            vec3 w_end;
            k = cut_step(m, &b, p, w, hs, w1, k, len, last, last_prim, hit, &x_hit, &w_end,
                         &out->gap);
            out->n_w = exit_index(&b, p_end_of(o, x_hit), w_end);
            vec3 p_end = xform_point_to_object(&o->xf, x_hit);
            reftrace_sample_field(o, p_end, &f1);
            accumulate(m, &b, p, &f0, p_end, &f1);
            m->x = x_hit;
            m->d = xform_dir_to_world(&o->xf, vec3_normalize(w_end));
            return k;
        }
        reftrace_sample_field(o, p1, &f1);
        accumulate(m, &b, p, &f0, p1, &f1);
        p = p1;
        w = w1;
        f0 = f1;
        m->x = xform_point_to_world(&o->xf, p1);
        m->d = xform_dir_to_world(&o->xf, vec3_normalize(w));
        last = -1; /* away from the surface entered by: any crossing now is a real one */
        if (throughput(m) < cut) {
            stop(m, RAY_ABSORBED);
            return -1;
        }
    }
}
