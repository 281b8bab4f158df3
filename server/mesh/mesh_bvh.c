/*
 * mesh_bvh.c - the bounding volume hierarchy over a mesh's triangles, with the data the
 * far-field winding number needs in every node (mesh_internal.h states the invariant).
 *
 * Build: top down, splitting each node's triangles at the median of their centroids
 * along the longest axis of the centroids' box (quickselect, O(n) per level), until a
 * node holds MESH_BVH_LEAF_SIZE triangles or fewer. Median splits keep the tree balanced,
 * so its depth is about log2(n / 8) + 1 (19 for 2M triangles), far below
 * MESH_BVH_MAX_DEPTH, which bounds the queries' stacks. Nodes are appended in
 * depth-first order; the two children of a node are adjacent.
 *
 * Node data (Barill et al. 2018 sect. 3.2): the area vector sum of (b - a) x (c - a) / 2,
 * the area-weighted mean of the triangle centroids (the plain mean when the area is 0),
 * the first moment sum of area_vector (x) (centroid - centre) (exact for flat triangles:
 * the integral of a linear function over a triangle is its area times the value at the
 * centroid), and the radius of the ball about the centre that holds every vertex.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"

struct builder {
    const struct mesh *m;
    double (*centroid)[3];
    uint32_t *order;
    struct mesh_bvh_node *nodes;
    size_t count, cap;
};

static const double *vtx(const struct mesh *m, uint32_t t, int c)
{
    return m->vertices[m->triangles[t][c]];
}

/* Fills a node's box, area vector, centre and radius from order[first .. first + n). */
static void node_data(const struct builder *b, struct mesh_bvh_node *nd)
{
    double area_sum = 0.0, wc[3] = {0, 0, 0}, mean[3] = {0, 0, 0};
    for (int a = 0; a < 3; a++) {
        nd->lo[a] = INFINITY;
        nd->hi[a] = -INFINITY;
        nd->area_normal[a] = 0.0;
    }
    for (uint32_t i = nd->first; i < nd->first + nd->count; i++) {
        uint32_t t = b->order[i];
        const double *p0 = vtx(b->m, t, 0), *p1 = vtx(b->m, t, 1), *p2 = vtx(b->m, t, 2);
        vec3 e1 = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]},
             e2 = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
        vec3 n = vec3_scale(vec3_cross(e1, e2), 0.5);
        double area = vec3_length(n);
        nd->area_normal[0] += n.x;
        nd->area_normal[1] += n.y;
        nd->area_normal[2] += n.z;
        area_sum += area;
        for (int k = 0; k < 3; k++) {
            wc[k] += area * b->centroid[t][k];
            mean[k] += b->centroid[t][k];
        }
        for (int c = 0; c < 3; c++) {
            const double *p = vtx(b->m, t, c);
            for (int k = 0; k < 3; k++) {
                nd->lo[k] = fmin(nd->lo[k], p[k]);
                nd->hi[k] = fmax(nd->hi[k], p[k]);
            }
        }
    }
    for (int k = 0; k < 3; k++)
        nd->centre[k] = area_sum > 0.0 ? wc[k] / area_sum : mean[k] / nd->count;
    double r2 = 0.0;
    memset(nd->moment, 0, sizeof nd->moment);
    for (uint32_t i = nd->first; i < nd->first + nd->count; i++) {
        uint32_t t = b->order[i];
        const double *p0 = vtx(b->m, t, 0), *p1 = vtx(b->m, t, 1), *p2 = vtx(b->m, t, 2);
        vec3 e1 = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]},
             e2 = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
        vec3 n = vec3_scale(vec3_cross(e1, e2), 0.5);
        const double an[3] = {n.x, n.y, n.z};
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                nd->moment[r][c] += an[r] * (b->centroid[t][c] - nd->centre[c]);
    }
    for (uint32_t i = nd->first; i < nd->first + nd->count; i++) {
        for (int c = 0; c < 3; c++) {
            const double *p = vtx(b->m, b->order[i], c);
            double dx = p[0] - nd->centre[0], dy = p[1] - nd->centre[1], dz = p[2] - nd->centre[2];
            r2 = fmax(r2, dx * dx + dy * dy + dz * dz);
        }
    }
    nd->radius = sqrt(r2);
}

/* Partially sorts order[lo .. hi) so that order[k] has the k-th smallest centroid along
 * axis, none larger before it and none smaller after (Wirth's quickselect; signed indices
 * because j may step one below lo). */
static void select_median(const struct builder *b, uint32_t lo, uint32_t hi, uint32_t k, int axis)
{
    uint32_t *o = b->order;
    long long l = lo, r = (long long)hi - 1;
    while (l < r) {
        double x = b->centroid[o[k]][axis];
        long long i = l, j = r;
        do {
            while (b->centroid[o[i]][axis] < x)
                i++;
            while (x < b->centroid[o[j]][axis])
                j--;
            if (i <= j) {
                uint32_t t = o[i];
                o[i] = o[j];
                o[j] = t;
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

static bool push_node(struct builder *b, uint32_t first, uint32_t count, size_t *index)
{
    if (b->count == b->cap) {
        size_t cap = b->cap ? b->cap * 2 : 64;
        struct mesh_bvh_node *n = realloc(b->nodes, cap * sizeof *n);
        if (n == NULL)
            return false;
        b->nodes = n;
        b->cap = cap;
    }
    struct mesh_bvh_node *nd = &b->nodes[b->count];
    memset(nd, 0, sizeof *nd);
    nd->first = first;
    nd->count = count;
    node_data(b, nd);
    *index = b->count++;
    return true;
}

/* Splits node `index` (holding its range in first/count) recursively. */
static bool split(struct builder *b, size_t index, int depth)
{
    struct mesh_bvh_node nd = b->nodes[index];
    if (nd.count <= MESH_BVH_LEAF_SIZE || depth >= MESH_BVH_MAX_DEPTH - 2)
        return true;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (uint32_t i = nd.first; i < nd.first + nd.count; i++) {
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(lo[k], b->centroid[b->order[i]][k]);
            hi[k] = fmax(hi[k], b->centroid[b->order[i]][k]);
        }
    }
    int axis = 0;
    for (int k = 1; k < 3; k++)
        axis = hi[k] - lo[k] > hi[axis] - lo[axis] ? k : axis;
    uint32_t half = nd.count / 2;
    select_median(b, nd.first, nd.first + nd.count, nd.first + half, axis);
    size_t left, right;
    if (!push_node(b, nd.first, half, &left) ||
        !push_node(b, nd.first + half, nd.count - half, &right))
        return false;
    b->nodes[index].count = 0;
    b->nodes[index].left = (uint32_t)left;
    return split(b, left, depth + 1) && split(b, right, depth + 1);
}

enum refract_code mesh_bvh_build(struct mesh *m, struct err *e)
{
    struct builder b = {.m = m};
    struct mesh_bvh *bvh = calloc(1, sizeof *bvh);
    b.centroid = malloc(m->triangle_count * sizeof *b.centroid);
    b.order = malloc(m->triangle_count * sizeof *b.order);
    bool ok = bvh != NULL && b.centroid != NULL && b.order != NULL;
    for (size_t t = 0; ok && t < m->triangle_count; t++) {
        b.order[t] = (uint32_t)t;
        for (int k = 0; k < 3; k++)
            b.centroid[t][k] = (vtx(m, (uint32_t)t, 0)[k] + vtx(m, (uint32_t)t, 1)[k] +
                                vtx(m, (uint32_t)t, 2)[k]) /
                               3.0;
    }
    size_t root;
    ok = ok && push_node(&b, 0, (uint32_t)m->triangle_count, &root) && split(&b, root, 0);
    free(b.centroid);
    if (!ok) {
        free(b.order);
        free(b.nodes);
        free(bvh);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "out of memory building the hierarchy of a mesh of %zu triangles",
                       m->triangle_count);
    }
    bvh->nodes = b.nodes;
    bvh->node_count = b.count;
    bvh->order = b.order;
    m->bvh = bvh;
    return REFRACT_E_OK;
}

void mesh_bvh_destroy(struct mesh_bvh *b)
{
    if (b == NULL)
        return;
    free(b->nodes);
    free(b->order);
    free(b);
}
