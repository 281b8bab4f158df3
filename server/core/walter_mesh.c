/*
 * walter_mesh.c - refracted connecting paths through triangles with interpolated shading
 * normals (walter2009 sect. 3.3-3.4; walter.h).
 *
 * On triangle (p0, p1, p2) with normals (n0, n1, n2), barycentrics (a, b):
 *   P(a, b) = p0 + a (p1 - p0) + b (p2 - p0),  N_s = m / |m|, m = n0 + a (n1 - n0) + b (n2 - n0)
 *   f(a, b) = H + N_s, H = (eta omega_V + omega_L) / |eta omega_V + omega_L|      (eq. 8)
 * which vanishes exactly at the solutions (H points into the medium, N_s out of it).
 *
 * The search (sect. 3.3.2, the guaranteed variant): the parameter square [0, 1]^2 (the
 * triangle is its lower half) is split into four while the Krawczyk test cannot settle a
 * box X: with F, F' the interval extensions of f and its 3x2 Jacobian over X, m0 X's
 * midpoint, M the midpoint matrix of F'(X) and M+ its pseudo-inverse,
 *   K(X) = m0 - M+ f(m0) + [I - M+ F'(X)] (X - m0)                              (eq. 11)
 * X holds no solution when 0 is outside F(X) (eq. 12) or K(X) misses X (eq. 13); it holds
 * exactly one, to which Newton converges, when K(X) lies inside X and the norm of
 * I - M+ F'(X) is below 1 (eq. 14-15). The intervals are widened by a few ulps after each
 * evaluation: rounding does not make the test exclude a box that holds a solution. Boxes
 * still open at WALTER_MAX_DEPTH (2^-20 of the triangle) get a Newton run from their centre
 * and are counted (walter_stats.unresolved).
 */
#include <math.h>
#include <string.h>

#include "walter.h"

#define WALTER_MAX_DEPTH 20

/* ---- intervals ---- */

struct iv {
    double lo, hi;
};

struct ivec {
    struct iv x, y, z;
};

static struct iv iv_add(struct iv a, struct iv b)
{
    return (struct iv){a.lo + b.lo, a.hi + b.hi};
}

static struct iv iv_sub(struct iv a, struct iv b)
{
    return (struct iv){a.lo - b.hi, a.hi - b.lo};
}

static struct iv iv_scale(struct iv a, double s)
{
    return s >= 0.0 ? (struct iv){a.lo * s, a.hi * s} : (struct iv){a.hi * s, a.lo * s};
}

static struct iv iv_mul(struct iv a, struct iv b)
{
    double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
    struct iv r = {p[0], p[0]};
    for (int i = 1; i < 4; i++) {
        r.lo = fmin(r.lo, p[i]);
        r.hi = fmax(r.hi, p[i]);
    }
    return r;
}

static struct iv iv_sqr(struct iv a)
{
    double l = a.lo * a.lo, h = a.hi * a.hi;
    if (a.lo <= 0.0 && a.hi >= 0.0)
        return (struct iv){0.0, fmax(l, h)};
    return (struct iv){fmin(l, h), fmax(l, h)};
}

/* 1 / a for a > 0 (the lengths below); an interval touching 0 gives [0, inf]. */
static struct iv iv_recip_pos(struct iv a)
{
    if (!(a.lo > 0.0))
        return (struct iv){0.0, INFINITY};
    return (struct iv){1.0 / a.hi, 1.0 / a.lo};
}

static struct iv iv_sqrt(struct iv a)
{
    return (struct iv){sqrt(fmax(a.lo, 0.0)), sqrt(fmax(a.hi, 0.0))};
}

/* A few ulps outward: what rounding could have moved. */
static struct iv iv_widen(struct iv a)
{
    double e = 4e-16 * (fabs(a.lo) + fabs(a.hi)) + 1e-300;
    return (struct iv){a.lo - e, a.hi + e};
}

static struct ivec ivec_point(vec3 v)
{
    return (struct ivec){{v.x, v.x}, {v.y, v.y}, {v.z, v.z}};
}

static struct ivec ivec_add(struct ivec a, struct ivec b)
{
    return (struct ivec){iv_add(a.x, b.x), iv_add(a.y, b.y), iv_add(a.z, b.z)};
}

static struct ivec ivec_sub(struct ivec a, struct ivec b)
{
    return (struct ivec){iv_sub(a.x, b.x), iv_sub(a.y, b.y), iv_sub(a.z, b.z)};
}

static struct ivec ivec_mul(struct ivec a, struct iv s)
{
    return (struct ivec){iv_mul(a.x, s), iv_mul(a.y, s), iv_mul(a.z, s)};
}

static struct ivec ivec_scale(struct ivec a, double s)
{
    return (struct ivec){iv_scale(a.x, s), iv_scale(a.y, s), iv_scale(a.z, s)};
}

/* The vector v times the interval s: [s] v. */
static struct ivec ivec_along(vec3 v, struct iv s)
{
    return (struct ivec){iv_scale(s, v.x), iv_scale(s, v.y), iv_scale(s, v.z)};
}

static struct iv ivec_dot(struct ivec a, struct ivec b)
{
    return iv_add(iv_add(iv_mul(a.x, b.x), iv_mul(a.y, b.y)), iv_mul(a.z, b.z));
}

static struct iv ivec_dot_v(struct ivec a, vec3 b)
{
    return iv_add(iv_add(iv_scale(a.x, b.x), iv_scale(a.y, b.y)), iv_scale(a.z, b.z));
}

static struct iv ivec_norm2(struct ivec a)
{
    return iv_add(iv_add(iv_sqr(a.x), iv_sqr(a.y)), iv_sqr(a.z));
}

static struct ivec ivec_widen(struct ivec a)
{
    return (struct ivec){iv_widen(a.x), iv_widen(a.y), iv_widen(a.z)};
}

static bool iv_has_zero(struct iv a)
{
    return a.lo <= 0.0 && a.hi >= 0.0;
}

/* u / |u| over intervals, and |u|^2 in *len2_out. */
static struct ivec ivec_unit(struct ivec u, struct iv *len2_out)
{
    struct iv l2 = ivec_norm2(u);
    *len2_out = l2;
    return ivec_mul(u, iv_recip_pos(iv_sqrt(l2)));
}

/* The derivative of u / |u| along du, (|u|^2 du - (u . du) u) / |u|^3 (eq. 10), over
 * intervals (l2: |u|^2). */
static struct ivec ivec_unit_deriv(struct ivec u, struct iv l2, struct ivec du)
{
    struct ivec num = ivec_sub(ivec_mul(du, l2), ivec_mul(u, ivec_dot(u, du)));
    struct iv l3 = iv_mul(l2, iv_sqrt(l2));
    return ivec_mul(num, iv_recip_pos(l3));
}

/* ---- f and its Jacobian ---- */

struct tri_problem {
    const struct walter_triangle *t;
    vec3 e1, e2, dn1, dn2, L, V;
    double eta;
    bool at_infinity;
};

static struct tri_problem tri_problem(const struct walter_triangle *t, double eta, vec3 L,
                                      bool at_infinity, vec3 V)
{
    struct tri_problem q = {t,
                            vec3_sub(t->p[1], t->p[0]),
                            vec3_sub(t->p[2], t->p[0]),
                            vec3_sub(t->n[1], t->n[0]),
                            vec3_sub(t->n[2], t->n[0]),
                            L,
                            V,
                            eta,
                            at_infinity};
    return q;
}

/* f(a, b) and, when J is not NULL, its columns d f / da, d f / db. */
static vec3 tri_f(const struct tri_problem *q, double a, double b, vec3 J[2])
{
    vec3 P = vec3_add(q->t->p[0], vec3_add(vec3_scale(q->e1, a), vec3_scale(q->e2, b)));
    vec3 m = vec3_add(q->t->n[0], vec3_add(vec3_scale(q->dn1, a), vec3_scale(q->dn2, b)));
    vec3 u = vec3_sub(q->V, P), w = vec3_sub(q->L, P);
    vec3 wV = vec3_normalize(u);
    vec3 wL = q->at_infinity ? vec3_scale(q->L, -1.0) : vec3_normalize(w);
    vec3 h = vec3_madd(wL, wV, q->eta);
    vec3 f = vec3_add(vec3_normalize(h), vec3_normalize(m));
    if (J != NULL) {
        vec3 dP[2] = {q->e1, q->e2}, dm[2] = {q->dn1, q->dn2};
        for (int k = 0; k < 2; k++) {
            vec3 mdP = vec3_scale(dP[k], -1.0);
            vec3 hp = vec3_scale(walter_unit_deriv(u, mdP), q->eta);
            if (!q->at_infinity)
                hp = vec3_add(hp, walter_unit_deriv(w, mdP));
            J[k] = vec3_add(walter_unit_deriv(h, hp), walter_unit_deriv(m, dm[k]));
        }
    }
    return f;
}

/* F(X) and F'(X) over the box [a0, a1] x [b0, b1]. Returns false when a length interval
 * touches zero (nothing can be concluded; the box is split). */
static bool tri_F(const struct tri_problem *q, const struct iv X[2], struct ivec *F,
                  struct ivec Fp[2])
{
    struct ivec P = ivec_add(ivec_point(q->t->p[0]),
                             ivec_add(ivec_along(q->e1, X[0]), ivec_along(q->e2, X[1])));
    struct ivec m = ivec_add(ivec_point(q->t->n[0]),
                             ivec_add(ivec_along(q->dn1, X[0]), ivec_along(q->dn2, X[1])));
    struct ivec u = ivec_sub(ivec_point(q->V), P);
    struct iv lu2, lw2 = {1, 1}, lh2, lm2;
    struct ivec wV = ivec_unit(u, &lu2), w = {{0, 0}, {0, 0}, {0, 0}}, wL;
    if (q->at_infinity) {
        wL = ivec_point(vec3_scale(q->L, -1.0));
    } else {
        w = ivec_sub(ivec_point(q->L), P);
        wL = ivec_unit(w, &lw2);
    }
    struct ivec h = ivec_add(ivec_scale(wV, q->eta), wL);
    struct ivec H = ivec_unit(h, &lh2);
    struct ivec Ns = ivec_unit(m, &lm2);
    if (!(lu2.lo > 0.0) || !(lw2.lo > 0.0) || !(lh2.lo > 0.0) || !(lm2.lo > 0.0))
        return false;
    *F = ivec_widen(ivec_add(H, Ns));
    vec3 dP[2] = {q->e1, q->e2}, dm[2] = {q->dn1, q->dn2};
    for (int k = 0; k < 2; k++) {
        vec3 mdP = vec3_scale(dP[k], -1.0);
        struct ivec hp = ivec_scale(ivec_unit_deriv(u, lu2, ivec_point(mdP)), q->eta);
        if (!q->at_infinity)
            hp = ivec_add(hp, ivec_unit_deriv(w, lw2, ivec_point(mdP)));
        Fp[k] = ivec_widen(
            ivec_add(ivec_unit_deriv(h, lh2, hp), ivec_unit_deriv(m, lm2, ivec_point(dm[k]))));
    }
    return true;
}

/* Pseudo-inverse (M^T M)^-1 M^T of the 3x2 matrix with columns c0, c1 (rows of the 2x3
 * result in r0, r1). Returns false when M^T M is singular. */
static bool pseudo_inverse(vec3 c0, vec3 c1, vec3 *r0, vec3 *r1)
{
    double a = vec3_dot(c0, c0), b = vec3_dot(c0, c1), d = vec3_dot(c1, c1);
    double det = a * d - b * b;
    if (!(fabs(det) > 1e-300) || !(fabs(det) > 1e-14 * a * d))
        return false;
    /* (M^T M)^-1 = [d -b; -b a] / det */
    *r0 = vec3_scale(vec3_madd(vec3_scale(c0, d), c1, -b), 1.0 / det);
    *r1 = vec3_scale(vec3_madd(vec3_scale(c1, a), c0, -b), 1.0 / det);
    return true;
}

bool walter_triangle_newton(const struct walter_triangle *t, double eta, vec3 L, bool at_infinity,
                            vec3 V, double *a, double *b)
{
    struct tri_problem q = tri_problem(t, eta, L, at_infinity, V);
    double x = *a, y = *b;
    vec3 J[2];
    vec3 f = tri_f(&q, x, y, J);
    double fn = vec3_length(f);
    for (int it = 0; it < 40; it++) {
        if (fn < 1e-12) {
            *a = x, *b = y;
            return true;
        }
        vec3 r0, r1;
        if (!pseudo_inverse(J[0], J[1], &r0, &r1))
            return false;
        double da = vec3_dot(r0, f), db = vec3_dot(r1, f);
        double s = sqrt(da * da + db * db);
        if (!(s < INFINITY))
            return false;
        if (s > 0.5) /* at most half the triangle a step */
            da *= 0.5 / s, db *= 0.5 / s;
        bool better = false;
        for (int h = 0; h < 12 && !better; h++) {
            double nx = x - da, ny = y - db;
            vec3 Jn[2];
            vec3 fnew = tri_f(&q, nx, ny, Jn);
            double nn = vec3_length(fnew);
            if (nn < fn) {
                x = nx, y = ny, f = fnew, fn = nn, J[0] = Jn[0], J[1] = Jn[1];
                better = true;
            } else {
                da *= 0.5, db *= 0.5;
            }
        }
        if (!better || x < -1.0 || y < -1.0 || x + y > 2.0)
            return false; /* stuck, or wandered a triangle's size away: no solution here */
    }
    if (fn < 1e-12) {
        *a = x, *b = y;
        return true;
    }
    return false;
}

struct walter_normal walter_triangle_normal(const struct walter_triangle *t, double a, double b)
{
    vec3 e1 = vec3_sub(t->p[1], t->p[0]), e2 = vec3_sub(t->p[2], t->p[0]);
    vec3 Ng = vec3_normalize(vec3_cross(e1, e2));
    vec3 m = vec3_add(t->n[0], vec3_add(vec3_scale(vec3_sub(t->n[1], t->n[0]), a),
                                        vec3_scale(vec3_sub(t->n[2], t->n[0]), b)));
    if (vec3_dot(Ng, vec3_add(t->n[0], vec3_add(t->n[1], t->n[2]))) < 0.0)
        Ng = vec3_scale(Ng, -1.0);
    /* The dual basis of (e1, e2) in the triangle's plane: g_a . e1 = 1, g_a . e2 = 0, ... */
    double A = vec3_dot(e1, e1), B = vec3_dot(e1, e2), C = vec3_dot(e2, e2), det = A * C - B * B;
    vec3 ga = vec3_scale(vec3_madd(vec3_scale(e1, C), e2, -B), 1.0 / det);
    vec3 gb = vec3_scale(vec3_madd(vec3_scale(e2, A), e1, -B), 1.0 / det);
    struct walter_normal n = {m, vec3_sub(t->n[1], t->n[0]), vec3_sub(t->n[2], t->n[0]), ga, gb,
                              Ng};
    return n;
}

/* ---- the cone test (walter2009 sect. 3.3.1) ---- */

struct cone {
    vec3 axis;
    double angle; /* half-angle, radians */
};

/* A bounding cone of n unit vectors: the axis their normalised
 * mean, the angle the largest to any. Since {angle to the axis <= theta} is convex for
 * theta < 90 degrees, the cone also bounds every direction of their spherical hull: the
 * directions from a fixed point to a convex polygon, or a linear interpolation of
 * normals, normalised. */
static struct cone cone_of(const vec3 *u, int n)
{
    vec3 s = {0, 0, 0};
    for (int i = 0; i < n; i++)
        s = vec3_add(s, u[i]);
    struct cone c = {vec3_normalize(s), 0.0};
    if (!(vec3_length(s) > 1e-9)) {
        c.angle = M_PI;
        return c;
    }
    double cmin = 1.0;
    for (int i = 0; i < n; i++)
        cmin = fmin(cmin, vec3_dot(u[i], c.axis));
    c.angle = acos(fmax(-1.0, fmin(1.0, cmin)));
    return c;
}

/* The bounding box of the unit vectors of a cone: per coordinate, the cosine of the
 * coordinate axis's angle to the cone's axis plus or minus the cone's angle. */
static void cone_box(struct cone c, double s, double lo[3], double hi[3])
{
    for (int i = 0; i < 3; i++) {
        double phi = acos(fmax(-1.0, fmin(1.0, vec3_get(c.axis, i))));
        double a = cos(fmin(M_PI, phi + c.angle)), b = cos(fmax(0.0, phi - c.angle));
        lo[i] += s * a;
        hi[i] += s * b;
    }
}

/* True when box X (parameters) may hold a solution by the cones: the cone of -H (from the
 * boxes of omega_V's and omega_L's cones, eta times the first plus the second, Minkowski)
 * overlaps the cone of the shading normals. */
static bool cones_overlap(const struct tri_problem *q, const struct iv X[2])
{
    double A[4] = {X[0].lo, X[0].hi, X[0].lo, X[0].hi}, B[4] = {X[1].lo, X[1].lo, X[1].hi, X[1].hi};
    vec3 wv[4], wl[4], nm[4];
    for (int k = 0; k < 4; k++) {
        vec3 P = vec3_add(q->t->p[0], vec3_add(vec3_scale(q->e1, A[k]), vec3_scale(q->e2, B[k])));
        wv[k] = vec3_normalize(vec3_sub(q->V, P));
        wl[k] = q->at_infinity ? vec3_scale(q->L, -1.0) : vec3_normalize(vec3_sub(q->L, P));
        nm[k] = vec3_normalize(
            vec3_add(q->t->n[0], vec3_add(vec3_scale(q->dn1, A[k]), vec3_scale(q->dn2, B[k]))));
    }
    struct cone cv = cone_of(wv, 4), cl = cone_of(wl, 4), cn = cone_of(nm, 4);
    if (cv.angle >= 0.5 * M_PI || cl.angle >= 0.5 * M_PI || cn.angle >= 0.5 * M_PI)
        return true;
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    cone_box(cv, q->eta, lo, hi);
    cone_box(cl, 1.0, lo, hi);
    if (lo[0] <= 0 && hi[0] >= 0 && lo[1] <= 0 && hi[1] >= 0 && lo[2] <= 0 && hi[2] >= 0)
        return true; /* h may vanish: nothing to conclude */
    vec3 corners[8];
    for (int k = 0; k < 8; k++)
        corners[k] = vec3_normalize(
            vec3_make(k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1], k & 4 ? hi[2] : lo[2]));
    struct cone ch = cone_of(corners, 8);
    if (ch.angle >= 0.5 * M_PI)
        return true;
    double between = acos(fmax(-1.0, fmin(1.0, -vec3_dot(ch.axis, cn.axis))));
    return between <= ch.angle + cn.angle + 1e-12;
}

/* ---- the interval search over one triangle ---- */

struct tri_search {
    const struct tri_problem *q;
    struct walter_path *out;
    int n, max;
    struct walter_stats *st;
};

static void tri_try(struct tri_search *s, double a, double b)
{
    if (s->st)
        s->st->newton_runs++;
    const struct walter_triangle *t = s->q->t;
    if (!walter_triangle_newton(t, s->q->eta, s->q->L, s->q->at_infinity, s->q->V, &a, &b))
        return;
    const double tol = 1e-9;
    if (a < -tol || b < -tol || a + b > 1.0 + tol || s->n >= s->max)
        return;
    struct walter_path p = {0};
    p.P = vec3_add(t->p[0], vec3_add(vec3_scale(s->q->e1, a), vec3_scale(s->q->e2, b)));
    struct walter_normal nrm = walter_triangle_normal(t, a, b);
    if (!walter_path_finish(&p, s->q->V, s->q->L, s->q->at_infinity, s->q->eta, &nrm))
        return;
    double scale = vec3_length(s->q->e1) + vec3_length(s->q->e2);
    for (int i = 0; i < s->n; i++)
        if (vec3_length(vec3_sub(s->out[i].P, p.P)) < 1e-9 * scale)
            return;
    s->out[s->n++] = p;
}

static void tri_box(struct tri_search *s, double a0, double a1, double b0, double b1, int depth)
{
    if (a0 + b0 > 1.0 + 1e-12) /* wholly outside the triangle */
        return;
    if (s->st)
        s->st->boxes++;
    struct iv X[2] = {{a0, a1}, {b0, b1}};
    if (!cones_overlap(s->q, X))
        return;
    struct ivec F, Fp[2];
    bool have = tri_F(s->q, X, &F, Fp);
    if (have && (!iv_has_zero(F.x) || !iv_has_zero(F.y) || !iv_has_zero(F.z)))
        return; /* eq. 12 */
    double ma = 0.5 * (a0 + a1), mb = 0.5 * (b0 + b1);
    if (have) {
        vec3 c0 = {0.5 * (Fp[0].x.lo + Fp[0].x.hi), 0.5 * (Fp[0].y.lo + Fp[0].y.hi),
                   0.5 * (Fp[0].z.lo + Fp[0].z.hi)};
        vec3 c1 = {0.5 * (Fp[1].x.lo + Fp[1].x.hi), 0.5 * (Fp[1].y.lo + Fp[1].y.hi),
                   0.5 * (Fp[1].z.lo + Fp[1].z.hi)};
        vec3 r[2];
        if (pseudo_inverse(c0, c1, &r[0], &r[1])) {
            vec3 f0 = tri_f(s->q, ma, mb, NULL);
            double y[2] = {ma - vec3_dot(r[0], f0), mb - vec3_dot(r[1], f0)};
            double rad[2] = {0.5 * (a1 - a0), 0.5 * (b1 - b0)};
            struct iv K[2];
            double norm = 0.0;
            for (int i = 0; i < 2; i++) {
                struct iv Ki = {y[i], y[i]};
                double row = 0.0;
                for (int j = 0; j < 2; j++) {
                    /* Z_ij = delta_ij - sum_k M+_ik F'_kj */
                    struct iv Z = iv_widen(ivec_dot_v(Fp[j], r[i]));
                    Z = iv_sub((struct iv){i == j, i == j}, Z);
                    row += fmax(fabs(Z.lo), fabs(Z.hi));
                    Ki = iv_add(Ki, iv_mul(Z, (struct iv){-rad[j], rad[j]}));
                }
                K[i] = iv_widen(Ki);
                norm = fmax(norm, row);
            }
            if (K[0].hi < X[0].lo || K[0].lo > X[0].hi || K[1].hi < X[1].lo || K[1].lo > X[1].hi)
                return; /* eq. 13 */
            if (norm < 1.0 && K[0].lo > X[0].lo && K[0].hi < X[0].hi && K[1].lo > X[1].lo &&
                K[1].hi < X[1].hi) {
                tri_try(s, ma, mb); /* eq. 14-15: exactly one solution, Newton finds it */
                return;
            }
        }
    }
    if (depth >= WALTER_MAX_DEPTH) {
        if (s->st)
            s->st->unresolved++;
        tri_try(s, ma, mb);
        return;
    }
    tri_box(s, a0, ma, b0, mb, depth + 1);
    tri_box(s, ma, a1, b0, mb, depth + 1);
    tri_box(s, a0, ma, mb, b1, depth + 1);
    tri_box(s, ma, a1, mb, b1, depth + 1);
}

int walter_triangle_paths(const struct walter_triangle *t, double eta, vec3 L, bool at_infinity,
                          vec3 V, struct walter_path *out, int max, struct walter_stats *st)
{
    struct tri_problem q = tri_problem(t, eta, L, at_infinity, V);
    struct tri_search s = {&q, out, 0, max, st};
    tri_box(&s, 0.0, 1.0, 0.0, 1.0, 0);
    return s.n;
}

/* eq. 4 on the triangle's plane, and the spindle (sect. 3.4, fig. 4). A refraction bends
 * light by less than 90 degrees minus the critical angle, so the angle LPV is at least
 * alpha = 90 + beta degrees, sin beta = min(eta, 1 / eta). By the inscribed-angle theorem
 * such P lie in the spindle |P - M|^2 + 2 h tan(beta) r <= h^2 (M the midpoint of LV, h half
 * its length, r the distance of P from the line LV); walter2009 eq. 16 writes 1 / eta for
 * tan(beta), a weaker bound. Over the triangle both terms are bounded below through its
 * centroid C (each is 1-Lipschitz): |P - M| >= |C - M| - rho, r >= r(C) - rho, rho the
 * centroid's largest distance to a vertex. */
static bool triangle_may_connect(const struct walter_triangle *t, double eta, vec3 L,
                                 bool at_infinity, vec3 V)
{
    vec3 Ng = vec3_cross(vec3_sub(t->p[1], t->p[0]), vec3_sub(t->p[2], t->p[0]));
    if (vec3_dot(Ng, vec3_add(t->n[0], vec3_add(t->n[1], t->n[2]))) < 0.0)
        Ng = vec3_scale(Ng, -1.0);
    if (vec3_dot(vec3_sub(V, t->p[0]), Ng) > 0.0)
        return false;
    if (at_infinity)
        return vec3_dot(L, Ng) <= 0.0;
    if (vec3_dot(vec3_sub(L, t->p[0]), Ng) < 0.0)
        return false;
    vec3 C = vec3_scale(vec3_add(t->p[0], vec3_add(t->p[1], t->p[2])), 1.0 / 3.0);
    double rho = 0.0;
    for (int k = 0; k < 3; k++)
        rho = fmax(rho, vec3_length(vec3_sub(t->p[k], C)));
    vec3 M = vec3_scale(vec3_add(L, V), 0.5), axis = vec3_sub(L, V);
    double h = 0.5 * vec3_length(axis);
    axis = vec3_scale(axis, 0.5 / h);
    vec3 cm = vec3_sub(C, M);
    double rc = vec3_length(vec3_madd(cm, axis, -vec3_dot(cm, axis)));
    double s = fmin(eta, 1.0 / eta), tan_beta = s / sqrt(fmax(1e-300, 1.0 - s * s));
    double dm = fmax(0.0, vec3_length(cm) - rho), dr = fmax(0.0, rc - rho);
    return dm * dm + 2.0 * h * tan_beta * dr <= h * h * (1.0 + 1e-12);
}

int walter_mesh_paths(const struct walter_triangle *tris, size_t count, double eta, vec3 L,
                      bool at_infinity, vec3 V, struct walter_path *out, int max,
                      struct walter_stats *st)
{
    int n = 0;
    struct walter_path buf[WALTER_MAX_PATHS];
    for (size_t i = 0; i < count && n < max; i++) {
        if (!triangle_may_connect(&tris[i], eta, L, at_infinity, V))
            continue;
        if (st)
            st->triangles_tested++;
        int k = walter_triangle_paths(&tris[i], eta, L, at_infinity, V, buf, WALTER_MAX_PATHS, st);
        double scale = vec3_length(vec3_sub(tris[i].p[1], tris[i].p[0]));
        for (int j = 0; j < k && n < max; j++) {
            bool dup = false;
            for (int m = 0; m < n && !dup; m++)
                dup = vec3_length(vec3_sub(out[m].P, buf[j].P)) < 1e-7 * scale;
            if (!dup)
                out[n++] = buf[j];
        }
    }
    return n;
}
