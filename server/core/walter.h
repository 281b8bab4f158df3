/*
 * walter.h - exact single scattering through a refracting boundary (walter2009; issue 15
 * item 2, docs/walter.md): every path light -> P -> V that crosses the boundary of a
 * medium once at P and obeys Snell's law there, with the light it carries to V.
 *
 * The problem (walter2009 sect. 3.1): V lies inside a medium of index n_in, the light L
 * outside in n_out, eta = n_in / n_out. With omega_V = (V - P) / |V - P| (the light's
 * direction of travel inside, eq. 1) and omega_L = (L - P) / |L - P| (eq. 2), P is a
 * solution when eta omega_V + omega_L is parallel to the shading normal N_s (the
 * half-vector condition, eq. 3-4: its component along the surface vanishes, which is
 * Snell's law) and L, V lie on the outer and inner side of the tangent plane (eq. 4).
 * The condition holds for any eta (an air bubble in water too), not only eta > 1.
 *
 * What a path carries (walter2009 sect. 4): the irradiance at V from a point light of
 * radiant intensity I along it is
 *     E = I T exp(-sigma_t d_V) eta^2 / D                                 (eq. 17)
 * with T = 1 - R the unpolarised Fresnel transmittance at P (frisvad2010), d_V = |V - P|,
 * and D = dA_L / domega_V the spread of the path (eq. 19-26: the area around L, normal to
 * omega_L, that a unit solid angle of directions at V maps to). The factor eta^2 is the
 * n^2 law of radiance (etendue n^2 dA domega is conserved): the paper's formula leaves it
 * out along with the 1 / eta^2 of the view ray leaving the medium, which our view march
 * applies (docs/tracing.md "Scattering inside surfaces"), so E here is the true irradiance
 * at V. A directional light (L at infinity, irradiance E0 normal to its direction) gives
 * E = E0 T exp(-sigma_t d_V) eta^2 / D_inf, D_inf = |domega_L/domega_V| (the limit of
 * D / d_L^2).
 *
 * Two boundaries: an exact sphere (walter_sphere_paths: the paths lie in the plane of the
 * centre, L and V, a 1D search; the GLSL twin shaders/walter.glsl, same names) and triangle
 * meshes with interpolated shading normals (walter_mesh.c: 2D Newton on each triangle with
 * the paper's Krawczyk interval test, which guarantees every solution is found).
 *
 * Conventions: double precision; normals point out of the medium; directions unit.
 * Thread: any; no globals.
 */
#ifndef REFRACT_WALTER_H
#define REFRACT_WALTER_H

#include <stdbool.h>
#include <stddef.h>

#include "vec3.h"

/* Most paths one query returns (a sphere has at most a few; a bumpy mesh more). */
#define WALTER_MAX_PATHS 32

/* Brackets of the sphere's 1D search over the arc of the circle that L sees
 * (walter_sphere_paths; the GLSL twin uses the same count). */
#define WALTER_SPHERE_BRACKETS 48

/* One connecting path. */
struct walter_path {
    vec3 P;       /* the refraction point on the boundary */
    vec3 N;       /* the shading normal there (unit, out of the medium) */
    vec3 omega_V; /* (V - P) / d_V: the light's direction of travel at V */
    vec3 omega_L; /* (L - P) / d_L; for a directional light, minus its direction */
    double d_V;   /* |V - P| */
    double d_L;   /* |L - P|; INFINITY for a directional light */
    double T;     /* Fresnel transmittance 1 - R at P (unpolarised, frisvad2010) */
    double D;     /* spread, eq. 26 (D_inf for a directional light) */
    double gain;  /* eta^2 T / D: irradiance at V per unit intensity (per unit E0),
                     before the medium's attenuation exp(-sigma_t d_V) */
};

/* The shading normal near P as the spread needs it: N_s = m / |m| with m's change along
 * the surface dm = dm_a (g_a . dP) + dm_b (g_b . dP) for a tangent step dP (g_a, g_b the
 * dual basis of the surface's parameters: barycentric a, b on a triangle; for a sphere an
 * orthonormal tangent basis with dm_a = g_a, dm_b = g_b); N_g the geometric normal (the
 * tangent plane P moves in, eq. 21). */
struct walter_normal {
    vec3 m, dm_a, dm_b, g_a, g_b, N_g;
};

/* The spread D of the path V <- P <- L (eq. 19-26; derived again in docs/walter.md
 * "Spread" with the sign of omega_V' fixed): for two orthonormal perturbations of omega_V,
 * P' in the tangent plane (eq. 21), omega_L' from Snell's law (eq. 22-24), L' normal to
 * omega_L (eq. 25), D = |L'_1 x L'_2| (eq. 26). at_infinity: L is a directional light's
 * and D_inf = |omega_L'_1 x omega_L'_2| is returned. 0 on a caustic (focus). */
double walter_spread(vec3 V, vec3 L, bool at_infinity, vec3 P, double eta,
                     const struct walter_normal *nrm);

/* Fills a path's T, D and gain from P, V, L and the normal (after a solver found P).
 * Returns false when the path is not valid after all (wrong side, grazing, D = 0). */
bool walter_path_finish(struct walter_path *p, vec3 V, vec3 L, bool at_infinity, double eta,
                        const struct walter_normal *nrm);

/* All paths from L (a point; at_infinity: L is the unit direction light travels) to V
 * through the sphere (centre c, radius R) whose inside has relative index eta; V inside,
 * L outside. The paths lie in the plane of c, L and V; P(theta) on that circle, theta over
 * the arc L sees, cut in WALTER_SPHERE_BRACKETS brackets; a root is bracketed by a sign
 * change of the tangential condition, and a pair of roots inside one bracket by a minimum
 * of its modulus that crosses zero (found by bisection on the derivative). Returns the
 * count written to out (at most max). */
int walter_sphere_paths(vec3 c, double R, double eta, vec3 L, bool at_infinity, vec3 V,
                        struct walter_path *out, int max);

/* The light a unit light (intensity 1; a directional one: irradiance 1) scatters per unit
 * sigma_s toward -d at V inside the sphere: sum over walter_sphere_paths of
 * p_HG(g, omega_V . -d) gain exp(-sigma_t d_V) (eq. 17 with the phase function), the paths
 * of a spot light only where -omega_L lies in its cone (spot_dir, cos_spot; cos_spot <= -1:
 * no cone). The twin of walter.glsl's; the fast renderer's CPU reference and the path
 * tracer's connections both use it. */
vec3 walter_sphere_inscatter(vec3 c, double R, double eta, vec3 L, bool at_infinity, vec3 V, vec3 d,
                             double g, vec3 sigma_t, vec3 spot_dir, double cos_spot);

/* The derivative of u / |u| along u' (walter2009 eq. 10). */
vec3 walter_unit_deriv(vec3 u, vec3 du);

/* ---- triangle meshes (walter_mesh.c) ---- */

/* A boundary triangle: vertices and their shading normals (unit, out of the medium). */
struct walter_triangle {
    vec3 p[3];
    vec3 n[3];
};

/* Work counters of a mesh query (for tests and benchmarks). */
struct walter_stats {
    long triangles_tested; /* after the sidedness and spindle tests */
    long boxes;            /* parameter boxes the interval test looked at */
    long newton_runs;      /* Newton iterations started */
    long unresolved;       /* boxes at the depth limit the interval test could not settle */
};

/* All paths through one triangle (walter2009 sect. 3.3): the parameter square is split
 * until the Krawczyk test (eq. 11-15) proves a box empty or holding exactly one solution,
 * which 2D Newton with the pseudo-inverse (eq. 8-10) then finds. Solutions on the
 * triangle's edges are kept (the neighbour finds them too; walter_mesh_paths merges). */
int walter_triangle_paths(const struct walter_triangle *t, double eta, vec3 L, bool at_infinity,
                          vec3 V, struct walter_path *out, int max, struct walter_stats *st);

/* All paths through a mesh: each triangle whose plane separates L from V (eq. 4) and that
 * meets the spindle's bounding sphere (eq. 16 with r >= 0: the angle LPV exceeds a right
 * angle) is searched; paths closer than 1e-9 of the mesh's size are one. */
int walter_mesh_paths(const struct walter_triangle *tris, size_t count, double eta, vec3 L,
                      bool at_infinity, vec3 V, struct walter_path *out, int max,
                      struct walter_stats *st);

/* 2D Newton from (a, b) on triangle t (eq. 9, steps at most 1/2, halved while they do not
 * reduce |f|; given up when no step reduces |f| or the iterate is a triangle's size outside
 * it). Returns true with the solution's barycentrics when |f| < 1e-12. */
bool walter_triangle_newton(const struct walter_triangle *t, double eta, vec3 L, bool at_infinity,
                            vec3 V, double *a, double *b);

/* The triangle's shading normal record at barycentrics (a, b), for walter_spread. */
struct walter_normal walter_triangle_normal(const struct walter_triangle *t, double a, double b);

#endif
