/*
 * photon.h - caustic photons on the receiver plane (issue 15 item 1, docs/photons.md):
 * photons traced from the lights through the exact surfaces and stored where they land on
 * the receiver, then the kernel estimate of their irradiance on a lattice over the plane,
 * which the fast renderer samples (shaders/photons.glsl, the same names).
 *
 * The split of the receiver's light (docs/photons.md "Which light is whose"): a surface is
 * *optical* when its medium differs from the ambient one (another index, absorption or
 * scattering); light that reaches the plane without touching an optical surface is direct
 * light, which the renderer computes with a shadow ray (blocked by every optical surface);
 * light that touched one (refracted, reflected, absorbed on the way) is carried by photons
 * only. The two parts are disjoint and together are all light that reaches the plane
 * straight from a light or through specular interfaces: the caustic is what the light
 * simulator's irradiance volume smeared over its voxels (tevs2007 sect. 6.2), here resolved
 * to the gather radius.
 *
 * The estimator: photons are emitted with the pathtrace lights' emission (point, spot,
 * directional, Lambertian sphere) into the cone that holds the optical surfaces' bounding
 * sphere (a projection map: no photon is spent on directions that can only give direct
 * light) and weighted by what they stand for; at each interface the photon reflects with
 * probability R (unpolarised Fresnel, frisvad2010) and refracts otherwise, its power
 * unchanged (the Fresnel-weighted choice of the path tracer); absorbing media multiply it by
 * exp(-sigma_a d) (Beer-Lambert). The irradiance at x is the kernel estimate
 * E(x) = sum_p phi_p K(|x - x_p|) with Epanechnikov's K(s) = 2 / (pi r^2) (1 - s^2 / r^2)
 * for s < r (unit integral over the plane): consistent as the photon count grows and r
 * shrinks (docs/photons.md "Radius").
 *
 * Conventions: world units; power in W per channel (the pathtrace lights' values);
 * irradiance in W / unit^2 on the plane (the cosine is in the photon density).
 * Ownership: lists and grids own their arrays (photon_list_free, photon_grid_free).
 * Thread: any; no globals.
 */
#ifndef REFRACT_PHOTON_H
#define REFRACT_PHOTON_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "bindings.h"
#include "err.h"
#include "pathtrace.h"
#include "pixel_sample.h"

#define PHOTON_MAX_EVENTS 128        /* interface events of one photon at most */
#define PHOTON_RADIUS_SCENE 0.02     /* auto radius: this times the optical surfaces' */
#define PHOTON_RADIUS_COUNT 1048576L /* bounding radius at this many photons, times */
                                     /* (count / PHOTON_RADIUS_COUNT)^(-1/6) */

/* One photon where it landed on the receiver plane. */
struct photon {
    double x, z;     /* world x, z on the plane y = receiver.height */
    double power[3]; /* W per channel */
};

struct photon_list {
    struct photon *items;
    size_t count, capacity;
    long emitted;     /* photons emitted (landed or not) */
    double lost[3];   /* power of photons ended by PHOTON_MAX_EVENTS (W): should be ~0 */
    double landed[3]; /* sum of the stored photons' power (W) */
};

/* The optical surfaces' bounding sphere (centre, radius), false when there is none or one is
 * unbounded (an infinite plane: docs/photons.md "Not yet"); *unbounded (may be NULL) is then
 * the index of that surface, else -1. */
bool photon_target(const struct pathtrace_scene *s, vec3 *center, double *radius, int *unbounded);

/* True when surface k changes light (docs/photons.md "Which light is whose"). */
bool photon_surface_optical(const struct pathtrace_scene *s, int k);

/* Traces `count` photons (shared evenly by the lights) under `seed`; each photon k uses the
 * random stream (seed, light, k), so a list is the same whatever the caller's threads.
 * first/stride pick photons first, first + stride, ... (threads split the work that way;
 * 0, 1 for all). Appends to out. Returns REFRACT_E_OK, REFRACT_E_OUT_OF_MEMORY, or
 * REFRACT_E_CONFLICT when the scene has no bounded target (photon_target) or a scattering
 * medium (docs/photons.md "Not yet"). */
enum refract_code photon_trace(const struct pathtrace_scene *s, long count, uint64_t seed,
                               long first, long stride, struct photon_list *out, struct err *e);
/* Appends b's photons and sums to a (threads' partial lists). */
enum refract_code photon_list_merge(struct photon_list *a, const struct photon_list *b,
                                    struct err *e);
/* One estimate from two independent lists traced with acc_count and batch_count photons
 * (each photon's power is its light's power over its own list's count): the powers of
 * acc's photons times acc_count / (acc_count + batch_count), batch's appended times
 * batch_count / (acc_count + batch_count), as if all had been one list of the sum
 * (progressive refinement, docs/photons.md "The cache"). emitted adds up. */
enum refract_code photon_list_accumulate(struct photon_list *acc, long acc_count,
                                         const struct photon_list *batch, long batch_count,
                                         struct err *e);
void photon_list_free(struct photon_list *l);

/* The gather radius for count photons (docs/photons.md "Radius"): radius_setting when > 0,
 * else PHOTON_RADIUS_SCENE times the target's radius times
 * (count / PHOTON_RADIUS_COUNT)^(-1/6). */
double photon_radius(const struct pathtrace_scene *s, long count, double radius_setting);

/* The photons' kernel estimate, evaluated where it is not zero: at the points (i h, j h)
 * of a lattice over the plane (h = radius / PHOTON_LATTICE_PER_RADIUS) that lie within the
 * radius of some photon, each holding the exact estimate E(i h, j h), kept in a hash table
 * (open addressing, linear probing). Between lattice points E is bilinear; a lattice point
 * that is not in the table has no photon within the radius, so E is exactly 0 there. A
 * lookup costs four probes of at most `probe_max + 1` slots each, whatever the photon
 * density: a gather loop over photons is not an option on llvmpipe, which ends a shader's
 * loops after 65535 iterations in all (LP_MAX_TGSI_LOOP_ITERATIONS; docs/photons.md
 * "Density estimate"). The landed photons may spread over kilometres (an infinite floor):
 * only the lattice points near them are stored. */
struct photon_grid {
    double cell;        /* lattice spacing h, world units */
    double radius;      /* kernel radius */
    uint32_t capacity;  /* hash slots, a power of two (0: no photon landed) */
    uint32_t used;      /* lattice points stored */
    uint32_t probe_max; /* the longest probe sequence of any stored point */
    int32_t *keys;      /* 2 per slot: i, j; PHOTON_EMPTY_KEY in an empty slot */
    double *E_double;   /* 3 per slot: E rgb (the CPU reference reads these) */
    float *E;           /* 4 per slot: E rgb, 0 (the GPU's copy) */
};

#define PHOTON_LATTICE_PER_RADIUS 3.0 /* lattice spacing = radius / this */
#define PHOTON_LATTICE_MAX 8388608u   /* lattice points at most; a coarser spacing beyond */
/* PHOTON_EMPTY_KEY (the key of an empty slot: indices never reach it) and PHOTON_CELL_MAX
 * (lattice indices are clamped to +-it) are in shaders/bindings.h, shared with the GLSL. */

/* The slot where the probe for lattice point (i, j) starts (the twin of photon_hash in
 * shaders/photons.glsl: 32-bit unsigned arithmetic, wrapping). pixel_hash (Chris Wellons'
 * lowbias32) mixes the two indices: neighbouring lattice points land in unrelated slots, so
 * linear probing does not pile them into long runs (a plain multiply-xor hash made runs of
 * 141). */
static inline uint32_t photon_hash(int32_t i, int32_t j, uint32_t capacity)
{
    return pixel_hash((uint32_t)i ^ pixel_hash((uint32_t)j + 0x9e3779b9u)) & (capacity - 1u);
}

/* Builds the lattice of the landed photons' kernel estimate for the radius. */
enum refract_code photon_grid_build(const struct photon_list *l, double radius,
                                    struct photon_grid *g, struct err *e);
/* A lattice from its n stored points, each (i, j) in ij[2 p ..] and E rgb in E[3 p ..],
 * spacing `cell` and kernel radius `radius` as built (a map read back from the data
 * directory): the table is made anew (capacity, probe_max). STORAGE for more than
 * PHOTON_LATTICE_MAX points, a bad spacing or indices out of range. */
enum refract_code photon_grid_from_points(double cell, double radius, uint32_t n,
                                          const int32_t *ij, const double *E,
                                          struct photon_grid *g, struct err *e);
/* E at world (x, z): bilinear between the four lattice points about it (the twin of
 * photon_irradiance in shaders/photons.glsl). */
void photon_irradiance(const struct photon_grid *g, double x, double z, double E[3]);
/* E at lattice point (i, j) as stored (0 when absent). */
void photon_lattice_at(const struct photon_grid *g, int32_t i, int32_t j, double E[3]);
/* The same over the whole list by brute force (no grid): what the grid is tested against. */
void photon_kernel_estimate(const struct photon_list *l, double radius, double x, double z,
                            double E[3]);
/* The same with its standard error per channel (the square root of the sum of the squared
 * terms: the photons are independent), for tests that compare two photon sets. */
void photon_kernel_estimate_se(const struct photon_list *l, double radius, double x, double z,
                               double E[3], double se[3]);
void photon_grid_free(struct photon_grid *g);

/* ---- photon_receiver.c: the receiver's light in the "photons" mode ---- */

/* False when an optical surface lies between receiver point at and light j's centre (the
 * direct part's shadow ray; the twin of photon_light_visible in shaders/photons.glsl). The
 * receiver's radiance in this mode is reftrace_light_receiver's (reftrace_lighting.photons),
 * the twin of the fast renderer's light_receiver. */
bool photon_light_visible(const struct pathtrace_scene *s, int j, vec3 at);
/* ---- photon_map.c: the whole map for a scene (threads, radius, grid) ---- */

struct photon_map_stats {
    long emitted;
    size_t landed;
    double radius;
    double trace_ms, grid_ms;
};

/* Traces `count` photons on `threads` threads (1..64) into a new list (the same set
 * whatever the thread count). On failure out is empty. */
enum refract_code photon_map_trace(const struct pathtrace_scene *s, long count, uint64_t seed,
                                   int threads, struct photon_list *out, struct err *e);
/* photon_map_trace, then the grid with photon_radius(s, count, radius_setting). On failure
 * g is empty. */
enum refract_code photon_map_build(const struct pathtrace_scene *s, long count,
                                   double radius_setting, uint64_t seed, int threads,
                                   struct photon_grid *g, struct photon_map_stats *stats,
                                   struct err *e);

/* ---- a light's map, refined in passes (docs/photons.md "The cache") ---- */

#define PHOTON_LEVELS 3 /* a map refines in passes of count / 16, count / 4 and count photons */

/* The photons of pass `level` (0 .. PHOTON_LEVELS - 1) of a map of `count`:
 * count / 4^(PHOTON_LEVELS - 1 - level), at least 1024 and at most count. */
long photon_level_count(long count, int level);
/* The seed of a pass: the pass of `count` photons uses seed 1, as the map render_view builds
 * at once; each pass its own. */
uint64_t photon_level_seed(int level);

/* A light's map is made in passes (docs/photons.md "The cache"): first the levels above, up
 * to the pass of `count` photons (photon_initial_passes of them), each a map of its own
 * that replaces the last; then, while the map has fewer than `count_max` photons, passes
 * that double its photons (the last up to count_max), accumulated with every photon before
 * (photon_list_accumulate), the radius that of the total. Doubling keeps the lattice
 * rebuilds to log2(count_max / count) of them, about twice the cost of the last. */
int photon_initial_passes(long count);
int photon_pass_count(long count, long count_max);
/* The photons of the map after pass `pass` (0-based), and those that pass traces. */
long photon_pass_total(long count, long count_max, int pass);
long photon_pass_batch(long count, long count_max, int pass);
/* *out = s with light l as its only light (a light's own map; l at unit intensity makes
 * a map that the light's colour times intensity scales). out->surfaces stays s's. */
void photon_scene_one_light(const struct pathtrace_scene *s, const struct pathtrace_light *l,
                            struct pathtrace_scene *out);

#endif
