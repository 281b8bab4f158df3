/*
 * mesh_rt_build.c - the ray-tracing hierarchy of a mesh (mesh_rt.h states the layout and
 * the invariants): binned SAH, flattened into the GPU's node, triangle and vertex arrays.
 *
 * Build: top down over an array of per-triangle records (float box rounded outward,
 * centroid, index) that is partitioned in place, so each node's triangles are one
 * contiguous run and the passes stream through memory instead of chasing indices (1M
 * triangles in well under the 2 s budget, BENCHMARKS.md). Each node: one pass for its box
 * and its centroids' box, one pass binning the centroids along all three axes, a sweep
 * over the MESH_RT_BINS - 1 candidate planes per axis choosing the least
 * area_left * count_left + area_right * count_right (the constant traversal and
 * intersection costs of the full SAH do not change which plane wins), one partition. A
 * node of MESH_RT_LEAF_MAX triangles or fewer is always a leaf and a larger one is always
 * split: leaves are then 1..4 triangles (about 2.5 on average), which keeps the GPU arrays
 * near 50 bytes a triangle (the budget is 64).
 *
 * Depth bound: SAH may peel one triangle off a node at a time (a fan of slivers), so below
 * MESH_RT_SAH_DEPTH nodes are split at their median centroid instead. That halves a node,
 * and 2^31 triangles need at most 30 halvings to reach 4, so no path is longer than
 * 32 + 30 = 62 < MESH_RT_MAX_DEPTH nodes.
 *
 * Float boxes: a box's double bounds rounded outward (down for lo, up for hi) contain
 * every double vertex, and every vertex's round-to-nearest float too (rounding is
 * monotonic), so the same boxes are conservative for the CPU's double traversal and the
 * GPU's float one.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"
#include "mesh_rt.h"

_Static_assert(sizeof(struct mesh_rt_node) == 32, "node: two vec4 (std430)");
_Static_assert(sizeof(struct mesh_rt_tri) == 16, "triangle: one uvec4 (std430)");
_Static_assert(sizeof(struct mesh_rt_vertex) == 16, "vertex: one vec4 (std430)");
_Static_assert(MESH_RT_SAH_DEPTH + 30 <= MESH_RT_MAX_DEPTH, "the depth bound (file comment)");

struct prim {
    float lo[3], hi[3]; /* the triangle's box, rounded outward */
    float c[3];         /* its centroid (only orders the binning; precision is irrelevant) */
    uint32_t index;     /* the triangle's index in struct mesh.triangles */
};

struct build {
    struct prim *p;
    struct mesh_rt_node *nodes; /* 2n - 1 slots: a binary tree of n nonempty leaves */
    size_t count;
    int depth;
};

static float round_down(double v)
{
    float f = (float)v;
    return (double)f > v ? nextafterf(f, -INFINITY) : f;
}

static float round_up(double v)
{
    float f = (float)v;
    return (double)f < v ? nextafterf(f, INFINITY) : f;
}

static double half_area(const float lo[3], const float hi[3])
{
    double dx = (double)hi[0] - lo[0], dy = (double)hi[1] - lo[1], dz = (double)hi[2] - lo[2];
    return dx * dy + dy * dz + dz * dx;
}

struct bin {
    float lo[3], hi[3];
    uint32_t n;
};

static void bin_reset(struct bin *b)
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = INFINITY;
        b->hi[k] = -INFINITY;
    }
    b->n = 0;
}

static void bin_grow(struct bin *b, const float lo[3], const float hi[3])
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = fminf(b->lo[k], lo[k]);
        b->hi[k] = fmaxf(b->hi[k], hi[k]);
    }
}

/* The bin of a centroid coordinate; the one expression both binning and partitioning use,
 * so they agree on every triangle. */
static int bin_of(float c, float cmin, float scale)
{
    int k = (int)((c - cmin) * scale);
    return k < 0 ? 0 : (k >= MESH_RT_BINS ? MESH_RT_BINS - 1 : k);
}

/* Best SAH plane of p[0 .. n): *axis and *split (triangles of bin < split go left).
 * False when no axis has extent. */
static bool sah_plane(const struct prim *p, uint32_t n, const float cmin[3], const float cmax[3],
                      int *axis, int *split, float *scale_out)
{
    double best = INFINITY;
    for (int a = 0; a < 3; a++) {
        if (!(cmax[a] > cmin[a]))
            continue;
        float scale = (float)MESH_RT_BINS * 0.99999f / (cmax[a] - cmin[a]);
        struct bin bins[MESH_RT_BINS];
        for (int i = 0; i < MESH_RT_BINS; i++)
            bin_reset(&bins[i]);
        for (uint32_t i = 0; i < n; i++) {
            struct bin *b = &bins[bin_of(p[i].c[a], cmin[a], scale)];
            bin_grow(b, p[i].lo, p[i].hi);
            b->n++;
        }
        /* right_cost[s]: area * count of bins s .. BINS-1 */
        double right_cost[MESH_RT_BINS];
        uint32_t right_n[MESH_RT_BINS];
        struct bin acc;
        bin_reset(&acc);
        for (int s = MESH_RT_BINS - 1; s > 0; s--) {
            if (bins[s].n)
                bin_grow(&acc, bins[s].lo, bins[s].hi);
            acc.n += bins[s].n;
            right_n[s] = acc.n;
            right_cost[s] = acc.n ? half_area(acc.lo, acc.hi) * acc.n : 0.0;
        }
        bin_reset(&acc);
        for (int s = 1; s < MESH_RT_BINS; s++) {
            if (bins[s - 1].n)
                bin_grow(&acc, bins[s - 1].lo, bins[s - 1].hi);
            acc.n += bins[s - 1].n;
            if (acc.n == 0 || right_n[s] == 0)
                continue;
            double cost = half_area(acc.lo, acc.hi) * acc.n + right_cost[s];
            if (cost < best) {
                best = cost;
                *axis = a;
                *split = s;
                *scale_out = scale;
            }
        }
    }
    return best < INFINITY;
}

static void swap_prim(struct prim *a, struct prim *b)
{
    struct prim t = *a;
    *a = *b;
    *b = t;
}

/* Moves the triangles whose bin is below split to the front; returns how many. */
static uint32_t partition_bins(struct prim *p, uint32_t n, int axis, int split, float cmin,
                               float scale)
{
    uint32_t i = 0, j = n;
    while (i < j) {
        if (bin_of(p[i].c[axis], cmin, scale) < split)
            i++;
        else
            swap_prim(&p[i], &p[--j]);
    }
    return i;
}

/* Partially sorts p[0 .. n) along axis so that p[k] is in its sorted place (quickselect
 * with Hoare partitions around the middle element; signed indices as j may pass 0). */
static void select_kth(struct prim *p, uint32_t n, uint32_t k, int axis)
{
    long long l = 0, r = (long long)n - 1;
    while (l < r) {
        float x = p[(l + r) / 2].c[axis];
        long long i = l, j = r;
        do {
            while (p[i].c[axis] < x)
                i++;
            while (x < p[j].c[axis])
                j--;
            if (i <= j) {
                swap_prim(&p[i], &p[j]);
                i++;
                j--;
            }
        } while (i <= j);
        if (j < (long long)k)
            l = i;
        if ((long long)k < i)
            r = j;
    }
}

/* Fills nodes[slot] with p[first .. first + n) and recurses (depth: slot's, root = 1). */
static void fill(struct build *b, size_t slot, uint32_t first, uint32_t n, int depth)
{
    struct prim *p = b->p + first;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    float cmin[3] = {INFINITY, INFINITY, INFINITY}, cmax[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = 0; i < n; i++) {
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], p[i].lo[k]);
            hi[k] = fmaxf(hi[k], p[i].hi[k]);
            cmin[k] = fminf(cmin[k], p[i].c[k]);
            cmax[k] = fmaxf(cmax[k], p[i].c[k]);
        }
    }
    struct mesh_rt_node *nd = &b->nodes[slot];
    memcpy(nd->lo, lo, sizeof lo);
    memcpy(nd->hi, hi, sizeof hi);
    if (depth > b->depth)
        b->depth = depth;
    if (n <= MESH_RT_LEAF_MAX) {
        nd->left_or_first = first;
        nd->count = n;
        return;
    }
    int axis = 0, split = 0;
    float scale = 0.0f;
    uint32_t mid = 0;
    if (depth < MESH_RT_SAH_DEPTH && sah_plane(p, n, cmin, cmax, &axis, &split, &scale))
        mid = partition_bins(p, n, axis, split, cmin[axis], scale);
    if (mid == 0 || mid == n) { /* deep, or every centroid in one point: the median */
        for (int k = 1; k < 3; k++)
            axis = cmax[k] - cmin[k] > cmax[axis] - cmin[axis] ? k : axis;
        mid = n / 2;
        select_kth(p, n, mid, axis);
    }
    size_t left = b->count;
    b->count += 2;
    nd->left_or_first = (uint32_t)left;
    nd->count = 0;
    fill(b, left, first, mid, depth + 1);
    fill(b, left + 1, first + mid, n - mid, depth + 1);
}

/* ---- octahedral normals (Cigolle et al. 2014, "A Survey of Efficient Representations
 * for Independent Unit Vectors", sect. 3.1) ---- */

static double sign_not_zero(double v)
{
    return v >= 0.0 ? 1.0 : -1.0;
}

static double snorm16_to_double(int16_t q)
{
    return fmax(-1.0, (double)q / 32767.0); /* unpackSnorm2x16 */
}

vec3 mesh_rt_oct_decode(uint32_t bits)
{
    double x = snorm16_to_double((int16_t)(bits & 0xffffu));
    double y = snorm16_to_double((int16_t)(bits >> 16));
    vec3 v = {x, y, 1.0 - fabs(x) - fabs(y)};
    if (v.z < 0.0) {
        double vx = v.x;
        v.x = (1.0 - fabs(v.y)) * sign_not_zero(vx);
        v.y = (1.0 - fabs(vx)) * sign_not_zero(v.y);
    }
    return vec3_normalize(v);
}

uint32_t mesh_rt_oct_encode(vec3 n)
{
    double l1 = fabs(n.x) + fabs(n.y) + fabs(n.z);
    if (!(l1 > 0.0))
        return 0; /* decodes to +z; only for vertices no triangle with area uses */
    double x = n.x / l1, y = n.y / l1;
    if (n.z < 0.0) {
        double px = x;
        x = (1.0 - fabs(y)) * sign_not_zero(px);
        y = (1.0 - fabs(px)) * sign_not_zero(y);
    }
    /* Of the four roundings of (x, y) to the snorm16 grid, the one that decodes nearest
     * to n: about half the error of rounding to nearest (Cigolle et al., "precise"). */
    double fx = floor(x * 32767.0), fy = floor(y * 32767.0);
    uint32_t best = 0;
    double best_dot = -2.0;
    vec3 u = vec3_normalize(n);
    for (int i = 0; i < 4; i++) {
        double qx = fmin(32767.0, fmax(-32767.0, fx + (i & 1)));
        double qy = fmin(32767.0, fmax(-32767.0, fy + (i >> 1)));
        uint32_t bits = (uint32_t)(uint16_t)(int16_t)qx | (uint32_t)(uint16_t)(int16_t)qy << 16;
        double d = vec3_dot(mesh_rt_oct_decode(bits), u);
        if (d > best_dot) {
            best_dot = d;
            best = bits;
        }
    }
    return best;
}

/* Area-weighted vertex normals: the sum of the unnormalised face normals (b - a) x (c - a)
 * of the triangles around a vertex, normalised. Cheaper than angle weights and as good on
 * the meshes we get (docs/tracing.md "Triangle meshes"); the sum follows the winding. */
static void vertex_normals(const struct mesh *m, double (*nrm)[3])
{
    memset(nrm, 0, m->vertex_count * sizeof *nrm);
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tri = m->triangles[t];
        const double *a = m->vertices[tri[0]], *b = m->vertices[tri[1]], *c = m->vertices[tri[2]];
        vec3 f = vec3_cross(vec3_make(b[0] - a[0], b[1] - a[1], b[2] - a[2]),
                            vec3_make(c[0] - a[0], c[1] - a[1], c[2] - a[2]));
        for (int k = 0; k < 3; k++) {
            nrm[tri[k]][0] += f.x;
            nrm[tri[k]][1] += f.y;
            nrm[tri[k]][2] += f.z;
        }
    }
    for (size_t v = 0; v < m->vertex_count; v++) {
        vec3 u = vec3_normalize(vec3_make(nrm[v][0], nrm[v][1], nrm[v][2]));
        nrm[v][0] = u.x;
        nrm[v][1] = u.y;
        nrm[v][2] = u.z;
    }
}

void mesh_rt_pack_vertices(struct mesh_rt *rt)
{
    for (size_t v = 0; v < rt->vertex_count; v++) {
        for (int k = 0; k < 3; k++)
            rt->verts[v].p[k] = (float)rt->positions[v][k];
        rt->verts[v].n_oct =
            mesh_rt_oct_encode(vec3_make(rt->normals[v][0], rt->normals[v][1], rt->normals[v][2]));
    }
}

enum refract_code mesh_rt_build(const struct mesh *m, struct mesh_rt **out, struct err *e)
{
    *out = NULL;
    size_t n = m->triangle_count;
    struct mesh_rt *rt = calloc(1, sizeof *rt);
    struct build b = {.p = malloc(n * sizeof *b.p), .nodes = malloc((2 * n - 1) * sizeof *b.nodes)};
    if (rt != NULL) {
        rt->tris = malloc(n * sizeof *rt->tris);
        rt->verts = malloc(m->vertex_count * sizeof *rt->verts);
        rt->normals = malloc(m->vertex_count * sizeof *rt->normals);
    }
    if (rt == NULL || b.p == NULL || b.nodes == NULL || rt->tris == NULL || rt->verts == NULL ||
        rt->normals == NULL) {
        free(b.p);
        free(b.nodes);
        mesh_rt_destroy(rt);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "out of memory for the ray-tracing hierarchy of a mesh of %zu triangles",
                       n);
    }
    for (size_t t = 0; t < n; t++) {
        struct prim *p = &b.p[t];
        for (int k = 0; k < 3; k++) {
            double v0 = m->vertices[m->triangles[t][0]][k], v1 = m->vertices[m->triangles[t][1]][k],
                   v2 = m->vertices[m->triangles[t][2]][k];
            p->lo[k] = round_down(fmin(v0, fmin(v1, v2)));
            p->hi[k] = round_up(fmax(v0, fmax(v1, v2)));
            p->c[k] = (float)((v0 + v1 + v2) / 3.0);
        }
        p->index = (uint32_t)t;
    }
    b.count = 1;
    fill(&b, 0, 0, (uint32_t)n, 1);
    for (size_t i = 0; i < n; i++) {
        uint32_t t = b.p[i].index;
        memcpy(rt->tris[i].v, m->triangles[t], sizeof rt->tris[i].v);
        rt->tris[i].orig = t;
    }
    free(b.p);
    struct mesh_rt_node *shrunk = realloc(b.nodes, b.count * sizeof *b.nodes);
    rt->nodes = shrunk != NULL ? shrunk : b.nodes;
    rt->node_count = b.count;
    rt->tri_count = n;
    rt->vertex_count = m->vertex_count;
    rt->positions = (const double(*)[3])m->vertices;
    rt->depth = b.depth;
    vertex_normals(m, rt->normals);
    mesh_rt_pack_vertices(rt);
    *out = rt;
    return REFRACT_E_OK;
}

void mesh_rt_destroy(struct mesh_rt *rt)
{
    if (rt == NULL)
        return;
    free(rt->nodes);
    free(rt->tris);
    free(rt->verts);
    free(rt->normals);
    free(rt);
}

struct mesh_rt_gpu mesh_rt_gpu_arrays(const struct mesh_rt *rt)
{
    struct mesh_rt_gpu g = {
        .nodes = rt->nodes,
        .node_count = rt->node_count,
        .node_bytes = rt->node_count * sizeof *rt->nodes,
        .tris = rt->tris,
        .tri_count = rt->tri_count,
        .tri_bytes = rt->tri_count * sizeof *rt->tris,
        .verts = rt->verts,
        .vertex_count = rt->vertex_count,
        .vertex_bytes = rt->vertex_count * sizeof *rt->verts,
    };
    g.total_bytes = g.node_bytes + g.tri_bytes + g.vertex_bytes;
    return g;
}
