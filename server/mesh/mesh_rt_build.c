/*
 * mesh_rt_build.c - the ray-tracing hierarchy of a mesh (mesh_rt.h states the layout and
 * the invariants): binned SAH, flattened into the GPU's node, triangle and vertex arrays.
 *
 * Build: top down over an array of 32-byte per-triangle records (the float box rounded
 * outward, in four lanes so min/max compile to vector instructions) partitioned in place,
 * the triangle indices alongside, so each node's triangles are one contiguous run and the
 * passes stream through memory instead of chasing indices. A triangle is binned by its
 * box's centre (as is common, e.g. Wald 2007, "On fast construction of SAH-based bounding
 * volume hierarchies"): no centroid to store. Per node two passes: one bins the centres
 * along all three axes at once (MESH_RT_BINS bins over the centres' extent), a sweep over
 * the bins picks the plane with the least area_left * count_left + area_right *
 * count_right (the constant traversal and intersection costs of the full SAH do not change
 * which plane wins), and one partition moves the triangles, gathering each side's centre
 * bounds as it goes; the children's boxes come from the sweep. 1M triangles build in under
 * a second of CPU (BENCHMARKS.md). A node of MESH_RT_LEAF_MAX triangles or fewer is always
 * a leaf and a larger one is always split: leaves are then 1..4 triangles (about 3 on
 * average), which keeps the GPU arrays near 45 bytes a triangle (the budget is 64).
 *
 * Depth bound: SAH may peel one triangle off a node at a time (a fan of slivers), so below
 * MESH_RT_SAH_DEPTH nodes are split at their median centre instead. That halves a node,
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

/* A triangle's box, rounded outward; four lanes (the fourth 0) so that the compiler
 * turns the min/max loops over them into single vector instructions. */
struct prim {
    float lo[4], hi[4];
};

/* A box, or the bounds of the prims' keys (lane 3 unused). */
struct bounds {
    float lo[4], hi[4];
};

struct build {
    struct prim *p;
    uint32_t *index;            /* the triangle of each prim, permuted with them */
    struct mesh_rt_node *nodes; /* 2n - 1 slots: a binary tree of n nonempty leaves */
    size_t count;
    int depth;
};

/* Plain comparisons rather than fminf/fmaxf: no NaN reaches here (mesh_create validated
 * the vertices), and these compile to one instruction (the build's inner loops are
 * mostly these). */
static inline float minf(float a, float b)
{
    return a < b ? a : b;
}
static inline float maxf(float a, float b)
{
    return a > b ? a : b;
}

static void bounds_empty(struct bounds *b)
{
    for (int k = 0; k < 4; k++) {
        b->lo[k] = INFINITY;
        b->hi[k] = -INFINITY;
    }
}

static inline void bounds_grow(struct bounds *b, const float lo[4], const float hi[4])
{
    for (int k = 0; k < 4; k++) {
        b->lo[k] = minf(b->lo[k], lo[k]);
        b->hi[k] = maxf(b->hi[k], hi[k]);
    }
}

/* A prim's position for binning: twice its box's centre (the factor 2 changes no order,
 * and the box centre needs no more memory than the box). */
static inline float key(const struct prim *p, int axis)
{
    return p->lo[axis] + p->hi[axis];
}

static inline void bounds_grow_key(struct bounds *b, const struct prim *p)
{
    for (int k = 0; k < 4; k++) {
        float c = key(p, k);
        b->lo[k] = minf(b->lo[k], c);
        b->hi[k] = maxf(b->hi[k], c);
    }
}

/* The box and key bounds of p[0 .. n). */
static void bounds_of(const struct prim *p, uint32_t n, struct bounds *box, struct bounds *keys)
{
    bounds_empty(box);
    bounds_empty(keys);
    for (uint32_t i = 0; i < n; i++) {
        bounds_grow(box, p[i].lo, p[i].hi);
        bounds_grow_key(keys, &p[i]);
    }
}

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

static double half_area(const struct bounds *b)
{
    double dx = (double)b->hi[0] - b->lo[0], dy = (double)b->hi[1] - b->lo[1],
           dz = (double)b->hi[2] - b->lo[2];
    return dx * dy + dy * dz + dz * dx;
}

/* The bin of a key; the one expression binning and partitioning share, so they agree on
 * every triangle. */
static inline int bin_of(float c, float cmin, float scale)
{
    /* Clamped before the conversion, which is undefined outside int's range: a key extent
     * that is a float denormal makes scale infinite, and 0 * inf is NaN (found by
     * tests/fuzz/fuzz_ply.c). A NaN fails both comparisons and lands in bin 0; binning and
     * partitioning call this one function, so they agree. */
    float t = (c - cmin) * scale;
    if (!(t >= 1.0f))
        return 0;
    return t >= (float)MESH_RT_BINS ? MESH_RT_BINS - 1 : (int)t;
}

struct split {
    int axis, bin;             /* triangles whose bin along axis is below `bin` go left */
    float cmin, scale;         /* of bin_of */
    struct bounds left, right; /* the children's boxes */
};

/* The best SAH plane for p[0 .. n), whose keys lie in kb: one pass bins all three axes,
 * then a sweep per axis. False when no axis has extent. */
static bool sah_split(const struct prim *p, uint32_t n, const struct bounds *kb, struct split *out)
{
    float scale[3];
    for (int a = 0; a < 3; a++) {
        float ext = kb->hi[a] - kb->lo[a];
        scale[a] = ext > 0.0f ? (float)MESH_RT_BINS * 0.99999f / ext : 0.0f;
    }
    struct bounds box[3][MESH_RT_BINS];
    uint32_t count[3][MESH_RT_BINS] = {{0}};
    for (int a = 0; a < 3; a++)
        for (int i = 0; i < MESH_RT_BINS; i++)
            bounds_empty(&box[a][i]);
    for (uint32_t i = 0; i < n; i++) {
        for (int a = 0; a < 3; a++) {
            int k = bin_of(key(&p[i], a), kb->lo[a], scale[a]);
            bounds_grow(&box[a][k], p[i].lo, p[i].hi);
            count[a][k]++;
        }
    }
    double best = INFINITY;
    for (int a = 0; a < 3; a++) {
        if (scale[a] == 0.0f)
            continue;
        /* right[s]: bins s .. BINS-1 */
        struct bounds right[MESH_RT_BINS], acc;
        uint32_t right_n[MESH_RT_BINS], acc_n = 0;
        bounds_empty(&acc);
        for (int s = MESH_RT_BINS - 1; s > 0; s--) {
            bounds_grow(&acc, box[a][s].lo, box[a][s].hi);
            acc_n += count[a][s];
            right[s] = acc;
            right_n[s] = acc_n;
        }
        bounds_empty(&acc);
        acc_n = 0;
        for (int s = 1; s < MESH_RT_BINS; s++) {
            bounds_grow(&acc, box[a][s - 1].lo, box[a][s - 1].hi);
            acc_n += count[a][s - 1];
            if (acc_n == 0 || right_n[s] == 0)
                continue;
            double cost = half_area(&acc) * acc_n + half_area(&right[s]) * right_n[s];
            if (cost < best) {
                best = cost;
                *out = (struct split){a, s, kb->lo[a], scale[a], acc, right[s]};
            }
        }
    }
    return best < INFINITY;
}

static inline void swap_prim(struct prim *p, uint32_t *index, size_t i, size_t j)
{
    struct prim t = p[i];
    p[i] = p[j];
    p[j] = t;
    uint32_t u = index[i];
    index[i] = index[j];
    index[j] = u;
}

/* Moves the triangles that go left to the front and returns how many, gathering each
 * side's key bounds as it classifies each triangle (exactly once). */
static uint32_t partition(struct prim *p, uint32_t *index, uint32_t n, const struct split *s,
                          struct bounds *lk, struct bounds *rk)
{
    bounds_empty(lk);
    bounds_empty(rk);
    uint32_t i = 0, j = n;
    while (i < j) {
        if (bin_of(key(&p[i], s->axis), s->cmin, s->scale) < s->bin) {
            bounds_grow_key(lk, &p[i]);
            i++;
        } else {
            bounds_grow_key(rk, &p[i]);
            swap_prim(p, index, i, --j);
        }
    }
    return i;
}

/* Partially sorts p[0 .. n) by key along axis so that p[k] is in its sorted place
 * (quickselect with Hoare partitions around the middle element; signed indices as j may
 * pass 0). */
static void select_kth(struct prim *p, uint32_t *index, uint32_t n, uint32_t k, int axis)
{
    long long l = 0, r = (long long)n - 1;
    while (l < r) {
        float x = key(&p[(l + r) / 2], axis);
        long long i = l, j = r;
        do {
            while (key(&p[i], axis) < x)
                i++;
            while (x < key(&p[j], axis))
                j--;
            if (i <= j) {
                swap_prim(p, index, (size_t)i, (size_t)j);
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

/* Fills nodes[slot] with p[first .. first + n), whose box and key bounds are given, and
 * recurses (depth: slot's, the root's is 1). */
static void fill(struct build *b, size_t slot, uint32_t first, uint32_t n, int depth,
                 const struct bounds *box, const struct bounds *keys)
{
    struct prim *p = b->p + first;
    uint32_t *index = b->index + first;
    struct mesh_rt_node *nd = &b->nodes[slot];
    memcpy(nd->lo, box->lo, sizeof nd->lo);
    memcpy(nd->hi, box->hi, sizeof nd->hi);
    if (depth > b->depth)
        b->depth = depth;
    if (n <= MESH_RT_LEAF_MAX) {
        nd->left_or_first = first;
        nd->count = n;
        return;
    }
    struct split s;
    struct bounds lbox, rbox, lk, rk;
    uint32_t mid = 0;
    if (depth < MESH_RT_SAH_DEPTH && sah_split(p, n, keys, &s)) {
        mid = partition(p, index, n, &s, &lk, &rk);
        lbox = s.left;
        rbox = s.right;
    }
    if (mid == 0 || mid == n) { /* deep, or every key in one point: the median */
        int axis = 0;
        for (int k = 1; k < 3; k++)
            axis = keys->hi[k] - keys->lo[k] > keys->hi[axis] - keys->lo[axis] ? k : axis;
        mid = n / 2;
        select_kth(p, index, n, mid, axis);
        bounds_of(p, mid, &lbox, &lk);
        bounds_of(p + mid, n - mid, &rbox, &rk);
    }
    size_t left = b->count;
    b->count += 2;
    nd->left_or_first = (uint32_t)left;
    nd->count = 0;
    fill(b, left, first, mid, depth + 1, &lbox, &lk);
    fill(b, left + 1, first + mid, n - mid, depth + 1, &rbox, &rk);
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

/* The GLSL decode before its normalize. */
static vec3 oct_direction(uint32_t bits)
{
    double x = snorm16_to_double((int16_t)(bits & 0xffffu));
    double y = snorm16_to_double((int16_t)(bits >> 16));
    vec3 v = {x, y, 1.0 - fabs(x) - fabs(y)};
    if (v.z < 0.0) {
        double vx = v.x;
        v.x = (1.0 - fabs(v.y)) * sign_not_zero(vx);
        v.y = (1.0 - fabs(vx)) * sign_not_zero(v.y);
    }
    return v;
}

vec3 mesh_rt_oct_decode(uint32_t bits)
{
    return vec3_normalize(oct_direction(bits));
}

uint32_t mesh_rt_oct_encode(vec3 n)
{
    double l1 = fabs(n.x) + fabs(n.y) + fabs(n.z);
    if (!(l1 > 0.0))
        return MESH_RT_NO_NORMAL; /* a crease vertex, or one no triangle with area uses */
    double x = n.x / l1, y = n.y / l1;
    if (n.z < 0.0) {
        double px = x;
        x = (1.0 - fabs(y)) * sign_not_zero(px);
        y = (1.0 - fabs(px)) * sign_not_zero(y);
    }
    /* Of the four roundings of (x, y) to the snorm16 grid, the one that decodes nearest
     * to n: about half the error of rounding to nearest (Cigolle et al., "precise"). The
     * nearest maximises cos^2 = (v . n)^2 / |v|^2 (v . n > 0 for all four): no sqrt, as
     * this runs once per vertex (3M for a soup of 1M triangles). */
    double fx = floor(x * 32767.0), fy = floor(y * 32767.0);
    uint32_t best = 0;
    double best_cos2 = -1.0;
    for (int i = 0; i < 4; i++) {
        double qx = fx + (i & 1), qy = fy + (i >> 1);
        qx = qx > 32767.0 ? 32767.0 : (qx < -32767.0 ? -32767.0 : qx);
        qy = qy > 32767.0 ? 32767.0 : (qy < -32767.0 ? -32767.0 : qy);
        uint32_t bits = (uint32_t)(uint16_t)(int16_t)qx | (uint32_t)(uint16_t)(int16_t)qy << 16;
        vec3 v = oct_direction(bits);
        double c = vec3_dot(v, n), cos2 = c > 0.0 ? c * c / vec3_dot(v, v) : -1.0;
        if (cos2 > best_cos2) {
            best_cos2 = cos2;
            best = bits;
        }
    }
    return best;
}

/* Vertex normals by Max's weights (N. Max 1999, "Weights for Computing Vertex Normals from
 * Facet Normals", JGT 4(2)): at each corner the face normal e1 x e2 divided by
 * |e1|^2 |e2|^2, e1 and e2 the corner's two edges, summed and normalised. The weights are
 * exact for vertices sampled from a sphere, which is what a tessellated glass ball is: with
 * area weights a 327,680-triangle icosphere's rim rays left up to 0.14 degrees off the
 * exact sphere's. The sum follows the winding. */
static void vertex_normals(const struct mesh *m, double (*nrm)[3])
{
    memset(nrm, 0, m->vertex_count * sizeof *nrm);
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tri = m->triangles[t];
        for (int k = 0; k < 3; k++) {
            const double *a = m->vertices[tri[k]], *b = m->vertices[tri[(k + 1) % 3]],
                         *c = m->vertices[tri[(k + 2) % 3]];
            vec3 e1 = vec3_make(b[0] - a[0], b[1] - a[1], b[2] - a[2]);
            vec3 e2 = vec3_make(c[0] - a[0], c[1] - a[1], c[2] - a[2]);
            double w = vec3_dot(e1, e1) * vec3_dot(e2, e2);
            if (!(w > 0.0))
                continue; /* a degenerate corner adds nothing */
            vec3 f = vec3_scale(vec3_cross(e1, e2), 1.0 / w);
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
    /* Creases: a vertex shared by faces that turn by more than MESH_RT_CREASE_DEG from its
     * averaged normal (a cube's corner: 54.7 degrees) has no smooth normal; a triangle with
     * such a corner shades with its own flat normal. Otherwise a cube's interpolated
     * normals would make its faces refract like a blob. */
    double cos_crease = cos(MESH_RT_CREASE_DEG * M_PI / 180.0);
    for (size_t t = 0; t < m->triangle_count; t++) {
        const uint32_t *tri = m->triangles[t];
        const double *a = m->vertices[tri[0]], *b = m->vertices[tri[1]], *c = m->vertices[tri[2]];
        vec3 f = vec3_normalize(vec3_cross(vec3_make(b[0] - a[0], b[1] - a[1], b[2] - a[2]),
                                           vec3_make(c[0] - a[0], c[1] - a[1], c[2] - a[2])));
        if (!(vec3_length(f) > 0.5))
            continue;
        for (int k = 0; k < 3; k++) {
            double *n = nrm[tri[k]];
            if (n[0] * f.x + n[1] * f.y + n[2] * f.z < cos_crease)
                n[0] = n[1] = n[2] = 0.0; /* marked: MESH_RT_NO_NORMAL on the GPU */
        }
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
    struct build b = {.p = malloc(n * sizeof *b.p),
                      .index = malloc(n * sizeof *b.index),
                      .nodes = malloc((2 * n - 1) * sizeof *b.nodes)};
    if (rt != NULL) {
        rt->tris = malloc(n * sizeof *rt->tris);
        rt->verts = malloc(m->vertex_count * sizeof *rt->verts);
        rt->normals = malloc(m->vertex_count * sizeof *rt->normals);
    }
    if (rt == NULL || b.p == NULL || b.index == NULL || b.nodes == NULL || rt->tris == NULL ||
        rt->verts == NULL || rt->normals == NULL) {
        free(b.p);
        free(b.index);
        free(b.nodes);
        mesh_rt_destroy(rt);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "out of memory for the ray-tracing hierarchy of a mesh of %zu triangles", n);
    }
    struct bounds box, keys;
    bounds_empty(&box);
    bounds_empty(&keys);
    for (size_t t = 0; t < n; t++) {
        struct prim *p = &b.p[t];
        for (int k = 0; k < 3; k++) {
            double v0 = m->vertices[m->triangles[t][0]][k], v1 = m->vertices[m->triangles[t][1]][k],
                   v2 = m->vertices[m->triangles[t][2]][k];
            double lo = v0 < v1 ? v0 : v1, hi = v0 < v1 ? v1 : v0;
            p->lo[k] = round_down(v2 < lo ? v2 : lo);
            p->hi[k] = round_up(v2 > hi ? v2 : hi);
        }
        p->lo[3] = p->hi[3] = 0.0f;
        b.index[t] = (uint32_t)t;
        bounds_grow(&box, p->lo, p->hi);
        bounds_grow_key(&keys, p);
    }
    b.count = 1;
    fill(&b, 0, 0, (uint32_t)n, 1, &box, &keys);
    for (size_t i = 0; i < n; i++) {
        uint32_t t = b.index[i];
        memcpy(rt->tris[i].v, m->triangles[t], sizeof rt->tris[i].v);
        rt->tris[i].orig = t;
    }
    free(b.p);
    free(b.index);
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
