/*
 * test_walter.c - exact single-scattering paths (core/walter.h, walter2009; issue 15 item 2):
 *   - the spread D against the paper's closed forms on a flat interface (normal incidence
 *     (d_V + eta d_L)^2, oblique eq. 18) and against a ray bundle traced through the
 *     exact sphere with Snell's law (finite differences), for point and directional lights;
 *   - the irradiance eta^2 T / D with extinction against the fluence of a ray bundle traced
 *     by Snell's law and Fresnel alone (track lengths in a small ball);
 *   - the sphere's 1D search finds what a dense scan of the same circle finds, on random
 *     point pairs (eta 1.5 and an air bubble's 1 / 1.33);
 *   - the guarantee on a bumpy sphere (walter2009 fig. 7's model, position-normal
 *     interpolated triangles): the interval search finds exactly the solutions of a
 *     brute-force dense search (Newton from a grid of starts on every triangle that can
 *     hold one) on 10,000 random point pairs, several paths per pair among them; a path
 *     through a shared vertex or edge is found once, not lost and not twice;
 *   - a finely tessellated sphere with exact vertex normals gives the exact sphere's paths.
 */
#include <math.h>
#include <stdlib.h>
#include <time.h>

#include "core/fresnel.h"
#include "core/walter.h"
#include "mesh_test_util.h"
#include "test.h"

static double rnd(uint64_t *s)
{
    *s = *s * 6364136223846793005ull + 1442695040888963407ull;
    return (double)(*s >> 11) * (1.0 / 9007199254740992.0);
}

static vec3 rnd_dir(uint64_t *s)
{
    double z = 2.0 * rnd(s) - 1.0, a = 2.0 * M_PI * rnd(s), r = sqrt(fmax(0.0, 1.0 - z * z));
    return vec3_make(r * cos(a), r * sin(a), z);
}

static vec3 rnd_in_ball(uint64_t *s, double R)
{
    return vec3_scale(rnd_dir(s), R * cbrt(rnd(s)));
}

/* ---- the spread on a flat interface ---- */

static struct walter_triangle flat_triangle(void)
{
    /* The plane y = 0, normal +y (the medium below), a triangle far larger than the paths. */
    struct walter_triangle t = {{{-100, 0, -100}, {100, 0, -100}, {0, 0, 200}},
                                {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}}};
    return t;
}

static void flat_spread_matches_closed_forms(void)
{
    struct walter_triangle t = flat_triangle();
    const double eta = 1.5;
    /* Normal incidence: D = (d_V + eta d_L)^2. */
    vec3 V = {0.3, -0.7, 0.2}, L = {0.3, 2.0, 0.2};
    struct walter_path p[4];
    int n = walter_triangle_paths(&t, eta, L, false, V, p, 4, NULL);
    CHECK_INT(n, 1);
    if (n == 1) {
        CHECK_NEAR(p[0].P.x, 0.3, 1e-12);
        CHECK_NEAR(p[0].D, (0.7 + eta * 2.0) * (0.7 + eta * 2.0), 1e-9);
        CHECK_NEAR(p[0].T, 1.0 - 0.04, 1e-12);
        CHECK_NEAR(p[0].gain, eta * eta * 0.96 / p[0].D, 1e-15);
    }
    /* Oblique, eq. 18: D = (d_V + eta d_L) (cos_L / cos_V d_V + cos_V / cos_L eta d_L). */
    uint64_t s = 11;
    for (int i = 0; i < 50; i++) {
        V = vec3_make(4 * rnd(&s) - 2, -0.1 - 2 * rnd(&s), 4 * rnd(&s) - 2);
        L = vec3_make(4 * rnd(&s) - 2, 0.1 + 3 * rnd(&s), 4 * rnd(&s) - 2);
        n = walter_triangle_paths(&t, eta, L, false, V, p, 4, NULL);
        CHECK_INT(n, 1);
        if (n != 1)
            continue;
        double cV = fabs(p[0].omega_V.y), cL = fabs(p[0].omega_L.y);
        double D = (p[0].d_V + eta * p[0].d_L) * (cL / cV * p[0].d_V + cV / cL * eta * p[0].d_L);
        CHECK_NEAR(p[0].D / D, 1.0, 1e-9);
        /* Snell's law at the point found. */
        double sin_L = sqrt(1 - cL * cL), sin_V = sqrt(1 - cV * cV);
        CHECK_NEAR(sin_L, eta * sin_V, 1e-10);
        CHECK_NEAR(p[0].T, 1.0 - fresnel_unpolarized(cL, 1.0, eta), 1e-12);
    }
}

/* ---- the spread against a traced ray bundle ---- */

/* From V backwards along -dir: the sphere's exit point, the refracted direction outside,
 * and where that ray meets the plane through Lp normal to nL (or, for a directional light,
 * the outgoing direction itself). */
static bool trace_back(vec3 c, double R, double eta, vec3 V, vec3 dir, vec3 Lp, vec3 nL,
                       bool at_infinity, vec3 *out)
{
    vec3 d = vec3_scale(dir, -1.0), o = vec3_sub(V, c);
    double b = vec3_dot(o, d), cc = vec3_dot(o, o) - R * R;
    double t = -b + sqrt(b * b - cc); /* V inside: the far root */
    vec3 P = vec3_madd(V, d, t), N = vec3_scale(vec3_sub(P, c), 1.0 / R);
    vec3 w;
    if (!snell_refract(d, N, eta, 1.0, &w))
        return false;
    if (at_infinity) {
        *out = w;
        return true;
    }
    double s = vec3_dot(vec3_sub(Lp, P), nL) / vec3_dot(w, nL);
    *out = vec3_madd(P, w, s);
    return true;
}

static void sphere_spread_matches_ray_bundle(void)
{
    const vec3 c = {0.2, -0.1, 0.3};
    const double R = 0.9;
    uint64_t s = 5;
    int checked = 0;
    for (int i = 0; i < 400; i++) {
        double eta = i % 2 ? 1.5 : 1.0 / 1.33;
        bool inf = i % 3 == 0;
        vec3 V = vec3_add(c, rnd_in_ball(&s, 0.95 * R));
        vec3 L = inf ? rnd_dir(&s) : vec3_add(c, vec3_scale(rnd_dir(&s), R * (1.2 + 4 * rnd(&s))));
        struct walter_path p[WALTER_MAX_PATHS];
        int n = walter_sphere_paths(c, R, eta, L, inf, V, p, WALTER_MAX_PATHS);
        for (int k = 0; k < n; k++) {
            vec3 u = p[k].omega_V, e1, e2;
            vec3 a = fabs(u.x) < 0.6 ? vec3_make(1, 0, 0) : vec3_make(0, 1, 0);
            e1 = vec3_normalize(vec3_madd(a, u, -vec3_dot(a, u)));
            e2 = vec3_cross(u, e1);
            vec3 nL = p[k].omega_L;
            vec3 Lp = inf ? nL : L, X[2][2];
            const double h = 1e-6;
            bool ok = true;
            for (int j = 0; j < 2 && ok; j++) {
                vec3 e = j ? e2 : e1;
                for (int sg = 0; sg < 2 && ok; sg++) {
                    vec3 dir = vec3_normalize(vec3_madd(u, e, sg ? h : -h));
                    ok = trace_back(c, R, eta, V, dir, Lp, nL, inf, &X[j][sg]);
                }
            }
            if (!ok || p[k].D < 1e-6 || vec3_dot(p[k].omega_L, p[k].N) < 0.02)
                continue; /* near a caustic or grazing: finite differences are poor there */
            vec3 d1 = vec3_scale(vec3_sub(X[0][1], X[0][0]), 0.5 / h);
            vec3 d2 = vec3_scale(vec3_sub(X[1][1], X[1][0]), 0.5 / h);
            double D = vec3_length(vec3_cross(d1, d2));
            CHECK_MSG(fabs(p[k].D / D - 1.0) < 2e-5,
                      "pair %d path %d/%d: D %.9g, bundle %.9g (eta %g%s) T %g cosL %g", i, k, n,
                      p[k].D, D, eta, inf ? ", directional" : "", p[k].T,
                      vec3_dot(p[k].omega_L, p[k].N));
            /* The path obeys Snell's law: eta omega_V + omega_L is along N. */
            vec3 hv = vec3_madd(p[k].omega_L, p[k].omega_V, eta);
            CHECK(vec3_length(vec3_madd(hv, p[k].N, -vec3_dot(hv, p[k].N))) < 1e-10);
            checked++;
        }
    }
    CHECK(checked > 300);
}

/* ---- the radiometry against a ray bundle's fluence ---- */

/* The fluence (scalar irradiance) at V, a point light's rays refracted into the sphere,
 * by the track-length estimator: rays from L, stratified over the cone that holds the
 * sphere, carry power I domega T exp(-sigma_t s) into the medium; the mean chord length
 * inside a small ball of radius eps around V over its volume is the fluence. Nothing of
 * walter.c is used: Snell by snell_refract, Fresnel by fresnel_unpolarized. */
static double bundle_fluence(vec3 c, double R, double eta, double sigma_t, vec3 L, vec3 V,
                             double eps, int n_side)
{
    vec3 axis = vec3_normalize(vec3_sub(c, L));
    double dl = vec3_length(vec3_sub(c, L)), cos_max = sqrt(1.0 - R * R / (dl * dl));
    vec3 e1, e2;
    vec3 a = fabs(axis.x) < 0.6 ? vec3_make(1, 0, 0) : vec3_make(0, 1, 0);
    e1 = vec3_normalize(vec3_madd(a, axis, -vec3_dot(a, axis)));
    e2 = vec3_cross(axis, e1);
    double omega = 2.0 * M_PI * (1.0 - cos_max), dw = omega / ((double)n_side * n_side);
    double sum = 0.0;
    uint64_t s = 77;
    for (int i = 0; i < n_side; i++)
        for (int j = 0; j < n_side; j++) {
            double u = (i + rnd(&s)) / n_side, v = (j + rnd(&s)) / n_side;
            double ct = 1.0 - u * (1.0 - cos_max), st = sqrt(fmax(0.0, 1.0 - ct * ct));
            double ph = 2.0 * M_PI * v;
            vec3 d = vec3_add(vec3_scale(axis, ct),
                              vec3_add(vec3_scale(e1, st * cos(ph)), vec3_scale(e2, st * sin(ph))));
            vec3 o = vec3_sub(L, c);
            double b = vec3_dot(o, d), cc = vec3_dot(o, o) - R * R, disc = b * b - cc;
            if (disc <= 0.0)
                continue;
            double t = -b - sqrt(disc);
            vec3 P = vec3_madd(L, d, t), N = vec3_scale(vec3_sub(P, c), 1.0 / R), w;
            double T = 1.0 - fresnel_unpolarized(fabs(vec3_dot(d, N)), 1.0, eta);
            if (!snell_refract(d, N, 1.0, eta, &w))
                continue;
            /* the chord of the small ball around V along P + s w */
            vec3 q = vec3_sub(P, V);
            double qb = vec3_dot(q, w), qc = vec3_dot(q, q) - eps * eps, qd = qb * qb - qc;
            if (qd <= 0.0)
                continue;
            double s0 = -qb - sqrt(qd), s1 = -qb + sqrt(qd);
            if (s0 < 0.0)
                continue; /* V's ball must lie ahead, inside the medium */
            /* power I dw T; extinction exp(-sigma_t s) integrated over the chord */
            double track = (exp(-sigma_t * s0) - exp(-sigma_t * s1)) / sigma_t;
            sum += dw * T * track;
        }
    return sum / (4.0 / 3.0 * M_PI * eps * eps * eps);
}

static void sphere_fluence_matches_ray_bundle(void)
{
    const vec3 c = {0, 0, 0};
    const double R = 1.0, sigma_t = 0.55;
    const vec3 L = {0, 1, -5};
    const vec3 Vs[4] = {{0, 0, 0}, {0.3, -0.2, 0.5}, {-0.2, 0.3, -0.4}, {-0.1, -0.35, 0.6}};
    const double etas[2] = {1.5, 1.0 / 1.33};
    int n_side = test_sanitized() ? 600 : 2000;
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < 4; i++) {
            struct walter_path p[WALTER_MAX_PATHS];
            int n = walter_sphere_paths(c, R, etas[k], L, false, Vs[i], p, WALTER_MAX_PATHS);
            double phi = 0.0;
            for (int j = 0; j < n; j++)
                phi += p[j].gain * exp(-sigma_t * p[j].d_V);
            double b = bundle_fluence(c, R, etas[k], sigma_t, L, Vs[i], 0.02, n_side);
            printf("fluence at (%g, %g, %g), eta %.3f: %d paths %.6f, ray bundle %.6f (%+.2f%%)\n",
                   Vs[i].x, Vs[i].y, Vs[i].z, etas[k], n, phi, b, 100.0 * (b / phi - 1.0));
            CHECK(n >= 1);
            CHECK_MSG(fabs(b / phi - 1.0) < (test_sanitized() ? 0.08 : 0.03),
                      "fluence %.6f by the paths, %.6f by the bundle", phi, b);
        }
}

/* ---- the sphere's search against a dense scan ---- */

static int dense_sphere_count(vec3 c, double R, double eta, vec3 L, bool inf, vec3 V, int n)
{
    /* The same circle as walter_sphere_paths, scanned at n points: sign changes of the
     * tangential condition. */
    vec3 toward = inf ? vec3_scale(L, -1.0) : vec3_sub(L, c);
    double dl = vec3_length(toward);
    vec3 e1 = vec3_scale(toward, 1.0 / dl), b = vec3_sub(V, c);
    vec3 e2 = vec3_normalize(vec3_madd(b, e1, -vec3_dot(b, e1)));
    double th_max = inf ? 0.5 * M_PI : acos(R / dl);
    int count = 0;
    double g0 = 0;
    for (int i = 0; i <= n; i++) {
        double th = -th_max + 2 * th_max * i / n;
        vec3 N = vec3_add(vec3_scale(e1, cos(th)), vec3_scale(e2, sin(th)));
        vec3 tg = vec3_add(vec3_scale(e1, -sin(th)), vec3_scale(e2, cos(th)));
        vec3 P = vec3_madd(c, N, R);
        vec3 wL = inf ? vec3_scale(L, -1.0) : vec3_normalize(vec3_sub(L, P));
        double g = vec3_dot(vec3_madd(wL, vec3_normalize(vec3_sub(V, P)), eta), tg);
        if (i > 0 && (g < 0) != (g0 < 0) && vec3_dot(wL, N) > 1e-9)
            count++;
        g0 = g;
    }
    return count;
}

static void sphere_search_finds_every_path(void)
{
    const vec3 c = {0, 0, 0};
    uint64_t s = 99;
    int pairs = test_sanitized() ? 300 : 3000, differ = 0, multi = 0;
    for (int i = 0; i < pairs; i++) {
        double eta = i % 2 ? 1.5 : 1.0 / 1.33;
        bool inf = i % 5 == 0;
        vec3 V = rnd_in_ball(&s, 0.999);
        vec3 L = inf ? rnd_dir(&s) : vec3_scale(rnd_dir(&s), 1.05 + 5 * rnd(&s));
        struct walter_path p[WALTER_MAX_PATHS];
        int n = walter_sphere_paths(c, 1.0, eta, L, inf, V, p, WALTER_MAX_PATHS);
        int m = dense_sphere_count(c, 1.0, eta, L, inf, V, 20000);
        if (m != n) /* two roots closer than the scan's step: scan 100 times finer */
            m = dense_sphere_count(c, 1.0, eta, L, inf, V, 2000000);
        if (n != m) {
            differ++;
            CHECK_MSG(n == m, "pair %d: %d paths, dense scan %d (eta %g)", i, n, m, eta);
        }
        multi += n > 1;
    }
    CHECK_INT(differ, 0);
    CHECK(multi > 0);
    printf("sphere: %d pairs, %d with more than one path\n", pairs, multi);
}

/* ---- the bumpy sphere ---- */

struct bumpy {
    struct walter_triangle *t;
    size_t n;
};

/* An icosphere of 320 triangles pushed out by r = 1 + 0.15 sin(5x) sin(5y) sin(5z), with
 * area-weighted vertex normals (as a user's mesh would have them). */
static struct bumpy bumpy_sphere(void)
{
    struct test_mesh m = test_icosphere(2, 1.0);
    vec3 *v = calloc(m.nv, sizeof *v), *nrm = calloc(m.nv, sizeof *nrm);
    for (size_t i = 0; i < m.nv; i++) {
        vec3 d = vec3_make(m.v[i][0], m.v[i][1], m.v[i][2]);
        double r = 1.0 + 0.15 * sin(5 * d.x) * sin(5 * d.y) * sin(5 * d.z);
        v[i] = vec3_scale(d, r);
    }
    for (size_t k = 0; k < m.nt; k++) {
        vec3 a = v[m.t[k][0]], b = v[m.t[k][1]], cc = v[m.t[k][2]];
        vec3 fn = vec3_cross(vec3_sub(b, a), vec3_sub(cc, a));
        for (int j = 0; j < 3; j++)
            nrm[m.t[k][j]] = vec3_add(nrm[m.t[k][j]], fn);
    }
    struct bumpy B = {calloc(m.nt, sizeof *B.t), m.nt};
    for (size_t k = 0; k < m.nt; k++)
        for (int j = 0; j < 3; j++) {
            B.t[k].p[j] = v[m.t[k][j]];
            B.t[k].n[j] = vec3_normalize(nrm[m.t[k][j]]);
        }
    free(v);
    free(nrm);
    test_mesh_free(&m);
    return B;
}

/* Brute force: Newton from every point of a grid of starts (spacing 1/G in a and b) on
 * every triangle whose plane separates L and V (eq. 4, a condition of the definition),
 * solutions merged by position. */
static int brute_force_count(const struct bumpy *B, double eta, vec3 L, vec3 V, int G, vec3 *found)
{
    int n = 0;
    vec3 mid = vec3_scale(vec3_add(L, V), 0.5);
    double r = 0.5 * vec3_length(vec3_sub(L, V));
    for (size_t k = 0; k < B->n; k++) {
        const struct walter_triangle *t = &B->t[k];
        vec3 Ng = vec3_cross(vec3_sub(t->p[1], t->p[0]), vec3_sub(t->p[2], t->p[0]));
        if (vec3_dot(vec3_sub(V, t->p[0]), Ng) > 0 || vec3_dot(vec3_sub(L, t->p[0]), Ng) < 0)
            continue;
        /* the angle LPV exceeds a right angle at a solution: P lies in the sphere on LV, so
         * a vertex lies within the longest edge of it */
        double dmin = INFINITY, edge = 0.0;
        for (int j = 0; j < 3; j++) {
            dmin = fmin(dmin, vec3_length(vec3_sub(t->p[j], mid)));
            edge = fmax(edge, vec3_length(vec3_sub(t->p[j], t->p[(j + 1) % 3])));
        }
        if (dmin > r + edge)
            continue;
        for (int i = 0; i <= G; i++)
            for (int j = 0; i + j <= G; j++) {
                double a = (double)i / G, b = (double)j / G;
                if (!walter_triangle_newton(t, eta, L, false, V, &a, &b))
                    continue;
                if (a < -1e-9 || b < -1e-9 || a + b > 1 + 1e-9)
                    continue;
                struct walter_path p = {0};
                p.P = vec3_add(t->p[0], vec3_add(vec3_scale(vec3_sub(t->p[1], t->p[0]), a),
                                                 vec3_scale(vec3_sub(t->p[2], t->p[0]), b)));
                struct walter_normal nn = walter_triangle_normal(t, a, b);
                if (!walter_path_finish(&p, V, L, false, eta, &nn))
                    continue;
                bool dup = false;
                for (int q = 0; q < n && !dup; q++)
                    dup = vec3_length(vec3_sub(found[q], p.P)) < 1e-7;
                if (!dup && n < WALTER_MAX_PATHS)
                    found[n++] = p.P;
            }
    }
    return n;
}

static void bumpy_sphere_guarantee(void)
{
    struct bumpy B = bumpy_sphere();
    uint64_t s = 2024;
    int pairs = test_sanitized() ? 300 : 10000, differ = 0, hist[6] = {0};
    struct walter_stats st = {0};
    for (int i = 0; i < pairs; i++) {
        vec3 V = rnd_in_ball(&s, 0.8);
        vec3 L = vec3_scale(rnd_dir(&s), 1.4 + 2.5 * rnd(&s));
        struct walter_path p[WALTER_MAX_PATHS];
        vec3 bf[WALTER_MAX_PATHS];
        int n = walter_mesh_paths(B.t, B.n, 1.5, L, false, V, p, WALTER_MAX_PATHS, &st);
        int m = brute_force_count(&B, 1.5, L, V, 3, bf);
        if (m != n) /* a coarse grid of starts may miss one: ask a dense one */
            m = brute_force_count(&B, 1.5, L, V, 16, bf);
        if (n != m) {
            differ++;
            CHECK_MSG(n == m, "pair %d: the interval search found %d paths, brute force %d", i, n,
                      m);
        }
        hist[n < 5 ? n : 5]++;
    }
    CHECK_INT(differ, 0);
    CHECK(hist[3] + hist[4] + hist[5] > pairs / 50); /* several paths per point, often */
    printf("bumpy sphere: %d pairs; paths 0:%d 1:%d 2:%d 3:%d 4:%d 5+:%d; per pair %.1f "
           "triangles searched, %.0f boxes, %.1f Newton runs, %ld unresolved boxes\n",
           pairs, hist[0], hist[1], hist[2], hist[3], hist[4], hist[5],
           (double)st.triangles_tested / pairs, (double)st.boxes / pairs,
           (double)st.newton_runs / pairs, st.unresolved);
    CHECK(st.unresolved == 0);

    /* A path through a shared vertex and one through a shared edge's midpoint: the straight
     * path at normal incidence (L and V on the line through the point along its normal, which
     * interpolation makes the same on every triangle that shares it) is found exactly once. */
    const struct walter_triangle *t0 = &B.t[0];
    vec3 pts[2] = {t0->p[0], vec3_scale(vec3_add(t0->p[0], t0->p[1]), 0.5)};
    vec3 nrms[2] = {t0->n[0], vec3_normalize(vec3_add(t0->n[0], t0->n[1]))};
    for (int k = 0; k < 2; k++) {
        vec3 V = vec3_madd(pts[k], nrms[k], -0.3), L = vec3_madd(pts[k], nrms[k], 1.0);
        struct walter_path p[WALTER_MAX_PATHS];
        int n = walter_mesh_paths(B.t, B.n, 1.5, L, false, V, p, WALTER_MAX_PATHS, NULL);
        int at = 0;
        for (int j = 0; j < n; j++)
            at += vec3_length(vec3_sub(p[j].P, pts[k])) < 1e-8;
        CHECK_MSG(at == 1, "%s: the path through it found %d times", k ? "edge" : "vertex", at);
    }
    free(B.t);
}

/* ---- a tessellated sphere with exact normals against the exact sphere ---- */

/* The largest relative gain error of a tessellated unit sphere (levels: 20 4^levels
 * triangles) with exact vertex normals against the exact sphere, over 40 random pairs. */
static double tessellated_gain_error(int levels, int *compared)
{
    struct test_mesh m = test_icosphere(levels, 1.0);
    struct walter_triangle *t = calloc(m.nt, sizeof *t);
    for (size_t k = 0; k < m.nt; k++)
        for (int j = 0; j < 3; j++) {
            vec3 v = vec3_make(m.v[m.t[k][j]][0], m.v[m.t[k][j]][1], m.v[m.t[k][j]][2]);
            t[k].p[j] = v;
            t[k].n[j] = v;
        }
    uint64_t s = 3;
    double worst = 0.0;
    for (int i = 0; i < 40; i++) {
        vec3 V = rnd_in_ball(&s, 0.7), L = vec3_scale(rnd_dir(&s), 2.0 + 3 * rnd(&s));
        struct walter_path a[WALTER_MAX_PATHS], b[WALTER_MAX_PATHS];
        int na = walter_sphere_paths((vec3){0, 0, 0}, 1.0, 1.5, L, false, V, a, WALTER_MAX_PATHS);
        int nb = walter_mesh_paths(t, m.nt, 1.5, L, false, V, b, WALTER_MAX_PATHS, NULL);
        CHECK_INT(nb, na);
        for (int k = 0; k < na && k < nb; k++) {
            int best = 0;
            for (int j = 1; j < nb; j++)
                if (vec3_length(vec3_sub(b[j].P, a[k].P)) <
                    vec3_length(vec3_sub(b[best].P, a[k].P)))
                    best = j;
            /* the flat facets sit up to 1 - cos(edge / 2) inside the sphere */
            CHECK(vec3_length(vec3_sub(b[best].P, a[k].P)) < 0.02);
            worst = fmax(worst, fabs(b[best].gain / a[k].gain - 1.0));
            (*compared)++;
        }
    }
    free(t);
    test_mesh_free(&m);
    return worst;
}

/* Interpolated normals stand in for the curvature the flat facets lack: the spread's error
 * is first order in the edge length (halves with each level). */
static void tessellated_sphere_matches_exact(void)
{
    int c3 = 0, c4 = 0;
    double e3 = tessellated_gain_error(3, &c3), e4 = tessellated_gain_error(4, &c4);
    printf("tessellated sphere: largest gain error %.4f at 1280 triangles, %.4f at 5120\n", e3, e4);
    CHECK(c3 >= 40 && c4 >= 40);
    CHECK(e4 < 0.05);
    CHECK(e4 < 0.6 * e3);
}

static void timed(const char *name, void (*f)(void))
{
    struct timespec a, b;
    clock_gettime(CLOCK_MONOTONIC, &a);
    f();
    clock_gettime(CLOCK_MONOTONIC, &b);
    printf("%s: %.2f s\n", name,
           (double)(b.tv_sec - a.tv_sec) + 1e-9 * (double)(b.tv_nsec - a.tv_nsec));
}

int main(void)
{
    timed("flat", flat_spread_matches_closed_forms);
    timed("bundle", sphere_spread_matches_ray_bundle);
    timed("fluence", sphere_fluence_matches_ray_bundle);
    timed("sphere search", sphere_search_finds_every_path);
    timed("tessellated", tessellated_sphere_matches_exact);
    timed("bumpy", bumpy_sphere_guarantee);
    return test_summary("walter");
}
