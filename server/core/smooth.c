/*
 * smooth.c - the double-precision references of the scene-load kernels: separable
 * Gaussian smoothing of the refractive index, its central-difference gradient, and the
 * trilinear sampling the GPU's texture units perform. docs/tracing.md "Precomputation"
 * (tevs2007 sect. 3.1) fixes every detail; this file is that text in C.
 *
 * It is not fast: it is what the GPU output is compared against, and what the
 * reference tracer samples. Grids are x fastest, then y, then z.
 */
#include "smooth.h"

#include <math.h>
#include <stdlib.h>

static size_t voxel_count(const int res[3])
{
    return (size_t)res[0] * (size_t)res[1] * (size_t)res[2];
}

static int clamp_index(int i, int n)
{
    return i < 0 ? 0 : (i >= n ? n - 1 : i);
}

/* One 1D pass along `axis`, in place in `grid`, using `line` (length >= res[axis]) as
 * scratch: out[i] = sum_k w[k + r] * in[clamp(i + k)], k = -r..r. */
static void convolve_axis(double *grid, const int res[3], int axis, const double *w, int r,
                          double *line)
{
    size_t stride = axis == 0 ? 1 : (axis == 1 ? (size_t)res[0] : (size_t)res[0] * res[1]);
    int len = res[axis];
    /* The two axes that are not `axis`, in x-fastest order. */
    int a1 = axis == 0 ? 1 : 0;
    int a2 = axis == 2 ? 1 : 2;
    size_t stride1 = a1 == 0 ? 1 : (size_t)res[0];
    size_t stride2 = a2 == 1 ? (size_t)res[0] : (size_t)res[0] * res[1];
    for (int j2 = 0; j2 < res[a2]; j2++) {
        for (int j1 = 0; j1 < res[a1]; j1++) {
            double *base = grid + (size_t)j1 * stride1 + (size_t)j2 * stride2;
            for (int i = 0; i < len; i++)
                line[i] = base[(size_t)i * stride];
            for (int i = 0; i < len; i++) {
                double acc = 0.0;
                for (int k = -r; k <= r; k++)
                    acc += w[k + r] * line[clamp_index(i + k, len)];
                base[(size_t)i * stride] = acc;
            }
        }
    }
}

/* On allocation failure (a few KB of scratch) `out` is filled with NaN rather than left
 * unsmoothed, so the failure cannot pass for a result: the scene loader rejects
 * non-finite grids. */
void smooth_gaussian_ref(const float *in, const int res[3], double sigma_voxels, double *out)
{
    size_t count = voxel_count(res);
    for (size_t i = 0; i < count; i++)
        out[i] = (double)in[i];
    if (!(sigma_voxels > 0.0))
        return; /* sigma = 0 skips smoothing */

    /* Kernel radius r = ceil(3 sigma); w_k = exp(-k^2 / (2 sigma^2)) normalised to sum 1.
     * sigma is a standard deviation in voxels (tevs2007 eq. 3.2 writes exp(-(x/s)^2),
     * whose s is sqrt(2) sigma). */
    int r = (int)ceil(3.0 * sigma_voxels);
    int max_len = res[0] > res[1] ? res[0] : res[1];
    max_len = res[2] > max_len ? res[2] : max_len;
    double *w = malloc(sizeof(double) * ((size_t)(2 * r + 1) + (size_t)max_len));
    if (w == NULL) {
        for (size_t i = 0; i < count; i++)
            out[i] = NAN;
        return;
    }
    double *line = w + 2 * r + 1;
    double sum = 0.0;
    for (int k = -r; k <= r; k++) {
        w[k + r] = exp(-(double)k * k / (2.0 * sigma_voxels * sigma_voxels));
        sum += w[k + r];
    }
    for (int k = -r; k <= r; k++)
        w[k + r] /= sum;
    /* Passes in x, then y, then z (the order matters only to rounding). */
    for (int axis = 0; axis < 3; axis++)
        convolve_axis(out, res, axis, w, r, line);
    free(w);
}

void gradient_central_ref(const double *n, const int res[3], vec3 voxel_size, double *out)
{
    double inv_h[3] = {1.0 / voxel_size.x, 1.0 / voxel_size.y, 1.0 / voxel_size.z};
    size_t sy = (size_t)res[0];
    size_t sz = (size_t)res[0] * res[1];
    for (int z = 0; z < res[2]; z++) {
        for (int y = 0; y < res[1]; y++) {
            for (int x = 0; x < res[0]; x++) {
                size_t idx = (size_t)x + y * sy + z * sz;
                /* tevs2007 eq. 3.1; at the grid's edges the neighbour outside is
                 * replaced by the voxel itself and the difference divided by the distance
                 * actually spanned (one-sided differences), so a linear field keeps its
                 * slope up to the bounds. */
                int x0 = clamp_index(x - 1, res[0]), x1 = clamp_index(x + 1, res[0]);
                int y0 = clamp_index(y - 1, res[1]), y1 = clamp_index(y + 1, res[1]);
                int z0 = clamp_index(z - 1, res[2]), z1 = clamp_index(z + 1, res[2]);
                size_t xm = (size_t)x0 + y * sy + z * sz, xp = (size_t)x1 + y * sy + z * sz;
                size_t ym = (size_t)x + y0 * sy + z * sz, yp = (size_t)x + y1 * sy + z * sz;
                size_t zm = (size_t)x + y * sy + z0 * sz, zp = (size_t)x + y * sy + z1 * sz;
                out[4 * idx + 0] = x1 > x0 ? (n[xp] - n[xm]) * inv_h[0] / (x1 - x0) : 0.0;
                out[4 * idx + 1] = y1 > y0 ? (n[yp] - n[ym]) * inv_h[1] / (y1 - y0) : 0.0;
                out[4 * idx + 2] = z1 > z0 ? (n[zp] - n[zm]) * inv_h[2] / (z1 - z0) : 0.0;
                out[4 * idx + 3] = n[idx];
            }
        }
    }
}

/* Splits a continuous voxel coordinate into a lower index and a weight, clamping to
 * [0, len - 1] like GL_CLAMP_TO_EDGE does for texel centres. fmin/fmax also map NaN to
 * the edge, so no NaN reaches the int conversion. */
static void axis_weights(double v, int len, int *i0, int *i1, double *f)
{
    v = fmax(0.0, fmin(v, (double)(len - 1)));
    int i = (int)floor(v);
    if (i > len - 2)
        i = len - 2 < 0 ? 0 : len - 2;
    *i0 = i;
    *i1 = i + 1 < len ? i + 1 : i;
    *f = v - (double)i;
    if (*i1 == *i0)
        *f = 0.0;
}

/* The 8 corner voxels (indices into a grid of res) and trilinear weights at v. */
static void trilinear_corners(const int res[3], vec3 v, size_t cell[8], double w[8])
{
    int x0, x1, y0, y1, z0, z1;
    double fx, fy, fz;
    axis_weights(v.x, res[0], &x0, &x1, &fx);
    axis_weights(v.y, res[1], &y0, &y1, &fy);
    axis_weights(v.z, res[2], &z0, &z1, &fz);
    size_t sy = (size_t)res[0];
    size_t sz = (size_t)res[0] * res[1];
    const int xs[2] = {x0, x1}, ys[2] = {y0, y1}, zs[2] = {z0, z1};
    const double wx[2] = {1.0 - fx, fx}, wy[2] = {1.0 - fy, fy}, wz[2] = {1.0 - fz, fz};
    for (int k = 0; k < 2; k++) {
        for (int j = 0; j < 2; j++) {
            for (int i = 0; i < 2; i++) {
                w[k * 4 + j * 2 + i] = wx[i] * wy[j] * wz[k];
                cell[k * 4 + j * 2 + i] = (size_t)xs[i] + ys[j] * sy + zs[k] * sz;
            }
        }
    }
}

void voxel_sample_trilinear(const double *grid, int comps, const int res[3], vec3 v, double *out)
{
    size_t cell[8];
    double w[8];
    trilinear_corners(res, v, cell, w);
    for (int c = 0; c < comps; c++)
        out[c] = 0.0;
    for (int k = 0; k < 8; k++)
        for (int c = 0; c < comps; c++)
            out[c] += w[k] * grid[cell[k] * comps + c];
}

void voxel_sample_trilinear_f(const float *grid, int comps, const int res[3], vec3 v, double *out)
{
    size_t cell[8];
    double w[8];
    trilinear_corners(res, v, cell, w);
    for (int c = 0; c < comps; c++)
        out[c] = 0.0;
    for (int k = 0; k < 8; k++)
        for (int c = 0; c < comps; c++)
            out[c] += w[k] * (double)grid[cell[k] * comps + c];
}
