/*
 * mesh_rt.h - ray tracing triangle meshes: a SAH bounding volume hierarchy built on the
 * CPU and flattened into GPU-ready arrays, watertight ray/triangle intersection in double
 * (here) and in float (shaders/geom/mesh.glsl, the same name and the same arrays), a
 * solidity check for meshes that bound a medium, and a generated icosphere.
 *
 * Every mesh has one (struct mesh.rt, built by mesh_create), so any mesh can be traced.
 * docs/tracing.md "Triangle meshes" explains the choices; the short form:
 *
 * - Build (mesh_rt_build.c): top down, binned SAH (MESH_RT_BINS bins on each axis of the
 *   centroids' box), a leaf whenever a node holds MESH_RT_LEAF_MAX triangles or fewer, so
 *   every leaf holds 1..MESH_RT_LEAF_MAX. Below depth MESH_RT_SAH_DEPTH splits are at the
 *   median, which halves a node, so no leaf is deeper than MESH_RT_MAX_DEPTH (bindings.h)
 *   whatever the geometry: the GLSL traversal's fixed stack can never overflow.
 * - Layout (the GPU arrays, std430, 16-byte records; `struct mesh_rt_gpu` hands them out):
 *     node     32 B  vec4(lo.xyz, uint bits: inner: left child; leaf: first triangle)
 *                    vec4(hi.xyz, uint bits: 0 = inner (children left, left + 1);
 *                                            else the leaf's triangle count)
 *     triangle 16 B  uvec4(v0, v1, v2, original triangle index), in leaf order
 *     vertex   16 B  vec4(position.xyz, uint bits: the unit shading normal, octahedral,
 *                    packSnorm2x16: x in the low 16 bits)
 *   Node 0 is the root; child, triangle and vertex indices are relative to the mesh's own
 *   first node, triangle and vertex, so several meshes can be concatenated. Boxes are
 *   rounded outward to float, so they contain the double vertices (the CPU traversal
 *   walks these same float boxes) and their float roundings (the GPU's).
 * - Intersection (mesh_rt_trace.c): Woop, Benthin and Wald 2013, "Watertight Ray/Triangle
 *   Intersection" (JCGT 2(1)): the ray's space is sheared so that the ray is +z, and the
 *   three edge functions of a triangle are 2D cross products of its sheared vertices. An
 *   edge shared by two triangles gets exactly opposite values in both (the same products,
 *   operands swapped), and a hit needs all three of one sign with zero counting for
 *   either, so a ray through an edge or a vertex hits at least one of the triangles there:
 *   no ray slips through a closed mesh. Exact zeros are recomputed in long double
 *   (paper sect. 3: "fall back to higher precision"), which decides most of them.
 *
 * Thread: a built mesh_rt is immutable (mesh_check_solid aside, before sharing); any
 * thread may trace it. This module never touches the GPU.
 */
#ifndef REFRACT_MESH_RT_H
#define REFRACT_MESH_RT_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"
#include "../core/vec3.h"
#include "bindings.h" /* MESH_RT_MAX_DEPTH, shared with the GLSL traversal's stack */
#include "mesh.h"

#define MESH_RT_BINS 16      /* SAH bins per axis */
#define MESH_RT_LEAF_MAX 4   /* triangles in a leaf: 1..4 */
#define MESH_RT_SAH_DEPTH 32 /* deeper nodes split at the median (see the depth bound) */
#define MESH_RT_CREASE_DEG 30.0 /* a vertex whose faces turn further from its averaged normal
                                   has none: its triangles shade flat (mesh_rt_build.c) */

/* GPU records; the C layout is the std430 one (static asserts in mesh_rt_build.c). */
struct mesh_rt_node {
    float lo[3];
    uint32_t left_or_first; /* inner: first child (second is + 1); leaf: first triangle */
    float hi[3];
    uint32_t count; /* 0: inner; else triangles in the leaf */
};
struct mesh_rt_tri {
    uint32_t v[3]; /* vertex indices (relative to the mesh's first vertex) */
    uint32_t orig; /* the triangle's index in struct mesh.triangles */
};
struct mesh_rt_vertex {
    float p[3];     /* position, mesh space, rounded to float */
    uint32_t n_oct; /* shading normal: packSnorm2x16 of its octahedral coordinates */
};

struct mesh_rt {
    struct mesh_rt_node *nodes; /* owned; depth first, node 0 the root */
    size_t node_count;
    struct mesh_rt_tri *tris; /* owned; triangle_count of them, grouped by leaf */
    size_t tri_count;
    struct mesh_rt_vertex *verts; /* owned; one per mesh vertex */
    size_t vertex_count;
    double (*normals)[3];         /* owned; unit shading normal per vertex (0 if unused) */
    const double (*positions)[3]; /* borrowed: struct mesh.vertices */
    int depth;                    /* nodes on the longest root-to-leaf path */
};

struct mesh_rt_hit {
    double t;      /* o + t d: the hit point (t in units of |d|) */
    vec3 n_geom;   /* unit; (v1 - v0) x (v2 - v0): outward for a counter-clockwise mesh */
    vec3 n_shade;  /* unit; the vertex normals interpolated with (1 - b1 - b2, b1, b2) */
    uint32_t tri;  /* the triangle's index in struct mesh.triangles */
    double b1, b2; /* barycentric weights of the triangle's vertices 1 and 2 */
};

/* Builds the hierarchy, the GPU arrays and the vertex normals of a validated mesh (its
 * vertices and triangles are borrowed for as long as the mesh_rt lives). Fails only on
 * OUT_OF_MEMORY. */
enum refract_code mesh_rt_build(const struct mesh *m, struct mesh_rt **out, struct err *e);
void mesh_rt_destroy(struct mesh_rt *rt);

/* The nearest hit of the ray o + t d with t in (tmin, tmax), ignoring the triangle whose
 * original index is skip_tri (-1: none; pass the triangle a ray leaves, so that it cannot
 * hit it again at t ~ 0). d need not be unit but must be finite and nonzero. Both faces
 * count. Returns false (hit untouched) when nothing is hit. Watertight: see above. */
bool mesh_rt_intersect(const struct mesh_rt *rt, vec3 o, vec3 d, double tmin, double tmax,
                       int64_t skip_tri, struct mesh_rt_hit *hit);

/* What an uploader needs: the three arrays (each a run of 16-byte records), their byte
 * sizes and counts. To concatenate meshes, give each its first node, triangle and vertex
 * in the shared buffers as mesh.xyz of the GLSL mesh_rt_intersect. */
struct mesh_rt_gpu {
    const struct mesh_rt_node *nodes;
    size_t node_count, node_bytes;
    const struct mesh_rt_tri *tris;
    size_t tri_count, tri_bytes;
    const struct mesh_rt_vertex *verts;
    size_t vertex_count, vertex_bytes;
    size_t total_bytes; /* node_bytes + tri_bytes + vertex_bytes */
};
struct mesh_rt_gpu mesh_rt_gpu_arrays(const struct mesh_rt *rt);

/* Octahedral unit-vector coding (Cigolle et al. 2014), as the GLSL decodes it: the
 * closest of the four snorm16 roundings. mesh_rt_oct_decode is the GLSL's decode in
 * double (tests). */
uint32_t mesh_rt_oct_encode(vec3 n);
vec3 mesh_rt_oct_decode(uint32_t bits);

/* ---- meshes that bound a medium (mesh_solid.c) ----
 *
 * Refuses (REFRACT_E_INVALID_MESH, naming the first offending triangle or edge and what to
 * do) a mesh with a degenerate triangle (zero area: a repeated vertex or three collinear
 * ones), an edge used by one triangle only (open), by more than two (non-manifold), or
 * twice in the same direction (inconsistent winding). A closed, consistently wound mesh
 * whose signed volume is negative (inside out) has its winding flipped in place (the
 * triangles, m->rt and m->bvh follow) and *flipped set; otherwise *flipped is false.
 * Not thread-safe: call it before the mesh is shared. */
enum refract_code mesh_check_solid(struct mesh *m, bool *flipped, struct err *e);
/* The same checks without changing the mesh: OK (with *inside_out for a negative signed
 * volume) or the refusal mesh_check_solid would give. Any thread. */
enum refract_code mesh_solid_status(const struct mesh *m, bool *inside_out, struct err *e);

/* Signed volume enclosed by the triangles (positive when wound counter-clockwise seen
 * from outside); meaningful for closed meshes. */
double mesh_signed_volume(const struct mesh *m);

/* ---- generated meshes (mesh_icosphere.c) ----
 *
 * An icosahedron subdivided `subdivisions` times (0..9), every vertex projected onto the
 * sphere of `radius` (> 0, finite) about the origin, wound counter-clockwise seen from
 * outside: 20 * 4^s triangles, 10 * 4^s + 2 vertices (s = 7: 327,680 triangles).
 * INVALID_FIELD for s or radius out of range; OUT_OF_MEMORY. */
enum refract_code mesh_make_icosphere(int subdivisions, double radius, struct mesh **out,
                                      struct err *e);

#endif
