/*
 * voxel_tricubic.c - tricubic Catmull-Rom reconstruction and its gradient; see
 * voxel_tricubic.h.
 */
#include "voxel_tricubic.h"

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

void voxel_catmull_rom_weights(double t, double w[4], double d[4])
{
    double t2 = t * t, t3 = t2 * t;
    w[0] = 0.5 * (-t3 + 2.0 * t2 - t);
    w[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
    w[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
    w[3] = 0.5 * (t3 - t2);
    d[0] = 0.5 * (-3.0 * t2 + 4.0 * t - 1.0);
    d[1] = 0.5 * (9.0 * t2 - 10.0 * t);
    d[2] = 0.5 * (-9.0 * t2 + 8.0 * t + 1.0);
    d[3] = 0.5 * (3.0 * t2 - 2.0 * t);
}

/* Folds the weight of a tap beyond the grid into the edge voxels it extrapolates from:
 * f[-1] = 2 f[0] - f[1] (below) and f[len] = 2 f[len-1] - f[len-2] (above). */
static void fold_edges(bool below, bool above, double w[4])
{
    if (below) {
        w[1] += 2.0 * w[0];
        w[2] -= w[0];
        w[0] = 0.0;
    }
    if (above) {
        w[2] += 2.0 * w[3];
        w[1] -= w[3];
        w[3] = 0.0;
    }
}

/* The taps (clamped indices) and weights along one axis. The cell is [i, i+1] with
 * i <= len-2, so at v = len-1 it is the last cell at t = 1 (the GPU does the same). */
static void axis_taps(double v, int len, int idx[4], double w[4], double d[4])
{
    v = fmax(0.0, fmin(v, (double)(len - 1)));
    double i = fmax(0.0, fmin(floor(v), (double)(len - 2)));
    voxel_catmull_rom_weights(v - i, w, d);
    bool below = i<1.0, above = i + 2.0>(double)(len - 1);
    fold_edges(below, above, w);
    fold_edges(below, above, d);
    for (int k = 0; k < 4; k++) {
        int j = (int)i - 1 + k;
        idx[k] = j < 0 ? 0 : (j > len - 1 ? len - 1 : j);
    }
}

double voxel_tricubic_value_grad(const double *grid, int comps, int comp, const int res[3], vec3 v,
                                 vec3 *grad_per_voxel)
{
    int ix[4], iy[4], iz[4];
    double wx[4], wy[4], wz[4], dx[4], dy[4], dz[4];
    axis_taps(v.x, res[0], ix, wx, dx);
    axis_taps(v.y, res[1], iy, wy, dy);
    axis_taps(v.z, res[2], iz, wz, dz);
    size_t sy = (size_t)res[0], sz = (size_t)res[0] * (size_t)res[1];
    double n = 0.0, gx = 0.0, gy = 0.0, gz = 0.0;
    for (int k = 0; k < 4; k++) {
        for (int j = 0; j < 4; j++) {
            size_t row = (size_t)iy[j] * sy + (size_t)iz[k] * sz;
            double r = 0.0, r_dx = 0.0;
            for (int i = 0; i < 4; i++) {
                double f = grid[(row + (size_t)ix[i]) * (size_t)comps + (size_t)comp];
                r += wx[i] * f;
                r_dx += dx[i] * f;
            }
            n += wy[j] * wz[k] * r;
            gx += wy[j] * wz[k] * r_dx;
            gy += dy[j] * wz[k] * r;
            gz += wy[j] * dz[k] * r;
        }
    }
    *grad_per_voxel = (vec3){gx, gy, gz};
    return n;
}
