/*
 * mesh_rt_trace.c - the double-precision nearest hit of a ray on a mesh_rt: the flattened
 * hierarchy walked with a fixed stack, and watertight ray/triangle intersection (Woop,
 * Benthin, Wald 2013). shaders/geom/mesh.glsl is the float twin, statement for statement;
 * change both together.
 *
 * Why it is watertight: the ray's space is translated to o and sheared so the ray runs
 * along +z (ray_space). A triangle's three edge functions are then 2D cross products of
 * its transformed vertices, each depending only on the two vertices of its edge; the
 * neighbour across an edge computes the same two products in the other order, so its
 * value is exactly the negation. A hit requires no two of a triangle's edge functions to
 * have opposite signs, a zero counting as either sign, so a ray through a shared edge or
 * vertex is accepted by at least one triangle on each side of it. An exact zero is
 * recomputed in long double (the paper's fallback), which resolves most of them to the
 * side the exact arithmetic would choose and stays consistent across the edge.
 *
 * Box test: slab intersection with t_far moved later by 2 gamma(3) |t_far| (Ize 2013,
 * "Robust BVH Ray Traversal"), so rounding never culls a box the ray touches.
 */
#include <float.h>
#include <math.h>

#include "mesh_rt.h"

/* The ray in the frame where it is +z: axes kx, ky, kz (kz the largest |d|, kx and ky
 * swapped when d[kz] < 0 to keep the winding) and the shear (paper sect. 3). */
struct ray_space {
    int kx, ky, kz;
    double sx, sy, sz;
    double o[3];
};

static struct ray_space ray_space_of(vec3 o, vec3 d)
{
    double dv[3] = {d.x, d.y, d.z};
    struct ray_space r = {.o = {o.x, o.y, o.z}};
    r.kz = fabs(dv[0]) >= fabs(dv[1]) ? (fabs(dv[0]) >= fabs(dv[2]) ? 0 : 2)
                                      : (fabs(dv[1]) >= fabs(dv[2]) ? 1 : 2);
    r.kx = (r.kz + 1) % 3;
    r.ky = (r.kx + 1) % 3;
    if (dv[r.kz] < 0.0) {
        int t = r.kx;
        r.kx = r.ky;
        r.ky = t;
    }
    r.sx = dv[r.kx] / dv[r.kz];
    r.sy = dv[r.ky] / dv[r.kz];
    r.sz = 1.0 / dv[r.kz];
    return r;
}

struct tri_hit {
    double t, u, v, w, det; /* u, v, w: the edge functions, weights of v0, v1, v2 times det */
};

/* The hit of the ray with triangle (a, b, c) at t in (tmin, tmax). */
static bool triangle_hit(const struct ray_space *r, const double *a, const double *b,
                         const double *c, double tmin, double tmax, struct tri_hit *h)
{
    const double A[3] = {a[0] - r->o[0], a[1] - r->o[1], a[2] - r->o[2]};
    const double B[3] = {b[0] - r->o[0], b[1] - r->o[1], b[2] - r->o[2]};
    const double C[3] = {c[0] - r->o[0], c[1] - r->o[1], c[2] - r->o[2]};
    const double ax = A[r->kx] - r->sx * A[r->kz], ay = A[r->ky] - r->sy * A[r->kz];
    const double bx = B[r->kx] - r->sx * B[r->kz], by = B[r->ky] - r->sy * B[r->kz];
    const double cx = C[r->kx] - r->sx * C[r->kz], cy = C[r->ky] - r->sy * C[r->kz];
    double u = cx * by - cy * bx, v = ax * cy - ay * cx, w = bx * ay - by * ax;
    if (u == 0.0 || v == 0.0 || w == 0.0) {
        u = (double)((long double)cx * by - (long double)cy * bx);
        v = (double)((long double)ax * cy - (long double)ay * cx);
        w = (double)((long double)bx * ay - (long double)by * ax);
    }
    if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0))
        return false;
    double det = u + v + w;
    if (det == 0.0) /* the ray lies in the triangle's plane */
        return false;
    double az = r->sz * A[r->kz], bz = r->sz * B[r->kz], cz = r->sz * C[r->kz];
    double t = (u * az + v * bz + w * cz) / det;
    if (!(t > tmin && t < tmax))
        return false;
    *h = (struct tri_hit){t, u, v, w, det};
    return true;
}

/* The ray's entry into a node's box within [tmin, tmax], or false. */
static bool box_hit(const struct mesh_rt_node *n, const double o[3], const double inv[3],
                    double tmin, double tmax, double *t_near)
{
    const double grow = 2.0 * (3.0 * DBL_EPSILON / 2.0) / (1.0 - 3.0 * DBL_EPSILON / 2.0);
    double t0 = tmin, t1 = tmax;
    for (int k = 0; k < 3; k++) {
        double a = ((double)n->lo[k] - o[k]) * inv[k], b = ((double)n->hi[k] - o[k]) * inv[k];
        double near = fmin(a, b), far = fmax(a, b);
        far += fabs(far) * grow; /* later, also when far < 0 */
        t0 = near > t0 ? near : t0;
        t1 = far < t1 ? far : t1;
    }
    *t_near = t0;
    return t0 <= t1;
}

static vec3 vertex_normal(const struct mesh_rt *rt, uint32_t v)
{
    return vec3_make(rt->normals[v][0], rt->normals[v][1], rt->normals[v][2]);
}

bool mesh_rt_intersect(const struct mesh_rt *rt, vec3 o, vec3 d, double tmin, double tmax,
                       int64_t skip_tri, struct mesh_rt_hit *hit)
{
    const struct ray_space rs = ray_space_of(o, d);
    const double dv[3] = {d.x, d.y, d.z};
    double inv[3];
    for (int k = 0; k < 3; k++) /* a zero component: a huge finite slope, never 0 * inf */
        inv[k] = 1.0 / (dv[k] != 0.0 ? dv[k] : DBL_MIN);
    struct {
        uint32_t node;
        double t_near;
    } stack[MESH_RT_MAX_DEPTH];
    int sp = 0;
    double t_best = tmax, t_near;
    struct tri_hit best = {0};
    size_t best_slot = SIZE_MAX;
    if (!box_hit(&rt->nodes[0], rs.o, inv, tmin, t_best, &t_near))
        return false;
    uint32_t node = 0;
    for (;;) {
        const struct mesh_rt_node *nd = &rt->nodes[node];
        if (nd->count > 0) {
            for (uint32_t i = nd->left_or_first; i < nd->left_or_first + nd->count; i++) {
                const struct mesh_rt_tri *tr = &rt->tris[i];
                struct tri_hit h;
                if ((int64_t)tr->orig == skip_tri)
                    continue;
                if (triangle_hit(&rs, rt->positions[tr->v[0]], rt->positions[tr->v[1]],
                                 rt->positions[tr->v[2]], tmin, t_best, &h)) {
                    t_best = h.t;
                    best = h;
                    best_slot = i;
                }
            }
        } else {
            uint32_t l = nd->left_or_first;
            double tl, tr;
            bool hl = box_hit(&rt->nodes[l], rs.o, inv, tmin, t_best, &tl);
            bool hr = box_hit(&rt->nodes[l + 1], rs.o, inv, tmin, t_best, &tr);
            if (hl && hr) {
                bool left_first = tl <= tr;
                stack[sp].node = left_first ? l + 1 : l;
                stack[sp++].t_near = left_first ? tr : tl;
                node = left_first ? l : l + 1;
                continue;
            }
            if (hl || hr) {
                node = hl ? l : l + 1;
                continue;
            }
        }
        /* pop the next node the ray can still reach before the best hit */
        while (sp > 0 && stack[sp - 1].t_near > t_best)
            sp--;
        if (sp == 0)
            break;
        node = stack[--sp].node;
    }
    if (best_slot == SIZE_MAX)
        return false;
    const struct mesh_rt_tri *tr = &rt->tris[best_slot];
    const double *a = rt->positions[tr->v[0]], *b = rt->positions[tr->v[1]],
                 *c = rt->positions[tr->v[2]];
    vec3 ng = vec3_normalize(vec3_cross(vec3_make(b[0] - a[0], b[1] - a[1], b[2] - a[2]),
                                        vec3_make(c[0] - a[0], c[1] - a[1], c[2] - a[2])));
    double b1 = best.v / best.det, b2 = best.w / best.det, b0 = best.u / best.det;
    vec3 n0 = vertex_normal(rt, tr->v[0]), n1 = vertex_normal(rt, tr->v[1]),
         n2 = vertex_normal(rt, tr->v[2]);
    vec3 ns = vec3_add(vec3_add(vec3_scale(n0, b0), vec3_scale(n1, b1)), vec3_scale(n2, b2));
    double ls = vec3_length(ns);
    /* A corner on a crease (no smooth normal, mesh_rt_build.c): the flat normal. */
    if (vec3_length(n0) == 0.0 || vec3_length(n1) == 0.0 || vec3_length(n2) == 0.0)
        ls = 0.0;
    *hit = (struct mesh_rt_hit){
        .t = best.t,
        .n_geom = ng,
        .n_shade = ls > 1e-12 ? vec3_scale(ns, 1.0 / ls) : ng,
        .tri = tr->orig,
        .b1 = b1,
        .b2 = b2,
    };
    return true;
}
