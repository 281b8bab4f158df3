/*
 * voxel_tricubic.h - tricubic Catmull-Rom reconstruction of a scalar voxel grid and its
 * exact gradient, in double precision: the CPU twin of shaders/volume_sample.glsl's
 * tricubic volume_sample_ior_grad (render.ior_filter "tricubic", docs/tracing.md "Index
 * filter").
 *
 * Per axis the cubic convolution kernel of Keys (1981) with a = -1/2 (Catmull-Rom) over
 * the taps i-1..i+2 of the cell [i, i+1] holding the point: it interpolates (returns the
 * voxel at voxel centres), its weights sum to 1, it reproduces polynomials up to degree 2
 * per axis inside the grid, and it is C1. The gradient is the derivative of that same
 * interpolant, so it is continuous and consistent with the value. A tap beyond the grid
 * stands for the linear extrapolation of the two edge voxels (f[-1] = 2 f[0] - f[1]), so
 * linear fields are exact up to the edge; coordinates clamp to [0, res-1] (voxel centres).
 * The GPU sums the same 64 taps with the same weights.
 *
 * Grids are x fastest, then y, then z. Ownership: the caller owns every buffer.
 */
#ifndef REFRACT_VOXEL_TRICUBIC_H
#define REFRACT_VOXEL_TRICUBIC_H

#include "vec3.h"

/* The four Catmull-Rom weights w and their derivatives d (per voxel) of the taps
 * i-1..i+2 at fraction t in [0, 1]; w sums to 1, d to 0. */
void voxel_catmull_rom_weights(double t, double w[4], double d[4]);

/* The tricubic Catmull-Rom value of component `comp` of a grid with `comps` values per
 * voxel at continuous voxel coordinates v (voxel centres at integers, each clamped to
 * [0, res-1]), and its gradient per voxel along x, y, z (divide by the voxel size for
 * object units). */
double voxel_tricubic_value_grad(const double *grid, int comps, int comp, const int res[3], vec3 v,
                                 vec3 *grad_per_voxel);

#endif
