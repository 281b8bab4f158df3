/*
 * geom.h - exact surfaces, one file per kind (docs/tracing.md "Surfaces"): sphere.c,
 * box.c, rounded_box.c, cylinder.c, plane.c, lathe.c here, triangle meshes in server/mesh/mesh_rt*.c.
 * Each kind has <kind>_intersect (nearest hit of a ray), <kind>_inside (is a point in
 * the solid the surface bounds) and <kind>_bounds (box of the solid). The GLSL twins in
 * shaders/geom/<kind>.glsl have the same names and argument order (in float).
 *
 * Rays are o + t d with d a unit vector, all in the surface's object space; a hit is the
 * nearest t in (tmin, tmax). Normals are unit and point out of the solid, so dot(d, N) < 0
 * means the ray enters. Pure functions in double precision; any thread.
 */
#ifndef REFRACT_GEOM_H
#define REFRACT_GEOM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../vec3.h"
#include "../xform.h"

/* The kinds are GEOM_SPHERE, GEOM_BOX, GEOM_CYLINDER, GEOM_PLANE, GEOM_LATHE, GEOM_MESH and
 * GEOM_ROUNDED_BOX
 * of bindings.h, the numbers the GPU's surface_params.kind.x holds. */
#include "bindings.h"

struct geom_hit {
    double t;
    vec3 normal;  /* geometric, unit, out of the solid */
    vec3 shading; /* the normal Snell and Fresnel use: = normal except on smooth meshes */
    int64_t prim; /* mesh: triangle index; lathe: profile edge; box: face; else 0 */
};

/* Keeps the hit at t when it is past tmin and nearer than *best (the kinds with several
 * candidate roots use it). */
static inline void geom_hit_consider(double t, double tmin, double *best, vec3 nrm, int64_t prim,
                                     struct geom_hit *h)
{
    if (t > tmin && t < *best) {
        *best = t;
        h->t = t;
        h->normal = nrm;
        h->shading = nrm;
        h->prim = prim;
    }
}

/* Sphere |p - c| = r. */
bool sphere_intersect(vec3 c, double r, vec3 o, vec3 d, double tmin, double tmax,
                      struct geom_hit *h);
bool sphere_inside(vec3 c, double r, vec3 p);
void sphere_bounds(vec3 c, double r, vec3 *lo, vec3 *hi);

/* Axis-aligned box of centre c and full edge lengths size. */
bool box_intersect(vec3 c, vec3 size, vec3 o, vec3 d, double tmin, double tmax, struct geom_hit *h);
bool box_inside(vec3 c, vec3 size, vec3 p);
void box_bounds(vec3 c, vec3 size, vec3 *lo, vec3 *hi);

/* Box of full sizes size about c with edges and corners rounded to radius r
 * (0 <= r <= min(size) / 2; 0 is the plain box). Its box is box_bounds'. */
bool rounded_box_intersect(vec3 c, vec3 size, double r, vec3 o, vec3 d, double tmin, double tmax,
                           struct geom_hit *h);
bool rounded_box_inside(vec3 c, vec3 size, double r, vec3 p);

/* Closed cylinder: radius r about the axis (0 x, 1 y, 2 z) through c, full length height. */
bool cylinder_intersect(vec3 c, double r, double height, int axis, vec3 o, vec3 d, double tmin,
                        double tmax, struct geom_hit *h);
bool cylinder_inside(vec3 c, double r, double height, int axis, vec3 p);
void cylinder_bounds(vec3 c, double r, double height, int axis, vec3 *lo, vec3 *hi);

/* Infinite plane through c with unit normal n; the solid is the half-space behind it
 * (dot(p - c, n) < 0), e.g. the body of water under its surface. */
bool plane_intersect(vec3 c, vec3 n, vec3 o, vec3 d, double tmin, double tmax, struct geom_hit *h);
bool plane_inside(vec3 c, vec3 n, vec3 p);
/* Infinite except along an axis-aligned normal (the solid is then a half-space box). */
void plane_bounds(vec3 c, vec3 n, vec3 *lo, vec3 *hi);

/* Solid of revolution of the closed, simple polygon pts[0..count) of (r, h) points
 * (r >= 0) about the axis (0 x, 1 y, 2 z) through base, h measured along the axis from
 * base. Each polygon edge sweeps a cone frustum, a cylinder or an annulus. */
bool lathe_intersect(vec3 base, int axis, const double (*pts)[2], size_t count, vec3 o, vec3 d,
                     double tmin, double tmax, struct geom_hit *h);
bool lathe_inside(vec3 base, int axis, const double (*pts)[2], size_t count, vec3 p);
void lathe_bounds(vec3 base, int axis, const double (*pts)[2], size_t count, vec3 *lo, vec3 *hi);
/* +1 for a counter-clockwise profile in the (r, h) plane, -1 for clockwise (from its signed
 * area): which side of each edge is out. */
double lathe_orientation(const double (*pts)[2], size_t count);
/* The profile's largest r and its lowest and highest h: the bounding cylinder. */
void lathe_extent(const double (*pts)[2], size_t count, double *r_max, double *h_lo, double *h_hi);

/* ---- a placed surface of any kind (surface.c): what the marches iterate over ---- */

/* Triangle meshes live in server/mesh (which links this module), so a surface reaches
 * its mesh through these two functions (mesh space = the surface's object space). */
struct geom_mesh_ops {
    bool (*intersect)(const void *mesh, vec3 o, vec3 d, double tmin, double tmax, int64_t skip_prim,
                      struct geom_hit *h);
    bool (*inside)(const void *mesh, vec3 p);
};

struct geom_surface {
    int kind;                   /* GEOM_* */
    struct xform xf;            /* world_from_object (similarity) */
    vec3 center;                /* sphere, box, cylinder; plane: a point on it */
    double radius;              /* sphere, cylinder; rounded box: corner radius */
    vec3 size;                  /* box, rounded box: full edge lengths */
    double height;              /* cylinder: full length */
    int axis;                   /* cylinder, lathe */
    vec3 normal;                /* plane: unit */
    vec3 base;                  /* lathe */
    const double (*profile)[2]; /* lathe: borrowed */
    size_t profile_count;
    const void *mesh;      /* mesh: borrowed, through mesh_ops */
    vec3 mesh_lo, mesh_hi; /* mesh: its box in object (mesh) space */
    const struct geom_mesh_ops *mesh_ops;
};

/* The nearest hit of the world ray o + t d (unit d) with t in (tmin, tmax), world units;
 * skip_prim: a mesh triangle the ray just left (-1: none). h->t is world distance, the
 * normals are world directions. */
bool geom_surface_intersect(const struct geom_surface *g, vec3 o, vec3 d, double tmin, double tmax,
                            int64_t skip_prim, struct geom_hit *h);
/* Is the world point p inside the solid. */
bool geom_surface_inside(const struct geom_surface *g, vec3 p);
/* World box of the solid (infinite components for planes). */
bool geom_surface_bounds(const struct geom_surface *g, vec3 *lo, vec3 *hi);
/* The world box of the object-space box lo..hi under xf (its 8 corners carried over). */
void geom_world_box(const struct xform *xf, vec3 lo, vec3 hi, vec3 *wlo, vec3 *whi);
/* A length that sets the surface's scale (world units): the self-intersection offset and
 * the convergence tolerance are relative to it. */
double geom_surface_size(const struct geom_surface *g);

/* ---- the GPU record (surface_pack.c) ---- */

/* Self-intersection offset of the surface a ray just left, relative to its size, for the
 * float marches: float hit points are off by about 1e-7 of their coordinates. */
#define GEOM_PACK_EPS 1e-5

struct surface_params; /* shaders/shared_types.h */

/* Packs g (its kind's numbers, transform, lathe orientation and bounding cylinder) and its
 * medium (n, sigma_a, L_e, sigma_s and the Henyey-Greenstein g) into sp; first_point: a
 * lathe's first profile point in the shared points buffer. A mesh's buffer offsets
 * (sp->mesh) are the caller's. */
void geom_surface_pack(const struct geom_surface *g, double ior, const double attenuation[3],
                       const double emission[3], const double scattering[3], double anisotropy,
                       int first_point, struct surface_params *sp);

#endif
