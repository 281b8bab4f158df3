/*
 * test_mesh_winding.c - the generalized winding number and the distance query against
 * closed forms on a unit icosphere: w = 1 inside and 0 outside a closed mesh; the
 * hierarchical (far-field) w agrees with the exact sum to 0.05 (mesh_winding.c gives the
 * trade-off of beta); a mesh with a hole, with
 * flipped triangles, or wound inside out still classifies every point further than 0.2
 * from the surface correctly by |w| >= 1/2; the distance is | |p| - 1 | up to the
 * polyhedron's sag.
 */
#include "mesh_test_util.h"
#include "test.h"

static uint64_t rng_state = 0x2545f4914f6cdd1dull;

static double uniform(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

/* A random point at distance r from the origin. */
static vec3 point_at(double r)
{
    double z = 2.0 * uniform() - 1.0, phi = 6.283185307179586 * uniform();
    double s = sqrt(1.0 - z * z);
    return vec3_make(r * s * cos(phi), r * s * sin(phi), r * z);
}

static void closed_mesh_winds_once_inside_and_zero_outside(void)
{
    struct test_mesh tm = test_icosphere(3, 1.0);
    struct mesh *m = test_mesh_make(&tm);
    CHECK(m->closed);
    double worst_in = 0.0, worst_out = 0.0, worst_fast = 0.0;
    for (int i = 0; i < 400; i++) {
        vec3 in = point_at(0.95 * uniform()), out = point_at(1.05 + 3.0 * uniform());
        worst_in = fmax(worst_in, fabs(mesh_winding_number_exact(m, in) - 1.0));
        worst_out = fmax(worst_out, fabs(mesh_winding_number_exact(m, out)));
        vec3 any = point_at(0.5 + uniform());
        worst_fast =
            fmax(worst_fast, fabs(mesh_winding_number(m, any) - mesh_winding_number_exact(m, any)));
    }
    CHECK_NEAR(worst_in, 0.0, 1e-9);
    CHECK_NEAR(worst_out, 0.0, 1e-9);
    CHECK_NEAR(worst_fast, 0.0, 0.05);
    fprintf(stderr, "fast vs exact: max |dw| = %.2e over 400 points\n", worst_fast);
    mesh_destroy(m);
    test_mesh_free(&tm);
}

/* Fraction of points at radius in [0, 0.8] (inside) and [1.2, 3] (outside) that
 * |w| >= 1/2 classifies correctly. */
static double classified(const struct mesh *m)
{
    int good = 0, n = 400;
    for (int i = 0; i < n / 2; i++) {
        good += fabs(mesh_winding_number(m, point_at(0.8 * uniform()))) >= 0.5;
        good += fabs(mesh_winding_number(m, point_at(1.2 + 1.8 * uniform()))) < 0.5;
    }
    return (double)good / n;
}

static void holes_and_flipped_triangles_still_classify(void)
{
    struct test_mesh tm = test_icosphere(3, 1.0);
    /* A hole: drop 16 triangles (a patch around the first icosahedron face's corner). */
    struct test_mesh holed = tm;
    holed.t = malloc(tm.nt * sizeof *holed.t);
    holed.v = malloc(tm.nv * sizeof *holed.v);
    memcpy(holed.v, tm.v, tm.nv * sizeof *tm.v);
    memcpy(holed.t, tm.t + 16, (tm.nt - 16) * sizeof *tm.t);
    holed.nt = tm.nt - 16;
    struct mesh *m = test_mesh_make(&holed);
    CHECK(!m->closed);
    CHECK_NEAR(classified(m), 1.0, 0.0);
    mesh_destroy(m);
    /* One triangle in 8 flipped. */
    struct test_mesh flipped = holed;
    memcpy(flipped.t, tm.t, tm.nt * sizeof *tm.t);
    flipped.nt = tm.nt;
    for (size_t i = 0; i < flipped.nt; i += 8) {
        uint32_t s = flipped.t[i][1];
        flipped.t[i][1] = flipped.t[i][2];
        flipped.t[i][2] = s;
    }
    m = test_mesh_make(&flipped);
    CHECK(!m->closed);
    CHECK_NEAR(classified(m), 1.0, 0.0);
    mesh_destroy(m);
    /* Inside out: w = -1 inside, so |w| classifies. */
    for (size_t i = 0; i < flipped.nt; i++) {
        flipped.t[i][1] = tm.t[i][2];
        flipped.t[i][2] = tm.t[i][1];
    }
    m = test_mesh_make(&flipped);
    CHECK(m->closed);
    CHECK_NEAR(mesh_winding_number(m, vec3_make(0.1, 0.2, 0.3)), -1.0, 0.05);
    CHECK_NEAR(classified(m), 1.0, 0.0);
    mesh_destroy(m);
    test_mesh_free(&holed);
    test_mesh_free(&tm);
}

static void distance_is_the_radial_distance_up_to_the_sag(void)
{
    struct test_mesh tm = test_icosphere(4, 1.0);
    struct mesh *m = test_mesh_make(&tm);
    /* Level 4: edges subtend about 0.08 rad, so the facets sag by about 1e-3 below the
     * sphere; a point's distance to the polyhedron is within that of | |p| - 1 |. */
    double worst = 0.0;
    for (int i = 0; i < 300; i++) {
        double r = 2.0 * uniform();
        worst = fmax(worst, fabs(mesh_distance(m, point_at(r)) - fabs(r - 1.0)));
    }
    CHECK_NEAR(worst, 0.0, 2e-3);
    CHECK_NEAR(mesh_distance(m, vec3_make(0, 0, 0)), 1.0, 2e-3);
    mesh_destroy(m);
    test_mesh_free(&tm);
}

int main(void)
{
    closed_mesh_winds_once_inside_and_zero_outside();
    holes_and_flipped_triangles_still_classify();
    distance_is_the_radial_distance_up_to_the_sag();
    return test_summary("mesh_winding");
}
