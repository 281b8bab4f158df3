/*
 * test_macrocell.c - the empty-space map (server/core/macrocell.c): which cells are empty
 * (the gradient, constant-n and channel rules over the cell plus its trilinear border,
 * partial cells at the grid's edge), and the DDA jump against a brute-force walk along
 * the ray that samples the map densely.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/macrocell.h"
#include "test.h"

#define R 20 /* voxels per axis: 5 cells of 4, or 3 of 8 (the last one partial) */

static size_t vox(int x, int y, int z)
{
    return ((size_t)z * R + (size_t)y) * R + (size_t)x;
}

static size_t cell_index(const struct macrocell_map *m, int x, int y, int z)
{
    return ((size_t)z * m->dims[1] + (size_t)y) * m->dims[0] + (size_t)x;
}

static void build_border(const double *n, const uint8_t *busy, int cell, int border,
                         struct macrocell_map *m)
{
    struct err e = {0};
    const int res[3] = {R, R, R};
    CHECK_INT(macrocell_build(n, busy, res, cell, border, m, &e), REFRACT_E_OK);
}

static void build(const double *n, const uint8_t *busy, int cell, struct macrocell_map *m)
{
    build_border(n, busy, cell, MACROCELL_BORDER_TRILINEAR, m);
}

static void busy_voxel_marks_its_cell_and_the_neighbours_whose_border_reads_it(void)
{
    static double n[R * R * R];
    static uint8_t busy[R * R * R];
    for (size_t v = 0; v < R * R * R; v++)
        n[v] = 1.33;
    memset(busy, 0, sizeof busy);
    busy[vox(8, 9, 10)] = 1; /* cell (2, 2, 2) of 4; x = 8 is the first texel of cell 2 */
    struct macrocell_map m;
    build(n, busy, 4, &m);
    CHECK_INT(m.dims[0], 5);
    CHECK(!m.empty[cell_index(&m, 2, 2, 2)]);
    /* cell 1 along x reads texels 3..8 (border 8): busy too */
    CHECK(!m.empty[cell_index(&m, 1, 2, 2)]);
    /* cell 3 along x reads texels 11..16: empty */
    CHECK(m.empty[cell_index(&m, 3, 2, 2)]);
    /* along y, 9 is inside cell 2 (8..11): cell 1 reads 3..8, cell 3 reads 11..16 */
    CHECK(m.empty[cell_index(&m, 2, 1, 2)]);
    CHECK(m.empty[cell_index(&m, 2, 3, 2)]);
    CHECK_INT((int)m.empty_count, 125 - 2);
    macrocell_free(&m);
    /* A tricubic footprint (2 texels beyond the cell: cell c reads 4c - 2 .. 4c + 5) reaches
     * (8, 9, 10) from cells 1-2 along x and y and 2-3 along z: 8 cells. */
    build_border(n, busy, 4, MACROCELL_BORDER_TRICUBIC, &m);
    CHECK(!m.empty[cell_index(&m, 2, 1, 2)]);
    CHECK(!m.empty[cell_index(&m, 1, 1, 3)]);
    CHECK(m.empty[cell_index(&m, 3, 2, 2)]);
    CHECK(m.empty[cell_index(&m, 2, 2, 1)]);
    CHECK_INT((int)m.empty_count, 125 - 8);
    macrocell_free(&m);
}

static void alternating_index_with_zero_central_differences_is_not_empty(void)
{
    static double n[R * R * R];
    static uint8_t busy[R * R * R];
    memset(busy, 0, sizeof busy);
    for (int z = 0; z < R; z++)
        for (int y = 0; y < R; y++)
            for (int x = 0; x < R; x++)
                n[vox(x, y, z)] = (x & 1) ? 1.5 : 1.0; /* (n[x+1] - n[x-1]) / 2 = 0 */
    struct macrocell_map m;
    build(n, busy, 8, &m);
    CHECK_INT(m.dims[0], 3); /* ceil(20 / 8) */
    CHECK_INT((int)m.empty_count, 0);
    macrocell_free(&m);
    /* n varying by MACROCELL_N_EPS is constant; twice that is not */
    for (size_t v = 0; v < R * R * R; v++)
        n[v] = 1.0 + ((v % 3) ? 0.0 : MACROCELL_N_EPS);
    build(n, busy, 8, &m);
    CHECK_INT((int)m.empty_count, 27);
    macrocell_free(&m);
    for (size_t v = 0; v < R * R * R; v++)
        n[v] = 1.0 + ((v % 3) ? 0.0 : 2.0 * MACROCELL_N_EPS);
    build(n, busy, 8, &m);
    CHECK_INT((int)m.empty_count, 0);
    macrocell_free(&m);
}

static void voxel_test_sees_gradient_and_every_channel(void)
{
    const double flat[4] = {0, 0, 0, 1.5}, small[4] = {1e-5, 0, 0, 1.5},
                 steep[4] = {3e-5, 0, 0, 1.5};
    const double zero[4] = {0, 0, 0, 0}, red[4] = {0.1, 0, 0, 0}, cover[4] = {0, 0, 0, 0.2};
    const double colour_only[4] = {0.5, 0.5, 0.5, 0};
    double h = 0.05; /* |grad| h: 5e-7 is within MACROCELL_GRAD_EPS, 1.5e-6 is not */
    CHECK(!macrocell_voxel_busy(flat, h, NULL, NULL, NULL, NULL));
    CHECK(!macrocell_voxel_busy(small, h, zero, zero, zero, zero));
    CHECK(macrocell_voxel_busy(steep, h, NULL, NULL, NULL, NULL));
    CHECK(macrocell_voxel_busy(flat, h, red, NULL, NULL, NULL));
    CHECK(macrocell_voxel_busy(flat, h, NULL, red, NULL, NULL));
    CHECK(macrocell_voxel_busy(flat, h, NULL, NULL, NULL, red));
    CHECK(macrocell_voxel_busy(flat, h, NULL, NULL, cover, NULL));
    /* an opaque colour without coverage never stops a ray */
    CHECK(!macrocell_voxel_busy(flat, h, NULL, NULL, colour_only, NULL));
}

/* The empty run from v0 along dv by fine sampling: the first sample in a non-empty cell or
 * past the bounds. */
static double brute_force(const struct macrocell_map *m, const double v0[3], const double dv[3],
                          double t_bounds, bool *to_bounds)
{
    const double dt = 1e-4;
    for (double t = 0.0;; t += dt) {
        if (t >= t_bounds) {
            *to_bounds = true;
            return t_bounds;
        }
        int c[3];
        for (int a = 0; a < 3; a++) {
            c[a] = (int)floor((v0[a] + t * dv[a]) / m->cell);
            c[a] = c[a] < 0 ? 0 : c[a] >= m->dims[a] ? m->dims[a] - 1 : c[a];
        }
        if (!m->empty[cell_index(m, c[0], c[1], c[2])]) {
            *to_bounds = false;
            return t;
        }
    }
}

static void dda_jump_matches_a_dense_walk(void)
{
    static double n[R * R * R];
    static uint8_t busy[R * R * R];
    for (size_t v = 0; v < R * R * R; v++)
        n[v] = 1.0;
    memset(busy, 0, sizeof busy);
    for (int k = 0; k < 6; k++) /* a few busy voxels scattered through the grid */
        busy[vox((7 * k + 3) % R, (11 * k + 5) % R, (13 * k + 2) % R)] = 1;
    struct macrocell_map m;
    build(n, busy, 4, &m);
    srand(7);
    int checked = 0, reached = 0;
    for (int i = 0; i < 400; i++) {
        double v0[3], q[3], len = 0.0;
        for (int a = 0; a < 3; a++) {
            v0[a] = R * (double)rand() / RAND_MAX;
            q[a] = 2.0 * rand() / RAND_MAX - 1.0;
            len += q[a] * q[a];
        }
        double t_bounds = INFINITY, dv[3];
        for (int a = 0; a < 3; a++) {
            q[a] /= sqrt(len);
            dv[a] = q[a] * 10.0; /* 10 voxels per object unit */
            if (dv[a] > 0)
                t_bounds = fmin(t_bounds, (R - v0[a]) / dv[a]);
            else if (dv[a] < 0)
                t_bounds = fmin(t_bounds, -v0[a] / dv[a]);
        }
        bool tb_dda, tb_ref;
        double t = macrocell_skip_distance(&m, v0, dv, t_bounds, &tb_dda);
        double want = brute_force(&m, v0, dv, t_bounds, &tb_ref);
        CHECK_MSG(tb_dda == tb_ref && fabs(t - want) <= 2e-4,
                  "ray %d: dda %g (bounds %d), walk %g (bounds %d)", i, t, tb_dda, want, tb_ref);
        checked++;
        reached += tb_dda;
    }
    CHECK_INT(checked, 400);
    CHECK(reached > 20 && reached < 380); /* both outcomes are exercised */
    macrocell_free(&m);
}

int main(void)
{
    busy_voxel_marks_its_cell_and_the_neighbours_whose_border_reads_it();
    alternating_index_with_zero_central_differences_is_not_empty();
    voxel_test_sees_gradient_and_every_channel();
    dda_jump_matches_a_dense_walk();
    return test_summary("test_macrocell");
}
