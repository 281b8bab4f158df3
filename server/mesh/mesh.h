/*
 * mesh.h - triangle meshes uploaded by users (OBJ and PLY), their generalized winding
 * number, and their voxelization into an inside fraction per voxel.
 *
 * A mesh is an indexed triangle list in its own "mesh space", validated completely when
 * it is made (finite coordinates, indices in range, at least one triangle, at most
 * mesh_limits.max_triangles), with a bounding volume hierarchy built over it at once, so
 * that every mesh that exists can be queried, and a second one for ray tracing (mesh_rt.h),
 * so that every mesh can be traced. Meshes need not be closed, manifold or
 * consistently wound: inside/outside comes from the generalized winding number
 * (Jacobson et al. 2013), not from ray parity.
 *
 * Ownership: mesh_parse and mesh_create return a new mesh; the caller destroys it with
 * mesh_destroy(). A mesh is immutable after creation (except mesh_check_solid, mesh_rt.h,
 * which may flip its winding before it is shared), so any thread may query it.
 * This module never touches the GPU, HTTP or files (it parses bytes it is given).
 */
#ifndef REFRACT_MESH_H
#define REFRACT_MESH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"
#include "../core/vec3.h"
#include "../core/xform.h"

enum mesh_format {
    MESH_FORMAT_UNKNOWN = 0,
    MESH_FORMAT_OBJ = 1, /* Wavefront OBJ: v and f statements */
    MESH_FORMAT_PLY = 2, /* Stanford PLY: ascii, binary_little_endian, binary_big_endian */
};

struct mesh_limits {
    size_t max_triangles; /* after fan triangulation of polygons; 0 = 2,000,000 */
};

struct mesh_bvh;  /* mesh_bvh.c */
struct mesh_memo; /* mesh_memo.c */
struct mesh_rt;   /* mesh_rt.h: ray tracing */

struct mesh {
    double (*vertices)[3]; /* mesh space; owned */
    size_t vertex_count;
    uint32_t (*triangles)[3]; /* vertex indices, counter-clockwise seen from outside when
                                 the file is consistently wound (not relied on); owned */
    size_t triangle_count;
    vec3 lo, hi;            /* bounds of the vertices that triangles use */
    bool closed;            /* every edge a->b is matched by as many edges b->a: the mesh
                               bounds a solid, and w is an integer off the surface */
    struct mesh_bvh *bvh;   /* owned */
    struct mesh_memo *memo; /* owned: the last voxelization (mesh_voxelize_memo); NULL when
                               it could not be allocated (then nothing is remembered) */
    struct mesh_rt *rt;     /* owned: the ray-tracing hierarchy and GPU arrays (mesh_rt.h) */
    bool solid;             /* it can bound a medium (mesh_solid_status at creation): closed,
                               manifold, consistently wound, no degenerate triangle */
    char solid_error[512];  /* when not solid: why, naming the first offending element */
};

#define MESH_DEFAULT_MAX_TRIANGLES 2000000

/* "obj", "ply" or "unknown". */
const char *mesh_format_name(enum mesh_format f);
/* MESH_FORMAT_PLY when bytes start with "ply" and a line end; MESH_FORMAT_OBJ when the
 * first non-blank, non-comment line starts with an OBJ statement (v, vt, vn, f, o, g, ...);
 * otherwise MESH_FORMAT_UNKNOWN. Reads at most the first 4 KiB. */
enum mesh_format mesh_sniff(const void *bytes, size_t len);

/* Parses an OBJ or PLY file (len bytes, need not be NUL-terminated). On success *out is a
 * new mesh. On failure returns REFRACT_E_INVALID_MESH (with the line or element number,
 * what was wrong and what to do), REFRACT_E_LIMIT_EXCEEDED (too many triangles; names the
 * limit and its flag, --max-mesh-triangles) or REFRACT_E_OUT_OF_MEMORY, and *out is NULL.
 * Borrows bytes until return. */
enum refract_code mesh_parse(const void *bytes, size_t len, enum mesh_format format,
                             const struct mesh_limits *limits, struct mesh **out, struct err *e);
enum refract_code mesh_parse_obj(const char *text, size_t len, const struct mesh_limits *limits,
                                 struct mesh **out, struct err *e);
enum refract_code mesh_parse_ply(const void *bytes, size_t len, const struct mesh_limits *limits,
                                 struct mesh **out, struct err *e);

/* Makes a mesh from arrays (validated like a parsed file: finite coordinates, indices <
 * vertex_count, 1..max_triangles triangles). Consumes `vertices` and `triangles` (freed on
 * failure too). */
enum refract_code mesh_create(double (*vertices)[3], size_t vertex_count, uint32_t (*triangles)[3],
                              size_t triangle_count, const struct mesh_limits *limits,
                              struct mesh **out, struct err *e);
void mesh_destroy(struct mesh *m);

/* ---- generalized winding number (mesh_winding.c) ----
 *
 * w(p) = sum over triangles of Omega_t(p) / (4 pi), Omega_t the signed solid angle of
 * triangle t seen from p (van Oosterom and Strackee 1983; Jacobson et al. 2013 eq. 2).
 * For a closed, consistently outward-wound mesh w = 1 inside and 0 outside; holes and
 * flipped triangles change w smoothly and locally, which is why it classifies broken
 * meshes well. All points in mesh space. */

/* The exact sum over every triangle: O(triangles); the reference for the tests. */
double mesh_winding_number_exact(const struct mesh *m, vec3 p);
/* The hierarchical approximation of Barill et al. 2018 ("fast winding numbers"): a BVH
 * node whose centre is more than MESH_WINDING_BETA times its radius away from p
 * contributes as a dipole (its area-weighted normal at its area-weighted centre); nearer
 * nodes are opened, leaves summed exactly. |error| < 0.05 on the test meshes (the
 * trade-off of beta is measured in mesh_winding.c). */
double mesh_winding_number(const struct mesh *m, vec3 p);
#define MESH_WINDING_BETA 2.5

/* Unsigned Euclidean distance from p to the nearest triangle (mesh space). */
double mesh_distance(const struct mesh *m, vec3 p);

/* ---- voxelization (mesh_voxelize.c) ---- */

struct mesh_voxelize_desc {
    int resolution[3];             /* voxels along x, y, z of the target grid */
    vec3 bounds_min;               /* grid bounds in object space (the scene object's) */
    vec3 voxel_size;               /* object units per voxel along each axis */
    struct xform object_from_mesh; /* p_object = translate + scale * R * p_mesh */
    int threads;                   /* 0 = the machine's online CPUs (at most 64) */
};

/* Writes the inside fraction of every voxel (x fastest, then y, then z) into coverage:
 * clamp(0.5 - sd / h_min, 0, 1) with h_min the smallest voxel edge and sd the signed
 * distance (object units) from the voxel centre to the mesh, negative where |w| >= 1/2.
 * That is the same one-voxel anti-aliased edge the procedural shapes get
 * (scene_field.c), so a mesh layer and a shape layer blend alike. Orientation-agnostic:
 * |w| is used, so a mesh wound inside-out is still solid. Borrows m and d until return;
 * runs d->threads pthreads. Fails only on OUT_OF_MEMORY or INTERNAL (thread creation). */
enum refract_code mesh_voxelize(const struct mesh *m, const struct mesh_voxelize_desc *d,
                                float *coverage, struct err *e);

/* mesh_voxelize, remembering the result: a second call with the same grid and transform
 * (d->threads aside) copies it instead of computing it again (mesh_memo.c says why).
 * Grids of more than MESH_MEMO_MAX_VOXELS are not kept. Any thread. */
#define MESH_MEMO_MAX_VOXELS ((size_t)1 << 24) /* 256^3: 64 MiB of coverage */
enum refract_code mesh_voxelize_memo(const struct mesh *m, const struct mesh_voxelize_desc *d,
                                     float *coverage, struct err *e);
/* How often the memo answered and how often it computed (tests, logs). */
void mesh_memo_counts(const struct mesh *m, long long *hits, long long *computed);

#endif
