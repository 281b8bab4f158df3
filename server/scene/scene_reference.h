/*
 * scene_reference.h - a parsed scene as the CPU reference tracer's objects
 * (core/reftrace.h), built exactly as the GPU builds its atlases (docs/tracing.md
 * "Precomputation"): the fields evaluated at voxel centres, the index smoothed by
 * smooth_gaussian_ref and differentiated by gradient_central_ref, in double precision.
 *
 * SCENE_REFERENCE_ANALYTIC instead hands the reference tracer the exact continuous index
 * field of objects whose ior is one GRIN profile or a constant (no voxels, no smoothing),
 * for measuring the discretisation error of the voxel path.
 *
 * Ownership: scene_reference_build fills *out with buffers it owns; release them with
 * scene_reference_free. It borrows the scene, which must outlive the reference.
 */
#ifndef REFRACT_SCENE_REFERENCE_H
#define REFRACT_SCENE_REFERENCE_H

#include "../core/reftrace.h"
#include "scene.h"

#define SCENE_REFERENCE_MAX_OBJECTS 16

enum scene_reference_mode {
    SCENE_REFERENCE_VOXELS = 0,   /* the same voxel fields the GPU uses */
    SCENE_REFERENCE_ANALYTIC = 1, /* the exact GRIN profile (ior only) */
};

struct scene_reference {
    struct reftrace_object objects[SCENE_REFERENCE_MAX_OBJECTS];
    int count;
    struct reftrace_settings settings; /* from the scene's render block: rk4/euler, step... */
    struct reftrace_grid grids[SCENE_REFERENCE_MAX_OBJECTS];
    double *buffers[SCENE_REFERENCE_MAX_OBJECTS][SCENE_CH_COUNT]; /* owned */
    struct grin_profile profiles[SCENE_REFERENCE_MAX_OBJECTS];
    double constants[SCENE_REFERENCE_MAX_OBJECTS];
    struct macrocell_map cells[SCENE_REFERENCE_MAX_OBJECTS]; /* voxel mode: the empty-space
                                                                maps (owned) */
    struct reftrace_surface surfaces[SCENE_MAX_SURFACES];    /* settings.surfaces points here */
};

/* The reference tracer's twin of a render stepper (adaptive -> REFTRACE_BS23). */
enum reftrace_stepper scene_reference_stepper(enum scene_stepper i);

/* INVALID_FIELD in analytic mode when an object's ior is not one profile or constant, or
 * has other channels; CONFLICT for missing volumes; OUT_OF_MEMORY. */
enum refract_code scene_reference_build(const struct scene *s, enum scene_reference_mode mode,
                                        scene_volume_lookup_fn lookup, void *ctx,
                                        struct scene_reference *out, struct err *e);
void scene_reference_free(struct scene_reference *r);

/* Rebuilds the voxel objects' empty-space maps with `cell` voxels per cell edge (the build
 * uses MACROCELL_DEFAULT_CELL, as the GPU does by default). */
enum refract_code scene_reference_set_cells(struct scene_reference *r, int cell, struct err *e);

#endif
