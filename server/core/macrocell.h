/*
 * macrocell.h - the empty-space map of one voxel object (docs/tracing.md "Empty space").
 *
 * The grid is cut into cubic macro cells of `cell` voxels per edge. A cell is empty when
 * every texel that sampling can read for a point in the closed cell (the cell plus a
 * border of one texel on each side for trilinear filtering, clamped to the grid) has grad n = 0
 * (|grad n| h_min at most MACROCELL_GRAD_EPS), n within MACROCELL_N_EPS of the others, and no
 * extinction, emission or opaque coverage. In an empty cell the ray equation (tevs2007
 * eqs. 4.8/4.9) has dw/ds = 0: the ray is a straight line with constant n, so the march
 * may cross the cell in one jump and add n ds to the optical path exactly.
 *
 * One implementation serves the GPU (server/render/scene_gpu.c uploads the map) and the
 * CPU twin (server/core/reftrace.c), so both skip the same cells.
 *
 * Ownership: a macrocell_map owns `empty`. Thread: any.
 */
#ifndef REFRACT_MACROCELL_H
#define REFRACT_MACROCELL_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "err.h"

/* |grad n| h_min (the index change per voxel) at or below this counts as no gradient.
 * Float rounding in the Gaussian pre-smoothing leaves ~1e-7 of noise in a constant region;
 * the bound on the bending this ignores is MACROCELL_GRAD_EPS per voxel crossed. */
#define MACROCELL_GRAD_EPS 1e-6
/* n varying by at most this over a cell counts as constant (the march's INDEX_EPS). */
#define MACROCELL_N_EPS 1e-6
/* The default cell edge in voxels (docs/accuracy.md "Only what a scene needs" measures
 * 4 against 8). */
#define MACROCELL_DEFAULT_CELL 4

struct macrocell_map {
    int cell;       /* voxels per cell edge */
    int dims[3];    /* cells per axis: ceil(res / cell) */
    uint8_t *empty; /* dims[0] * dims[1] * dims[2], x fastest: 1 = empty */
    size_t empty_count;
};

/* Texels a sample reads beyond the cell it lies in, per side: trilinear filtering reads
 * the two texels around it (1); a tricubic (Catmull-Rom) reconstruction of n reads four
 * (2), so its maps need the wider border. */
#define MACROCELL_BORDER_TRILINEAR 1
#define MACROCELL_BORDER_TRICUBIC 2

/* Per-voxel inputs: n (the smoothed index) and busy[v] != 0 where voxel v has a
 * gradient above MACROCELL_GRAD_EPS / h_min or any extinction, emission or opaque
 * coverage (the caller knows its channels' layout). res: voxels per axis; border: the
 * sampling footprint beyond the cell (MACROCELL_BORDER_*). */
enum refract_code macrocell_build(const double *n, const uint8_t *busy, const int res[3], int cell,
                                  int border, struct macrocell_map *out, struct err *e);
void macrocell_free(struct macrocell_map *m);

/* The per-voxel test of macrocell_build's busy input, shared by the GPU build and the CPU
 * twin so both mark the same voxels: ior_grad is (dn/dx, dn/dy, dn/dz, n) in object units;
 * the others are the voxel's 4 channel values or NULL (no channel): extinction (rgb),
 * emission (rgb), opaque (a: coverage), scattering (rgb). */
bool macrocell_voxel_busy(const double ior_grad[4], double h_min, const double *attenuation,
                          const double *emission, const double *opaque, const double *scattering);

/* Cells in the map. */
size_t macrocell_count(const struct macrocell_map *m);

/* True when a voxel's (grad n, n) sample counts as gradient-free: |grad| h_min <=
 * MACROCELL_GRAD_EPS. */
bool macrocell_gradient_free(double gx, double gy, double gz, double h_min);

/* The jump of the march over empty cells (the 3D DDA of Amanatides and Woo over macro
 * cells; the GLSL twin is march_skip_distance in shaders/ray_march.glsl). v0: the start in
 * continuous voxel coordinates (docs/tracing.md "Conventions": voxel i spans [i, i + 1]);
 * dv: voxels per object unit along the unit direction; t_bounds: the distance to the
 * bounds exit (object units). Returns the distance (object units) to the far side of the
 * last of the consecutive empty cells from v0 on, or t_bounds with *to_bounds set when
 * they reach the bounds; 0 when the start's own cell is not empty. */
double macrocell_skip_distance(const struct macrocell_map *m, const double v0[3],
                               const double dv[3], double t_bounds, bool *to_bounds);

#endif
