/*
 * macrocell.c - building the empty-space map; see macrocell.h.
 */
#include "macrocell.h"

#include <math.h>
#include <stdlib.h>

bool macrocell_gradient_free(double gx, double gy, double gz, double h_min)
{
    return sqrt(gx * gx + gy * gy + gz * gz) * h_min <= MACROCELL_GRAD_EPS;
}

static bool any_rgb(const double *v)
{
    return v != NULL && (v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0);
}

bool macrocell_voxel_busy(const double ior_grad[4], double h_min, const double *attenuation,
                          const double *emission, const double *opaque, const double *scattering)
{
    if (!macrocell_gradient_free(ior_grad[0], ior_grad[1], ior_grad[2], h_min))
        return true;
    return any_rgb(attenuation) || any_rgb(emission) || any_rgb(scattering) ||
           (opaque != NULL && opaque[3] != 0.0);
}

size_t macrocell_count(const struct macrocell_map *m)
{
    return (size_t)m->dims[0] * (size_t)m->dims[1] * (size_t)m->dims[2];
}

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

/* The texels a point in the closed cell c can read: voxel coordinates of the cell are
 * [c C, (c + 1) C]; trilinear filtering at coordinate v reads texels floor(v - 0.5) and
 * floor(v - 0.5) + 1 (volume_sample_coord clamps v to [0.5, res - 0.5]), so the cell reads
 * texels c C - 1 .. (c + 1) C; a filter reading b texels on each side reads
 * c C - b .. (c + 1) C + b - 1. */
static bool cell_empty(const double *n, const uint8_t *busy, const int res[3], int cell, int border,
                       const int c[3])
{
    int lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        lo[a] = clampi(c[a] * cell - border, 0, res[a] - 1);
        hi[a] = clampi((c[a] + 1) * cell + border - 1, 0, res[a] - 1);
    }
    double n_min = INFINITY, n_max = -INFINITY;
    for (int z = lo[2]; z <= hi[2]; z++) {
        for (int y = lo[1]; y <= hi[1]; y++) {
            size_t row = ((size_t)z * (size_t)res[1] + (size_t)y) * (size_t)res[0];
            for (int x = lo[0]; x <= hi[0]; x++) {
                if (busy[row + (size_t)x])
                    return false;
                double v = n[row + (size_t)x];
                n_min = fmin(n_min, v);
                n_max = fmax(n_max, v);
            }
        }
    }
    return n_max - n_min <= MACROCELL_N_EPS;
}

enum refract_code macrocell_build(const double *n, const uint8_t *busy, const int res[3], int cell,
                                  int border, struct macrocell_map *out, struct err *e)
{
    out->cell = cell;
    out->empty = NULL;
    out->empty_count = 0;
    for (int a = 0; a < 3; a++)
        out->dims[a] = (res[a] + cell - 1) / cell;
    out->empty = calloc(macrocell_count(out), 1);
    if (out->empty == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the empty-space map");
    int c[3];
    for (c[2] = 0; c[2] < out->dims[2]; c[2]++) {
        for (c[1] = 0; c[1] < out->dims[1]; c[1]++) {
            for (c[0] = 0; c[0] < out->dims[0]; c[0]++) {
                size_t k =
                    ((size_t)c[2] * (size_t)out->dims[1] + (size_t)c[1]) * (size_t)out->dims[0] +
                    (size_t)c[0];
                out->empty[k] = cell_empty(n, busy, res, cell, border, c) ? 1 : 0;
                out->empty_count += out->empty[k];
            }
        }
    }
    return REFRACT_E_OK;
}

void macrocell_free(struct macrocell_map *m)
{
    free(m->empty);
    m->empty = NULL;
}

double macrocell_skip_distance(const struct macrocell_map *m, const double v0[3],
                               const double dv[3], double t_bounds, bool *to_bounds)
{
    int ci[3], stp[3];
    double tmax[3], tdelta[3];
    for (int a = 0; a < 3; a++) {
        double c0 = v0[a] / m->cell, dc = dv[a] / m->cell;
        ci[a] = clampi((int)floor(c0), 0, m->dims[a] - 1);
        if (dc > 0.0) {
            stp[a] = 1;
            tmax[a] = ((double)(ci[a] + 1) - c0) / dc;
            tdelta[a] = 1.0 / dc;
        } else if (dc < 0.0) {
            stp[a] = -1;
            tmax[a] = ((double)ci[a] - c0) / dc;
            tdelta[a] = -1.0 / dc;
        } else {
            stp[a] = 0;
            tmax[a] = tdelta[a] = INFINITY;
        }
    }
    *to_bounds = false;
    double t = 0.0;
    int guard = m->dims[0] + m->dims[1] + m->dims[2] + 3;
    for (int k = 0; k < guard; k++) {
        size_t idx = ((size_t)ci[2] * (size_t)m->dims[1] + (size_t)ci[1]) * (size_t)m->dims[0] +
                     (size_t)ci[0];
        if (!m->empty[idx])
            break;
        int a = tmax[0] <= tmax[1] && tmax[0] <= tmax[2] ? 0 : tmax[1] <= tmax[2] ? 1 : 2;
        t = fmax(t, tmax[a]);
        if (t >= t_bounds) {
            t = t_bounds;
            *to_bounds = true;
            break;
        }
        ci[a] += stp[a];
        tmax[a] += tdelta[a];
        if (ci[a] < 0 || ci[a] >= m->dims[a]) {
            t = t_bounds; /* the cells end at the bounds (or beyond, in a partial cell) */
            *to_bounds = true;
            break;
        }
    }
    return t;
}
