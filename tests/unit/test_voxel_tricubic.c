/*
 * test_voxel_tricubic.c - the tricubic Catmull-Rom reconstruction (core/voxel_tricubic.h,
 * the CPU twin of render.ior_filter "tricubic") against closed forms:
 *   - the weights: partition of unity, interpolation at t = 0 and 1;
 *   - quadratic fields (with cross terms) reproduced exactly inside the grid, where all
 *     64 taps are real voxels; constants reproduced exactly everywhere, edges included;
 *   - interpolation: the voxel value at every voxel centre;
 *   - clamping: outside [0, res-1] the value at the clamped coordinate;
 *   - the chain the renderer uses: central differences (gradient_central_ref) of a
 *     quadratic index, reconstructed, give n and grad n exactly;
 *   - C1: on a random grid the one-sided derivatives meet at the planes through voxel
 *     centres (where the cubic pieces join), while trilinear's jump there, so the check
 *     can tell a C0 kernel from a C1 one.
 *
 * Tolerances: 1e-12 for exact reproduction (64 products of O(1) values in double);
 * derivative continuity with a one-sided difference of step 1e-6 voxels: the C1 kernel's
 * mismatch is O(step) = 1e-5, trilinear's O(1) on random data.
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

static double quad(int c, double x, double y, double z)
{
    switch (c) {
    case 0:
        return 1.0 + 0.3 * x - 0.2 * y + 0.1 * z;
    case 1:
        return 0.05 * x * x - 0.07 * x * y + 0.03 * z * z + 0.02 * y * z;
    case 2:
        return -0.4 + 0.01 * x * x * y * y; /* degree 2 per axis: tensor product reproduces */
    default:
        return 2.0 - 0.06 * y * y + 0.04 * x * z * z;
    }
}

static void fill_quadratic(double *grid)
{
    for (int z = 0; z < NZ; z++)
        for (int y = 0; y < NY; y++)
            for (int x = 0; x < NX; x++)
                for (int c = 0; c < 4; c++)
                    grid[((z * NY + y) * NX + x) * 4 + c] = quad(c, x, y, z);
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

static void test_weights(void)
{
    double worst = 0.0;
    for (int k = 0; k <= 100; k++) {
        double w[4];
        voxel_catmull_rom_weights(k / 100.0, w);
        worst = fmax(worst, fabs(w[0] + w[1] + w[2] + w[3] - 1.0));
    }
    CHECK_NEAR(worst, 0.0, 1e-15);
    double w0[4], w1[4];
    voxel_catmull_rom_weights(0.0, w0);
    voxel_catmull_rom_weights(1.0, w1);
    CHECK_NEAR(w0[0], 0.0, 1e-15);
    CHECK_NEAR(w0[1], 1.0, 1e-15);
    CHECK_NEAR(w0[2], 0.0, 1e-15);
    CHECK_NEAR(w1[2], 1.0, 1e-15);
    CHECK_NEAR(w1[3], 0.0, 1e-15);
}

static void test_quadratic(void)
{
    double *g = malloc(sizeof(double) * VOXELS * 4);
    CHECK(g != NULL);
    if (g == NULL)
        return;
    fill_quadratic(g);
    double worst = 0.0, worst_centre = 0.0;
    for (int k = 0; k < 400; k++) {
        /* Inside [1, res-2]: every tap is a voxel of the grid. */
        vec3 v = {1.0 + (NX - 3) * fmod(k * 0.6180339887, 1.0),
                  1.0 + (NY - 3) * fmod(k * 0.7548776662, 1.0),
                  1.0 + (NZ - 3) * fmod(k * 0.5698402910, 1.0)};
        double s[4];
        voxel_sample_tricubic(g, 4, res, v, s);
        for (int c = 0; c < 4; c++)
            worst = fmax(worst, fabs(s[c] - quad(c, v.x, v.y, v.z)));
    }
    for (int z = 0; z < NZ; z++)
        for (int y = 0; y < NY; y++)
            for (int x = 0; x < NX; x++) {
                double s[4];
                voxel_sample_tricubic(g, 4, res, (vec3){x, y, z}, s);
                for (int c = 0; c < 4; c++)
                    worst_centre = fmax(worst_centre, fabs(s[c] - quad(c, x, y, z)));
            }
    printf("quadratic: worst error inside %.3g, at voxel centres %.3g\n", worst, worst_centre);
    CHECK_NEAR(worst, 0.0, 1e-12);
    CHECK_NEAR(worst_centre, 0.0, 1e-12);
    /* Clamped: beyond the grid the value at the clamped coordinate. */
    double a[4], b[4];
    voxel_sample_tricubic(g, 4, res, (vec3){-3.0, 4.3, NZ + 2.0}, a);
    voxel_sample_tricubic(g, 4, res, (vec3){0.0, 4.3, NZ - 1.0}, b);
    for (int c = 0; c < 4; c++)
        CHECK_NEAR(a[c], b[c], 1e-15);
    /* Constants everywhere, edges included (partition of unity with clamped taps). */
    for (int k = 0; k < VOXELS * 4; k++)
        g[k] = 1.37;
    worst = 0.0;
    for (int k = 0; k < 200; k++) {
        vec3 v = {-0.5 + (NX)*fmod(k * 0.31, 1.0), -0.5 + (NY)*fmod(k * 0.77, 1.0),
                  -0.5 + (NZ)*fmod(k * 0.53, 1.0)};
        double s[4];
        voxel_sample_tricubic(g, 4, res, v, s);
        worst = fmax(worst, fabs(s[0] - 1.37));
    }
    CHECK_NEAR(worst, 0.0, 1e-13);
    free(g);
}

/* n = 1.3 + 0.02 x^2 - 0.01 y z + 0.015 z^2 (object units, voxel size (0.1, 0.2, 0.15)):
 * central differences of a quadratic are exact, and the reconstruction reproduces both
 * the quadratic n and its linear gradient. */
static void test_gradient_chain(void)
{
    const vec3 vs = {0.1, 0.2, 0.15};
    double *n = malloc(sizeof(double) * VOXELS), *ng = malloc(sizeof(double) * VOXELS * 4);
    CHECK(n != NULL && ng != NULL);
    if (n == NULL || ng == NULL) {
        free(n);
        free(ng);
        return;
    }
    for (int z = 0; z < NZ; z++)
        for (int y = 0; y < NY; y++)
            for (int x = 0; x < NX; x++) {
                double px = x * vs.x, py = y * vs.y, pz = z * vs.z;
                n[(z * NY + y) * NX + x] = 1.3 + 0.02 * px * px - 0.01 * py * pz + 0.015 * pz * pz;
            }
    gradient_central_ref(n, res, vs, ng);
    double worst_n = 0.0, worst_g = 0.0, worst_lin = 0.0;
    for (int k = 0; k < 300; k++) {
        /* Inside [2, res-3]: the taps' central differences are interior ones. */
        vec3 v = {2.0 + (NX - 5) * fmod(k * 0.6180339887, 1.0),
                  2.0 + (NY - 5) * fmod(k * 0.7548776662, 1.0),
                  2.0 + (NZ - 5) * fmod(k * 0.5698402910, 1.0)};
        double px = v.x * vs.x, py = v.y * vs.y, pz = v.z * vs.z;
        double exact_n = 1.3 + 0.02 * px * px - 0.01 * py * pz + 0.015 * pz * pz;
        vec3 exact_g = {0.04 * px, -0.01 * pz, -0.01 * py + 0.03 * pz};
        double s[4], l[4];
        voxel_sample_tricubic(ng, 4, res, v, s);
        voxel_sample_trilinear(ng, 4, res, v, l);
        worst_n = fmax(worst_n, fabs(s[3] - exact_n));
        worst_lin = fmax(worst_lin, fabs(l[3] - exact_n));
        worst_g = fmax(worst_g, fmax(fabs(s[0] - exact_g.x),
                                     fmax(fabs(s[1] - exact_g.y), fabs(s[2] - exact_g.z))));
    }
    printf("quadratic index: tricubic n error %.3g, grad error %.3g; trilinear n error %.3g\n",
           worst_n, worst_g, worst_lin);
    CHECK_NEAR(worst_n, 0.0, 1e-12);
    CHECK_NEAR(worst_g, 0.0, 1e-12);
    /* Trilinear does not reproduce a quadratic (its error is t (1 - t) / 2 f'' per axis):
     * the closed form above can tell the kernels apart. */
    CHECK_MSG(worst_lin > 1e-6, "trilinear reproduced a quadratic (%g)", worst_lin);
    free(n);
    free(ng);
}

typedef void (*sample_fn)(const double *grid, int comps, const int r[3], vec3 v, double *out);

/* The largest mismatch of the one-sided x, y and z derivatives at planes through voxel
 * centres, over interior points of a random grid. */
static double derivative_jump(sample_fn sample, const double *g)
{
    const double h = 1e-6;
    double worst = 0.0;
    for (int k = 0; k < 60; k++) {
        vec3 v = {2.0 + (k % 7), 2.0 + 5.0 * fmod(k * 0.7548776662, 1.0),
                  2.0 + 4.0 * fmod(k * 0.5698402910, 1.0)};
        for (int axis = 0; axis < 3; axis++) {
            vec3 at = v;
            if (axis == 1)
                at = (vec3){2.0 + 7.0 * fmod(k * 0.41, 1.0), 2.0 + (k % 5), v.z};
            if (axis == 2)
                at = (vec3){2.0 + 7.0 * fmod(k * 0.29, 1.0), v.y, 2.0 + (k % 4)};
            vec3 d = {axis == 0 ? h : 0.0, axis == 1 ? h : 0.0, axis == 2 ? h : 0.0};
            double lo, mid, hi;
            sample(g, 1, res, vec3_sub(at, d), &lo);
            sample(g, 1, res, at, &mid);
            sample(g, 1, res, vec3_add(at, d), &hi);
            worst = fmax(worst, fabs((hi - mid) / h - (mid - lo) / h));
        }
    }
    return worst;
}

static void test_c1(void)
{
    double *g = malloc(sizeof(double) * VOXELS);
    CHECK(g != NULL);
    if (g == NULL)
        return;
    fill_random(g);
    double cubic = derivative_jump(voxel_sample_tricubic, g);
    double linear = derivative_jump(voxel_sample_trilinear, g);
    printf("derivative jump across voxel-centre planes: tricubic %.3g, trilinear %.3g\n", cubic,
           linear);
    CHECK_MSG(cubic < 1e-4, "tricubic derivative jumps by %g", cubic);
    CHECK_MSG(linear > 1e-2, "trilinear derivative did not jump (%g): the check is blind", linear);
    free(g);
}

int main(void)
{
    test_weights();
    test_quadratic();
    test_gradient_chain();
    test_c1();
    return test_summary("test_voxel_tricubic");
}
