/*
 * smooth.h - double-precision references of the GPU's scene-load kernels
 * (shaders/smooth_ior.comp, shaders/gradient_ior.comp): separable Gaussian smoothing
 * of the refractive index and its central-difference gradient. The algorithm is fixed
 * by docs/tracing.md, "Precomputation"; tests bound the GPU's deviation from these.
 *
 * Grids are x fastest, then y, then z. Ownership: the caller owns every buffer.
 */
#ifndef REFRACT_SMOOTH_H
#define REFRACT_SMOOTH_H

#include "vec3.h"

/* Gaussian with standard deviation sigma_voxels (>= 0; 0 copies), radius ceil(3 sigma),
 * normalised weights, clamp-to-edge, passes x, y, z. in and out hold res[0]*res[1]*res[2]
 * values and may not alias. */
void smooth_gaussian_ref(const float *in, const int res[3], double sigma_voxels, double *out);

/* Central differences of n (tevs2007 eq. 3.1) divided by 2 * voxel_size per axis; at
 * the grid's edges one-sided differences (the clamped neighbour is the voxel itself, and
 * the difference is divided by the distance spanned). out holds 4 doubles per voxel: dn/dx, dn/dy,
 * dn/dz, n. */
void gradient_central_ref(const double *n, const int res[3], vec3 voxel_size, double *out);

/* Trilinear sample of a grid with `comps` values per voxel at continuous voxel
 * coordinates v (voxel centres at integers), each coordinate clamped to [0, res-1].
 * Writes comps doubles to out. */
void voxel_sample_trilinear(const double *grid, int comps, const int res[3], vec3 v, double *out);
/* The same for a float grid (the irradiance volumes read back from the GPU). */
void voxel_sample_trilinear_f(const float *grid, int comps, const int res[3], vec3 v, double *out);

#endif
