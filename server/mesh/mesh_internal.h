/*
 * mesh_internal.h - what the mesh module's files share: the growable arrays the parsers
 * fill, and the bounding volume hierarchy the queries walk. Not part of the module's
 * interface (include mesh.h instead).
 */
#ifndef REFRACT_MESH_INTERNAL_H
#define REFRACT_MESH_INTERNAL_H

#include "mesh.h"

/* Vertices and triangles as a parser reads them. mesh_builder_finish hands the arrays to
 * mesh_create; mesh_builder_fini frees what is left (either way, exactly once). */
struct mesh_builder {
    double (*v)[3];
    size_t nv, cap_v;
    uint32_t (*t)[3];
    size_t nt, cap_t;
    size_t max_triangles;
};

/* mesh_memo.c: made by mesh_create, freed by mesh_destroy. */
struct mesh_memo *mesh_memo_create(void);
void mesh_memo_destroy(struct mesh_memo *mm);

void mesh_builder_init(struct mesh_builder *b, const struct mesh_limits *limits);
void mesh_builder_fini(struct mesh_builder *b);
/* false: out of memory (the caller reports it with its position). */
bool mesh_builder_vertex(struct mesh_builder *b, double x, double y, double z);
/* false: out of memory. The caller checks the triangle limit first (mesh_builder_full). */
bool mesh_builder_triangle(struct mesh_builder *b, uint32_t i0, uint32_t i1, uint32_t i2);
bool mesh_builder_full(const struct mesh_builder *b);
/* LIMIT_EXCEEDED: "<where>: more than <max> triangles; ...--max-mesh-triangles". */
enum refract_code mesh_limit_error(const struct mesh_builder *b, const char *where, struct err *e);
/* Consumes the arrays into a new mesh (mesh_create's validation). */
enum refract_code mesh_builder_finish(struct mesh_builder *b, const struct mesh_limits *limits,
                                      struct mesh **out, struct err *e);

/* ---- the bounding volume hierarchy (mesh_bvh.c) ----
 *
 * INVARIANT: node 0 is the root. An inner node has count == 0 and children left, left + 1;
 * a leaf covers order[first .. first + count). Every node stores the box of its triangles
 * and, for the far-field winding number, their area vector, area-weighted centre, the
 * first moment of the area vector about that centre, and the radius of the ball about the
 * centre that holds all their vertices (Barill et al. 2018, sect. 3.2, terms of first and
 * second order). */
struct mesh_bvh_node {
    double lo[3], hi[3];
    double area_normal[3]; /* sum of (b - a) x (c - a) / 2: outward when wound CCW */
    double centre[3];
    double moment[3][3]; /* sum over triangles of area_vector_i (centroid - centre)_j */
    double radius;
    uint32_t first, count; /* leaf: the range of order[]; inner: count == 0 */
    uint32_t left;         /* inner: index of the first child; the second is left + 1 */
};

struct mesh_bvh {
    struct mesh_bvh_node *nodes;
    size_t node_count;
    uint32_t *order; /* triangle indices, grouped by leaf */
};

#define MESH_BVH_LEAF_SIZE 8

/* mesh_rt_build.c: rewrites the GPU vertex records (float positions, packed normals) from
 * rt->positions and rt->normals; mesh_check_solid calls it after flipping a mesh. */
struct mesh_rt;
void mesh_rt_pack_vertices(struct mesh_rt *rt);
#define MESH_BVH_MAX_DEPTH 64

/* Builds m->bvh (median splits along the longest axis of the centroids). */
enum refract_code mesh_bvh_build(struct mesh *m, struct err *e);
void mesh_bvh_destroy(struct mesh_bvh *b);

#endif
