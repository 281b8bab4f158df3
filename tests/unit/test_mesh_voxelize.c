/*
 * test_mesh_voxelize.c - a voxelized mesh sphere matches the procedural sphere: on a 48^3
 * grid every voxel's inside fraction equals the sphere shape's coverage
 * clamp(0.5 - (|p - c| - R) / h, 0, 1) (scene_field.c) to within 0.05, i.e. the boundary
 * is placed within 1/20 of a voxel everywhere (the 20480-triangle sphere sags 1e-4 below
 * the true one); so also through the mesh's transform (scale, rotation, translation); with
 * a hole and flipped triangles, every voxel more than 1.5 voxels from the surface is still
 * classified right; and 1 and 3 threads give identical fields.
 */
#include "mesh_test_util.h"
#include "test.h"

#define N 48

/* The largest |coverage - sphere coverage| and how many voxels differ by more than tol
 * among those at least `margin` voxels from the surface (margin 0: all). */
static double compare_to_sphere(const float *cov, vec3 c, double radius, double margin, double tol,
                                int *bad)
{
    double h = 2.0 / N, worst = 0.0;
    *bad = 0;
    for (int k = 0; k < N; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                vec3 p = {-1 + (i + 0.5) * h, -1 + (j + 0.5) * h, -1 + (k + 0.5) * h};
                double sd = vec3_length(vec3_sub(p, c)) - radius;
                if (fabs(sd) < margin * h)
                    continue;
                double want = fmin(fmax(0.5 - sd / h, 0.0), 1.0);
                double d = fabs(cov[((size_t)k * N + (size_t)j) * N + (size_t)i] - want);
                worst = fmax(worst, d);
                *bad += d > tol;
            }
    return worst;
}

static struct mesh_voxelize_desc grid(struct xform x, int threads)
{
    return (struct mesh_voxelize_desc){
        .resolution = {N, N, N},
        .bounds_min = {-1, -1, -1},
        .voxel_size = {2.0 / N, 2.0 / N, 2.0 / N},
        .object_from_mesh = x,
        .threads = threads,
    };
}

static void voxelized_mesh_sphere_matches_the_procedural_sphere(void)
{
    struct test_mesh tm = test_icosphere(5, 0.6);
    struct mesh *m = test_mesh_make(&tm);
    float *a = malloc(sizeof(float) * N * N * N), *b = malloc(sizeof(float) * N * N * N);
    struct err e = {0};
    struct mesh_voxelize_desc d = grid(xform_identity(), 1);
    CHECK_INT(mesh_voxelize(m, &d, a, &e), REFRACT_E_OK);
    int bad;
    double worst = compare_to_sphere(a, vec3_make(0, 0, 0), 0.6, 0.0, 0.05, &bad);
    CHECK_NEAR(worst, 0.0, 0.05);
    fprintf(stderr, "identity: max |coverage - sphere| = %.4f\n", worst);
    d.threads = 3;
    CHECK_INT(mesh_voxelize(m, &d, b, &e), REFRACT_E_OK);
    CHECK(memcmp(a, b, sizeof(float) * N * N * N) == 0);
    /* Mesh radius 0.6 scaled by 0.75 = 0.45, turned, moved to (0.2, -0.1, 0.3). */
    d = grid(xform_make(vec3_make(0.2, -0.1, 0.3), vec3_make(1, 2, 3), 37.0, 0.75), 2);
    CHECK_INT(mesh_voxelize(m, &d, a, &e), REFRACT_E_OK);
    worst = compare_to_sphere(a, vec3_make(0.2, -0.1, 0.3), 0.45, 0.0, 0.05, &bad);
    CHECK_NEAR(worst, 0.0, 0.05);
    fprintf(stderr, "transformed: max |coverage - sphere| = %.4f\n", worst);
    free(a);
    free(b);
    mesh_destroy(m);
    test_mesh_free(&tm);
}

/* mesh_voxelize_memo gives mesh_voxelize's bytes, computes once per grid and placement,
 * ignores the thread count, and computes again for another grid or placement (and for
 * the previous one after that: it keeps one). */
static void memo_remembers_the_last_grid(void)
{
    struct test_mesh tm = test_icosphere(3, 0.6);
    struct mesh *m = test_mesh_make(&tm);
    size_t n = (size_t)N * N * N;
    float *direct = malloc(sizeof(float) * n), *memo = malloc(sizeof(float) * n);
    struct err e = {0};
    struct mesh_voxelize_desc d = grid(xform_identity(), 1);
    CHECK_INT(mesh_voxelize(m, &d, direct, &e), REFRACT_E_OK);
    long long hits = -1, computed = -1;
    for (int round = 0; round < 3; round++) {
        memset(memo, 0xff, sizeof(float) * n); /* NaN: a copy that skipped voxels shows */
        d.threads = 1 + round;
        CHECK_INT(mesh_voxelize_memo(m, &d, memo, &e), REFRACT_E_OK);
        CHECK(memcmp(direct, memo, sizeof(float) * n) == 0);
    }
    mesh_memo_counts(m, &hits, &computed);
    CHECK_INT(computed, 1);
    CHECK_INT(hits, 2);
    struct mesh_voxelize_desc moved =
        grid(xform_make(vec3_make(0.1, 0, 0), vec3_make(0, 0, 1), 0.0, 1.0), 1);
    CHECK_INT(mesh_voxelize_memo(m, &moved, memo, &e), REFRACT_E_OK);
    CHECK(memcmp(direct, memo, sizeof(float) * n) != 0);
    CHECK_INT(mesh_voxelize_memo(m, &d, memo, &e), REFRACT_E_OK);
    CHECK(memcmp(direct, memo, sizeof(float) * n) == 0);
    mesh_memo_counts(m, &hits, &computed);
    CHECK_INT(computed, 3);
    CHECK_INT(hits, 2);
    free(direct);
    free(memo);
    mesh_destroy(m);
    test_mesh_free(&tm);
}

static void broken_mesh_sphere_still_voxelizes(void)
{
    struct test_mesh tm = test_icosphere(4, 0.6);
    /* A hole of 8 triangles and one triangle in 7 flipped. */
    memmove(tm.t, tm.t + 8, (tm.nt - 8) * sizeof *tm.t);
    tm.nt -= 8;
    for (size_t i = 0; i < tm.nt; i += 7) {
        uint32_t s = tm.t[i][1];
        tm.t[i][1] = tm.t[i][2];
        tm.t[i][2] = s;
    }
    struct mesh *m = test_mesh_make(&tm);
    float *a = malloc(sizeof(float) * N * N * N);
    struct err e = {0};
    struct mesh_voxelize_desc d = grid(xform_identity(), 2);
    CHECK_INT(mesh_voxelize(m, &d, a, &e), REFRACT_E_OK);
    int bad;
    compare_to_sphere(a, vec3_make(0, 0, 0), 0.6, 1.5, 0.0, &bad);
    CHECK_INT(bad, 0);
    free(a);
    mesh_destroy(m);
    test_mesh_free(&tm);
}

int main(void)
{
    voxelized_mesh_sphere_matches_the_procedural_sphere();
    broken_mesh_sphere_still_voxelizes();
    memo_remembers_the_last_grid();
    return test_summary("mesh_voxelize");
}
