/*
 * test_voxel_tricubic.c - the tricubic Catmull-Rom reconstruction and its gradient
 * (core/voxel_tricubic.h, the CPU twin of render.ior_filter "tricubic") against closed
 * forms:
 *   - the weights: partition of unity (w sums to 1, d to 0), interpolation at t = 0 and
 *     1, d the derivative of w;
 *   - quadratic fields (with cross terms, degree 2 per axis) and their gradients
 *     reproduced exactly inside the grid, where all 64 taps are voxels of it;
 *   - linear fields and their gradients exactly everywhere, edge cells included (taps
 *     beyond the grid extrapolate the edge voxels linearly); constants everywhere;
 *   - interpolation: the voxel value at every voxel centre;
 *   - clamping: outside [0, res-1] the value at the clamped coordinate, and the gradient
 *     on the last plane the limit from inside;
 *   - C1 and consistency: on a random grid the returned gradient is continuous across the
 *     planes through voxel centres (where the cubic pieces join) and equals the finite
 *     difference of the returned value, while trilinear's derivative jumps there, so the
 *     check can tell a C0 kernel from a C1 one.
 *
 * Tolerances: 1e-12 for exact reproduction (64 products of O(1) values in double);
 * continuity with offsets of 1e-7 voxels: a C1 gradient moves by O(1e-7 * f''), under
 * 1e-4 here; trilinear's derivative jumps by O(1) on random data. The finite difference
 * (central, step 1e-5) matches to O(1e-10 * f''') + rounding 1e-11.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/smooth.h"
#include "core/voxel_tricubic.h"
#include "test.h"

#define NX 12
#define NY 10
#define NZ 9
#define VOXELS (NX * NY * NZ)

static const int res[3] = {NX, NY, NZ};

/* Four fields (one per component) and their gradients in voxel coordinates: 0 linear,
 * 1-3 quadratic per axis. */
static double field(int c, double x, double y, double z, vec3 *g)
{
    switch (c) {
    case 0:
        *g = (vec3){0.3, -0.2, 0.1};
        return 1.0 + 0.3 * x - 0.2 * y + 0.1 * z;
    case 1:
        *g = (vec3){0.1 * x - 0.07 * y, -0.07 * x + 0.02 * z, 0.06 * z + 0.02 * y};
        return 0.05 * x * x - 0.07 * x * y + 0.03 * z * z + 0.02 * y * z;
    case 2:
        *g = (vec3){0.02 * x * y * y, 0.02 * x * x * y, 0.0};
        return -0.4 + 0.01 * x * x * y * y;
    default:
        *g = (vec3){0.04 * z * z, -0.12 * y, 0.08 * x * z};
        return 2.0 - 0.06 * y * y + 0.04 * x * z * z;
    }
}

static void fill_fields(double *grid)
{
    vec3 g;
    for (int z = 0; z < NZ; z++)
        for (int y = 0; y < NY; y++)
            for (int x = 0; x < NX; x++)
                for (int c = 0; c < 4; c++)
                    grid[((z * NY + y) * NX + x) * 4 + c] = field(c, x, y, z, &g);
}

static double vec_err(vec3 a, vec3 b)
{
    return fmax(fabs(a.x - b.x), fmax(fabs(a.y - b.y), fabs(a.z - b.z)));
}

static void test_weights(void)
{
    double worst_w = 0.0, worst_d = 0.0, worst_fd = 0.0;
    for (int k = 0; k <= 100; k++) {
        double t = k / 100.0, w[4], d[4], wp[4], wm[4], dd[4];
        voxel_catmull_rom_weights(t, w, d);
        worst_w = fmax(worst_w, fabs(w[0] + w[1] + w[2] + w[3] - 1.0));
        worst_d = fmax(worst_d, fabs(d[0] + d[1] + d[2] + d[3]));
        voxel_catmull_rom_weights(t + 1e-6, wp, dd);
        voxel_catmull_rom_weights(t - 1e-6, wm, dd);
        for (int i = 0; i < 4; i++)
            worst_fd = fmax(worst_fd, fabs((wp[i] - wm[i]) / 2e-6 - d[i]));
    }
    CHECK_NEAR(worst_w, 0.0, 1e-15);
    CHECK_NEAR(worst_d, 0.0, 1e-15);
    CHECK_NEAR(worst_fd, 0.0, 1e-8);
    double w0[4], w1[4], d[4];
    voxel_catmull_rom_weights(0.0, w0, d);
    voxel_catmull_rom_weights(1.0, w1, d);
    CHECK_NEAR(w0[0], 0.0, 1e-15);
    CHECK_NEAR(w0[1], 1.0, 1e-15);
    CHECK_NEAR(w0[2], 0.0, 1e-15);
    CHECK_NEAR(w1[2], 1.0, 1e-15);
    CHECK_NEAR(w1[3], 0.0, 1e-15);
}

/* The k-th of n quasi-random points in [lo, hi_x] x [lo, hi_y] x [lo, hi_z]. */
static vec3 point(int k, double lo, double margin)
{
    return (vec3){lo + (NX - 1 - margin - lo) * fmod(k * 0.6180339887, 1.0),
                  lo + (NY - 1 - margin - lo) * fmod(k * 0.7548776662, 1.0),
                  lo + (NZ - 1 - margin - lo) * fmod(k * 0.5698402910, 1.0)};
}

static void test_polynomials(void)
{
    double *g = malloc(sizeof(double) * VOXELS * 4);
    CHECK(g != NULL);
    if (g == NULL)
        return;
    fill_fields(g);
    double worst_q = 0.0, worst_qg = 0.0, worst_l = 0.0, worst_lg = 0.0, worst_centre = 0.0;
    for (int k = 0; k < 400; k++) {
        vec3 v = point(k, 1.0, 1.0); /* [1, res-2]: every tap is a voxel of the grid */
        for (int c = 1; c < 4; c++) {
            vec3 grad, exact_g;
            double s = voxel_tricubic_value_grad(g, 4, c, res, v, &grad);
            worst_q = fmax(worst_q, fabs(s - field(c, v.x, v.y, v.z, &exact_g)));
            worst_qg = fmax(worst_qg, vec_err(grad, exact_g));
        }
        vec3 u = point(k, 0.0, 0.0); /* the whole clamped range */
        if (k < 8)                   /* the corner cells */
            u = (vec3){(k & 1) ? NX - 1.3 : 0.3, (k & 2) ? NY - 1.7 : 0.6,
                       (k & 4) ? NZ - 1.1 : 0.9};
        vec3 grad, exact_g;
        double s = voxel_tricubic_value_grad(g, 4, 0, res, u, &grad);
        worst_l = fmax(worst_l, fabs(s - field(0, u.x, u.y, u.z, &exact_g)));
        worst_lg = fmax(worst_lg, vec_err(grad, exact_g));
    }
    for (int z = 0; z < NZ; z++)
        for (int y = 0; y < NY; y++)
            for (int x = 0; x < NX; x++)
                for (int c = 0; c < 4; c++) {
                    vec3 grad, exact_g;
                    double s = voxel_tricubic_value_grad(g, 4, c, res, (vec3){x, y, z}, &grad);
                    worst_centre = fmax(worst_centre, fabs(s - field(c, x, y, z, &exact_g)));
                }
    printf("quadratics inside: value %.3g, gradient %.3g; linear up to the edges: value %.3g, "
           "gradient %.3g; at voxel centres %.3g\n",
           worst_q, worst_qg, worst_l, worst_lg, worst_centre);
    CHECK_NEAR(worst_q, 0.0, 1e-12);
    CHECK_NEAR(worst_qg, 0.0, 1e-12);
    CHECK_NEAR(worst_l, 0.0, 1e-12);
    CHECK_NEAR(worst_lg, 0.0, 1e-12);
    CHECK_NEAR(worst_centre, 0.0, 1e-12);
    /* Clamped: beyond the grid the value at the clamped coordinate. */
    vec3 ga, gb;
    double a = voxel_tricubic_value_grad(g, 4, 3, res, (vec3){-3.0, 4.3, NZ + 2.0}, &ga);
    double b = voxel_tricubic_value_grad(g, 4, 3, res, (vec3){0.0, 4.3, NZ - 1.0}, &gb);
    CHECK_NEAR(a, b, 1e-15);
    CHECK_NEAR(vec_err(ga, gb), 0.0, 1e-15);
    /* The gradient on the last plane is the limit from inside. */
    double c = voxel_tricubic_value_grad(g, 4, 3, res, (vec3){NX - 1.0 - 1e-9, 4.3, 2.2}, &ga);
    double e = voxel_tricubic_value_grad(g, 4, 3, res, (vec3){NX - 1.0, 4.3, 2.2}, &gb);
    CHECK_NEAR(c, e, 1e-8);
    CHECK_NEAR(vec_err(ga, gb), 0.0, 1e-7);
    /* Constants everywhere, edges included. */
    for (int k = 0; k < VOXELS * 4; k++)
        g[k] = 1.37;
    double worst = 0.0;
    for (int k = 0; k < 200; k++) {
        vec3 grad, v = point(k, -0.5, -0.5);
        double s = voxel_tricubic_value_grad(g, 4, 2, res, v, &grad);
        worst = fmax(worst, fmax(fabs(s - 1.37), vec_err(grad, (vec3){0, 0, 0})));
    }
    CHECK_NEAR(worst, 0.0, 1e-13);
    free(g);
}

/* A deterministic pseudo-random grid (LCG), one component. */
static void fill_random(double *grid)
{
    unsigned s = 12345u;
    for (int k = 0; k < VOXELS; k++) {
        s = s * 1103515245u + 12345u;
        grid[k] = (double)((s >> 8) & 0xffff) / 65535.0;
    }
}

static vec3 unit(int axis, double h)
{
    return (vec3){axis == 0 ? h : 0.0, axis == 1 ? h : 0.0, axis == 2 ? h : 0.0};
}

/* Points on planes through voxel centres (one coordinate an integer), interior and edge. */
static vec3 on_plane(int k, int axis)
{
    vec3 v = {1.0 + 9.0 * fmod(k * 0.41, 1.0), 1.0 + 7.0 * fmod(k * 0.7548776662, 1.0),
              1.0 + 6.0 * fmod(k * 0.5698402910, 1.0)};
    double plane = 1.0 + (k % 6);
    if (axis == 0)
        v.x = plane;
    else if (axis == 1)
        v.y = plane;
    else
        v.z = plane;
    return v;
}

static void test_c1(void)
{
    double *g = malloc(sizeof(double) * VOXELS);
    CHECK(g != NULL);
    if (g == NULL)
        return;
    fill_random(g);
    double jump = 0.0, inconsistent = 0.0, linear_jump = 0.0;
    for (int k = 0; k < 60; k++) {
        for (int axis = 0; axis < 3; axis++) {
            vec3 at = on_plane(k, axis), glo, ghi, gmid, dummy;
            voxel_tricubic_value_grad(g, 1, 0, res, vec3_sub(at, unit(axis, 1e-7)), &glo);
            voxel_tricubic_value_grad(g, 1, 0, res, vec3_add(at, unit(axis, 1e-7)), &ghi);
            jump = fmax(jump, vec_err(glo, ghi));
            /* Consistency: the gradient is the derivative of the value. */
            vec3 off = {0.37, 0.21, 0.44}; /* inside a cell */
            vec3 q = vec3_add(at, off);
            double np =
                voxel_tricubic_value_grad(g, 1, 0, res, vec3_add(q, unit(axis, 1e-5)), &dummy);
            double nm =
                voxel_tricubic_value_grad(g, 1, 0, res, vec3_sub(q, unit(axis, 1e-5)), &dummy);
            voxel_tricubic_value_grad(g, 1, 0, res, q, &gmid);
            double fd = (np - nm) / 2e-5;
            double an = axis == 0 ? gmid.x : (axis == 1 ? gmid.y : gmid.z);
            inconsistent = fmax(inconsistent, fabs(fd - an));
            /* Trilinear's one-sided derivatives at the same plane. */
            const double h = 1e-6;
            double lo, mid, hi;
            voxel_sample_trilinear(g, 1, res, vec3_sub(at, unit(axis, h)), &lo);
            voxel_sample_trilinear(g, 1, res, at, &mid);
            voxel_sample_trilinear(g, 1, res, vec3_add(at, unit(axis, h)), &hi);
            linear_jump = fmax(linear_jump, fabs((hi - mid) / h - (mid - lo) / h));
        }
    }
    printf("gradient jump across voxel-centre planes: tricubic %.3g (trilinear's derivative "
           "%.3g); gradient vs finite difference of the value %.3g\n",
           jump, linear_jump, inconsistent);
    CHECK_MSG(jump < 1e-4, "tricubic gradient jumps by %g", jump);
    CHECK_MSG(inconsistent < 1e-6, "gradient differs from the value's derivative by %g",
              inconsistent);
    CHECK_MSG(linear_jump > 1e-2, "trilinear derivative did not jump (%g): the check is blind",
              linear_jump);
    free(g);
}

int main(void)
{
    test_weights();
    test_polynomials();
    test_c1();
    return test_summary("test_voxel_tricubic");
}
