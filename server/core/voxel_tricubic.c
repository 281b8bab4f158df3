/*
 * voxel_tricubic.c - tricubic Catmull-Rom reconstruction; see voxel_tricubic.h.
 */
#include "voxel_tricubic.h"

#include <math.h>
#include <stddef.h>

void voxel_catmull_rom_weights(double t, double w[4])
{
    double t2 = t * t, t3 = t2 * t;
    w[0] = 0.5 * (-t3 + 2.0 * t2 - t);
    w[1] = 0.5 * (3.0 * t3 - 5.0 * t2 + 2.0);
    w[2] = 0.5 * (-3.0 * t3 + 4.0 * t2 + t);
    w[3] = 0.5 * (t3 - t2);
}

/* The four tap indices (clamped to the grid) and their weights along one axis. */
static void axis_taps(double v, int len, int idx[4], double w[4])
{
    v = fmax(0.0, fmin(v, (double)(len - 1)));
    double i = floor(v);
    voxel_catmull_rom_weights(v - i, w);
    for (int k = 0; k < 4; k++) {
        int j = (int)i - 1 + k;
        idx[k] = j < 0 ? 0 : (j > len - 1 ? len - 1 : j);
    }
}

void voxel_sample_tricubic(const double *grid, int comps, const int res[3], vec3 v, double *out)
{
    int ix[4], iy[4], iz[4];
    double wx[4], wy[4], wz[4];
    axis_taps(v.x, res[0], ix, wx);
    axis_taps(v.y, res[1], iy, wy);
    axis_taps(v.z, res[2], iz, wz);
    size_t sy = (size_t)res[0], sz = (size_t)res[0] * (size_t)res[1];
    for (int c = 0; c < comps; c++)
        out[c] = 0.0;
    for (int k = 0; k < 4; k++) {
        for (int j = 0; j < 4; j++) {
            double wyz = wy[j] * wz[k];
            size_t row = (size_t)iy[j] * sy + (size_t)iz[k] * sz;
            for (int i = 0; i < 4; i++) {
                double wt = wx[i] * wyz;
                const double *cell = grid + (row + (size_t)ix[i]) * (size_t)comps;
                for (int c = 0; c < comps; c++)
                    out[c] += wt * cell[c];
            }
        }
    }
}
