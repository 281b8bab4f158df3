/*
 * voxel_bspline.h - tricubic B-spline reconstruction of a voxel grid in double precision:
 * the CPU twin of shaders/volume_sample.glsl's tricubic volume_sample_ior_grad
 * (render.ior_filter "tricubic", docs/tracing.md "Index filter").
 *
 * The voxel values are the coefficients of a uniform cubic B-spline (no prefilter), so
 * the reconstruction is C2 and reproduces constants and linear fields exactly, but it
 * approximates rather than interpolates: it adds the spline's variance of 1/3 voxel^2 per
 * axis, i.e. f + f''/6 per axis in voxel units for a quadratic (Unser 1999, "Splines: a
 * perfect fit for signal and image processing"). The GPU evaluates the same 64-tap sum
 * with 8 trilinear fetches (Sigg & Hadwiger 2005, GPU Gems 2 ch. 20); in exact
 * arithmetic the two agree, including at the edges: coordinates clamp to [0, res-1] (voxel
 * centres) and taps beyond the grid take the edge voxel (clamp-to-edge), which is what a
 * trilinear fetch clamped to the object's texels in the atlas reads.
 *
 * Grids are x fastest, then y, then z. Ownership: the caller owns every buffer.
 */
#ifndef REFRACT_VOXEL_BSPLINE_H
#define REFRACT_VOXEL_BSPLINE_H

#include "vec3.h"

/* The four cubic B-spline weights of the taps floor(c) - 1 .. floor(c) + 2 at fraction
 * t in [0, 1]; they sum to 1. */
void voxel_bspline_weights(double t, double w[4]);

/* Tricubic B-spline sample of a grid with `comps` values per voxel at continuous voxel
 * coordinates v (voxel centres at integers), each coordinate clamped to [0, res-1].
 * Writes comps doubles to out. */
void voxel_sample_bspline(const double *grid, int comps, const int res[3], vec3 v, double *out);

#endif
