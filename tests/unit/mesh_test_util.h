/*
 * mesh_test_util.h - what the mesh tests share (header-only): a generated icosphere (a
 * subdivided icosahedron pushed onto the sphere, wound counter-clockwise seen from
 * outside) and writers of it in OBJ, ASCII PLY and binary PLY of either byte order, so
 * that every round trip starts from the same exact geometry.
 */
#ifndef REFRACT_MESH_TEST_UTIL_H
#define REFRACT_MESH_TEST_UTIL_H

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh/mesh.h"

struct test_mesh {
    double (*v)[3];
    size_t nv;
    uint32_t (*t)[3];
    size_t nt;
};

static inline void test_mesh_free(struct test_mesh *m)
{
    free(m->v);
    free(m->t);
    memset(m, 0, sizeof *m);
}

/* Index of the midpoint of edge (a, b), made once per edge via an open-addressing table. */
static inline uint32_t ico_midpoint(struct test_mesh *m, uint64_t *keys, uint32_t *vals, size_t cap,
                                    uint32_t a, uint32_t b, double radius)
{
    uint64_t key = a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
    size_t h = (size_t)((key * 11400714819323198485ull) >> 20) % cap;
    while (keys[h] != UINT64_MAX && keys[h] != key)
        h = (h + 1) % cap;
    if (keys[h] == key)
        return vals[h];
    double p[3], len = 0.0;
    for (int k = 0; k < 3; k++) {
        p[k] = 0.5 * (m->v[a][k] + m->v[b][k]);
        len += p[k] * p[k];
    }
    len = sqrt(len);
    for (int k = 0; k < 3; k++)
        m->v[m->nv][k] = p[k] * radius / len;
    keys[h] = key;
    vals[h] = (uint32_t)m->nv;
    return (uint32_t)m->nv++;
}

/* 20 * 4^levels triangles on a sphere of `radius` about the origin. */
static inline struct test_mesh test_icosphere(int levels, double radius)
{
    const double g = (1.0 + sqrt(5.0)) / 2.0;
    const double base[12][3] = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0},
                                {0, -1, g}, {0, 1, g}, {0, -1, -g}, {0, 1, -g},
                                {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
    const uint32_t faces[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
    size_t nt = 20, nv_max = 12;
    for (int l = 0; l < levels; l++)
        nt *= 4;
    nv_max = nt / 2 + 2;
    struct test_mesh m = {.v = malloc(nv_max * sizeof *m.v), .t = malloc(nt * sizeof *m.t)};
    double blen = sqrt(1 + g * g);
    for (int i = 0; i < 12; i++)
        for (int k = 0; k < 3; k++)
            m.v[i][k] = base[i][k] * radius / blen;
    m.nv = 12;
    memcpy(m.t, faces, sizeof faces);
    m.nt = 20;
    uint32_t(*next)[3] = malloc(nt * sizeof *next);
    size_t cap = 4 * nv_max + 7;
    uint64_t *keys = malloc(cap * sizeof *keys);
    uint32_t *vals = malloc(cap * sizeof *vals);
    for (int l = 0; l < levels; l++) {
        memset(keys, 0xff, cap * sizeof *keys);
        size_t n = 0;
        for (size_t i = 0; i < m.nt; i++) {
            uint32_t a = m.t[i][0], b = m.t[i][1], c = m.t[i][2];
            uint32_t ab = ico_midpoint(&m, keys, vals, cap, a, b, radius);
            uint32_t bc = ico_midpoint(&m, keys, vals, cap, b, c, radius);
            uint32_t ca = ico_midpoint(&m, keys, vals, cap, c, a, radius);
            const uint32_t quad[4][3] = {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}};
            memcpy(next + n, quad, sizeof quad);
            n += 4;
        }
        memcpy(m.t, next, n * sizeof *next);
        m.nt = n;
    }
    free(next);
    free(keys);
    free(vals);
    return m;
}

/* A new mesh_create()d copy (the test mesh keeps its arrays). */
static inline struct mesh *test_mesh_make(const struct test_mesh *tm)
{
    double(*v)[3] = malloc(tm->nv * sizeof *v);
    uint32_t(*t)[3] = malloc(tm->nt * sizeof *t);
    memcpy(v, tm->v, tm->nv * sizeof *v);
    memcpy(t, tm->t, tm->nt * sizeof *t);
    struct mesh *m = NULL;
    struct err e = {0};
    if (mesh_create(v, tm->nv, t, tm->nt, NULL, &m, &e) != REFRACT_E_OK)
        fprintf(stderr, "test_mesh_make: %s\n", e.msg);
    return m;
}

/* A growable byte buffer for the writers. */
struct test_buf {
    char *p;
    size_t len, cap;
};

static inline void buf_put(struct test_buf *b, const void *data, size_t n)
{
    if (b->len + n + 1 > b->cap) {
        b->cap = (b->len + n + 1) * 2;
        b->p = realloc(b->p, b->cap);
    }
    memcpy(b->p + b->len, data, n);
    b->len += n;
    b->p[b->len] = '\0';
}

static inline void buf_printf(struct test_buf *b, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
static inline void buf_printf(struct test_buf *b, const char *fmt, ...)
{
    char tmp[512];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(tmp, sizeof tmp, fmt, ap);
    va_end(ap);
    buf_put(b, tmp, (size_t)n);
}

static inline struct test_buf test_write_obj(const struct test_mesh *m)
{
    struct test_buf b = {0};
    buf_printf(&b, "# icosphere, %zu triangles\no sphere\n", m->nt);
    for (size_t i = 0; i < m->nv; i++)
        buf_printf(&b, "v %.17g %.17g %.17g\n", m->v[i][0], m->v[i][1], m->v[i][2]);
    buf_printf(&b, "vn 0 0 1\nvt 0.5 0.5\n");
    for (size_t i = 0; i < m->nt; i++) {
        if (i % 2)
            buf_printf(&b, "f %u/1/1 %u/1/1 %u/1/1\n", m->t[i][0] + 1, m->t[i][1] + 1,
                       m->t[i][2] + 1);
        else
            buf_printf(&b, "f %u//1 %u %u\n", m->t[i][0] + 1, m->t[i][1] + 1, m->t[i][2] + 1);
    }
    return b;
}

static inline void put_scalar(struct test_buf *b, const void *p, size_t n, bool big_endian)
{
    unsigned char tmp[8];
    memcpy(tmp, p, n);
    const uint16_t probe = 1;
    bool host_le = *(const unsigned char *)&probe == 1;
    if (host_le == big_endian) {
        for (size_t i = 0; i < n / 2; i++) {
            unsigned char c = tmp[i];
            tmp[i] = tmp[n - 1 - i];
            tmp[n - 1 - i] = c;
        }
    }
    buf_put(b, tmp, n);
}

enum test_ply_kind { TEST_PLY_ASCII, TEST_PLY_LE, TEST_PLY_BE };

/* Vertices as double x, y, z plus a float "confidence" that the reader must skip; faces as
 * uchar-counted int lists plus a uchar-counted list of extra ints (also skipped). */
static inline struct test_buf test_write_ply(const struct test_mesh *m, enum test_ply_kind kind)
{
    static const char *const fmt[] = {"ascii", "binary_little_endian", "binary_big_endian"};
    struct test_buf b = {0};
    buf_printf(&b,
               "ply\nformat %s 1.0\ncomment icosphere\nelement vertex %zu\nproperty double x\n"
               "property double y\nproperty double z\nproperty float confidence\n"
               "element face %zu\nproperty list uchar int vertex_indices\n"
               "property list uchar int extra\nend_header\n",
               fmt[kind], m->nv, m->nt);
    for (size_t i = 0; i < m->nv; i++) {
        if (kind == TEST_PLY_ASCII) {
            buf_printf(&b, "%.17g %.17g %.17g 0.5\n", m->v[i][0], m->v[i][1], m->v[i][2]);
            continue;
        }
        for (int k = 0; k < 3; k++)
            put_scalar(&b, &m->v[i][k], 8, kind == TEST_PLY_BE);
        float conf = 0.5f;
        put_scalar(&b, &conf, 4, kind == TEST_PLY_BE);
    }
    for (size_t i = 0; i < m->nt; i++) {
        if (kind == TEST_PLY_ASCII) {
            buf_printf(&b, "3 %u %u %u 1 7\n", m->t[i][0], m->t[i][1], m->t[i][2]);
            continue;
        }
        unsigned char three = 3, one = 1;
        buf_put(&b, &three, 1);
        for (int k = 0; k < 3; k++) {
            int32_t idx = (int32_t)m->t[i][k];
            put_scalar(&b, &idx, 4, kind == TEST_PLY_BE);
        }
        buf_put(&b, &one, 1);
        int32_t extra = 7;
        put_scalar(&b, &extra, 4, kind == TEST_PLY_BE);
    }
    return b;
}

/* The parse error of `text` (NUL-terminated) in format f, with its code checked. */
static inline const char *test_mesh_error(const char *text, size_t len, enum mesh_format f,
                                          size_t max_triangles, enum refract_code want,
                                          struct err *e)
{
    struct mesh_limits lim = {.max_triangles = max_triangles};
    struct mesh *m = (struct mesh *)1;
    enum refract_code rc = mesh_parse(text, len, f, &lim, &m, e);
    if (rc != want)
        fprintf(stderr, "expected code %d, got %d (%s) for:\n%.200s\n", want, rc, e->msg, text);
    if (m != NULL) {
        fprintf(stderr, "expected *out = NULL on failure\n");
        mesh_destroy(m == (struct mesh *)1 ? NULL : m);
        return "(out not reset)";
    }
    return rc == want ? e->msg : "(wrong code)";
}

#endif
