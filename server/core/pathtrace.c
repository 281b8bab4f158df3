/*
 * pathtrace.c - the path of one camera sample (pathtrace.h): nearest hit, medium
 * collision, surface event, next-event estimation, Russian roulette. The estimators are
 * listed in pathtrace.h and derived in docs/pathtracer.md; light sampling is in
 * pathtrace_light.c, free flights in pathtrace_medium.c, directions in pathtrace_sample.c.
 *
 * What it deliberately is not (yet): GRIN (continuous index) media, heterogeneous (voxel)
 * media, BRDFs other than the Lambertian receiver, environment sampling. Each is listed
 * in docs/pathtracer.md "Not yet".
 */
#include "pathtrace.h"

#include <math.h>

#include "env.h"
#include "interface.h"
#include "phase.h"
#include "walter.h"

enum hit_kind { HIT_NONE = 0, HIT_SURFACE, HIT_RECEIVER, HIT_LIGHT };

struct pt_hit {
    enum hit_kind kind;
    int index; /* surface or light */
    double t;
    vec3 shading; /* surface: the normal Fresnel uses */
    int64_t prim;
};

/* Where the path is and what it carries (one line per member). */
struct pt_state {
    vec3 o, d;        /* the ray */
    uint32_t inside;  /* surfaces whose solids contain o */
    double beta[3];   /* throughput */
    bool specular;    /* the last event was delta (or the camera): emitters count fully */
    bool camera;      /* still the camera ray: invisible emitters are skipped */
    double last_pdf;  /* solid-angle pdf of the last diffuse/phase sampling */
    vec3 last_p;      /* where that sampling happened */
    int last_surface; /* the surface o lies on (-1: none), for mesh self-hits */
    int64_t last_prim;
    int scatters; /* medium scattering events so far (pathtrace_scene.max_scatter) */
    int walter;   /* 1: the last event scattered in the walter medium (exact connections
                     made there); 2: then refracted out of it: a small light met now was
                     counted by those connections (pathtrace_scene.walter) */
};

static double eps_at(vec3 p)
{
    return 1e-9 * (1.0 + fmax(fabs(p.x), fmax(fabs(p.y), fabs(p.z))));
}

static const struct pathtrace_medium *medium_of(const struct pathtrace_scene *s, uint32_t inside)
{
    int k = interface_medium(inside);
    return k < 0 ? &s->ambient : &s->surfaces[k].medium;
}

uint32_t pathtrace_inside_set(const struct pathtrace_scene *s, vec3 p)
{
    uint32_t set = 0;
    for (int k = 0; k < s->surface_count; k++)
        if (geom_surface_inside(&s->surfaces[k].geom, p))
            set |= 1u << k;
    return set;
}

bool pathtrace_receiver_hit(const struct pathtrace_receiver *r, vec3 o, vec3 d, double tmin,
                            double tmax, double *t)
{
    if (!r->enabled || d.y == 0.0)
        return false;
    double tt = (r->height - o.y) / d.y;
    if (!(tt > tmin && tt < tmax))
        return false;
    vec3 p = vec3_madd(o, d, tt);
    if (fabs(p.x - r->center[0]) > r->half_size || fabs(p.z - r->center[1]) > r->half_size)
        return false;
    *t = tt;
    return true;
}

/* The nearest surface, receiver or (when lights is true) spherical light along the ray. */
static struct pt_hit nearest(const struct pathtrace_scene *s, vec3 o, vec3 d, double tmax,
                             int last_surface, int64_t last_prim, bool lights, bool camera)
{
    struct pt_hit h = {.kind = HIT_NONE, .t = tmax};
    double tmin = eps_at(o);
    for (int k = 0; k < s->surface_count; k++) {
        struct geom_hit gh;
        int64_t skip = k == last_surface ? last_prim : -1;
        if (geom_surface_intersect(&s->surfaces[k].geom, o, d, tmin, h.t, skip, &gh)) {
            h = (struct pt_hit){HIT_SURFACE, k, gh.t, gh.shading, gh.prim};
        }
    }
    double t;
    if (pathtrace_receiver_hit(&s->receiver, o, d, tmin, h.t, &t))
        h = (struct pt_hit){HIT_RECEIVER, 0, t, vec3_make(0.0, 1.0, 0.0), 0};
    for (int k = 0; lights && k < s->light_count; k++) {
        if (camera && !s->lights[k].visible)
            continue;
        if (pathtrace_light_hit(&s->lights[k], o, d, tmin, h.t, &t))
            h = (struct pt_hit){HIT_LIGHT, k, t, vec3_make(0.0, 1.0, 0.0), 0};
    }
    return h;
}

/* Transmittance of a shadow ray from p (inside set `inside`) along wi over dist, into
 * tr[]: 0 when a refracting interface or the receiver is in the way (a shadow ray cannot
 * follow a delta refraction), else the media's exp(-sigma_t d) over each segment. */
static void shadow(const struct pathtrace_scene *s, vec3 p, vec3 wi, double dist, uint32_t inside,
                   int last_surface, int64_t last_prim, double tr[3])
{
    vec3 o = p;
    for (int crossings = 0; crossings < 2 * PATHTRACE_MAX_SURFACES + 2; crossings++) {
        struct pt_hit h = nearest(s, o, wi, dist, last_surface, last_prim, false, false);
        pathtrace_medium_transmittance(medium_of(s, inside), h.t, tr);
        if (h.kind == HIT_NONE)
            return;
        if (h.kind == HIT_RECEIVER)
            break;
        uint32_t next = inside ^ (1u << h.index);
        if (medium_of(s, next)->ior != medium_of(s, inside)->ior)
            break;
        o = vec3_madd(o, wi, h.t);
        dist -= h.t;
        inside = next;
        last_surface = h.index;
        last_prim = h.prim;
    }
    tr[0] = tr[1] = tr[2] = 0.0;
}

static double balance(double a, double b)
{
    return a + b > 0.0 ? a / (a + b) : 0.0;
}

/* Next-event estimation from p towards every light. phase_g: the medium's anisotropy
 * when p is a medium vertex, NAN when p is on the receiver with normal n. */
static void next_event(const struct pathtrace_scene *s, const struct pt_state *st, vec3 p, vec3 n,
                       const double albedo[3], double phase_g, struct pathtrace_rng *rng,
                       double L[3])
{
    for (int k = 0; k < s->light_count; k++) {
        struct pathtrace_light_sample ls;
        pathtrace_light_sample(&s->lights[k], p, rng, &ls);
        if (ls.Li_over_pdf[0] <= 0.0 && ls.Li_over_pdf[1] <= 0.0 && ls.Li_over_pdf[2] <= 0.0)
            continue;
        double f, pdf_b;
        if (isnan(phase_g)) {
            double c = vec3_dot(n, ls.wi);
            if (c <= 0.0)
                continue;
            f = c / M_PI; /* times albedo below */
            pdf_b = c / M_PI;
        } else {
            f = phase_hg(phase_g, vec3_dot(st->d, ls.wi));
            pdf_b = f;
        }
        double tr[3] = {1.0, 1.0, 1.0};
        shadow(s, p, ls.wi, ls.dist, st->inside, st->last_surface, st->last_prim, tr);
        double w = ls.pdf_sa > 0.0 ? balance(ls.pdf_sa, pdf_b) : 1.0;
        for (int c = 0; c < 3; c++)
            L[c] += st->beta[c] * albedo[c] * f * ls.Li_over_pdf[c] * tr[c] * w;
    }
}

bool pathtrace_walter_light(const struct pathtrace_scene *s, int k)
{
    const struct pathtrace_light *l = &s->lights[k];
    if (!s->walter.enabled)
        return false;
    if (l->kind == PATHTRACE_LIGHT_DIRECTIONAL)
        return true;
    double d = vec3_length(vec3_sub(l->position, s->walter.center));
    if (d <= s->walter.radius)
        return false; /* inside: shadow rays reach the medium */
    return l->kind != PATHTRACE_LIGHT_SPHERE || l->radius <= s->walter.lamp_ratio * d;
}

/* Exact connections from the walter medium's vertex p to every small light (walter.h):
 * per path the irradiance I T eta^2 / D exp(-sigma_t d_V), divided by eta^2 since path
 * radiance here is not scaled by n^2 across interfaces (camera and lights outside: the
 * factors cancel), times the phase function toward the camera path. */
static void walter_next_event(const struct pathtrace_scene *s, const struct pt_state *st, vec3 p,
                              double g, double L[3])
{
    const struct pathtrace_walter *w = &s->walter;
    const struct pathtrace_medium *m = &s->surfaces[w->surface].medium;
    for (int k = 0; k < s->light_count; k++) {
        if (!pathtrace_walter_light(s, k))
            continue;
        const struct pathtrace_light *l = &s->lights[k];
        bool inf = l->kind == PATHTRACE_LIGHT_DIRECTIONAL;
        double I[3];
        for (int c = 0; c < 3; c++) /* a sphere lamp's far field: L_e pi r^2 */
            I[c] = l->kind == PATHTRACE_LIGHT_SPHERE ? l->value[c] * M_PI * l->radius * l->radius
                                                     : l->value[c];
        vec3 e = walter_sphere_inscatter(
            w->center, w->radius, w->eta, inf ? l->direction : l->position, inf, p, st->d, g,
            vec3_make(m->sigma_a[0] + m->sigma_s[0], m->sigma_a[1] + m->sigma_s[1],
                      m->sigma_a[2] + m->sigma_s[2]),
            l->direction, l->kind == PATHTRACE_LIGHT_SPOT ? l->cos_spot : -2.0);
        for (int c = 0; c < 3; c++)
            L[c] += st->beta[c] * I[c] * vec3_get(e, c) / (w->eta * w->eta);
    }
}

static vec3 environment(const struct pathtrace_scene *s, vec3 d)
{
    if (s->env_kind == PATHTRACE_ENV_PROCEDURAL)
        return env_procedural(d);
    return vec3_make(1.0, 1.0, 1.0);
}

static void add_env(const struct pathtrace_scene *s, const struct pt_state *st, double L[3])
{
    vec3 e = environment(s, st->d);
    const double ev[3] = {e.x, e.y, e.z};
    for (int c = 0; c < 3; c++)
        L[c] += st->beta[c] * ev[c] * s->env_radiance[c];
}

static void add_emitter(const struct pathtrace_scene *s, const struct pt_state *st, int k,
                        double L[3])
{
    const struct pathtrace_light *l = &s->lights[k];
    double w = st->specular ? 1.0 : balance(st->last_pdf, pathtrace_light_pdf(l, st->last_p));
    for (int c = 0; c < 3; c++)
        L[c] += st->beta[c] * l->value[c] * w;
}

/* Survival of Russian roulette: false ends the path; else beta grows by 1/q. */
static bool roulette(struct pt_state *st, int depth, struct pathtrace_rng *rng)
{
    if (depth < PATHTRACE_RR_DEPTH)
        return true;
    double q = fmax(st->beta[0], fmax(st->beta[1], st->beta[2]));
    if (q >= 1.0)
        return true;
    if (q <= 0.0 || pathtrace_rng_uniform(rng) >= q)
        return false;
    for (int c = 0; c < 3; c++)
        st->beta[c] /= q;
    return true;
}

static void scatter_medium(const struct pathtrace_scene *s, struct pt_state *st, vec3 p,
                           struct pathtrace_rng *rng, double L[3])
{
    static const double one[3] = {1.0, 1.0, 1.0};
    double g = medium_of(s, st->inside)->g;
    st->last_surface = -1;
    next_event(s, st, p, vec3_make(0.0, 1.0, 0.0), one, g, rng, L);
    st->walter = 0;
    if (s->walter.enabled && st->inside == 1u << s->walter.surface) {
        walter_next_event(s, st, p, g, L);
        st->walter = 1;
    }
    vec3 nd = pathtrace_sample_hg(st->d, g, rng);
    st->last_pdf = phase_hg(g, vec3_dot(st->d, nd));
    st->last_p = p;
    st->specular = false;
    st->o = p;
    st->d = nd;
}

static void bounce_receiver(const struct pathtrace_scene *s, struct pt_state *st, vec3 p,
                            struct pathtrace_rng *rng, double L[3])
{
    vec3 n = vec3_make(0.0, st->d.y < 0.0 ? 1.0 : -1.0, 0.0);
    st->last_surface = -1;
    st->walter = 0;
    next_event(s, st, p, n, s->receiver.albedo, NAN, rng, L);
    vec3 nd = pathtrace_sample_cosine(n, rng);
    for (int c = 0; c < 3; c++)
        st->beta[c] *= s->receiver.albedo[c];
    st->last_pdf = vec3_dot(n, nd) / M_PI;
    st->last_p = p;
    st->specular = false;
    st->o = p;
    st->d = nd;
}

/* The Fresnel-weighted choice at surface h (or a plain crossing of an index-matched
 * boundary, which is no event: the MIS state carries over). Returns true for an event. */
static bool cross_surface(const struct pathtrace_scene *s, struct pt_state *st,
                          const struct pt_hit *h, vec3 p, struct pathtrace_rng *rng)
{
    uint32_t next = st->inside ^ (1u << h->index);
    double n_i = medium_of(s, st->inside)->ior, n_t = medium_of(s, next)->ior;
    st->o = p;
    st->last_surface = h->index;
    st->last_prim = h->prim;
    if (n_i == n_t) {
        st->inside = next;
        return false;
    }
    struct interface_event ev = interface_cross(st->d, h->shading, n_i, n_t);
    bool keep = s->walter.connected_only && st->walter != 0;
    if (ev.tir || pathtrace_rng_uniform(rng) < ev.R) {
        st->d = ev.reflected;
        st->walter = keep ? 1 : 0;
    } else {
        st->d = ev.refracted;
        st->inside = next;
        /* out of the walter medium straight after scattering in it */
        st->walter = st->walter == 1 && h->index == s->walter.surface && next == 0 ? 2
                     : keep                                                        ? 1
                                                                                   : 0;
    }
    st->specular = true;
    return true;
}

void pathtrace_radiance(const struct pathtrace_scene *s, vec3 origin, vec3 dir, uint32_t inside,
                        bool camera, struct pathtrace_rng *rng, double L[3])
{
    struct pt_state st = {.o = origin,
                          .d = dir,
                          .inside = inside,
                          .beta = {1.0, 1.0, 1.0},
                          .specular = true,
                          .camera = camera,
                          .last_surface = -1,
                          .last_prim = -1};
    L[0] = L[1] = L[2] = 0.0;
    for (int depth = 0; depth < PATHTRACE_MAX_DEPTH; depth++) {
        struct pt_hit h =
            nearest(s, st.o, st.d, INFINITY, st.last_surface, st.last_prim, true, st.camera);
        double t;
        if (pathtrace_medium_sample(medium_of(s, st.inside), h.t, rng, st.beta, &t)) {
            if (s->max_scatter > 0 && st.scatters++ >= s->max_scatter)
                return; /* paths with more scattering events are left out */
            st.camera = false;
            scatter_medium(s, &st, vec3_madd(st.o, st.d, t), rng, L);
            if (!roulette(&st, depth, rng))
                return;
            continue;
        }
        if (h.kind == HIT_NONE) {
            add_env(s, &st, L);
            return;
        }
        if (h.kind == HIT_LIGHT) {
            bool made = st.walter == 2 || (st.walter != 0 && s->walter.connected_only);
            if (!(made && pathtrace_walter_light(s, h.index)))
                add_emitter(s, &st, h.index, L); /* else made by walter_next_event */
            return;
        }
        vec3 p = vec3_madd(st.o, st.d, h.t);
        if (h.kind == HIT_RECEIVER) {
            st.camera = false;
            bounce_receiver(s, &st, p, rng, L);
        } else {
            /* An index-matched crossing keeps a camera ray a camera ray; after a real
             * event emitters count even when invisible to the camera (seen in glass). */
            if (cross_surface(s, &st, &h, p, rng))
                st.camera = false;
        }
        if (!roulette(&st, depth, rng))
            return;
    }
}
