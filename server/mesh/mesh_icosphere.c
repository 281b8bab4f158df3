/*
 * mesh_icosphere.c - a generated sphere: the icosahedron, each triangle split into four
 * `subdivisions` times at its edge midpoints, every new vertex pushed onto the sphere.
 *
 * Why an icosphere and not a UV sphere: its triangles are nearly equal (no slivers at the
 * poles), which is what the tracing tests and benchmarks want, and it is closed and
 * manifold by construction (each edge midpoint is made once and shared, through a hash
 * table keyed by the edge), so it passes mesh_check_solid as made.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_rt.h"

struct midpoints {
    uint64_t *keys; /* UINT64_MAX = empty */
    uint32_t *vals;
    size_t cap;
};

static uint32_t midpoint(struct midpoints *h, double (*v)[3], size_t *nv, uint32_t a, uint32_t b,
                         double radius)
{
    uint64_t key = a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
    size_t i = (size_t)((key * 11400714819323198485ull) >> 17) % h->cap;
    while (h->keys[i] != UINT64_MAX && h->keys[i] != key)
        i = (i + 1) % h->cap;
    if (h->keys[i] == key)
        return h->vals[i];
    double p[3], len2 = 0.0;
    for (int k = 0; k < 3; k++) {
        p[k] = 0.5 * (v[a][k] + v[b][k]);
        len2 += p[k] * p[k];
    }
    double s = radius / sqrt(len2);
    for (int k = 0; k < 3; k++)
        v[*nv][k] = p[k] * s;
    h->keys[i] = key;
    h->vals[i] = (uint32_t)*nv;
    return (uint32_t)(*nv)++;
}

enum refract_code mesh_make_icosphere(int subdivisions, double radius, struct mesh **out,
                                      struct err *e)
{
    *out = NULL;
    if (subdivisions < 0 || subdivisions > 9)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "icosphere subdivisions %d: must be 0..9 (20 * 4^s triangles; 9 is "
                       "5,242,880)",
                       subdivisions);
    if (!(radius > 0.0) || !isfinite(radius) || radius > 1e15)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "icosphere radius %g: must be a finite number > 0 (at most 1e15)", radius);
    const double g = (1.0 + sqrt(5.0)) / 2.0;
    const double base[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    /* counter-clockwise seen from outside */
    const uint32_t faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    size_t nt_final = 20;
    for (int s = 0; s < subdivisions; s++)
        nt_final *= 4;
    size_t nv_final = nt_final / 2 + 2; /* Euler: V - E + F = 2, E = 3F/2 */
    double(*v)[3] = malloc(nv_final * sizeof *v);
    uint32_t(*t)[3] = malloc(nt_final * sizeof *t);
    uint32_t(*next)[3] = malloc(nt_final * sizeof *next);
    struct midpoints h = {.cap = 2 * nv_final + 1};
    h.keys = malloc(h.cap * sizeof *h.keys);
    h.vals = malloc(h.cap * sizeof *h.vals);
    if (v == NULL || t == NULL || next == NULL || h.keys == NULL || h.vals == NULL) {
        free(v);
        free(t);
        free(next);
        free(h.keys);
        free(h.vals);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "out of memory for an icosphere of %zu triangles", nt_final);
    }
    double blen = sqrt(1.0 + g * g);
    for (int i = 0; i < 12; i++)
        for (int k = 0; k < 3; k++)
            v[i][k] = base[i][k] * radius / blen;
    size_t nv = 12, nt = 20;
    memcpy(t, faces, sizeof faces);
    for (int s = 0; s < subdivisions; s++) {
        memset(h.keys, 0xff, h.cap * sizeof *h.keys);
        for (size_t i = 0; i < nt; i++) {
            uint32_t a = t[i][0], b = t[i][1], c = t[i][2];
            uint32_t ab = midpoint(&h, v, &nv, a, b, radius);
            uint32_t bc = midpoint(&h, v, &nv, b, c, radius);
            uint32_t ca = midpoint(&h, v, &nv, c, a, radius);
            const uint32_t quad[4][3] = {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}};
            memcpy(next + 4 * i, quad, sizeof quad);
        }
        nt *= 4;
        uint32_t(*swap)[3] = t;
        t = next;
        next = swap;
    }
    free(next);
    free(h.keys);
    free(h.vals);
    struct mesh_limits lim = {.max_triangles = nt};
    return mesh_create(v, nv, t, nt, &lim, out, e);
}
