/*
 * reftrace.c - the CPU double-precision reference march of docs/tracing.md "The march":
 * object selection by slab test, ambient optical path, Fresnel and Snell at the bounds
 * faces (total internal reflection included), integration inside the field with the
 * straight-segment cut at the bounds, trapezoid accumulation of optical path,
 * absorption and emission, Fresnel events at sharp boundaries inside the field, opaque
 * embeddings, jumps over empty space (macrocell.c), and the statuses. The steppers and field
 * sampling are in reftrace_integrate.c.
 *
 * It is the twin of shaders/ray_march.glsl and follows the page step for step; the
 * numbered comments below are the page's numbers. Where the page is silent this file
 * makes the choice the GLSL twin makes (noted "page silent").
 *
 * REFTRACE_ADAPTIVE is the one deliberate departure: it integrates the optical path,
 * absorption and emission as part of its ODE state (see reftrace_integrate.c) and it
 * lands exactly on the bounds face instead of cutting a straight segment, because it
 * is the "exact" reference for analytic fields, not a model of the GPU.
 *
 * The light-dependent terms (in-scattering, the lights' reflected light, the receiver;
 * docs/tracing.md "Light") are evaluated by reftrace_light.c when settings->lighting is
 * set. Not here: rendering images, image environments, light simulation.
 */
#include "reftrace.h"

#include <assert.h>
#include <float.h>
#include <math.h>
#include <stddef.h>

#include "env.h"
#include "fresnel.h"
#include "interface.h"
#include "medium_step.h"
#include "reftrace_integrate.h"
#include "reftrace_march.h"
#include "reftrace_light.h"

/* docs/tracing.md constants. */
#define INDEX_EPS 1e-6       /* |n - ambient_n| at or below this: no interface */
#define EXIT_EPS_VOXELS 1e-3 /* an object counts only if its exit is further than this */
#define RAMP_SLOPE_RATIO 0.5 /* zone sides keep this much of the slope: a ramp, no event */
#define SKIP_EXIT_PAD 1e-3   /* voxels: a skip to the bounds ends this far past them */
/* Adaptive stepper: step-size factors per step and the smallest step relative to
 * the object's largest extent. */
#define ADAPT_SHRINK_MIN 0.2
#define ADAPT_GROW_MAX 5.0
#define ADAPT_SAFETY 0.9
#define ADAPT_MIN_STEP_REL 1e-9
/* The GPU's adaptive stepper (Bogacki-Shampine 3(2)): the same constants as
 * shaders/ray_equation.glsl RAY_BS23_*. */
#define BS23_SAFETY 0.9
#define BS23_SHRINK_MIN 0.2
#define BS23_GROW_MAX 5.0
#define BS23_FLOOR 1e-3 /* smallest step, in units of the largest */
/* Page silent: a ray that keeps reflecting off faces between objects could pass from
 * object to object forever without taking a step. Same cap as the GLSL twin; reaching it
 * ends the ray with status max_steps. */
#define MAX_PASSES (4 * MAX_OBJECTS + 64)

/* An object's per-march constants. */
struct object_frame {
    const struct reftrace_object *o;
    double scale; /* world units per object unit */
    vec3 vs;      /* voxel size, object units */
    double h_min; /* min(vs) */
};

static vec3 environment(const struct march *m, vec3 d_world)
{
    return vec3_scale(env_procedural(d_world), m->set->env_intensity);
}

/* What a ray leaving the scene at world x along world d sees: a lamp (a point light with
 * a radius) where it meets one first, else the receiver where it hits it (with lighting),
 * else the environment (ray_march.glsl's march_seen). primary: the ray has met nothing. */
static vec3 seen_from(const struct march *m, vec3 x, vec3 d, bool primary)
{
    vec3 seen = environment(m, d), plane, lamp;
    if (m->set->lighting == NULL)
        return seen;
    double t_max = INFINITY;
    if (reftrace_light_receiver(m->set->lighting, environment(m, (vec3){0, 1, 0}), x, d, &plane)) {
        seen = plane;
        t_max = (m->set->lighting->receiver.height - x.y) / d.y;
    }
    if (reftrace_light_emitter(m->set->lighting, x, d, t_max, primary, &lamp))
        seen = lamp;
    return seen;
}

/* L += T_f exp(-alpha) * R * seen_from(x_world, d_world): a reflection that looks up the
 * receiver or the environment directly (tevs2007 sect. 6.3: reflected rays are not cast
 * back through the volume; the receiver since issue 14 item 4). */
static void add_reflection(struct march *m, double R, vec3 x_world, vec3 d_world)
{
    vec3 t = vec3_scale(exp_neg(m->alpha), m->t_f * R);
    m->L = vec3_add(m->L, vec3_mul(t, seen_from(m, x_world, d_world, false)));
}

/* The lights' reflected radiance at a Fresnel event (the delta(x) R L_r term of tevs2007
 * eq. 5.4) at object-space p, view direction q before the event, normal nrm (object
 * space), index n_view on the viewer's side. */
static void add_light_reflection(struct march *m, const struct reftrace_object *o, vec3 p, vec3 q,
                                 vec3 nrm, double R, double n_view)
{
    if (m->set->lighting == NULL || m->set->lighting->count == 0)
        return;
    vec3 Lr =
        reftrace_light_reflected(m->set->lighting, &o->brdf, xform_point_to_world(&o->xf, p),
                                 xform_dir_to_world(&o->xf, q), xform_dir_to_world(&o->xf, nrm), R);
    double w = m->t_f * basic_radiance(m, n_view);
    m->L = vec3_add(m->L, vec3_mul(vec3_scale(exp_neg(m->alpha), w), Lr));
}

static vec3 axis_normal(int axis, double sign)
{
    vec3 n = {0, 0, 0};
    vec3_set(&n, axis, sign);
    return n;
}

static bool outside_bounds(const struct reftrace_object *o, vec3 p)
{
    for (int a = 0; a < 3; a++) {
        double v = vec3_get(p, a);
        if (v < vec3_get(o->bmin, a) || v > vec3_get(o->bmax, a))
            return true;
    }
    return false;
}

/* Slab test of the object-space ray o + t q against the bounds (t in object units).
 * Returns false when the line misses the box. t0 may be negative (origin inside);
 * axis and sign name the entry face (its outward normal is sign along axis). */
static bool slab_test(const struct reftrace_object *o, vec3 org, vec3 q, double *t0, double *t1,
                      int *axis, double *sign)
{
    *t0 = -INFINITY;
    *t1 = INFINITY;
    *axis = 0;
    *sign = -1.0;
    for (int a = 0; a < 3; a++) {
        double oa = vec3_get(org, a), qa = vec3_get(q, a);
        double lo = vec3_get(o->bmin, a), hi = vec3_get(o->bmax, a);
        if (qa == 0.0) {
            if (oa < lo || oa > hi)
                return false;
            continue;
        }
        double ta = (lo - oa) / qa, tb = (hi - oa) / qa;
        double tn = fmin(ta, tb), tf = fmax(ta, tb);
        if (tn > *t0) {
            *t0 = tn;
            *axis = a;
            *sign = qa > 0.0 ? -1.0 : 1.0;
        }
        *t1 = fmin(*t1, tf);
    }
    return *t0 <= *t1;
}

/* The entry chosen in step 1. */
struct entry {
    int index;
    double t_world; /* distance from the current position, world units */
    bool inside;    /* the position is already inside the bounds */
    int axis;       /* entry face */
    double sign;
};

/* Step 1: the object with the smallest entry distance among those whose exit is
 * further than EXIT_EPS_VOXELS of its smallest voxel edge; ties go to the lower index ("the first
 * one entered wins"). Returns false when there is none. */
static bool next_object(const struct march *m, const struct reftrace_object *objects, int count,
                        struct entry *e)
{
    e->index = -1;
    e->t_world = INFINITY;
    for (int i = 0; i < count; i++) {
        const struct reftrace_object *o = &objects[i];
        if (o->bound)
            continue; /* seen only inside its surface */
        vec3 org = xform_point_to_object(&o->xf, m->x);
        vec3 q = xform_dir_to_object(&o->xf, m->d);
        double t0, t1, sign;
        int axis;
        if (!slab_test(o, org, q, &t0, &t1, &axis, &sign))
            continue;
        vec3 vs = reftrace_voxel_size(o);
        if (t1 <= EXIT_EPS_VOXELS * fmin(vs.x, fmin(vs.y, vs.z)))
            continue;
        double tw = fmax(t0, 0.0) * o->xf.scale;
        if (tw < e->t_world) {
            e->index = i;
            e->t_world = tw;
            /* An origin on the face counts as inside (page silent; as the GLSL twin). */
            e->inside = t0 <= 0.0;
            e->axis = axis;
            e->sign = sign;
        }
    }
    return e->index >= 0;
}

/* Crossing a bounds face (outward normal nrm, object space) from n_from to n_to, with
 * the object-space direction *q. Returns false on total internal reflection, with *q
 * mirrored; otherwise gathers the reflection, multiplies T_f by 1 - R and refracts *q
 * (frisvad2010: Fresnel equations, law of refraction). */
static bool cross_face(struct march *m, const struct object_frame *fr, vec3 p, vec3 *q, vec3 nrm,
                       double n_from, double n_to)
{
    if (fabs(n_from - n_to) <= INDEX_EPS)
        return true;
    double R = fresnel_unpolarized(fabs(vec3_dot(*q, nrm)), n_from, n_to);
    vec3 r = vec3_reflect(*q, nrm);
    vec3 t;
    if (R >= 1.0 || !snell_refract(*q, nrm, n_from, n_to, &t)) {
        *q = r;
        return false;
    }
    add_reflection(m, R, xform_point_to_world(&fr->o->xf, p), xform_dir_to_world(&fr->o->xf, r));
    add_light_reflection(m, fr->o, p, *q, nrm, R, n_from);
    m->t_f *= 1.0 - R;
    *q = t;
    return true;
}

/* Sharp boundaries inside the field (docs/tracing.md "Sharp boundaries"): entering a
 * zone where |grad n| h_min exceeds the threshold probes the index k = (3 sigma + 2)
 * h_min to either side along grad n; the Fresnel event happens where the ray crosses the
 * zone's middle index, once per zone, unless the slope continues on both sides (a ramp). */
struct zone {
    bool inside, armed;
    double n_lo, n_hi, n_mid;
    double slope_sides; /* the smaller slope along the normal at the two probes */
};

static void zone_enter(struct zone *z, const struct object_frame *fr, vec3 p, vec3 grad)
{
    vec3 nrm = vec3_normalize(grad);
    double k = (3.0 * fr->o->smoothing_sigma_voxels + 2.0) * fr->h_min;
    vec3 g_lo, g_hi;
    z->n_lo = reftrace_sample_ior(fr->o, vec3_madd(p, nrm, -k), &g_lo);
    z->n_hi = reftrace_sample_ior(fr->o, vec3_madd(p, nrm, k), &g_hi);
    z->n_mid = 0.5 * (z->n_lo + z->n_hi);
    z->slope_sides = fmin(vec3_dot(g_lo, nrm), vec3_dot(g_hi, nrm));
    z->inside = true;
    z->armed = true;
}

static bool zone_crossed(const struct zone *z, double n_before, double n_after)
{
    return z->armed && n_before != n_after && (n_before - z->n_mid) * (n_after - z->n_mid) <= 0.0;
}

/* The crossing at p: unpolarised Fresnel from the side the ray comes from. n_i sin_i >=
 * n_t means the ray equation itself turns the ray around (tevs2007 sect. 5.2);
 * fresnel_unpolarized returns exactly 1 then and nothing is added. */
static void zone_event(struct march *m, struct zone *z, const struct object_frame *fr, vec3 p,
                       vec3 grad, double n_before, double n_after, vec3 q)
{
    z->armed = false;
    if (vec3_length(grad) <= 0.0)
        return;
    /* A smooth ramp, not an interface: the slope continues on both sides of the zone at
     * more than half its value here. The ray equation bends the ray; there is no surface
     * to reflect from (a steep GRIN field must not lose light to grazing "Fresnel"). */
    if (z->slope_sides > RAMP_SLOPE_RATIO * vec3_length(grad))
        return;
    vec3 nrm = vec3_normalize(grad);
    bool rising = n_after > n_before;
    double n_i = rising ? z->n_lo : z->n_hi;
    double R = fresnel_unpolarized(fabs(vec3_dot(q, nrm)), n_i, rising ? z->n_hi : z->n_lo);
    if (R >= 1.0)
        return;
    add_reflection(m, R, xform_point_to_world(&fr->o->xf, p),
                   xform_dir_to_world(&fr->o->xf, vec3_reflect(q, nrm)));
    add_light_reflection(m, fr->o, p, q, nrm, R, n_i);
    m->t_f *= 1.0 - R;
}

/* Opaque embedding hit at p (tevs2007 sect. 6.1, T6): the normal is the coverage
 * gradient by central differences one voxel to either side, pointing out of the
 * embedding (towards lower coverage). */
static void opaque_hit(struct march *m, const struct object_frame *fr, vec3 p, vec3 q,
                       double n_here, vec3 colour)
{
    vec3 g = {0, 0, 0};
    for (int a = 0; a < 3; a++) {
        double h = vec3_get(fr->vs, a);
        vec3 e = axis_normal(a, h);
        vec3 c_unused;
        double cp = 0.0, cm = 0.0;
        reftrace_sample_opaque(fr->o, vec3_add(p, e), &c_unused, &cp);
        reftrace_sample_opaque(fr->o, vec3_sub(p, e), &c_unused, &cm);
        vec3_set(&g, a, (cp - cm) / (2.0 * h));
    }
    /* Uniform coverage (the ray started inside): face the ray. Page silent; as GLSL. */
    vec3 nrm = vec3_length(g) > 1e-12 ? vec3_scale(vec3_normalize(g), -1.0) : vec3_scale(q, -1.0);
    double R = fresnel_unpolarized(fabs(vec3_dot(q, nrm)), n_here, fr->o->opaque_ior);
    vec3 env_r = seen_from(m, xform_point_to_world(&fr->o->xf, p),
                           xform_dir_to_world(&fr->o->xf, vec3_reflect(q, nrm)), false);
    vec3 seen = vec3_add(vec3_scale(env_r, R), vec3_scale(colour, 1.0 - R));
    m->L = vec3_add(m->L, vec3_mul(vec3_scale(exp_neg(m->alpha), m->t_f), seen));
    add_light_reflection(m, fr->o, p, q, nrm, R, n_here);
}

/* Fraction f in [0, 1] of the segment p0 -> p1 (p1 outside) that stays inside the
 * bounds, and the face it leaves through. */
static double exit_fraction(const struct reftrace_object *o, vec3 p0, vec3 p1, int *axis,
                            double *sign)
{
    double f = 1.0;
    *axis = 0;
    *sign = 1.0;
    for (int a = 0; a < 3; a++) {
        double a0 = vec3_get(p0, a), a1 = vec3_get(p1, a), da = a1 - a0;
        double fa = 2.0;
        if (a1 > vec3_get(o->bmax, a) && da > 0.0)
            fa = (vec3_get(o->bmax, a) - a0) / da;
        else if (a1 < vec3_get(o->bmin, a) && da < 0.0)
            fa = (vec3_get(o->bmin, a) - a0) / da;
        if (fa < f) {
            f = fa;
            *axis = a;
            *sign = da > 0.0 ? 1.0 : -1.0;
        }
    }
    return fmin(fmax(f, 0.0), 1.0);
}

/* Puts p exactly on the face (axis, sign), removing rounding from the cut. */
static vec3 snap_to_face(const struct reftrace_object *o, vec3 p, int axis, double sign)
{
    vec3_set(&p, axis, vec3_get(sign > 0.0 ? o->bmax : o->bmin, axis));
    return p;
}

/* One step's outcome, whichever stepper took it. */
struct step_out {
    vec3 p, w;               /* end of the step (on the face when leaving) */
    struct reftrace_field f; /* field at p */
    bool leaving;
    int axis; /* exit face when leaving */
    double sign;
    bool rejected; /* REFTRACE_BS23: the error was too large; retry from the same point */
};

/* ray_equation_next_step's twin: the controller h (tol / err)^(1/3), bounded. */
static double bs23_next_step(double h, double err, double tol, double h_max)
{
    double fac = err > 0.0 ? BS23_SAFETY * pow(tol / err, 1.0 / 3.0) : BS23_GROW_MAX;
    fac = fmin(fmax(fac, BS23_SHRINK_MIN), BS23_GROW_MAX);
    return fmin(fmax(h * fac, BS23_FLOOR * h_max), h_max);
}

static void finish_step(struct march *m, const struct object_frame *fr, vec3 p, vec3 w,
                        const struct reftrace_field *f0, struct step_out *s);

/* Euler, RK2, RK4 or Bogacki-Shampine step with the straight-segment cut and trapezoid
 * accumulation: the steppers the GPU has. The page is silent on w at the cut; like
 * the GLSL twin it is interpolated with the same fraction, w + f (w' - w). For BS23, *h
 * carries the step size between calls, and a step whose error exceeds the tolerance
 * comes back rejected with nothing accumulated (unless it is already the smallest). */
static void fixed_step(struct march *m, const struct object_frame *fr, vec3 p, vec3 w,
                       const struct reftrace_field *f0, double *h_io, struct step_out *s)
{
    double h_max = m->set->step_voxels * fr->h_min;
    double h = m->set->stepper == REFTRACE_BS23 ? *h_io : h_max;
    s->p = p;
    s->w = w;
    s->rejected = false;
    if (m->set->stepper == REFTRACE_EULER) {
        reftrace_step_euler(fr->o, h, &s->p, &s->w);
    } else if (m->set->stepper == REFTRACE_RK2) {
        reftrace_step_rk2(fr->o, h, &s->p, &s->w);
    } else if (m->set->stepper == REFTRACE_BS23) {
        vec3 ext = vec3_sub(fr->o->bmax, fr->o->bmin);
        double extent = fmax(ext.x, fmax(ext.y, ext.z));
        double tol = m->set->tolerance_voxels * fr->h_min;
        double err = reftrace_step_bs23(fr->o, h, extent, &s->p, &s->w);
        *h_io = bs23_next_step(h, err, tol, h_max);
        if (err > tol && h > BS23_FLOOR * h_max * 1.0001) {
            s->rejected = true;
            return;
        }
    } else {
        reftrace_step_rk4(fr->o, h, &s->p, &s->w);
    }
    finish_step(m, fr, p, w, f0, s);
}

/* The rest of a step from (p, w) to (s->p, s->w), for an integration step and a skip
 * alike: the straight-segment cut at the bounds, then the trapezoid accumulation. */
static void finish_step(struct march *m, const struct object_frame *fr, vec3 p, vec3 w,
                        const struct reftrace_field *f0, struct step_out *s)
{
    s->leaving = outside_bounds(fr->o, s->p);
    if (s->leaving) {
        double f = exit_fraction(fr->o, p, s->p, &s->axis, &s->sign);
        s->p = snap_to_face(fr->o, vec3_madd(p, vec3_sub(s->p, p), f), s->axis, s->sign);
        s->w = vec3_madd(w, vec3_sub(s->w, w), f);
    }
    reftrace_sample_field(fr->o, s->p, &s->f);
    /* Trapezoid rule over the segment's world length (tevs2007 eq. 5.9 for alpha, eq.
     * 5.10's emission term for L). */
    double ds = vec3_length(vec3_sub(s->p, p)) * fr->scale;
    m->opl += 0.5 * (f0->n + s->f.n) * ds;
    vec3 sigma_t0 = vec3_add(f0->sigma_a, f0->sigma_s);
    vec3 sigma_t1 = vec3_add(s->f.sigma_a, s->f.sigma_s);
    m->alpha = vec3_madd(m->alpha, vec3_add(sigma_t0, sigma_t1), 0.5 * ds);
    vec3 t = vec3_scale(exp_neg(m->alpha), m->t_f * ds * basic_radiance(m, s->f.n));
    m->L = vec3_add(m->L, vec3_mul(t, s->f.emission));
    /* In-scattering L_s (tevs2007 eqs. 5.4/5.5) at the step's end, towards the eye. */
    const struct reftrace_lighting *lt = m->set->lighting;
    if (lt != NULL && (s->f.sigma_s.x > 0.0 || s->f.sigma_s.y > 0.0 || s->f.sigma_s.z > 0.0)) {
        vec3 Ls = reftrace_light_inscatter(lt, xform_point_to_world(&fr->o->xf, s->p),
                                           xform_dir_to_world(&fr->o->xf, vec3_normalize(s->w)),
                                           s->f.sigma_s, s->f.g);
        m->L = vec3_add(m->L, vec3_mul(t, Ls));
    }
}

/* Empty-space skipping (docs/tracing.md "Empty space"; the GLSL twin is the MARCH_SKIP
 * block of march_through_object in shaders/ray_march.glsl): where p's macro cell and the ones after
 * it along the ray are empty, the ray equation gives a straight line with constant n (tevs2007
 * eqs. 4.8/4.9 with grad n = 0), so one jump to the far side of the last empty cell replaces the
 * integration steps there; w is unchanged. The jump is a whole number of steps (in empty
 * space a step advances p by exactly h w / n), so it lands where the steps would have; one
 * that reaches the bounds goes a little past them (SKIP_EXIT_PAD voxels) so the usual cut
 * lands it on the face, as the last step would. Returns false, touching nothing, when the
 * jump would replace fewer than two steps. */
static bool skip_step(struct march *m, const struct object_frame *fr, vec3 p, vec3 w,
                      const struct reftrace_field *f0, struct step_out *s)
{
    const struct reftrace_object *o = fr->o;
    vec3 q = vec3_normalize(w);
    double v0[3], dv[3];
    double t_bounds = INFINITY;
    for (int a = 0; a < 3; a++) {
        double vs = vec3_get(fr->vs, a), qa = vec3_get(q, a), pa = vec3_get(p, a);
        v0[a] = (pa - vec3_get(o->bmin, a)) / vs;
        dv[a] = qa / vs;
        if (qa > 0.0)
            t_bounds = fmin(t_bounds, (vec3_get(o->bmax, a) - pa) / qa);
        else if (qa < 0.0)
            t_bounds = fmin(t_bounds, (vec3_get(o->bmin, a) - pa) / qa);
    }
    t_bounds = fmax(t_bounds, 0.0);
    bool to_bounds;
    double t = macrocell_skip_distance(o->cells, v0, dv, t_bounds, &to_bounds);
    /* A step in empty space moves p by h w / n, of length h |w| / n: h only as far as the
     * integration kept |w| = n. */
    vec3 move = vec3_scale(w, m->set->step_voxels * fr->h_min / f0->n);
    double step_len = vec3_length(move);
    if (to_bounds) {
        if (t < 2.0 * step_len)
            return false;
        s->p = vec3_madd(p, q, t + SKIP_EXIT_PAD * fr->h_min); /* the cut lands it on the face */
    } else {
        /* Whole steps only: the jump ends where the steps it replaces would have, so the
         * integration after it samples the same points as without skipping. */
        double k = floor(t / step_len);
        if (k < 2.0)
            return false;
        s->p = vec3_madd(p, move, k);
    }
    s->w = w;
    s->rejected = false;
    finish_step(m, fr, p, w, f0, s);
    return true;
}

/* How far p is outside the box along the worst axis: > 0 outside, <= 0 inside (minus
 * the distance to the nearest face). Also names that face. */
static double box_excess(const struct reftrace_object *o, vec3 p, int *axis, double *sign)
{
    double worst = -INFINITY;
    for (int a = 0; a < 3; a++) {
        double below = vec3_get(o->bmin, a) - vec3_get(p, a);
        double above = vec3_get(p, a) - vec3_get(o->bmax, a);
        if (below > worst) {
            worst = below;
            *axis = a;
            *sign = -1.0;
        }
        if (above > worst) {
            worst = above;
            *axis = a;
            *sign = 1.0;
        }
    }
    return worst;
}

/* Dormand-Prince 5(4) step with error control on the position, step factors bounded
 * to [0.2, 5], steps never below 1e-9 of the bounds' largest extent. A step that would
 * leave the bounds is shortened by bisection on its length until it ends inside within
 * `tolerance` of a face, then snapped onto it. The step's integrals are added to the
 * march. *h carries the step size between calls.
 *
 * The error norm is in object units: |e_p| + D |e_w| / |w| + |e_opl| / scale, the
 * position error, plus the displacement a direction error would cause over the
 * object's largest extent D, plus the optical path error. The direction term matters
 * where grad n jumps (the surface of a Luneburg lens or a fish-eye): there the embedded
 * estimate of p stays small while w takes an O(h dg) error, which showed up as exit
 * directions off by 1e-5 at tolerance 1e-10; the path term keeps the OPL, which is a
 * reference value too, at the same accuracy (1e-8 at 1e-10 without it). */
static void adaptive_step(struct march *m, const struct object_frame *fr, vec3 p, vec3 w, double *h,
                          struct step_out *s)
{
    double tol = m->set->tolerance;
    vec3 ext = vec3_sub(fr->o->bmax, fr->o->bmin);
    double extent = fmax(ext.x, fmax(ext.y, ext.z));
    double h_floor = ADAPT_MIN_STEP_REL * extent;
    double w_weight = extent / fmax(vec3_length(w), 1e-300);
    struct reftrace_ode y0 = {.p = p, .w = w}, y1;
    double err, e[3], hs = fmax(*h, h_floor);
    hs = fmin(hs, m->set->step_voxels * fr->h_min);
    for (;;) {
        reftrace_step_dopri(fr->o, fr->scale, hs, &y0, &y1, e);
        err = e[0] + w_weight * e[1] + e[2] / fr->scale;
        if (err <= tol || hs <= h_floor)
            break;
        double fac = fmax(ADAPT_SAFETY * pow(tol / err, 0.2), ADAPT_SHRINK_MIN);
        hs = fmax(hs * fac, h_floor);
    }
    double grow = err > 0.0 ? ADAPT_SAFETY * pow(tol / err, 0.2) : ADAPT_GROW_MAX;
    /* Never grow beyond the configured step: in a uniform region the error estimate is
     * zero and the step would grow until it jumps over a thin feature (the rim of a
     * Luneburg lens) without ever sampling it. */
    double h_max = m->set->step_voxels * fr->h_min;
    *h = fmin(fmax(hs * fmin(fmax(grow, ADAPT_SHRINK_MIN), ADAPT_GROW_MAX), h_floor), h_max);

    s->leaving = outside_bounds(fr->o, y1.p);
    if (s->leaving) {
        /* Exact exit: bisection on the step length between lo (inside) and hi
         * (outside), from the same start, until the end point is inside and within tol
         * of a face. Shorter steps than an accepted one are at least as accurate. */
        double lo = 0.0, hi = hs;
        struct reftrace_ode y_lo = y0, ym;
        for (int it = 0; it < 200 && hi - lo > DBL_EPSILON * hs; it++) {
            double mid = 0.5 * (lo + hi), e_unused[3];
            int ax;
            double sg;
            reftrace_step_dopri(fr->o, fr->scale, mid, &y0, &ym, e_unused);
            double excess = box_excess(fr->o, ym.p, &ax, &sg);
            if (excess > 0.0) {
                hi = mid;
                continue;
            }
            lo = mid;
            y_lo = ym;
            if (excess >= -tol)
                break;
        }
        y1 = y_lo;
        box_excess(fr->o, y1.p, &s->axis, &s->sign);
        y1.p = snap_to_face(fr->o, y1.p, s->axis, s->sign);
    }
    s->p = y1.p;
    s->w = y1.w;
    reftrace_sample_field(fr->o, s->p, &s->f);
    m->opl += y1.opl;
    double amb2 = m->set->ambient_ior * m->set->ambient_ior; /* emit is in basic radiance */
    m->L = vec3_add(m->L, vec3_mul(vec3_scale(exp_neg(m->alpha), m->t_f * amb2), y1.emit));
    m->alpha = vec3_add(m->alpha, y1.alpha);
}

/* Step 4: integrates through one object from object-space p with unit direction q until
 * the ray leaves the bounds (m->x, m->d updated, m->running still true) or stops. */
static void march_object(struct march *m, const struct object_frame *fr, vec3 p, vec3 q)
{
    const struct reftrace_settings *set = m->set;
    struct reftrace_field f0;
    reftrace_sample_field(fr->o, p, &f0);
    vec3 w = vec3_scale(q, f0.n); /* tevs2007 eqs. 4.8/4.9: w = n dx/ds */
    struct zone zone = {.inside = false, .armed = false};
    double h_adapt = set->step_voxels * fr->h_min;
    bool can_skip = set->empty_space_skipping && fr->o->cells != NULL && fr->o->grid != NULL &&
                    set->stepper != REFTRACE_ADAPTIVE;
    bool skipped = false; /* the last step was a skip: integrate once before the next */
    double cut = reftrace_absorbed_cut(set);
    for (;;) {
        /* The budget is checked before each step (as the GLSL twin). */
        if (m->steps >= set->max_steps) {
            stop(m, RAY_MAX_STEPS);
            m->x = xform_point_to_world(&fr->o->xf, p);
            m->d = xform_dir_to_world(&fr->o->xf, vec3_normalize(w));
            return;
        }
        struct step_out s = {.rejected = false};
        bool skip = can_skip && !skipped && skip_step(m, fr, p, w, &f0, &s);
        if (skip)
            h_adapt = set->step_voxels * fr->h_min; /* BS23 after a skip: as in empty space */
        else if (set->stepper == REFTRACE_ADAPTIVE)
            adaptive_step(m, fr, p, w, &h_adapt, &s);
        else
            fixed_step(m, fr, p, w, &f0, &h_adapt, &s);
        skipped = skip;
        /* A skip counts as one step; a rejected BS23 attempt counts against the budget too
         * (as on the GPU). */
        m->steps++;
        if (s.rejected)
            continue;
        vec3 q1 = vec3_normalize(s.w);

        /* Sharp boundaries: zone entry, then one event where the middle index is crossed. */
        double g = vec3_length(s.f.grad) * fr->h_min;
        if (!zone.inside && g > set->boundary_threshold)
            zone_enter(&zone, fr, s.p, s.f.grad);
        if (zone_crossed(&zone, f0.n, s.f.n))
            zone_event(m, &zone, fr, s.p, s.f.grad, f0.n, s.f.n, q1);
        if (zone.inside && g < 0.5 * set->boundary_threshold)
            zone.inside = zone.armed = false;

        vec3 colour;
        double coverage;
        bool stopped = false;
        if (reftrace_sample_opaque(fr->o, s.p, &colour, &coverage) && coverage >= 0.5) {
            opaque_hit(m, fr, s.p, q1, s.f.n, colour);
            stop(m, RAY_ABSORBED);
            stopped = true;
        } else if (throughput(m) < cut) {
            stop(m, RAY_ABSORBED);
            stopped = true;
        }
        if (stopped) {
            m->x = xform_point_to_world(&fr->o->xf, s.p);
            m->d = xform_dir_to_world(&fr->o->xf, q1);
            return;
        }

        p = s.p;
        w = s.w;
        f0 = s.f;
        if (s.leaving) {
            /* Exit face: from the index the ray carries, n_w = |w|, to the ambient index
             * (docs/tracing.md "The rim"). Along an exact ray |w| = n (tevs2007 eq. 4.8,
             * w = n dx/ds); in the half voxel before a face the sampled n is clamped while
             * grad n still changes w, so n(p') and |w| part there, and Snell from n(p')
             * turned the ray by the difference (0.29 deg median for a Luneburg lens whose
             * focus lies on the face). From |w| the face conserves w's tangential part. */
            vec3 nrm = axis_normal(s.axis, s.sign);
            double n_w = vec3_length(w);
            if (cross_face(m, fr, p, &q1, nrm, n_w, set->ambient_ior)) {
                m->x = xform_point_to_world(&fr->o->xf, p);
                m->d = xform_dir_to_world(&fr->o->xf, q1);
                return;
            }
            /* Totally reflected (q1 mirrored): march on with the sampled n, as before (with
             * |w| kept, 3 of 6 rays of the steep mirage of test_hard_reftrace stopped turning). */
            w = vec3_scale(q1, s.f.n);
        }
    }
}

/* ---- exact surfaces (docs/tracing.md "Surfaces") ---- */

/* Self-intersection offsets relative to a surface's size: the surface a ray just left is
 * searched from this far on, the others from SURFACE_EPS_OTHER (a hit at the origin of a
 * surface the ray did not come from is a real crossing). */
#define SURFACE_EPS_SAME 1e-9
#define SURFACE_EPS_OTHER 1e-13

uint32_t reftrace_inside_set(const struct reftrace_surface *surfaces, int count, vec3 p)
{
    uint32_t set = 0;
    for (int k = 0; k < count && k < INTERFACE_MAX_SURFACES; k++)
        if (geom_surface_inside(&surfaces[k].geom, p))
            set |= 1u << k;
    return set;
}

int reftrace_next_surface(const struct reftrace_settings *set, vec3 x, vec3 d, double t_max,
                          int last, int64_t last_prim, struct geom_hit *hit)
{
    int best = -1;
    double t_best = t_max;
    for (int k = 0; k < set->surface_count; k++) {
        const struct reftrace_surface *sf = &set->surfaces[k];
        double size = geom_surface_size(&sf->geom);
        double tmin = (k == last ? SURFACE_EPS_SAME : SURFACE_EPS_OTHER) * size;
        struct geom_hit h;
        if (geom_surface_intersect(&sf->geom, x, d, tmin, t_best, k == last ? last_prim : -1, &h)) {
            t_best = h.t;
            *hit = h;
            best = k;
        }
    }
    return best;
}

double reftrace_medium_ior(const struct reftrace_settings *set, int medium, vec3 x)
{
    if (medium < 0)
        return set->ambient_ior;
    const struct reftrace_object *o = set->surfaces[medium].field;
    if (o == NULL)
        return set->surfaces[medium].ior;
    vec3 grad_unused;
    return reftrace_sample_ior(o, xform_point_to_object(&o->xf, x), &grad_unused);
}

static double medium_ior(const struct march *m, int medium)
{
    return reftrace_medium_ior(m->set, medium, m->x);
}

/* A straight leg of length t (world) through the medium of surface `medium` (-1: the
 * ambient medium, which neither absorbs, scatters nor emits): optical path n t, optical
 * depth sigma_t t with sigma_t = sigma_a + sigma_s (Beer-Lambert, tevs2007 eq. 5.9), and
 * eq. 5.4's source terms with frisvad2010's basic radiance factor: the emission and, with
 * lights and sigma_s > 0, the single in-scattering of eq. 5.5 (phase_hg with the medium's
 * g), over the steps of medium_step.h: per step the transmittance integrated exactly,
 * exp(-alpha_i) (1 - exp(-sigma_t h)) / sigma_t, times the source at the step's midpoint
 * (exact for the constant emission). Twin of march_surface_leg in shaders/ray_march.glsl. */
static void surface_leg(struct march *m, int medium, double t)
{
    m->opl += medium_ior(m, medium) * t;
    if (medium >= 0) {
        const struct reftrace_surface *sf = &m->set->surfaces[medium];
        double w = m->t_f * basic_radiance(m, sf->ior);
        vec3 sigma_t =
            vec3_make(reftrace_surface_extinction(sf, 0), reftrace_surface_extinction(sf, 1),
                      reftrace_surface_extinction(sf, 2));
        vec3 sigma_s = vec3_make(sf->scattering[0], sf->scattering[1], sf->scattering[2]);
        vec3 emission = vec3_make(sf->emission[0], sf->emission[1], sf->emission[2]);
        const struct reftrace_lighting *lt = m->set->lighting;
        bool scatters = lt != NULL && (sigma_s.x > 0.0 || sigma_s.y > 0.0 || sigma_s.z > 0.0);
        int steps = scatters ? medium_step_count(t, reftrace_light_inscatter_step(lt)) : 1;
        if (m->defer == NULL) /* the deferred ray: weighted by a reflectance (docs/walter.md) */
            steps = steps / 4 > 1 ? steps / 4 : 1;
        double h = t / steps;
        vec3 weight = vec3_make(medium_step_weight(sigma_t.x, h), medium_step_weight(sigma_t.y, h),
                                medium_step_weight(sigma_t.z, h));
        for (int i = 0; i < steps; i++) {
            vec3 source = emission;
            if (scatters) {
                /* the inner steps' point shifted per pixel sample in walter scenes */
                double o = i == 0 || i == steps - 1 || !lt->walter.enabled ||
                                   !(lt->walter.step_offset > 0.0)
                               ? 0.5
                               : lt->walter.step_offset;
                source = vec3_add(source,
                                  reftrace_light_inscatter(lt, vec3_madd(m->x, m->d, (i + o) * h),
                                                           m->d, sigma_s, sf->anisotropy));
            }
            vec3 before = vec3_scale(exp_neg(m->alpha), w);
            m->L = vec3_add(m->L, vec3_mul(vec3_mul(before, weight), source));
            m->alpha = vec3_madd(m->alpha, sigma_t, h);
        }
    }
    m->x = vec3_madd(m->x, m->d, t);
}

static void record_event(struct reftrace_result *out, enum reftrace_event_kind kind,
                         const struct march *m, const struct geom_hit *h, int k, int from, int to,
                         double n_from, double n_to, double R, double gap)
{
    if (out->event_count < REFTRACE_MAX_EVENTS) {
        struct reftrace_event *ev = &out->events[out->event_count];
        ev->kind = kind;
        ev->point = m->x;
        ev->normal = vec3_dot(h->shading, m->d) > 0.0 ? vec3_scale(h->shading, -1.0) : h->shading;
        ev->surface = k;
        ev->medium_from = from;
        ev->medium_to = to;
        ev->n_from = n_from;
        ev->n_to = n_to;
        ev->fresnel_R = R;
        ev->step_gap = gap;
    }
    out->event_count++;
}

static bool surface_scatters(const struct reftrace_surface *sf)
{
    return sf->scattering[0] > 0.0 || sf->scattering[1] > 0.0 || sf->scattering[2] > 0.0;
}

/* The crossing of surface k at the march's position (interface.h): toggles k in *inside;
 * where the medium changes, the Fresnel event of interface_cross with the environment's
 * reflection gathered (as at a bounds face) or total internal reflection. */
static void surface_event(struct march *m, uint32_t *inside, int k, const struct geom_hit *h,
                          const struct reftrace_bound_exit *bx, struct reftrace_result *out)
{
    uint32_t next = *inside ^ (1u << k);
    int from = interface_medium(*inside), to = interface_medium(next);
    double gap = bx != NULL ? bx->gap : 0.0;
    m->steps++;
    m->crossed = true;
    if (from == to) {
        *inside = next; /* k lies inside a higher-priority solid: not an interface here */
        return;
    }
    /* Leaving a field: n on the inside as reftrace_bound_march found it (the sample at the
     * hit, or |w| where the sample is clamped: docs/tracing.md "The rim"). */
    double n_from = bx != NULL ? bx->n_w : medium_ior(m, from), n_to = medium_ior(m, to);
    struct interface_event ev = interface_cross(m->d, h->shading, n_from, n_to);
    if (fabs(n_from - n_to) <= INDEX_EPS) {
        ev.R = 0.0; /* index-matched: the ray passes unchanged */
        ev.tir = false;
        ev.refracted = m->d;
    }
    record_event(out, ev.tir ? REFTRACE_EVENT_REFLECTED : REFTRACE_EVENT_REFRACTED, m, h, k, from,
                 ev.tir ? from : to, n_from, n_to, ev.R, gap);
    if (ev.tir) {
        m->d = ev.reflected;
        return;
    }
    const struct reftrace_lighting *lt = m->set->lighting;
    if (m->defer != NULL && !m->defer->set && lt != NULL && lt->walter.enabled && from >= 0 &&
        ev.R > 0.0 && surface_scatters(&m->set->surfaces[from])) {
        /* Leaving a walter scene's scattering medium: the reflected ray runs back through
         * it, gathering in-scattered light (docs/walter.md "The view ray's reflection"). */
        *m->defer = (struct march_deferred){
            true,    m->x, ev.reflected, vec3_scale(exp_neg(m->alpha), m->t_f * ev.R),
            *inside, k,    h->prim};
    } else if (ev.R > 0.0) {
        add_reflection(m, ev.R, m->x, ev.reflected);
    }
    if (m->set->lighting != NULL && m->set->lighting->count > 0) {
        /* The lights' reflected radiance (eq. 5.6/5.8) with the surface's BRDF. */
        vec3 Lr = reftrace_light_reflected(m->set->lighting, &m->set->surfaces[k].brdf, m->x, m->d,
                                           h->shading, ev.R);
        double w = m->t_f * basic_radiance(m, n_from);
        m->L = vec3_add(m->L, vec3_mul(vec3_scale(exp_neg(m->alpha), w), Lr));
    }
    m->t_f *= 1.0 - ev.R;
    m->d = ev.refracted;
    *inside = next;
}

/* One view ray from origin (inside the solids of `inside`, on surface last_surface's
 * primitive last_prim or -1) with the deferral record `defer` (NULL: none). */
static void trace(const struct reftrace_object *objects, int count,
                  const struct reftrace_settings *settings, vec3 origin, vec3 dir, uint32_t inside,
                  int last_surface, int64_t last_prim, struct march_deferred *defer,
                  struct reftrace_result *out)
{
    struct march m = {
        .set = settings,
        .defer = defer,
        .x = origin,
        .d = vec3_normalize(dir),
        .t_f = 1.0,
        .running = true,
    };
    out->event_count = 0;
    for (int pass = 0; m.running; pass++) {
        /* A surface event counts as a step (as on the GPU, where the pass cap grows by
         * max_steps only in the surfaces variant). */
        if (pass >= MAX_PASSES + (settings->surface_count > 0 ? settings->max_steps : 0)) {
            stop(&m, RAY_MAX_STEPS);
            break;
        }
        /* 1. The object entered first; voxel objects lie in the ambient medium, outside
         * every surface (scene_parse refuses overlaps), so inside a surface only surfaces
         * are searched. Then the nearest surface, when it comes first. */
        struct entry e;
        bool have_object = inside == 0 && next_object(&m, objects, count, &e);
        int med = interface_medium(inside);
        if (med >= 0 && settings->surfaces[med].field != NULL) {
            /* A field fills this medium: the ray equation up to the next surface. */
            struct reftrace_bound_exit bx;
            int k = reftrace_bound_march(&m, med, last_surface, last_prim, &bx);
            if (k < 0)
                break;
            surface_event(&m, &inside, k, &bx.hit, &bx, out);
            last_surface = k;
            last_prim = bx.hit.prim;
            if (throughput(&m) < reftrace_absorbed_cut(settings))
                stop(&m, RAY_ABSORBED);
            continue;
        }
        if (settings->surface_count > 0) {
            struct geom_hit h;
            int k =
                reftrace_next_surface(settings, m.x, m.d, INFINITY, last_surface, last_prim, &h);
            if (k >= 0 && (!have_object || h.t <= e.t_world)) {
                if (m.steps >= settings->max_steps) {
                    stop(&m, RAY_MAX_STEPS);
                    break;
                }
                surface_leg(&m, med, h.t);
                surface_event(&m, &inside, k, &h, NULL, out);
                last_surface = k;
                last_prim = h.prim;
                if (throughput(&m) < reftrace_absorbed_cut(settings))
                    stop(&m, RAY_ABSORBED);
                continue;
            }
            last_surface = -1;
            if (!have_object && inside != 0) {
                /* Inside a solid that never ends (a half-space): a medium whose extinction
                 * is positive in every channel takes all the light; one that is not lets
                 * it go. */
                const struct reftrace_surface *sf = &settings->surfaces[interface_medium(inside)];
                if (reftrace_surface_extinction(sf, 0) > 0.0 &&
                    reftrace_surface_extinction(sf, 1) > 0.0 &&
                    reftrace_surface_extinction(sf, 2) > 0.0) {
                    m.alpha = vec3_make(INFINITY, INFINITY, INFINITY);
                    stop(&m, RAY_ABSORBED);
                    break;
                }
            }
        }
        if (!have_object) {
            stop(&m, m.crossed ? RAY_EXITED : RAY_MISSED);
            /* 5. The receiver where the ray hits it, else the background term of tevs2007
             * eq. 5.10. */
            vec3 t = vec3_scale(exp_neg(m.alpha), m.t_f);
            m.L = vec3_add(
                m.L, vec3_mul(t, seen_from(&m, m.x, m.d, !m.crossed && out->event_count == 0)));
            break;
        }
        const struct reftrace_object *o = &objects[e.index];
        struct object_frame fr = {.o = o, .scale = o->xf.scale, .vs = reftrace_voxel_size(o)};
        fr.h_min = fmin(fr.vs.x, fmin(fr.vs.y, fr.vs.z));
        m.crossed = true;

        /* 2. Advance to the entry point through the ambient medium. */
        m.x = vec3_madd(m.x, m.d, e.t_world);
        m.opl += settings->ambient_ior * e.t_world;
        vec3 p = xform_point_to_object(&o->xf, m.x);
        vec3 q = xform_dir_to_object(&o->xf, m.d);

        /* 3. Entry face. */
        if (!e.inside) {
            p = snap_to_face(o, p, e.axis, e.sign);
            vec3 g_unused;
            double n_in = reftrace_sample_ior(o, p, &g_unused);
            if (!cross_face(&m, &fr, p, &q, axis_normal(e.axis, e.sign), settings->ambient_ior,
                            n_in)) {
                m.d = xform_dir_to_world(&o->xf, q); /* reflected, never entered */
                continue;
            }
        }
        /* 4. Through the field. */
        march_object(&m, &fr, p, q);
    }
    out->status = m.status;
    out->exit_origin = m.x;
    out->exit_direction = m.d;
    out->transmittance = vec3_scale(exp_neg(m.alpha), m.t_f);
    out->optical_path_length = m.opl;
    out->steps = m.steps;
    out->radiance = m.L;
}

void reftrace_ray(const struct reftrace_object *objects, int count,
                  const struct reftrace_settings *settings, vec3 origin, vec3 dir,
                  struct reftrace_result *out)
{
    assert(settings->step_voxels > 0.0);
    assert(settings->stepper != REFTRACE_ADAPTIVE || settings->tolerance > 0.0);
    assert(settings->stepper != REFTRACE_BS23 || settings->tolerance_voxels > 0.0);
    struct march_deferred defer = {0};
    uint32_t inside = reftrace_inside_set(settings->surfaces, settings->surface_count, origin);
    trace(objects, count, settings, origin, dir, inside, -1, -1, &defer, out);
    if (defer.set) {
        /* The radiance only: events, status and transmittance stay the first ray's. */
        static _Thread_local struct reftrace_result r;
        trace(objects, count, settings, defer.x, defer.d, defer.inside, defer.surface, defer.prim,
              NULL, &r);
        out->radiance = vec3_add(out->radiance, vec3_mul(defer.w, r.radiance));
    }
}
