/*
 * photon_grid.c - the kernel estimate of the landed photons' irradiance on a sparse
 * lattice over the receiver plane (photon.h, docs/photons.md "Density estimate"):
 * E(x) = sum_p phi_p K(|x - x_p|), Epanechnikov's K(s) = 2 / (pi r^2) (1 - s^2 / r^2) for
 * s < r (a unit integral over the plane), evaluated exactly at every lattice point within r
 * of a photon and kept in an open-addressing hash table; bilinear in between. The GLSL
 * twin of the lookup is photon_irradiance in shaders/photons.glsl.
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
    photon_kernel_estimate_se(l, radius, x, z, E, NULL);
}

void photon_kernel_estimate_se(const struct photon_list *l, double radius, double x, double z,
                               double E[3], double se[3])
{
    double sq[3] = {0.0, 0.0, 0.0};
    E[0] = E[1] = E[2] = 0.0;
    double r2 = radius * radius;
    for (size_t i = 0; i < l->count; i++) {
        const struct photon *p = &l->items[i];
        double dx = p->x - x, dz = p->z - z;
        double k = kernel(dx * dx + dz * dz, r2);
        for (int c = 0; k > 0.0 && c < 3; c++) {
            E[c] += p->power[c] * k;
            sq[c] += p->power[c] * k * p->power[c] * k;
        }
    }
    for (int c = 0; se != NULL && c < 3; c++)
        se[c] = sqrt(sq[c]);
}

/* The lattice index of coordinate v: round(v / h) clamped to +-PHOTON_CELL_MAX. */
static int32_t index_of(double v)
{
    if (!(v > -PHOTON_CELL_MAX))
        return (int32_t)-PHOTON_CELL_MAX;
    if (v > PHOTON_CELL_MAX)
        return (int32_t)PHOTON_CELL_MAX;
    return (int32_t)v;
}

/* The slot of lattice point (i, j): where it is, or the empty slot where it would go. */
static uint32_t find(const struct photon_grid *g, int32_t i, int32_t j, uint32_t *probes)
{
    uint32_t mask = g->capacity - 1u, s = photon_hash(i, j, g->capacity), n = 0;
    while (g->keys[2 * s] != PHOTON_EMPTY_KEY && (g->keys[2 * s] != i || g->keys[2 * s + 1] != j)) {
        s = (s + 1u) & mask;
        n++;
    }
    if (probes)
        *probes = n;
    return s;
}

static enum refract_code table_alloc(struct photon_grid *g, uint32_t capacity, struct err *e)
{
    g->capacity = capacity;
    g->used = 0;
    g->keys = malloc((size_t)capacity * 2 * sizeof *g->keys);
    g->E_double = calloc((size_t)capacity * 3, sizeof *g->E_double);
    if (g->keys == NULL || g->E_double == NULL) {
        free(g->keys);
        free(g->E_double);
        g->keys = NULL;
        g->E_double = NULL;
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "photons: out of memory for a lattice of %u slots", capacity);
    }
    for (size_t s = 0; s < (size_t)capacity * 2; s++)
        g->keys[s] = PHOTON_EMPTY_KEY;
    return REFRACT_E_OK;
}

/* Doubles the table, moving every stored point. */
static enum refract_code grow(struct photon_grid *g, struct err *e)
{
    struct photon_grid old = *g;
    enum refract_code rc = table_alloc(g, old.capacity * 2u, e);
    if (rc != REFRACT_E_OK) {
        *g = old;
        return rc;
    }
    for (uint32_t s = 0; s < old.capacity; s++) {
        if (old.keys[2 * s] == PHOTON_EMPTY_KEY)
            continue;
        uint32_t t = find(g, old.keys[2 * s], old.keys[2 * s + 1], NULL);
        g->keys[2 * t] = old.keys[2 * s];
        g->keys[2 * t + 1] = old.keys[2 * s + 1];
        memcpy(&g->E_double[3 * t], &old.E_double[3 * s], 3 * sizeof(double));
        g->used++;
    }
    free(old.keys);
    free(old.E_double);
    return REFRACT_E_OK;
}

/* Splats every photon onto the lattice points within the radius. */
static enum refract_code splat(const struct photon_list *l, struct photon_grid *g, struct err *e)
{
    double h = g->cell, r2 = g->radius * g->radius;
    int reach = (int)ceil(g->radius / h);
    for (size_t p = 0; p < l->count; p++) {
        const struct photon *ph = &l->items[p];
        double ci = floor(ph->x / h + 0.5), cj = floor(ph->z / h + 0.5);
        for (int dj = -reach; dj <= reach; dj++) {
            for (int di = -reach; di <= reach; di++) {
                int32_t i = index_of(ci + di), j = index_of(cj + dj);
                double dx = i * h - ph->x, dz = j * h - ph->z;
                double w = kernel(dx * dx + dz * dz, r2);
                if (w <= 0.0)
                    continue;
                if (4u * (g->used + 1u) > g->capacity) {
                    if (g->used >= PHOTON_LATTICE_MAX)
                        return REFRACT_E_LIMIT_EXCEEDED; /* the caller coarsens */
                    enum refract_code rc = grow(g, e);
                    if (rc != REFRACT_E_OK)
                        return rc;
                }
                uint32_t s = find(g, i, j, NULL);
                if (g->keys[2 * s] == PHOTON_EMPTY_KEY) {
                    g->keys[2 * s] = i;
                    g->keys[2 * s + 1] = j;
                    g->used++;
                }
                for (int c = 0; c < 3; c++)
                    g->E_double[3 * s + c] += ph->power[c] * w;
            }
        }
    }
    return REFRACT_E_OK;
}

static enum refract_code finish(struct photon_grid *g, struct err *e);

enum refract_code photon_grid_build(const struct photon_list *l, double radius,
                                    struct photon_grid *g, struct err *e)
{
    memset(g, 0, sizeof *g);
    g->radius = radius;
    if (l->count == 0 || !(radius > 0.0) || !isfinite(radius))
        return REFRACT_E_OK;
    /* The spacing: radius / PHOTON_LATTICE_PER_RADIUS, coarser (x 1.5 each time) while the
     * points would exceed PHOTON_LATTICE_MAX (photons scattered thinly over a huge floor). */
    for (double per = PHOTON_LATTICE_PER_RADIUS;; per /= 1.5) {
        g->cell = radius / per;
        uint32_t capacity = 1024;
        while (capacity < 4 * l->count && capacity < 4 * PHOTON_LATTICE_MAX)
            capacity *= 2;
        enum refract_code rc = table_alloc(g, capacity, e);
        if (rc == REFRACT_E_OK)
            rc = splat(l, g, e);
        if (rc == REFRACT_E_OK)
            break;
        free(g->keys);
        free(g->E_double);
        g->keys = NULL;
        g->E_double = NULL;
        if (rc != REFRACT_E_LIMIT_EXCEEDED || per < 0.75) {
            memset(g, 0, sizeof *g);
            return rc == REFRACT_E_LIMIT_EXCEEDED
                       ? err_set(e, rc,
                                 "photons: %zu landed photons need more than %u lattice points "
                                 "even at a spacing of the radius; give a larger "
                                 "receiver.photon_radius",
                                 l->count, PHOTON_LATTICE_MAX)
                       : rc;
        }
    }
    return finish(g, e);
}

/* The GPU's float copy of E and the longest probe sequence, once the table is complete. */
static enum refract_code finish(struct photon_grid *g, struct err *e)
{
    g->probe_max = 0;
    g->E = malloc((size_t)g->capacity * 4 * sizeof *g->E);
    if (g->E == NULL) {
        photon_grid_free(g);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "photons: out of memory for the lattice");
    }
    for (uint32_t s = 0; s < g->capacity; s++) {
        for (int c = 0; c < 3; c++)
            g->E[4 * s + c] = (float)g->E_double[3 * s + c];
        g->E[4 * s + 3] = 0.0f;
        if (g->keys[2 * s] != PHOTON_EMPTY_KEY) {
            uint32_t probes;
            find(g, g->keys[2 * s], g->keys[2 * s + 1], &probes);
            if (probes > g->probe_max)
                g->probe_max = probes;
        }
    }
    return REFRACT_E_OK;
}

enum refract_code photon_grid_from_points(double cell, double radius, uint32_t n,
                                          const int32_t *ij, const double *E,
                                          struct photon_grid *g, struct err *e)
{
    memset(g, 0, sizeof *g);
    g->radius = radius;
    g->cell = cell;
    if (n == 0)
        return REFRACT_E_OK;
    if (n > PHOTON_LATTICE_MAX || !(cell > 0.0) || !isfinite(cell))
        return err_set(e, REFRACT_E_STORAGE,
                       "photons: a lattice of %u points with spacing %g is not one this build "
                       "makes (at most %u points, a positive spacing)",
                       n, cell, PHOTON_LATTICE_MAX);
    uint32_t capacity = 1024;
    while (capacity < 4u * n)
        capacity *= 2u;
    enum refract_code rc = table_alloc(g, capacity, e);
    if (rc != REFRACT_E_OK)
        return rc;
    for (uint32_t p = 0; p < n; p++) {
        int32_t i = ij[2 * p], j = ij[2 * p + 1];
        if (i == PHOTON_EMPTY_KEY || fabs((double)i) > PHOTON_CELL_MAX ||
            fabs((double)j) > PHOTON_CELL_MAX) {
            photon_grid_free(g);
            return err_set(e, REFRACT_E_STORAGE,
                           "photons: lattice point %u has indices out of range", p);
        }
        uint32_t s = find(g, i, j, NULL);
        if (g->keys[2 * s] == PHOTON_EMPTY_KEY) {
            g->keys[2 * s] = i;
            g->keys[2 * s + 1] = j;
            g->used++;
        }
        memcpy(&g->E_double[3 * s], &E[3 * p], 3 * sizeof(double));
    }
    return finish(g, e);
}

void photon_lattice_at(const struct photon_grid *g, int32_t i, int32_t j, double E[3])
{
    E[0] = E[1] = E[2] = 0.0;
    if (g->capacity == 0)
        return;
    uint32_t mask = g->capacity - 1u, s = photon_hash(i, j, g->capacity);
    for (uint32_t n = 0; n <= g->probe_max; n++, s = (s + 1u) & mask) {
        if (g->keys[2 * s] == PHOTON_EMPTY_KEY)
            return;
        if (g->keys[2 * s] == i && g->keys[2 * s + 1] == j) {
            memcpy(E, &g->E_double[3 * s], 3 * sizeof(double));
            return;
        }
    }
}

void photon_irradiance(const struct photon_grid *g, double x, double z, double E[3])
{
    E[0] = E[1] = E[2] = 0.0;
    if (g->capacity == 0)
        return;
    double u = x / g->cell, v = z / g->cell, fu = u - floor(u), fv = v - floor(v);
    int32_t i = index_of(floor(u)), j = index_of(floor(v));
    double e00[3], e10[3], e01[3], e11[3];
    photon_lattice_at(g, i, j, e00);
    photon_lattice_at(g, i + 1, j, e10);
    photon_lattice_at(g, i, j + 1, e01);
    photon_lattice_at(g, i + 1, j + 1, e11);
    for (int c = 0; c < 3; c++)
        E[c] =
            (1 - fv) * ((1 - fu) * e00[c] + fu * e10[c]) + fv * ((1 - fu) * e01[c] + fu * e11[c]);
}

void photon_grid_free(struct photon_grid *g)
{
    free(g->keys);
    free(g->E_double);
    free(g->E);
    memset(g, 0, sizeof *g);
}
