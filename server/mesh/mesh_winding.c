/*
 * mesh_winding.c - point queries on a mesh: the generalized winding number, exact and
 * hierarchical, and the unsigned distance to the nearest triangle.
 *
 * Winding number (Jacobson, Kavan and Sorkine-Hornung 2013, eq. 2 and 3):
 *     w(p) = 1/(4 pi) sum_t Omega_t(p),
 *     tan(Omega_t / 2) = a . (b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|)
 * with a, b, c the triangle's corners relative to p (van Oosterom and Strackee 1983);
 * atan2 gives Omega_t in (-2 pi, 2 pi) with the sign of the orientation. A triangle wound
 * counter-clockwise seen from outside subtends a positive angle from inside.
 *
 * Far field (Barill, Dickson, Schmidt, Levin and Jacobson 2018, sect. 3.2): seen from far
 * away, a cluster of triangles with area vector N = sum of area * normal and
 * area-weighted centre c subtends Omega ~ N . (c - p) / |c - p|^3 (a dipole) plus the
 * second-order term of the Taylor expansion (far_field). It is used when |c - p| >
 * beta * r (r: the cluster's radius about c). A cluster's relative error then falls as
 * (r / |c - p|)^2 (measured: 4.5e-2, 1.1e-2, 2.7e-3 as the distance doubles). On a
 * 1280-triangle unit sphere the worst |w - w_exact| over points at radius 0.5..1.5 was
 * 0.043 / 0.028 / 0.016 / 0.0066 / 0.0015 at beta = 2 / 2.5 / 3 / 4 / 6, at 5 / 7.5 /
 * 16 / 32 us per query (beta 2.5 / 3 / 4 / 6) on a 327,680-triangle sphere. beta = 2.5
 * is ample: classification compares |w| with 1/2, and the voxelizer takes the
 * boundary's position from the distance, not from w (mesh_voxelize.c); the third-order
 * term of Barill et al. is left out for that reason.
 *
 * Distance: depth-first descent of the BVH, nearer child first, pruning boxes farther
 * than the best triangle so far; the closest point on a triangle by Voronoi regions
 * (Ericson, Real-Time Collision Detection, sect. 5.1.5).
 */
#include <math.h>

#include "mesh_internal.h"

static const double inv_4pi = 0.07957747154594767; /* 1 / (4 pi) */

static vec3 corner(const struct mesh *m, uint32_t t, int c)
{
    const double *v = m->vertices[m->triangles[t][c]];
    return vec3_make(v[0], v[1], v[2]);
}

/* Omega_t(p), signed. */
static double solid_angle(const struct mesh *m, uint32_t t, vec3 p)
{
    vec3 a = vec3_sub(corner(m, t, 0), p), b = vec3_sub(corner(m, t, 1), p),
         c = vec3_sub(corner(m, t, 2), p);
    double la = vec3_length(a), lb = vec3_length(b), lc = vec3_length(c);
    double num = vec3_dot(a, vec3_cross(b, c));
    double den = la * lb * lc + vec3_dot(a, b) * lc + vec3_dot(b, c) * la + vec3_dot(c, a) * lb;
    if (num == 0.0 && den <= 0.0)
        return 0.0; /* p on the triangle's plane, inside or on it: the jump's midpoint */
    return 2.0 * atan2(num, den);
}

double mesh_winding_number_exact(const struct mesh *m, vec3 p)
{
    double sum = 0.0;
    for (size_t t = 0; t < m->triangle_count; t++)
        sum += solid_angle(m, (uint32_t)t, p);
    return sum * inv_4pi;
}

/* A cluster's solid angle seen from p, d = centre - p, to second order: with
 * G(x) = (x - p) / |x - p|^3, Omega = integral of G . n dA ~ G(c) . N + sum_ij
 * dG_i/dx_j(c) M_ij, dG_i/dx_j = delta_ij / |d|^3 - 3 d_i d_j / |d|^5. */
static double far_field(const struct mesh_bvh_node *nd, vec3 d, double d2)
{
    double inv = 1.0 / sqrt(d2), inv3 = inv * inv * inv, inv5 = inv3 * inv * inv;
    const double r[3] = {d.x, d.y, d.z};
    double first =
        nd->area_normal[0] * r[0] + nd->area_normal[1] * r[1] + nd->area_normal[2] * r[2];
    double trace = nd->moment[0][0] + nd->moment[1][1] + nd->moment[2][2], rmr = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            rmr += r[i] * nd->moment[i][j] * r[j];
    return first * inv3 + trace * inv3 - 3.0 * rmr * inv5;
}

double mesh_winding_number(const struct mesh *m, vec3 p)
{
    const struct mesh_bvh *bvh = m->bvh;
    uint32_t stack[2 * MESH_BVH_MAX_DEPTH];
    int sp = 0;
    double sum = 0.0; /* solid angles */
    stack[sp++] = 0;
    while (sp > 0) {
        const struct mesh_bvh_node *nd = &bvh->nodes[stack[--sp]];
        vec3 d = vec3_make(nd->centre[0] - p.x, nd->centre[1] - p.y, nd->centre[2] - p.z);
        double d2 = vec3_dot(d, d), reach = MESH_WINDING_BETA * nd->radius;
        if (d2 > reach * reach && d2 > 0.0) {
            sum += far_field(nd, d, d2);
            continue;
        }
        if (nd->count > 0) {
            for (uint32_t i = nd->first; i < nd->first + nd->count; i++)
                sum += solid_angle(m, bvh->order[i], p);
            continue;
        }
        stack[sp++] = nd->left;
        stack[sp++] = nd->left + 1;
    }
    return sum * inv_4pi;
}

/* Squared distance from p to the closest point of triangle t (Ericson 5.1.5). */
static double triangle_dist2(const struct mesh *m, uint32_t t, vec3 p)
{
    vec3 a = corner(m, t, 0), b = corner(m, t, 1), c = corner(m, t, 2);
    vec3 ab = vec3_sub(b, a), ac = vec3_sub(c, a), ap = vec3_sub(p, a);
    double d1 = vec3_dot(ab, ap), d2 = vec3_dot(ac, ap);
    vec3 q;
    if (d1 <= 0.0 && d2 <= 0.0) {
        q = a;
    } else {
        vec3 bp = vec3_sub(p, b);
        double d3 = vec3_dot(ab, bp), d4 = vec3_dot(ac, bp);
        vec3 cp = vec3_sub(p, c);
        double d5 = vec3_dot(ab, cp), d6 = vec3_dot(ac, cp);
        double vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
        if (d3 >= 0.0 && d4 <= d3) {
            q = b;
        } else if (d6 >= 0.0 && d5 <= d6) {
            q = c;
        } else if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
            q = vec3_madd(a, ab, d1 / (d1 - d3));
        } else if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
            q = vec3_madd(a, ac, d2 / (d2 - d6));
        } else if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
            q = vec3_madd(b, vec3_sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
        } else {
            double sum = va + vb + vc;
            if (!(sum > 0.0)) {
                q = a; /* degenerate (zero-area) triangle: its edges were handled above */
            } else {
                double v = vb / sum, w = vc / sum;
                q = vec3_add(a, vec3_add(vec3_scale(ab, v), vec3_scale(ac, w)));
            }
        }
    }
    vec3 d = vec3_sub(p, q);
    return vec3_dot(d, d);
}

static double box_dist2(const struct mesh_bvh_node *nd, vec3 p)
{
    double s = 0.0, q[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; k++) {
        double d = fmax(fmax(nd->lo[k] - q[k], q[k] - nd->hi[k]), 0.0);
        s += d * d;
    }
    return s;
}

double mesh_distance(const struct mesh *m, vec3 p)
{
    const struct mesh_bvh *bvh = m->bvh;
    uint32_t stack[2 * MESH_BVH_MAX_DEPTH];
    int sp = 0;
    double best = INFINITY;
    stack[sp++] = 0;
    while (sp > 0) {
        const struct mesh_bvh_node *nd = &bvh->nodes[stack[--sp]];
        if (box_dist2(nd, p) >= best)
            continue;
        if (nd->count > 0) {
            for (uint32_t i = nd->first; i < nd->first + nd->count; i++)
                best = fmin(best, triangle_dist2(m, bvh->order[i], p));
            continue;
        }
        const struct mesh_bvh_node *l = &bvh->nodes[nd->left], *r = &bvh->nodes[nd->left + 1];
        double dl = box_dist2(l, p), dr = box_dist2(r, p);
        /* Push the farther child first so the nearer one is searched first. */
        if (dl <= dr) {
            stack[sp++] = nd->left + 1;
            stack[sp++] = nd->left;
        } else {
            stack[sp++] = nd->left;
            stack[sp++] = nd->left + 1;
        }
    }
    return sqrt(best);
}
