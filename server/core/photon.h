/*
 * photon.h - caustic photons on the receiver plane (issue 15 item 1, docs/photons.md):
 * photons traced from the lights through the exact surfaces and stored where they land on
 * the receiver, then the kernel estimate of their irradiance, gathered from a hash grid of them,
 * that the fast renderer samples (shaders/photons.glsl, the same names).
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

#include "err.h"
#include "pathtrace.h"

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
void photon_list_free(struct photon_list *l);

/* The gather radius for count photons (docs/photons.md "Radius"): radius_setting when > 0,
 * else PHOTON_RADIUS_SCENE times the target's radius times
 * (count / PHOTON_RADIUS_COUNT)^(-1/6). */
double photon_radius(const struct pathtrace_scene *s, long count, double radius_setting);

/* The photons in a hash grid over the plane (Teschner et al. 2003's spatial hash, as GPU
 * photon mappers use it): square cells of edge `cell` (a hair over the radius, so the disk
 * of radius r about any point lies in the 3 x 3 cells about it), cell (i, j) in bucket
 * photon_hash(i, j, buckets); the photons sorted by bucket, bucket b's being
 * [start[b], start[b + 1]). A gather scans the distinct buckets of the 3 x 3 cells and keeps
 * the photons within the radius: the exact kernel estimate at any point of the plane,
 * however far the photons spread (an infinite floor catches reflected photons kilometres
 * away). */
struct photon_grid {
    double cell;      /* cell edge, world units: radius * (1 + PHOTON_CELL_SLACK) */
    double radius;    /* kernel radius */
    uint32_t buckets; /* a power of two >= 2 * count (0: no photon landed) */
    size_t count;
    uint32_t *start;       /* buckets + 1 */
    struct photon *sorted; /* count, by bucket */
    float *gpu;            /* 8 floats per photon (x, z, 0, 0, power rgb, 0): the GPU's layout */
};

#define PHOTON_CELL_SLACK 1e-3       /* the float gather's cell index may be off at a cell's edge */
#define PHOTON_CELL_MAX 1073741824.0 /* cell indices are clamped to +-this (far photons share) */

/* The bucket of cell (i, j) (the twin of photon_hash in shaders/photons.glsl: 32-bit
 * unsigned arithmetic, wrapping). */
static inline uint32_t photon_hash(int32_t i, int32_t j, uint32_t buckets)
{
    return (((uint32_t)i * 73856093u) ^ ((uint32_t)j * 19349663u)) & (buckets - 1u);
}

/* Builds the hash grid of the landed photons for the kernel radius. */
enum refract_code photon_grid_build(const struct photon_list *l, double radius,
                                    struct photon_grid *g, struct err *e);
/* E at world (x, z) (the twin of photon_irradiance in shaders/photons.glsl): the kernel
 * estimate over the photons within the radius. */
void photon_irradiance(const struct photon_grid *g, double x, double z, double E[3]);
/* The same over the whole list by brute force (no grid): what the grid is tested against. */
void photon_kernel_estimate(const struct photon_list *l, double radius, double x, double z,
                            double E[3]);
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

/* Traces `count` photons on `threads` threads (1..64), then builds the grid with
 * photon_radius(s, count, radius_setting). On failure g is empty. */
enum refract_code photon_map_build(const struct pathtrace_scene *s, long count,
                                   double radius_setting, uint64_t seed, int threads,
                                   struct photon_grid *g, struct photon_map_stats *stats,
                                   struct err *e);

#endif
