/*
 * voxel_tricubic.h - tricubic Catmull-Rom reconstruction of a voxel grid in double
 * precision: the CPU twin of shaders/volume_sample.glsl's tricubic volume_sample_ior_grad
 * (render.ior_filter "tricubic", docs/tracing.md "Index filter").
 *
 * Per axis the cubic convolution kernel of Keys (1981) with a = -1/2 (Catmull-Rom): it
 * interpolates (returns the voxel at voxel centres), its weights sum to 1, it reproduces
 * polynomials up to degree 2 exactly, and it is C1, so the derivative of the reconstruction
 * is continuous across voxel faces. The GPU evaluates the same 64-tap sum with 27 trilinear
 * fetches; in exact arithmetic the two agree, including at the edges: coordinates clamp to
 * [0, res-1] (voxel centres) and taps beyond the grid take the edge voxel (clamp-to-edge),
 * which is what a fetch clamped to the object's texels in the atlas reads.
 *
 * Grids are x fastest, then y, then z. Ownership: the caller owns every buffer.
 */
#ifndef REFRACT_VOXEL_TRICUBIC_H
#define REFRACT_VOXEL_TRICUBIC_H

#include "vec3.h"

/* The four Catmull-Rom weights of the taps floor(c) - 1 .. floor(c) + 2 at fraction t in
 * [0, 1]; they sum to 1. */
void voxel_catmull_rom_weights(double t, double w[4]);

/* Tricubic Catmull-Rom sample of a grid with `comps` values per voxel at continuous voxel
 * coordinates v (voxel centres at integers), each coordinate clamped to [0, res-1].
 * Writes comps doubles to out. */
void voxel_sample_tricubic(const double *grid, int comps, const int res[3], vec3 v, double *out);

#endif
