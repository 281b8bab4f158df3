/*
 * lightsim.h - the wavefront light simulator (tevs2007 ch. 4.2 and 6.2, ziegler2007):
 * light wavefronts, tessellated into patches of four particles, are propagated through a
 * scene's refractive-index field with the constant-time-step ray equation (eqs.
 * 4.12/4.13), and their power is voxelised into an irradiance volume and a local
 * light-direction volume that the view renderer uses for in-scattering, reflected light
 * and receivers (eqs. 5.4-5.8).
 *
 * docs/lightsim.md is the specification. Two implementations follow it: the GPU one
 * (lightsim_gpu.h, GLSL compute in shaders/lightsim_*.comp) and the CPU double-precision
 * reference here (lightsim_ref_run), and tests bound the distance between them.
 *
 * The simulation runs on a world-space *light grid* that covers the light domain of a
 * scene and a light (all objects and their footprint on the receiver as the light sees
 * it): cubic voxels. Its input fields (index, gradient, extinction, opaque coverage) are
 * built on the CPU from the scene's reference voxel fields (scene_reference.h) once per
 * transport hash and light grid.
 *
 * Ownership: functions that fill a struct with buffers document how to free them.
 * Thread: any for everything in this header (no GL).
 */
#ifndef REFRACT_LIGHTSIM_H
#define REFRACT_LIGHTSIM_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"
#include "../core/vec3.h"
#include "../scene/scene.h"

/* A world-space grid of cubic voxels: voxel (i, j, k) has its centre at
 * bmin + (i + 0.5, j + 0.5, k + 0.5) * voxel. */
struct light_grid {
    int dims[3];
    vec3 bmin;
    double voxel; /* edge length, world units */
};

/* The light domain of a scene and a light (docs/lightsim.md "Domain"): the union of the
 * objects' and the surfaces' world bounding boxes and, with a receiver, their footprint
 * on it as light l sees it (clipped to the receiver's square and to LIGHTSIM_FOOTPRINT_MAX
 * times the objects' longest extent), padded by two voxels, with cubic voxels and
 * set->resolution voxels along its longest axis. Without a receiver it does not depend on
 * the light. l NULL: the whole receiver square instead of the footprint (the objects'
 * extent for an infinite receiver). A mesh surface's box comes with its upload: the
 * _lookup and _light forms find it through lookup (as lightsim_fields_build does);
 * lightsim_domain, and a mesh lookup cannot find, add none. */
#define LIGHTSIM_FOOTPRINT_MAX 4.0
void lightsim_domain(const struct scene *s, struct light_grid *out);
void lightsim_domain_lookup(const struct scene *s, scene_volume_lookup_fn lookup, void *ctx,
                            struct light_grid *out);
void lightsim_domain_light(const struct scene *s, const struct scene_light *l,
                           scene_volume_lookup_fn lookup, void *ctx, struct light_grid *out);

/* How many time steps a patch accumulates before a flux deposit (docs/lightsim.md step
 * 5): max(1, floor(1 / step_voxels)), so deposits lie about one voxel apart. */
int lightsim_deposit_every(const struct scene_lightsim *set);

struct reftrace_surface; /* core/reftrace.h (not included: shaders/bindings.h names the
                            geometry kinds as macros for the GPU files that include both) */

/* The simulator's input on the light grid. x fastest, then y, then z. */
struct lightsim_fields {
    struct light_grid grid;
    double ambient_ior;
    double probe_distance;     /* world units: k of the interface probe (docs/lightsim.md) */
    double boundary_threshold; /* index change per light voxel that marks an interface */
    double *ior_grad;          /* 4 per voxel: dn/dx, dn/dy, dn/dz (world units), n; owned */
    double *extinction;        /* 4 per voxel: sigma_t = sigma_a + sigma_s (r, g, b) per world
                                  unit, opaque coverage; owned */
    /* Exact surfaces (docs/lightsim.md "Surfaces"), by nesting priority as in the scene:
     * geometry and the constant medium inside. Lathe profiles point into profile_points. */
    struct reftrace_surface *surfaces; /* owned; NULL when surface_count is 0 */
    int surface_count;
    double (*profile_points)[2]; /* owned copies of the lathes' profiles */
    /* Owned copies of the mesh surfaces' meshes (the fields outlive the scene version
     * whose uploads they were made from), each once; the surfaces' geom.mesh point here. */
    struct mesh **meshes;
    int mesh_count;
};

/* Builds the fields from the scene (docs/lightsim.md "Fields") on the light grid of light
 * l (lightsim_domain_light; NULL: the whole receiver). CONFLICT for a missing volume or
 * mesh, INVALID_MESH for a mesh surface whose mesh cannot bound a medium, INVALID_FIELD for
 * a receiver above a mesh surface's bottom, OUT_OF_MEMORY. Free with lightsim_fields_free.
 * lightsim_fields_build is lightsim_fields_build_light with l NULL. */
enum refract_code lightsim_fields_build(const struct scene *s, scene_volume_lookup_fn lookup,
                                        void *ctx, struct lightsim_fields *out, struct err *e);
enum refract_code lightsim_fields_build_light(const struct scene *s, const struct scene_light *l,
                                              scene_volume_lookup_fn lookup, void *ctx,
                                              struct lightsim_fields *out, struct err *e);
void lightsim_fields_free(struct lightsim_fields *f);

/* Where the power went, per colour channel, for a light of colour (1, 1, 1) and intensity
 * 1. flux_in = flux_out + flux_reflected + flux_absorbed + flux_culled + what the live
 * patches still carry (flux_live). */
struct lightsim_stats {
    double flux_in[3];        /* power of the initial patches aimed at the domain */
    double flux_out[3];       /* left the domain (incl. through the receiver plane) */
    double flux_reflected[3]; /* sent back by Fresnel reflection at interfaces */
    double flux_absorbed[3];  /* extinction along the way, and opaque embeddings */
    double flux_culled[3];    /* energy threshold, max level, orientation flip, capacity */
    double flux_live[3];      /* still carried by live patches */
    long long steps;          /* wavefront time steps taken */
    long long patch_steps;    /* sum over steps of the live patch count */
    long long splits;         /* patches split in four */
    long long culled_energy, culled_level, culled_flip, culled_capacity;
    int patches_initial; /* patches of the initial wavefront aimed at the domain */
    int patches_live;    /* now */
    int patches_peak;
    double progress; /* 0..1: fraction of the domain swept (docs/lightsim.md) */
    bool done;
};

/* The output: one irradiance volume per light, on the light grid. */
struct irradiance_volume {
    struct light_grid grid;
    float *irradiance; /* 4 per voxel: E r, g, b (unit light), 0; owned */
    float *direction;  /* 4 per voxel: unit mean light direction (world), 1 where light
                          passed, else (0, 0, 0, 0); owned */
    struct lightsim_stats stats;
};
void irradiance_volume_free(struct irradiance_volume *v);
size_t irradiance_volume_bytes(const struct irradiance_volume *v);

/* Runs the whole simulation of one light on the CPU in double precision (the reference
 * of the GPU kernels). Slow: for tests and coarse grids. out is filled with new buffers
 * (irradiance_volume_free). OUT_OF_MEMORY; LIMIT_EXCEEDED never (capacity culls). */
enum refract_code lightsim_ref_run(const struct lightsim_fields *f, const struct scene_light *l,
                                   const struct scene_lightsim *set, struct irradiance_volume *out,
                                   struct err *e);

/* The same reference in resumable form, so a comparison can stop after N steps (the GPU
 * run's lightsim_gpu_begin/advance/stats/read). The run borrows f, which must outlive it;
 * l and set are copied. */
struct lightsim_ref;
enum refract_code lightsim_ref_begin(const struct lightsim_fields *f, const struct scene_light *l,
                                     const struct scene_lightsim *set, struct lightsim_ref **out,
                                     struct err *e);
/* Advances at most max_steps time steps; *done is set when the run has ended. */
enum refract_code lightsim_ref_advance(struct lightsim_ref *run, int max_steps, bool *done,
                                       struct err *e);
/* Statistics as of now (flux_live summed over the live patches). */
void lightsim_ref_stats(const struct lightsim_ref *run, struct lightsim_stats *out);
/* The volumes as deposited so far (new buffers: irradiance_volume_free), with the stats. */
enum refract_code lightsim_ref_read(const struct lightsim_ref *run, struct irradiance_volume *out,
                                    struct err *e);
void lightsim_ref_destroy(struct lightsim_ref *run);

/* The largest relative violation of the bookkeeping identity over the channels:
 * |in - (out + reflected + absorbed + culled + live)| / in (0 when in is 0). */
double lightsim_stats_imbalance(const struct lightsim_stats *s);

#endif
