/*
 * mesh_rt_test_util.h - what the ray-tracing mesh tests share (header-only): a
 * reproducible random source, small hand-made meshes whose every coordinate is exact
 * (a box, a tetrahedron), and a brute-force nearest hit over all triangles with
 * Moller-Trumbore, written independently of mesh_rt_trace.c so the two check each other.
 */
#ifndef REFRACT_MESH_RT_TEST_UTIL_H
#define REFRACT_MESH_RT_TEST_UTIL_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh.h"
#include "mesh/mesh_rt.h"

struct rt_rng {
    uint64_t s;
};

/* xorshift64: uniform in [0, 1) */
static inline double rt_uniform(struct rt_rng *r)
{
    r->s ^= r->s << 13;
    r->s ^= r->s >> 7;
    r->s ^= r->s << 17;
    return (double)(r->s >> 11) / 9007199254740992.0;
}

static inline vec3 rt_unit(struct rt_rng *r)
{
    double z = 2.0 * rt_uniform(r) - 1.0, phi = 6.283185307179586 * rt_uniform(r);
    double s = sqrt(fmax(0.0, 1.0 - z * z));
    return vec3_make(s * cos(phi), s * sin(phi), z);
}

static inline vec3 rt_v3(const double p[3])
{
    return vec3_make(p[0], p[1], p[2]);
}

/* A mesh from literal arrays (copied); NULL with the message printed on failure. */
static inline struct mesh *rt_mesh_from(const double (*v)[3], size_t nv, const uint32_t (*t)[3],
                                        size_t nt, struct err *e)
{
    double(*vc)[3] = malloc(nv * sizeof *vc);
    uint32_t(*tc)[3] = malloc(nt * sizeof *tc);
    memcpy(vc, v, nv * sizeof *vc);
    memcpy(tc, t, nt * sizeof *tc);
    struct mesh *m = NULL;
    if (mesh_create(vc, nv, tc, nt, NULL, &m, e) != REFRACT_E_OK)
        return NULL;
    return m;
}

/* The box [-h, h]^3 as 12 triangles, counter-clockwise seen from outside; each face is
 * split along its diagonal from its lowest-index corner. */
static inline struct mesh *rt_box_mesh(double h)
{
    double v[8][3];
    for (int i = 0; i < 8; i++) {
        v[i][0] = (i & 1) ? h : -h;
        v[i][1] = (i & 2) ? h : -h;
        v[i][2] = (i & 4) ? h : -h;
    }
    static const uint32_t t[12][3] = {
        {0, 2, 3}, {0, 3, 1}, /* z = -h, normal -z */
        {4, 5, 7}, {4, 7, 6}, /* z = +h */
        {0, 1, 5}, {0, 5, 4}, /* y = -h */
        {2, 6, 7}, {2, 7, 3}, /* y = +h */
        {0, 4, 6}, {0, 6, 2}, /* x = -h */
        {1, 3, 7}, {1, 7, 5}, /* x = +h */
    };
    struct err e = {0};
    return rt_mesh_from((const double(*)[3])v, 8, t, 12, &e);
}

/* The unit tetrahedron's vertices and its four faces, counter-clockwise from outside. */
static const double rt_tetra_v[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {2, 0, 0}};
static const uint32_t rt_tetra_t[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

/* Moller-Trumbore in double: t of the ray's hit with triangle (a, b, c) or -1. */
static inline double rt_mt(vec3 o, vec3 d, const double *a, const double *b, const double *c)
{
    vec3 e1 = vec3_make(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
    vec3 e2 = vec3_make(c[0] - a[0], c[1] - a[1], c[2] - a[2]);
    vec3 p = vec3_cross(d, e2);
    double det = vec3_dot(e1, p);
    if (det == 0.0)
        return -1.0;
    vec3 s = vec3_make(o.x - a[0], o.y - a[1], o.z - a[2]);
    double u = vec3_dot(s, p) / det;
    if (u < 0.0 || u > 1.0)
        return -1.0;
    vec3 q = vec3_cross(s, e1);
    double v = vec3_dot(d, q) / det;
    if (v < 0.0 || u + v > 1.0)
        return -1.0;
    return vec3_dot(e2, q) / det;
}

/* Brute force: the nearest t in (tmin, tmax) over every triangle but skip, or -1;
 * *tri its index. */
static inline double rt_brute(const struct mesh *m, vec3 o, vec3 d, double tmin, double tmax,
                              int64_t skip, uint32_t *tri)
{
    double best = -1.0;
    for (size_t i = 0; i < m->triangle_count; i++) {
        if ((int64_t)i == skip)
            continue;
        const uint32_t *t = m->triangles[i];
        double th = rt_mt(o, d, m->vertices[t[0]], m->vertices[t[1]], m->vertices[t[2]]);
        if (th > tmin && th < tmax && (best < 0.0 || th < best)) {
            best = th;
            *tri = (uint32_t)i;
        }
    }
    return best;
}

#endif
