/*
 * walter.c - the spread of a refracted path (walter2009 eq. 19-26), what a path carries
 * (eq. 17) and the exact sphere's paths (walter.h). Twin: shaders/walter.glsl.
 */
#include "walter.h"

#include <math.h>

#include "fresnel.h"
#include "phase.h"

vec3 walter_unit_deriv(vec3 u, vec3 du)
{
    double l2 = vec3_dot(u, u), l = sqrt(l2);
    return vec3_scale(vec3_madd(vec3_scale(du, l2), u, -vec3_dot(u, du)), 1.0 / (l2 * l));
}

/* Two unit vectors normal to u and to each other. */
static void tangent_basis(vec3 u, vec3 *e1, vec3 *e2)
{
    vec3 a = fabs(u.x) < 0.6 ? vec3_make(1, 0, 0) : vec3_make(0, 1, 0);
    *e1 = vec3_normalize(vec3_madd(a, u, -vec3_dot(a, u)));
    *e2 = vec3_cross(u, *e1);
}

double walter_spread(vec3 V, vec3 L, bool at_infinity, vec3 P, double eta,
                     const struct walter_normal *nrm)
{
    vec3 dv = vec3_sub(V, P);
    double d_V = vec3_length(dv);
    if (!(d_V > 0.0))
        return 0.0;
    vec3 u = vec3_scale(dv, 1.0 / d_V); /* omega_V */
    vec3 wL;
    double d_L = 0.0;
    if (at_infinity) {
        wL = vec3_scale(L, -1.0);
    } else {
        vec3 dl = vec3_sub(L, P);
        d_L = vec3_length(dl);
        if (!(d_L > 0.0))
            return 0.0;
        wL = vec3_scale(dl, 1.0 / d_L);
    }
    vec3 N = vec3_normalize(nrm->m);
    double c = vec3_dot(u, N), cos_L = vec3_dot(wL, N), ug = vec3_dot(u, nrm->N_g);
    if (!(c < 0.0) || !(cos_L > 0.0) || fabs(ug) < 1e-300)
        return 0.0;
    /* wL = mu N - eta u (Snell: the tangential parts of eta omega_V + omega_L cancel),
     * mu = cos_L + eta c (eq. 22). */
    double mu = cos_L + eta * c;
    vec3 e[2], Lp[2];
    tangent_basis(u, &e[0], &e[1]);
    for (int k = 0; k < 2; k++) {
        vec3 du = e[k];
        /* P = V - s u stays on the tangent plane (eq. 21; the paper's omega_V' has the
         * opposite sign). */
        vec3 Pp = vec3_scale(vec3_madd(du, u, -vec3_dot(du, nrm->N_g) / ug), -d_V);
        vec3 mp = vec3_add(vec3_scale(nrm->dm_a, vec3_dot(nrm->g_a, Pp)),
                           vec3_scale(nrm->dm_b, vec3_dot(nrm->g_b, Pp)));
        vec3 Np = walter_unit_deriv(nrm->m, mp);
        double cp = vec3_dot(du, N) + vec3_dot(u, Np);
        double mup = cp * (eta + eta * eta * c / cos_L);                       /* eq. 23 */
        vec3 wLp = vec3_madd(vec3_madd(vec3_scale(N, mup), Np, mu), du, -eta); /* eq. 24 */
        Lp[k] =
            at_infinity ? wLp : vec3_madd(vec3_madd(Pp, wL, -vec3_dot(Pp, wL)), wLp, d_L); /* 25 */
    }
    return vec3_length(vec3_cross(Lp[0], Lp[1])); /* eq. 26 */
}

bool walter_path_finish(struct walter_path *p, vec3 V, vec3 L, bool at_infinity, double eta,
                        const struct walter_normal *nrm)
{
    vec3 dv = vec3_sub(V, p->P);
    p->d_V = vec3_length(dv);
    if (!(p->d_V > 0.0))
        return false;
    p->omega_V = vec3_scale(dv, 1.0 / p->d_V);
    if (at_infinity) {
        p->omega_L = vec3_scale(L, -1.0);
        p->d_L = INFINITY;
    } else {
        vec3 dl = vec3_sub(L, p->P);
        p->d_L = vec3_length(dl);
        if (!(p->d_L > 0.0))
            return false;
        p->omega_L = vec3_scale(dl, 1.0 / p->d_L);
    }
    p->N = vec3_normalize(nrm->m);
    double cos_L = vec3_dot(p->omega_L, p->N);
    /* eq. 4: V below and L above the tangent plane; the shading normal agrees. */
    if (!(vec3_dot(p->omega_V, nrm->N_g) <= 0.0) || !(vec3_dot(p->omega_L, nrm->N_g) >= 0.0) ||
        !(cos_L > 0.0) || !(vec3_dot(p->omega_V, p->N) < 0.0))
        return false;
    p->T = 1.0 - fresnel_unpolarized(cos_L, 1.0, eta);
    p->D = walter_spread(V, L, at_infinity, p->P, eta, nrm);
    if (!(p->T > 0.0) || !(p->D > 0.0) || !isfinite(p->D))
        return false;
    p->gain = eta * eta * p->T / p->D;
    return true;
}

/* ---- the sphere ---- */

/* The sphere's search: P(theta) = c + R (cos theta e1 + sin theta e2) in the plane of c,
 * L and V, e1 toward the light. */
struct sphere_plane {
    vec3 c, e1, e2, L, V;
    double R, eta;
    bool at_infinity;
};

static vec3 sphere_point(const struct sphere_plane *s, double th, vec3 *N, vec3 *tg)
{
    double ct = cos(th), st = sin(th);
    *N = vec3_add(vec3_scale(s->e1, ct), vec3_scale(s->e2, st));
    *tg = vec3_add(vec3_scale(s->e1, -st), vec3_scale(s->e2, ct));
    return vec3_madd(s->c, *N, s->R);
}

/* The tangential part g(theta) = (eta omega_V + omega_L) . t(theta) of the half-vector
 * condition, and its derivative. */
static double sphere_g(const struct sphere_plane *s, double th, double *dg)
{
    vec3 N, tg;
    vec3 P = sphere_point(s, th, &N, &tg);
    vec3 u = vec3_sub(s->V, P), w = vec3_sub(s->L, P);
    vec3 wV = vec3_normalize(u);
    vec3 wL = s->at_infinity ? vec3_scale(s->L, -1.0) : vec3_normalize(w);
    vec3 h = vec3_madd(wL, wV, s->eta);
    if (dg != NULL) {
        vec3 Pp = vec3_scale(tg, s->R);
        vec3 hp = vec3_scale(walter_unit_deriv(u, vec3_scale(Pp, -1.0)), s->eta);
        if (!s->at_infinity)
            hp = vec3_add(hp, walter_unit_deriv(w, vec3_scale(Pp, -1.0)));
        *dg = vec3_dot(hp, tg) - vec3_dot(h, N); /* t' = -N */
    }
    return vec3_dot(h, tg);
}

/* The root of g in [a, b] (g(a), g(b) of opposite signs): Newton kept inside the bracket,
 * bisection where it would leave. */
static double sphere_root(const struct sphere_plane *s, double a, double b, double ga)
{
    double x = 0.5 * (a + b);
    for (int it = 0; it < 100 && b - a > 1e-15; it++) {
        double dg, g = sphere_g(s, x, &dg);
        if (g == 0.0)
            return x;
        if ((g < 0.0) == (ga < 0.0))
            a = x, ga = g;
        else
            b = x;
        double xn = dg != 0.0 ? x - g / dg : 0.5 * (a + b);
        x = xn > a && xn < b ? xn : 0.5 * (a + b);
    }
    return x;
}

static int sphere_add(const struct sphere_plane *s, double th, struct walter_path *out, int n,
                      int max)
{
    if (n >= max)
        return n;
    vec3 N, tg;
    struct walter_path p = {0};
    p.P = sphere_point(s, th, &N, &tg);
    vec3 b2 = vec3_cross(s->e1, s->e2);
    /* m = P - c: along the surface dm = dP = t (t . dP) + b2 (b2 . dP). */
    struct walter_normal nrm = {vec3_scale(N, s->R), tg, b2, tg, b2, N};
    if (!walter_path_finish(&p, s->V, s->L, s->at_infinity, s->eta, &nrm))
        return n;
    for (int i = 0; i < n; i++) /* a root on a bracket's end, found twice */
        if (vec3_length(vec3_sub(out[i].P, p.P)) < 1e-12 * s->R)
            return n;
    out[n] = p;
    return n + 1;
}

int walter_sphere_paths(vec3 c, double R, double eta, vec3 L, bool at_infinity, vec3 V,
                        struct walter_path *out, int max)
{
    struct sphere_plane s = {
        .c = c, .L = L, .V = V, .R = R, .eta = eta, .at_infinity = at_infinity};
    vec3 toward = at_infinity ? vec3_scale(L, -1.0) : vec3_sub(L, c);
    double dl = vec3_length(toward);
    if (!(R > 0.0) || !(dl > 0.0) || (!at_infinity && dl <= R) ||
        vec3_length(vec3_sub(V, c)) >= R || max <= 0)
        return 0;
    s.e1 = vec3_scale(toward, 1.0 / dl);
    vec3 b = vec3_sub(V, c);
    vec3 bp = vec3_madd(b, s.e1, -vec3_dot(b, s.e1));
    double bl = vec3_length(bp);
    if (bl < 1e-12 * R) {
        /* V on the axis through the light: the straight path; the ring of paths around it
         * (where there is one) is a caustic line, of measure zero, left out. */
        vec3 e2;
        tangent_basis(s.e1, &s.e2, &e2);
        return sphere_add(&s, 0.0, out, 0, max);
    }
    s.e2 = vec3_scale(bp, 1.0 / bl);
    /* The arc L sees: cos theta > R / |L - c| (a directional light: the lit hemisphere). */
    double th_max = at_infinity ? 0.5 * M_PI : acos(R / dl);
    int n = 0;
    double h = 2.0 * th_max / WALTER_SPHERE_BRACKETS;
    double t0 = -th_max, d0, g0 = sphere_g(&s, t0, &d0);
    for (int i = 1; i <= WALTER_SPHERE_BRACKETS; i++) {
        double t1 = -th_max + i * h, d1, g1 = sphere_g(&s, t1, &d1);
        if (g0 == 0.0) {
            n = sphere_add(&s, t0, out, n, max);
        } else if ((g0 < 0.0) != (g1 < 0.0) && g1 != 0.0) {
            n = sphere_add(&s, sphere_root(&s, t0, t1, g0), out, n, max);
        } else if (g0 * d0 < 0.0 && g1 * d1 > 0.0) {
            /* |g| falls from t0 and rises into t1: its minimum, where g' = 0, may cross
             * zero (two roots close together, near a caustic). */
            double a = t0, bb = t1, da = d0;
            for (int it = 0; it < 60; it++) {
                double m = 0.5 * (a + bb), dm;
                sphere_g(&s, m, &dm);
                if ((dm < 0.0) == (da < 0.0))
                    a = m, da = dm;
                else
                    bb = m;
            }
            double tm = 0.5 * (a + bb), gm = sphere_g(&s, tm, NULL);
            if ((gm < 0.0) != (g0 < 0.0)) {
                n = sphere_add(&s, sphere_root(&s, t0, tm, g0), out, n, max);
                n = sphere_add(&s, sphere_root(&s, tm, t1, gm), out, n, max);
            }
        }
        t0 = t1, g0 = g1, d0 = d1;
    }
    return n;
}

vec3 walter_sphere_inscatter(vec3 c, double R, double eta, vec3 L, bool at_infinity, vec3 V, vec3 d,
                             double g, vec3 sigma_t, vec3 spot_dir, double cos_spot)
{
    struct walter_path p[WALTER_MAX_PATHS];
    int n = walter_sphere_paths(c, R, eta, L, at_infinity, V, p, WALTER_MAX_PATHS);
    vec3 sum = {0, 0, 0}, toward_eye = vec3_scale(d, -1.0);
    for (int k = 0; k < n; k++) {
        if (vec3_dot(vec3_scale(p[k].omega_L, -1.0), spot_dir) < cos_spot)
            continue;
        double w = phase_hg(g, vec3_dot(p[k].omega_V, toward_eye)) * p[k].gain;
        for (int ch = 0; ch < 3; ch++)
            vec3_set(&sum, ch, vec3_get(sum, ch) + w * exp(-vec3_get(sigma_t, ch) * p[k].d_V));
    }
    return sum;
}
