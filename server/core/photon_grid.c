/*
 * photon_grid.c - the landed photons in a hash grid over the receiver plane and the kernel
 * estimate of their irradiance (photon.h, docs/photons.md "Density estimate"):
 * E(x) = sum_p phi_p K(|x - x_p|), Epanechnikov's K(s) = 2 / (pi r^2) (1 - s^2 / r^2) for
 * s < r, a unit integral over the plane. The GLSL twin of the gather is photon_irradiance
 * in shaders/photons.glsl.
 */
#include "photon.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double kernel(double s2, double r2)
{
    return s2 < r2 ? 2.0 / (M_PI * r2) * (1.0 - s2 / r2) : 0.0;
}

void photon_kernel_estimate(const struct photon_list *l, double radius, double x, double z,
                            double E[3])
{
    E[0] = E[1] = E[2] = 0.0;
    double r2 = radius * radius;
    for (size_t i = 0; i < l->count; i++) {
        const struct photon *p = &l->items[i];
        double dx = p->x - x, dz = p->z - z;
        double k = kernel(dx * dx + dz * dz, r2);
        for (int c = 0; k > 0.0 && c < 3; c++)
            E[c] += p->power[c] * k;
    }
}

/* The cell index of coordinate v: floor(v / cell), clamped to +-PHOTON_CELL_MAX. */
static int32_t cell_of(double v, double cell)
{
    double c = floor(v / cell);
    if (!(c > -PHOTON_CELL_MAX))
        c = -PHOTON_CELL_MAX;
    if (c > PHOTON_CELL_MAX)
        c = PHOTON_CELL_MAX;
    return (int32_t)c;
}

static uint32_t bucket_of(const struct photon_grid *g, double x, double z)
{
    return photon_hash(cell_of(x, g->cell), cell_of(z, g->cell), g->buckets);
}

enum refract_code photon_grid_build(const struct photon_list *l, double radius,
                                    struct photon_grid *g, struct err *e)
{
    memset(g, 0, sizeof *g);
    g->radius = radius;
    g->cell = radius * (1.0 + PHOTON_CELL_SLACK);
    if (l->count == 0 || !(radius > 0.0) || !isfinite(radius))
        return REFRACT_E_OK;
    if (l->count > (size_t)1 << 30)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED, "photons: %zu landed, more than 2^30",
                       l->count);
    uint32_t buckets = 1024;
    while (buckets < 2 * l->count)
        buckets *= 2;
    g->buckets = buckets;
    g->count = l->count;
    g->start = calloc((size_t)buckets + 1, sizeof *g->start);
    g->sorted = malloc(l->count * sizeof *g->sorted);
    g->gpu = malloc(l->count * 8 * sizeof *g->gpu);
    uint32_t *bucket = malloc(l->count * sizeof *bucket);
    if (g->start == NULL || g->sorted == NULL || g->gpu == NULL || bucket == NULL) {
        free(bucket);
        photon_grid_free(g);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "photons: out of memory for %zu photons",
                       l->count);
    }
    /* counting sort by bucket */
    for (size_t i = 0; i < l->count; i++) {
        bucket[i] = bucket_of(g, l->items[i].x, l->items[i].z);
        g->start[bucket[i] + 1]++;
    }
    for (uint32_t b = 0; b < buckets; b++)
        g->start[b + 1] += g->start[b];
    for (size_t i = 0; i < l->count; i++) {
        uint32_t at = g->start[bucket[i]]++;
        g->sorted[at] = l->items[i];
    }
    for (uint32_t b = buckets; b > 0; b--) /* the increments moved each start to the next's */
        g->start[b] = g->start[b - 1];
    g->start[0] = 0;
    free(bucket);
    for (size_t i = 0; i < l->count; i++) {
        const struct photon *p = &g->sorted[i];
        float *q = &g->gpu[8 * i];
        q[0] = (float)p->x;
        q[1] = (float)p->z;
        q[2] = q[3] = q[7] = 0.0f;
        for (int c = 0; c < 3; c++)
            q[4 + c] = (float)p->power[c];
    }
    return REFRACT_E_OK;
}

void photon_irradiance(const struct photon_grid *g, double x, double z, double E[3])
{
    E[0] = E[1] = E[2] = 0.0;
    if (g->buckets == 0)
        return;
    int32_t ci = cell_of(x, g->cell), cj = cell_of(z, g->cell);
    uint32_t seen[9];
    int n_seen = 0;
    double r2 = g->radius * g->radius;
    for (int dj = -1; dj <= 1; dj++) {
        for (int di = -1; di <= 1; di++) {
            uint32_t b = photon_hash(ci + di, cj + dj, g->buckets);
            bool dup = false;
            for (int k = 0; k < n_seen; k++)
                dup = dup || seen[k] == b;
            if (dup)
                continue; /* two cells in one bucket: its photons count once */
            seen[n_seen++] = b;
            for (uint32_t k = g->start[b]; k < g->start[b + 1]; k++) {
                const struct photon *p = &g->sorted[k];
                double dx = p->x - x, dz = p->z - z;
                double w = kernel(dx * dx + dz * dz, r2);
                for (int c = 0; w > 0.0 && c < 3; c++)
                    E[c] += p->power[c] * w;
            }
        }
    }
}

void photon_grid_free(struct photon_grid *g)
{
    free(g->start);
    free(g->sorted);
    free(g->gpu);
    memset(g, 0, sizeof *g);
}
