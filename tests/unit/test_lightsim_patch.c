/*
 * test_lightsim_patch.c - the patch geometry shared by the light simulator's initial
 * wavefront, step and split (server/lightsim/lightsim_patch.h, docs/lightsim.md
 * "Patches", "Children of a split"), and the field sampling rules ("Fields").
 *
 * Tolerances: 1e-12 for sums and areas of a few terms in double precision.
 */
#include <math.h>

#include "lightsim/lightsim_patch.h"
#include "lightsim/lightsim_sample.h"
#include "test.h"

static struct ls_patch quad(vec3 a, vec3 b, vec3 c, vec3 d, double n)
{
    struct ls_patch p = {.P = {1.0, 2.0, 3.0}, .level = 2, .in_zone = true, .n_lo = 1, .n_hi = 1.5};
    vec3 x[4] = {a, b, c, d};
    for (int k = 0; k < 4; k++) {
        p.x[k] = x[k];
        p.w[k] = (vec3){0, 0, n};
    }
    return p;
}

static void test_derive(void)
{
    struct ls_patch p =
        quad((vec3){0, 0, 0}, (vec3){2, 0, 0}, (vec3){2, 1, 0}, (vec3){0, 1, 0}, 1.5);
    struct ls_derived g;
    ls_patch_derive(&p, &g);
    CHECK_NEAR(g.c.x, 1.0, 1e-15);
    CHECK_NEAR(g.c.y, 0.5, 1e-15);
    CHECK_NEAR(g.area, 2.0, 1e-12);
    CHECK_NEAR(g.e_max, 2.0, 1e-15);
    CHECK_NEAR(g.d.z, 1.0, 1e-15);
    /* counter-clockwise seen from +z, moving along +z: positive orientation */
    CHECK(ls_patch_oriented(&g));
    /* mirrored (a fold through a caustic): negative */
    struct ls_patch m = quad((vec3){0, 0, 0}, (vec3){0, 1, 0}, (vec3){2, 1, 0}, (vec3){2, 0, 0}, 1);
    ls_patch_derive(&m, &g);
    CHECK(!ls_patch_oriented(&g));
}

static void test_split(void)
{
    /* a trapezoid, so the children's areas differ */
    struct ls_patch p =
        quad((vec3){0, 0, 0}, (vec3){4, 0, 0}, (vec3){3, 2, 0}, (vec3){1, 2, 0}, 1.5);
    p.w[1] = (vec3){0.3, 0, 1.4}; /* diverging ray vectors of different directions */
    struct ls_patch ch[4];
    ls_patch_split(&p, NULL, NULL, ch);
    struct ls_derived g;
    ls_patch_derive(&p, &g);
    double area = 0.0, P[3] = {0, 0, 0};
    for (int k = 0; k < 4; k++) {
        struct ls_derived gc;
        ls_patch_derive(&ch[k], &gc);
        area += gc.area;
        for (int c = 0; c < 3; c++)
            P[c] += ch[k].P[c];
        CHECK_INT(ch[k].level, 3);
        CHECK(ch[k].in_zone && ch[k].n_hi == 1.5); /* the parent's zone state */
        /* child k keeps parent corner k at position k */
        CHECK_NEAR(vec3_length(vec3_sub(ch[k].x[k], p.x[k])), 0.0, 0.0);
        /* P by area share */
        CHECK_NEAR(ch[k].P[0] / p.P[0], gc.area / g.area, 1e-12);
        CHECK(ls_patch_oriented(&gc));
    }
    CHECK_NEAR(area, g.area, 1e-12); /* a planar quad's children tile it */
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(P[c], p.P[c], 1e-12 * p.P[c]);
    /* edge midpoint m0 = (p00 + p10) / 2 with w rescaled to the mean length (1.5, 1.4318) */
    CHECK_NEAR(ch[0].x[1].x, 2.0, 1e-15);
    double len = 0.5 * (1.5 + vec3_length(p.w[1]));
    CHECK_NEAR(vec3_length(ch[0].w[1]), len, 1e-12);
    /* the centre is shared by all four children */
    for (int k = 1; k < 4; k++)
        CHECK_NEAR(vec3_length(vec3_sub(ch[0].x[2], ch[k].x[(k + 2) % 4])), 0.0, 1e-15);
}

static void test_halfline_box(void)
{
    vec3 lo = {0, 0, 0}, hi = {1, 1, 1};
    CHECK(ls_halfline_meets_box((vec3){0.5, 0.5, 0.5}, (vec3){1, 0, 0}, lo, hi)); /* inside */
    CHECK(ls_halfline_meets_box((vec3){-1, 0.5, 0.5}, (vec3){1, 0, 0}, lo, hi));
    CHECK(!ls_halfline_meets_box((vec3){-1, 0.5, 0.5}, (vec3){-1, 0, 0}, lo, hi)); /* behind */
    CHECK(!ls_halfline_meets_box((vec3){-1, 2, 0.5}, (vec3){1, 0, 0}, lo, hi)); /* parallel, off */
    CHECK(ls_halfline_meets_box((vec3){-1, 1, 0.5}, (vec3){1, 0, 0}, lo, hi));  /* on a face */
    CHECK(ls_halfline_meets_box((vec3){-1, -1, 0.5}, vec3_normalize((vec3){1, 1, 0}), lo, hi));
    CHECK(!ls_halfline_meets_box((vec3){-1, -0.1, 0.5}, vec3_normalize((vec3){1, 2, 0}), lo, hi));
    CHECK(ls_box_contains(lo, hi, (vec3){1, 1, 1}));
    CHECK(!ls_box_contains(lo, hi, (vec3){1, 1, 1.0000001}));
}

/* Sampling: trilinear inside the grid box, clamp to edge, ambient outside it. */
static void test_sampling(void)
{
    double ior_grad[2 * 2 * 2 * 4], ext[2 * 2 * 2 * 4];
    for (int v = 0; v < 8; v++) {
        int i = v & 1;
        ior_grad[4 * v + 0] = 0.5;
        ior_grad[4 * v + 1] = ior_grad[4 * v + 2] = 0.0;
        ior_grad[4 * v + 3] = 1.0 + 0.5 * i; /* n = 1 at x-index 0, 1.5 at index 1 */
        ext[4 * v + 0] = 2.0 * i;
        ext[4 * v + 1] = ext[4 * v + 2] = 0.0;
        ext[4 * v + 3] = i;
    }
    struct lightsim_fields f = {.grid = {.dims = {2, 2, 2}, .bmin = {0, 0, 0}, .voxel = 1.0},
                                .ambient_ior = 1.33,
                                .ior_grad = ior_grad,
                                .extinction = ext};
    struct ls_sample s;
    ls_sample_all(&f, (vec3){1.0, 1.0, 1.0}, &s); /* halfway between the centres */
    CHECK_NEAR(s.n, 1.25, 1e-15);
    CHECK_NEAR(s.sigma[0], 1.0, 1e-15);
    CHECK_NEAR(s.coverage, 0.5, 1e-15);
    CHECK_NEAR(s.grad.x, 0.5, 1e-15);
    ls_sample_all(&f, (vec3){0.1, 1.0, 1.0}, &s); /* clamp: before the first centre */
    CHECK_NEAR(s.n, 1.0, 1e-15);
    ls_sample_all(&f, (vec3){2.0, 2.0, 2.0}, &s); /* the box's far corner is inside */
    CHECK_NEAR(s.n, 1.5, 1e-15);
    ls_sample_all(&f, (vec3){2.01, 1.0, 1.0}, &s); /* outside: ambient, nothing else */
    CHECK_NEAR(s.n, 1.33, 0.0);
    CHECK_NEAR(s.grad.x + s.sigma[0] + s.coverage, 0.0, 0.0);
    double n;
    vec3 g;
    ls_sample_ior(&f, (vec3){-0.01, 1.0, 1.0}, &n, &g);
    CHECK_NEAR(n, 1.33, 0.0);
}

int main(void)
{
    test_derive();
    test_split();
    test_halfline_box();
    test_sampling();
    return test_summary("test_lightsim_patch");
}
