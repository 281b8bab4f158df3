/*
 * test_smooth.c - the Gaussian smoothing, central-difference gradient and trilinear
 * sampling references of docs/tracing.md "Precomputation" against closed forms.
 *
 * Tolerances: 1e-12 absolute on values of order 1 (sums of a few dozen products,
 * rounding only). The input is float, so test values are chosen exactly representable.
 */
#include <math.h>
#include <stdlib.h>

#include "core/smooth.h"
#include "test.h"

#define N 12

static const int res_cube[3] = {N, N, N};

static size_t idx(int x, int y, int z)
{
    return (size_t)x + (size_t)N * ((size_t)y + (size_t)N * (size_t)z);
}

static void constant_field_is_unchanged_by_smoothing(void)
{
    float *in = malloc(sizeof(float) * N * N * N);
    double *out = malloc(sizeof(double) * N * N * N);
    for (int i = 0; i < N * N * N; i++)
        in[i] = 1.375f;
    smooth_gaussian_ref(in, res_cube, 1.7, out);
    double worst = 0.0;
    for (int i = 0; i < N * N * N; i++)
        worst = fmax(worst, fabs(out[i] - 1.375));
    CHECK_NEAR(worst, 0.0, 1e-12);
    free(in);
    free(out);
}

static void sigma_zero_copies_the_input(void)
{
    float *in = malloc(sizeof(float) * N * N * N);
    double *out = malloc(sizeof(double) * N * N * N);
    for (int i = 0; i < N * N * N; i++)
        in[i] = (float)(i % 7) * 0.25f;
    smooth_gaussian_ref(in, res_cube, 0.0, out);
    int diff = 0;
    for (int i = 0; i < N * N * N; i++)
        diff += out[i] != (double)in[i];
    CHECK_INT(diff, 0);
    free(in);
    free(out);
}

/* An impulse at the centre, away from the edges (radius ceil(3 * 1.2) = 4 < 6): the
 * weights are normalised, so the total is preserved, and the result is the separable
 * product of the 1D kernel w_k = exp(-k^2 / (2 s^2)) / sum_j exp(-j^2 / (2 s^2)). */
static void impulse_spreads_as_normalised_gaussian_and_keeps_its_sum(void)
{
    const double s = 1.2;
    float *in = calloc(N * N * N, sizeof(float));
    double *out = malloc(sizeof(double) * N * N * N);
    in[idx(6, 6, 6)] = 1.0f;
    smooth_gaussian_ref(in, res_cube, s, out);
    double total = 0.0;
    for (int i = 0; i < N * N * N; i++)
        total += out[i];
    CHECK_NEAR(total, 1.0, 1e-12);

    int r = (int)ceil(3.0 * s);
    double norm = 0.0;
    for (int k = -r; k <= r; k++)
        norm += exp(-k * k / (2.0 * s * s));
    for (int k = 0; k <= r + 1; k++) {
        double w1 = k <= r ? exp(-k * k / (2.0 * s * s)) / norm : 0.0;
        double w0 = 1.0 / norm;
        /* Along x through the centre: w_k * w_0 * w_0. */
        CHECK_NEAR(out[idx(6 + k, 6, 6)], w1 * w0 * w0, 1e-12);
        CHECK_NEAR(out[idx(6, 6 - k, 6)], w1 * w0 * w0, 1e-12);
    }
    /* Off-axis: w_1 * w_2 * w_3. */
    double w[4];
    for (int k = 0; k < 4; k++)
        w[k] = exp(-k * k / (2.0 * s * s)) / norm;
    CHECK_NEAR(out[idx(7, 8, 3)], w[1] * w[2] * w[3], 1e-12);
    free(in);
    free(out);
}

/* Clamp-to-edge: samples left of voxel 0 read voxel 0. For an impulse in the corner,
 * output voxel i along an axis collects every weight w_k with i + k <= 0, so voxel 0
 * holds w_0 + w_-1 + w_-2 + w_-3 and the axis total is (w_0 + 2 w_1 + 3 w_2 + 4 w_3)
 * (not 1: clamping duplicates edge samples; it does not renormalise). */
static void edge_samples_clamp_to_the_nearest_voxel(void)
{
    float *in = calloc(N * N * N, sizeof(float));
    double *out = malloc(sizeof(double) * N * N * N);
    in[idx(0, 0, 0)] = 1.0f;
    smooth_gaussian_ref(in, res_cube, 1.0, out);
    double total = 0.0;
    for (int i = 0; i < N * N * N; i++)
        total += out[i];
    double w[4], norm = 0.0;
    for (int k = 0; k < 4; k++) {
        w[k] = exp(-k * k / 2.0);
        norm += k == 0 ? w[k] : 2.0 * w[k];
    }
    double corner = (w[0] + w[1] + w[2] + w[3]) / norm;
    double axis_total = (w[0] + 2.0 * w[1] + 3.0 * w[2] + 4.0 * w[3]) / norm;
    CHECK_NEAR(out[idx(0, 0, 0)], corner * corner * corner, 1e-12);
    CHECK_NEAR(total, axis_total * axis_total * axis_total, 1e-12);
    free(in);
    free(out);
}

/* n = a + b . x sampled at voxel centres: central differences are exact for a linear
 * function, so the gradient is b at every voxel: central differences inside, one-sided
 * differences (over one vs) at the first and last voxels. */
static void gradient_of_linear_field_is_exact_in_the_interior(void)
{
    const int res[3] = {6, 7, 8};
    const vec3 vs = {0.5, 0.25, 2.0};
    const vec3 b = {0.3, -1.25, 0.0625};
    size_t count = 6 * 7 * 8;
    double *n = malloc(sizeof(double) * count);
    double *g = malloc(sizeof(double) * 4 * count);
    for (int z = 0; z < 8; z++)
        for (int y = 0; y < 7; y++)
            for (int x = 0; x < 6; x++)
                n[x + 6 * (y + 7 * z)] =
                    1.5 + b.x * (x + 0.5) * vs.x + b.y * (y + 0.5) * vs.y + b.z * (z + 0.5) * vs.z;
    gradient_central_ref(n, res, vs, g);
    double worst = 0.0;
    for (int z = 1; z < 7; z++)
        for (int y = 1; y < 6; y++)
            for (int x = 1; x < 5; x++) {
                size_t i = (size_t)(x + 6 * (y + 7 * z));
                worst = fmax(worst, fabs(g[4 * i + 0] - b.x));
                worst = fmax(worst, fabs(g[4 * i + 1] - b.y));
                worst = fmax(worst, fabs(g[4 * i + 2] - b.z));
                worst = fmax(worst, fabs(g[4 * i + 3] - n[i]));
            }
    CHECK_NEAR(worst, 0.0, 1e-12);
    /* First and last voxel along each axis: (n[1] - n[0]) / vs = b exactly. */
    CHECK_NEAR(g[4 * (0 + 6 * (3 + 7 * 3)) + 0], b.x, 1e-12);
    CHECK_NEAR(g[4 * (5 + 6 * (3 + 7 * 3)) + 0], b.x, 1e-12);
    CHECK_NEAR(g[4 * (2 + 6 * (0 + 7 * 3)) + 1], b.y, 1e-12);
    CHECK_NEAR(g[4 * (2 + 6 * (6 + 7 * 7)) + 2], b.z, 1e-12);
    free(n);
    free(g);
}

/* Trilinear interpolation reproduces any linear function exactly between voxel centres
 * and clamps outside [0, res - 1]. */
static void trilinear_sampling_is_exact_for_linear_data_and_clamps(void)
{
    const int res[3] = {4, 5, 3};
    double grid[4 * 5 * 3 * 2];
    for (int z = 0; z < 3; z++)
        for (int y = 0; y < 5; y++)
            for (int x = 0; x < 4; x++) {
                size_t i = (size_t)(x + 4 * (y + 5 * z));
                grid[2 * i + 0] = 1.0 + 0.5 * x - 0.25 * y + 2.0 * z;
                grid[2 * i + 1] = (double)(x * y);
            }
    double out[2];
    voxel_sample_trilinear(grid, 2, res, (vec3){1.3, 2.6, 0.7}, out);
    CHECK_NEAR(out[0], 1.0 + 0.65 - 0.65 + 1.4, 1e-12);
    CHECK_NEAR(out[1], 1.3 * 2.6, 1e-12); /* bilinear x*y is exact too */
    /* Exactly on the last centre and beyond it. */
    voxel_sample_trilinear(grid, 2, res, (vec3){3.0, 4.0, 2.0}, out);
    CHECK_NEAR(out[0], 1.0 + 1.5 - 1.0 + 4.0, 1e-12);
    voxel_sample_trilinear(grid, 2, res, (vec3){-3.0, 9.0, 2.5}, out);
    CHECK_NEAR(out[0], 1.0 + 0.0 - 1.0 + 4.0, 1e-12);
}

int main(void)
{
    constant_field_is_unchanged_by_smoothing();
    sigma_zero_copies_the_input();
    impulse_spreads_as_normalised_gaussian_and_keeps_its_sum();
    edge_samples_clamp_to_the_nearest_voxel();
    gradient_of_linear_field_is_exact_in_the_interior();
    trilinear_sampling_is_exact_for_linear_data_and_clamps();
    return test_summary("test_smooth");
}
