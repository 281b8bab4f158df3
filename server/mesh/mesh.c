/*
 * mesh.c - making and destroying meshes: the validation every mesh passes whatever its
 * source (a parser or arrays), the parsers' growable arrays, format sniffing and the
 * parse dispatch.
 *
 * Not here: the file formats (mesh_obj.c, mesh_ply.c), the BVHs (mesh_bvh.c,
 * mesh_rt_build.c), queries (mesh_winding.c) and voxelization (mesh_voxelize.c).
 */
#include "mesh_internal.h"
#include "mesh_rt.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static size_t max_triangles_of(const struct mesh_limits *limits)
{
    return limits != NULL && limits->max_triangles > 0 ? limits->max_triangles
                                                       : MESH_DEFAULT_MAX_TRIANGLES;
}

const char *mesh_format_name(enum mesh_format f)
{
    return f == MESH_FORMAT_OBJ ? "obj" : f == MESH_FORMAT_PLY ? "ply" : "unknown";
}

/* ---- the builder ---- */

void mesh_builder_init(struct mesh_builder *b, const struct mesh_limits *limits)
{
    memset(b, 0, sizeof *b);
    b->max_triangles = max_triangles_of(limits);
}

void mesh_builder_fini(struct mesh_builder *b)
{
    free(b->v);
    free(b->t);
    memset(b, 0, sizeof *b);
}

/* Grows *arr (elements of `size` bytes) to hold at least need elements. */
static bool grow(void **arr, size_t *cap, size_t need, size_t size)
{
    if (need <= *cap)
        return true;
    size_t n = *cap ? *cap : 1024;
    while (n < need)
        n *= 2;
    void *p = realloc(*arr, n * size);
    if (p == NULL)
        return false;
    *arr = p;
    *cap = n;
    return true;
}

bool mesh_builder_vertex(struct mesh_builder *b, double x, double y, double z)
{
    if (!grow((void **)&b->v, &b->cap_v, b->nv + 1, sizeof *b->v))
        return false;
    b->v[b->nv][0] = x;
    b->v[b->nv][1] = y;
    b->v[b->nv][2] = z;
    b->nv++;
    return true;
}

bool mesh_builder_full(const struct mesh_builder *b)
{
    return b->nt >= b->max_triangles;
}

bool mesh_builder_triangle(struct mesh_builder *b, uint32_t i0, uint32_t i1, uint32_t i2)
{
    if (!grow((void **)&b->t, &b->cap_t, b->nt + 1, sizeof *b->t))
        return false;
    b->t[b->nt][0] = i0;
    b->t[b->nt][1] = i1;
    b->t[b->nt][2] = i2;
    b->nt++;
    return true;
}

enum refract_code mesh_limit_error(const struct mesh_builder *b, const char *where, struct err *e)
{
    return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                   "%s: the mesh has more than %zu triangles (after splitting polygons into "
                   "triangles), the limit max_mesh_triangles; simplify the mesh or start "
                   "refractd with --max-mesh-triangles to raise it",
                   where, b->max_triangles);
}

enum refract_code mesh_builder_finish(struct mesh_builder *b, const struct mesh_limits *limits,
                                      struct mesh **out, struct err *e)
{
    enum refract_code rc = mesh_create(b->v, b->nv, b->t, b->nt, limits, out, e);
    b->v = NULL;
    b->t = NULL;
    mesh_builder_fini(b);
    return rc;
}

/* ---- meshes ---- */

void mesh_destroy(struct mesh *m)
{
    if (m == NULL)
        return;
    mesh_bvh_destroy(m->bvh);
    mesh_rt_destroy(m->rt);
    mesh_memo_destroy(m->memo);
    free(m->vertices);
    free(m->triangles);
    free(m);
}

static enum refract_code validate(const double (*v)[3], size_t nv, const uint32_t (*t)[3],
                                  size_t nt, size_t max_t, struct err *e)
{
    if (nt == 0)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "the mesh has no triangles (%zu vertices, no faces); a mesh needs at "
                       "least one face of 3 or more vertices",
                       nv);
    if (nt > max_t)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "the mesh has %zu triangles, more than the limit max_mesh_triangles = "
                       "%zu; simplify the mesh or start refractd with --max-mesh-triangles to "
                       "raise it",
                       nt, max_t);
    if (nv > UINT32_MAX)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "the mesh has %zu vertices; at most 4294967295 can be indexed", nv);
    for (size_t i = 0; i < nv; i++) {
        for (int a = 0; a < 3; a++) {
            if (!isfinite(v[i][a]) || fabs(v[i][a]) > 1e15)
                return err_set(e, REFRACT_E_INVALID_MESH,
                               "vertex %zu: coordinate %c is %g; coordinates must be finite "
                               "numbers of magnitude at most 1e15",
                               i, "xyz"[a], v[i][a]);
        }
    }
    for (size_t i = 0; i < nt; i++) {
        for (int c = 0; c < 3; c++) {
            if (t[i][c] >= nv)
                return err_set(e, REFRACT_E_INVALID_MESH,
                               "triangle %zu: vertex index %u is out of range (the mesh has "
                               "%zu vertices, indices 0..%zu)",
                               i, t[i][c], nv, nv ? nv - 1 : 0);
        }
    }
    return REFRACT_E_OK;
}

struct directed_edge {
    uint64_t key; /* min << 32 | max */
    int sign;     /* +1 for min -> max, -1 for max -> min */
};

static int compare_edges(const void *a, const void *b)
{
    uint64_t x = ((const struct directed_edge *)a)->key, y = ((const struct directed_edge *)b)->key;
    return (x > y) - (x < y);
}

/* True when the triangles' oriented boundary is zero: each undirected edge is walked as
 * often in one direction as in the other (a closed, consistently wound surface, possibly
 * several, possibly non-manifold). Then the winding number is an integer that changes
 * only across the surface, which mesh_voxelize relies on to skip evaluations. Sorting
 * the 3n directed edges: O(n log n), about 30 ms for 100k triangles. */
static bool is_closed(const struct mesh *m)
{
    size_t n = 3 * m->triangle_count;
    struct directed_edge *e = malloc(n * sizeof *e);
    if (e == NULL)
        return false; /* only an optimisation is lost */
    for (size_t t = 0; t < m->triangle_count; t++) {
        for (int c = 0; c < 3; c++) {
            uint32_t a = m->triangles[t][c], b = m->triangles[t][(c + 1) % 3];
            uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
            e[3 * t + (size_t)c] =
                (struct directed_edge){((uint64_t)lo << 32) | hi, a < b ? 1 : -1};
        }
    }
    qsort(e, n, sizeof *e, compare_edges);
    bool closed = true;
    for (size_t i = 0; i < n && closed;) {
        size_t j = i;
        int sum = 0;
        while (j < n && e[j].key == e[i].key)
            sum += e[j++].sign;
        closed = sum == 0;
        i = j;
    }
    free(e);
    return closed;
}

enum refract_code mesh_create(double (*vertices)[3], size_t vertex_count, uint32_t (*triangles)[3],
                              size_t triangle_count, const struct mesh_limits *limits,
                              struct mesh **out, struct err *e)
{
    *out = NULL;
    enum refract_code rc =
        validate((const double(*)[3])vertices, vertex_count, (const uint32_t(*)[3])triangles,
                 triangle_count, max_triangles_of(limits), e);
    struct mesh *m = rc == REFRACT_E_OK ? calloc(1, sizeof *m) : NULL;
    if (rc == REFRACT_E_OK && m == NULL)
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a mesh of %zu triangles",
                     triangle_count);
    if (rc != REFRACT_E_OK) {
        free(vertices);
        free(triangles);
        return rc;
    }
    m->vertices = vertices;
    m->vertex_count = vertex_count;
    m->memo = mesh_memo_create();
    m->triangles = triangles;
    m->triangle_count = triangle_count;
    m->lo = vec3_make(INFINITY, INFINITY, INFINITY);
    m->hi = vec3_make(-INFINITY, -INFINITY, -INFINITY);
    for (size_t i = 0; i < triangle_count; i++) {
        for (int c = 0; c < 3; c++) {
            const double *p = vertices[triangles[i][c]];
            m->lo = vec3_make(fmin(m->lo.x, p[0]), fmin(m->lo.y, p[1]), fmin(m->lo.z, p[2]));
            m->hi = vec3_make(fmax(m->hi.x, p[0]), fmax(m->hi.y, p[1]), fmax(m->hi.z, p[2]));
        }
    }
    m->closed = is_closed(m);
    rc = mesh_bvh_build(m, e);
    if (rc == REFRACT_E_OK)
        rc = mesh_rt_build(m, &m->rt, e);
    if (rc != REFRACT_E_OK) {
        mesh_destroy(m);
        return rc;
    }
    /* Whether it can bound a medium as an exact surface (not a condition of being a mesh:
     * an open mesh still voxelizes by its winding number). An inside-out solid is fine as
     * it is: the march toggles media at each crossing whatever the winding. */
    struct err se = {0};
    bool inside_out = false;
    m->solid = mesh_solid_status(m, &inside_out, &se) == REFRACT_E_OK;
    if (!m->solid)
        snprintf(m->solid_error, sizeof m->solid_error, "%s", se.msg);
    *out = m;
    return REFRACT_E_OK;
}

/* ---- formats ---- */

static bool is_blank(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

enum mesh_format mesh_sniff(const void *bytes, size_t len)
{
    const char *s = bytes;
    if (len >= 4 && memcmp(s, "ply", 3) == 0 && (s[3] == '\n' || s[3] == '\r'))
        return MESH_FORMAT_PLY;
    static const char *const statements[] = {"v", "vt", "vn",     "vp",     "f", "o",
                                             "g", "s",  "usemtl", "mtllib", "l", NULL};
    size_t n = len < 4096 ? len : 4096, i = 0;
    while (i < n) {
        while (i < n && is_blank(s[i]))
            i++;
        if (i < n && s[i] == '#') {
            while (i < n && s[i] != '\n')
                i++;
            continue;
        }
        size_t w = i;
        while (w < n && !is_blank(s[w]))
            w++;
        for (const char *const *st = statements; *st; st++) {
            if (w - i == strlen(*st) && memcmp(s + i, *st, w - i) == 0 && w < n)
                return MESH_FORMAT_OBJ;
        }
        return MESH_FORMAT_UNKNOWN;
    }
    return MESH_FORMAT_UNKNOWN;
}

enum refract_code mesh_parse(const void *bytes, size_t len, enum mesh_format format,
                             const struct mesh_limits *limits, struct mesh **out, struct err *e)
{
    *out = NULL;
    if (format == MESH_FORMAT_UNKNOWN)
        format = mesh_sniff(bytes, len);
    switch (format) {
    case MESH_FORMAT_OBJ:
        return mesh_parse_obj(bytes, len, limits, out, e);
    case MESH_FORMAT_PLY:
        return mesh_parse_ply(bytes, len, limits, out, e);
    case MESH_FORMAT_UNKNOWN:
        break;
    }
    return err_set(e, REFRACT_E_INVALID_MESH,
                   "the file is neither PLY (it would start with the line \"ply\") nor OBJ (its "
                   "first statement would be v, vt, vn, f, o, g, ...); send an OBJ or PLY file, "
                   "or name the format with ?format=obj|ply");
}
