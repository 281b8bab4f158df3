/*
 * test_photon.c - caustic photons on the receiver (core/photon.h, issue 15 item 1) against
 * closed forms:
 *   - a glass slab over the floor under a directional light at normal incidence: the
 *     floor's irradiance under it is the slab's transmittance with its infinite series of
 *     internal reflections, (1 - R)^2 tau / (1 - R^2 tau^2) (tau = exp(-sigma_a h)), per
 *     channel, for a diamond-like index where the series differs from (1 - R)^2 tau by 3 %;
 *   - nothing direct is stored: a floor lit around the slab holds no photon outside it;
 *   - energy: every emitted photon's power is accounted for, none is lost to the event cap;
 *   - a glass ball's focus under a directional light: the brightest point on a floor at
 *     the paraxial focal distance nR / (2 (n - 1)) lies on the axis, many times brighter
 *     than the light;
 *   - the lattice holds the brute-force kernel estimate at its points (far-spread photons
 *     and a growing table included) and interpolates it between them;
 *   - the radius rule and the refusals (a scattering medium, an unbounded surface).
 * Tolerances: 4 standard errors of the kernel estimate (estimated from the photons
 * themselves), and never more than 1.5 %.
 */
#include <math.h>
#include <stdlib.h>

#include "core/photon.h"
#include "pathtrace_test_util.h"
#include "test.h"

static struct pathtrace_scene slab_scene(struct pathtrace_surface *slab, double n,
                                         const double sigma[3])
{
    struct pathtrace_scene s = pt_scene(0.0);
    *slab = pt_box(vec3_make(0, 1, 0), vec3_make(4, 0.2, 4), n);
    for (int c = 0; c < 3; c++)
        slab->medium.sigma_a[c] = sigma[c];
    s.surfaces = slab;
    s.surface_count = 1;
    s.receiver = (struct pathtrace_receiver){true, 0.0, INFINITY, {0.8, 0.8, 0.8}, {0, 0}};
    s.lights[0] = (struct pathtrace_light){
        .kind = PATHTRACE_LIGHT_DIRECTIONAL, .direction = {0, -1, 0}, .value = {1.0, 1.0, 1.0}};
    s.light_count = 1;
    return s;
}

static double slab_series(double n, double tau)
{
    double R = ((n - 1.0) / (n + 1.0)) * ((n - 1.0) / (n + 1.0));
    return (1.0 - R) * (1.0 - R) * tau / (1.0 - R * R * tau * tau);
}

static void slab_transmits_its_series(void)
{
    const double sigma[3] = {0.0, 0.5, 2.0}, h = 0.2;
    const double indices[2] = {2.42, 1.5};
    for (int k = 0; k < 2; k++) {
        struct pathtrace_surface slab;
        struct pathtrace_scene s = slab_scene(&slab, indices[k], sigma);
        struct photon_list l = {0};
        struct err e;
        CHECK_INT(photon_trace(&s, 400000, 7, 0, 1, &l, &e), REFRACT_E_OK);
        CHECK(l.count > 100000);
        CHECK_INT((int)l.emitted, 400000);
        double E[3], se[3];
        photon_kernel_estimate_se(&l, 1.0, 0.0, 0.0, E, se);
        for (int c = 0; c < 3; c++) {
            double expect = slab_series(indices[k], exp(-sigma[c] * h));
            CHECK_MSG(fabs(E[c] - expect) <= fmin(4.0 * se[c], 0.015 * expect),
                      "n %.2f channel %d: E %.5f expect %.5f se %.1e", indices[k], c, E[c], expect,
                      se[c]);
            CHECK(l.lost[c] <= 1e-9 * l.landed[c]);
        }
        if (k == 0) { /* the series is what is measured, not (1 - R)^2 */
            double R = (1.42 / 3.42) * (1.42 / 3.42);
            CHECK_MSG(fabs(E[0] - (1 - R) * (1 - R)) > 4.0 * se[0], "E %.5f", E[0]);
        }
        photon_list_free(&l);
    }
}

/* Photons that touch no optical surface are the shadow ray's: none lands outside the
 * slab's shadow, and a slab of air (index and media as the ambient's) stores nothing. */
static void direct_light_is_not_stored(void)
{
    const double zero[3] = {0, 0, 0};
    struct pathtrace_surface slab;
    struct pathtrace_scene s = slab_scene(&slab, 1.5, zero);
    struct photon_list l = {0};
    struct err e;
    CHECK_INT(photon_trace(&s, 100000, 3, 0, 1, &l, &e), REFRACT_E_OK);
    size_t outside = 0;
    for (size_t i = 0; i < l.count; i++)
        if (fabs(l.items[i].x) > 2.0 + 1e-9 || fabs(l.items[i].z) > 2.0 + 1e-9)
            outside++;
    CHECK_INT((int)outside, 0);
    CHECK(l.count > 50000);
    photon_list_free(&l);
    slab.medium.ior = 1.0;
    CHECK(!photon_surface_optical(&s, 0));
    CHECK_INT(photon_trace(&s, 100000, 3, 0, 1, &l, &e), REFRACT_E_OK);
    CHECK_INT((int)l.count, 0);
    photon_list_free(&l);
}

/* Energy: with a floor that catches everything below the slab and no absorption, the
 * landed power is the disk's power E pi r_target^2 times the fraction that goes down
 * through the slab: between the slab's series and 1; threads' lists merge to the same. */
static void threads_split_and_merge_to_the_same_list(void)
{
    const double zero[3] = {0, 0, 0};
    struct pathtrace_surface slab;
    struct pathtrace_scene s = slab_scene(&slab, 1.5, zero);
    struct photon_list all = {0}, a = {0}, b = {0};
    struct err e;
    CHECK_INT(photon_trace(&s, 20000, 11, 0, 1, &all, &e), REFRACT_E_OK);
    CHECK_INT(photon_trace(&s, 20000, 11, 0, 2, &a, &e), REFRACT_E_OK);
    CHECK_INT(photon_trace(&s, 20000, 11, 1, 2, &b, &e), REFRACT_E_OK);
    CHECK_INT(photon_list_merge(&a, &b, &e), REFRACT_E_OK);
    CHECK_INT((int)a.count, (int)all.count);
    CHECK_INT((int)a.emitted, (int)all.emitted);
    CHECK_NEAR(a.landed[0], all.landed[0], 1e-9 * all.landed[0]);
    photon_list_free(&all);
    photon_list_free(&a);
    photon_list_free(&b);
}

/* A glass ball R = 1 at the origin, light straight down, floor at the paraxial focus
 * y = -nR / (2 (n - 1)) = -1.5: the axis is the brightest place and far above 1. */
static void ball_focuses_on_its_axis(void)
{
    struct pathtrace_surface ball = pt_sphere(vec3_make(0, 0, 0), 1.0, 1.5);
    struct pathtrace_scene s = pt_scene(0.0);
    s.surfaces = &ball;
    s.surface_count = 1;
    s.receiver = (struct pathtrace_receiver){true, -1.5, INFINITY, {0.8, 0.8, 0.8}, {0, 0}};
    s.lights[0] = (struct pathtrace_light){
        .kind = PATHTRACE_LIGHT_DIRECTIONAL, .direction = {0, -1, 0}, .value = {1, 1, 1}};
    s.light_count = 1;
    struct photon_list l = {0};
    struct err e;
    CHECK_INT(photon_trace(&s, 200000, 5, 0, 1, &l, &e), REFRACT_E_OK);
    double r = 0.02, best = -1.0, best_x = NAN, E[3];
    for (int i = -40; i <= 40; i++) {
        double x = 0.01 * i;
        photon_kernel_estimate(&l, r, x, 0.0, E);
        if (E[0] > best) {
            best = E[0];
            best_x = x;
        }
    }
    CHECK_MSG(fabs(best_x) <= 0.02, "brightest at x = %.3f", best_x);
    CHECK_MSG(best > 20.0, "peak E %.2f", best);
    photon_kernel_estimate(&l, r, 0.35, 0.0, E);
    CHECK_MSG(E[0] < 0.2 * best, "E(0.35) %.2f vs peak %.2f", E[0], best);
    photon_list_free(&l);
}

/* The lattice holds the brute-force kernel estimate at its points: in the caustic, in the
 * shadow, where a few photons lie kilometres away (an infinite floor's reflected photons),
 * and with a radius so large that the table must grow; points not stored read 0 and have
 * no photon within the radius; between points the estimate is bilinear and close to the
 * kernel estimate there. */
static void lattice_holds_the_kernel_estimate(void)
{
    struct pathtrace_surface ball;
    struct pathtrace_scene s = pt_scene_a(&ball);
    struct photon_list l = {0};
    struct err e;
    CHECK_INT(photon_trace(&s, 100000, 9, 0, 1, &l, &e), REFRACT_E_OK);
    double far = 0.0;
    for (size_t i = 0; i < l.count; i++)
        far = fmax(far, fmax(fabs(l.items[i].x), fabs(l.items[i].z)));
    CHECK_MSG(far > 100.0, "farthest photon %.1f", far); /* what a dense grid cannot hold */
    for (int pass = 0; pass < 2; pass++) {
        double r = pass == 0 ? 0.05 : 0.6;
        struct photon_grid g;
        CHECK_INT(photon_grid_build(&l, r, &g, &e), REFRACT_E_OK);
        CHECK_NEAR(g.cell, r / PHOTON_LATTICE_PER_RADIUS, 1e-15);
        CHECK(g.capacity >= 4 * g.used && (g.capacity & (g.capacity - 1)) == 0);
        CHECK_MSG(g.probe_max < 40, "longest probe %u", g.probe_max);
        int lit = 0, stored = 0, absent = 0;
        double diff = 0.0, ref = 0.0;
        for (int k = 0; k < 600; k++) {
            /* lattice points over the caustic and the shadow, and next to far photons */
            int32_t i = (int32_t)floor((-0.8 + 0.004 * (k % 300)) / g.cell),
                    j = (int32_t)floor((-0.4 + 0.0021 * (k % 300)) / g.cell) + (k >= 300);
            if (k % 50 == 49) {
                const struct photon *p = &l.items[(size_t)k * 97 % l.count];
                i = (int32_t)floor(p->x / g.cell);
                j = (int32_t)floor(p->z / g.cell);
            }
            double El[3], Ek[3];
            photon_lattice_at(&g, i, j, El);
            photon_kernel_estimate(&l, r, i * g.cell, j * g.cell, Ek);
            for (int c = 0; c < 3; c++)
                CHECK_NEAR(El[c], Ek[c], 1e-9 * (1.0 + Ek[c]));
            stored += Ek[0] > 0.0;
            absent += Ek[0] == 0.0;
            lit += Ek[0] > (pass == 0 ? 1.0 : 0.05);
            /* a point between lattice points */
            double x = (i + 0.37) * g.cell, z = (j + 0.61) * g.cell, Eb[3];
            photon_irradiance(&g, x, z, Eb);
            photon_kernel_estimate(&l, r, x, z, Ek);
            diff += fabs(Eb[1] - Ek[1]);
            ref += Ek[1];
        }
        printf("radius %.2f: %u lattice points, longest probe %u; between points the bilinear "
               "estimate is off by %.2f %% of the kernel estimate\n",
               r, g.used, g.probe_max, 100.0 * diff / ref);
        CHECK_MSG(lit > 20 && stored > 100 && (pass == 1 || absent > 10),
                  "lit %d stored %d absent %d", lit, stored, absent);
        CHECK_MSG(diff <= 0.08 * ref, "bilinear vs kernel between points: %.4f of %.4f", diff, ref);
        photon_grid_free(&g);
    }
    /* no photon: 0 everywhere */
    struct photon_list empty = {0};
    struct photon_grid g;
    double E[3];
    CHECK_INT(photon_grid_build(&empty, 0.1, &g, &e), REFRACT_E_OK);
    photon_irradiance(&g, 0.0, 0.0, E);
    CHECK_NEAR(E[0], 0.0, 0.0);
    photon_grid_free(&g);
    photon_list_free(&l);
}

/* A map read back from disk (the irradiance cache's <key>.pmap holds the stored points) is
 * the same map: photon_grid_from_points makes a new table of the points that answers every
 * lookup alike. Bad points are refused. */
static void lattice_from_its_points_is_the_same(void)
{
    struct pathtrace_surface ball;
    struct pathtrace_scene s = pt_scene_a(&ball);
    struct photon_list l = {0};
    struct err e;
    CHECK_INT(photon_trace(&s, 50000, 3, 0, 1, &l, &e), REFRACT_E_OK);
    struct photon_grid g, h;
    CHECK_INT(photon_grid_build(&l, 0.05, &g, &e), REFRACT_E_OK);
    int32_t *ij = malloc((size_t)g.used * 2 * sizeof *ij);
    double *E = malloc((size_t)g.used * 3 * sizeof *E);
    uint32_t n = 0;
    for (uint32_t k = 0; k < g.capacity; k++) {
        if (g.keys[2 * k] == PHOTON_EMPTY_KEY)
            continue;
        ij[2 * n] = g.keys[2 * k];
        ij[2 * n + 1] = g.keys[2 * k + 1];
        memcpy(&E[3 * n], &g.E_double[3 * k], 3 * sizeof(double));
        n++;
    }
    CHECK_INT((int)n, (int)g.used);
    CHECK_INT(photon_grid_from_points(g.cell, g.radius, n, ij, E, &h, &e), REFRACT_E_OK);
    CHECK_INT((int)h.used, (int)g.used);
    CHECK(h.capacity >= 4 * h.used && (h.capacity & (h.capacity - 1)) == 0);
    int same = 0, lit = 0;
    for (int k = 0; k < 4000; k++) {
        double x = -1.0 + 0.0005 * k, z = -0.5 + 0.00031 * k, a[3], b[3];
        photon_irradiance(&g, x, z, a);
        photon_irradiance(&h, x, z, b);
        same += a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
        lit += a[1] > 0.0;
    }
    CHECK_INT(same, 4000);
    CHECK_MSG(lit > 100, "only %d of the probes lit", lit);
    photon_grid_free(&g);
    photon_grid_free(&h);
    /* bad points (a file that is not what this build wrote): an empty slot's key, an index
     * past the clamp, a bad spacing, too many points */
    int32_t bad[4] = {PHOTON_EMPTY_KEY, 0, 0, 2147483647};
    double Ebad[6] = {1, 1, 1, 1, 1, 1};
    CHECK_INT(photon_grid_from_points(0.01, 0.03, 1, bad, Ebad, &g, &e), REFRACT_E_STORAGE);
    CHECK(g.keys == NULL && g.capacity == 0);
    CHECK_INT(photon_grid_from_points(0.01, 0.03, 1, bad + 2, Ebad, &g, &e), REFRACT_E_STORAGE);
    CHECK_INT(photon_grid_from_points(0.0, 0.03, 1, ij, Ebad, &g, &e), REFRACT_E_STORAGE);
    CHECK_INT(photon_grid_from_points(0.01, 0.03, PHOTON_LATTICE_MAX + 1u, ij, Ebad, &g, &e),
              REFRACT_E_STORAGE);
    CHECK_CONTAINS(e.msg, "points");
    free(ij);
    free(E);
    photon_list_free(&l);
}

/* A map's passes: count / 16, count / 4, count photons (at least 1024, at most count), the
 * last with seed 1 (the map render_view makes at once), each with its own seed. */
static void passes_of_a_map(void)
{
    CHECK_INT((int)photon_level_count(1048576, 0), 65536);
    CHECK_INT((int)photon_level_count(1048576, 1), 262144);
    CHECK_INT((int)photon_level_count(1048576, 2), 1048576);
    CHECK_INT((int)photon_level_count(2000, 0), 1024);
    CHECK_INT((int)photon_level_count(2000, 2), 2000);
    CHECK_INT((int)photon_level_count(1024, 0), 1024);
    CHECK_INT((int)photon_level_seed(PHOTON_LEVELS - 1), 1);
    CHECK(photon_level_seed(0) != photon_level_seed(1) &&
          photon_level_seed(1) != photon_level_seed(2));
}

/* Passes past `count` (receiver.photons_max) accumulate: the schedule, and the weighting
 * that makes two independent lists one estimate (the kernel estimate of the accumulated
 * list is the count-weighted mean of the two lists' estimates). */
static void passes_accumulate_to_one_estimate(void)
{
    CHECK_INT(photon_initial_passes(1048576), 3);
    CHECK_INT(photon_initial_passes(1024), 1);
    CHECK_INT(photon_pass_count(1048576, 1048576), 3);
    CHECK_INT(photon_pass_count(1048576, 4194304), 5); /* then 2^21, 2^22 */
    CHECK_INT(photon_pass_count(1048576, 3000000), 5); /* 2^21, 3,000,000 */
    CHECK_INT(photon_pass_count(1048576, 1048576 + 5), 4);
    CHECK_INT((int)photon_pass_total(1048576, 4194304, 2), 1048576);
    CHECK_INT((int)photon_pass_total(1048576, 4194304, 3), 2097152);
    CHECK_INT((int)photon_pass_total(1048576, 4194304, 4), 4194304);
    CHECK_INT((int)photon_pass_total(1048576, 3000000, 4), 3000000);
    CHECK_INT((int)photon_pass_batch(1048576, 3000000, 4), 3000000 - 2097152);
    CHECK_INT((int)photon_pass_batch(1048576, 1048576 + 5, 3), 5);
    CHECK_INT((int)photon_pass_total(1048576, 1048576 + 5, 3), 1048576 + 5);
    CHECK(photon_level_seed(3) != photon_level_seed(4) && photon_level_seed(3) > 3);

    struct pathtrace_surface ball;
    struct pathtrace_scene s = pt_scene_a(&ball);
    struct photon_list a, b, acc = {0};
    struct err e;
    CHECK_INT(photon_map_trace(&s, 30000, 11, 2, &a, &e), REFRACT_E_OK);
    CHECK_INT(photon_map_trace(&s, 10000, 12, 2, &b, &e), REFRACT_E_OK);
    CHECK_INT(photon_list_merge(&acc, &a, &e), REFRACT_E_OK); /* a copy of a */
    CHECK_INT(photon_list_accumulate(&acc, 30000, &b, 10000, &e), REFRACT_E_OK);
    CHECK_INT((int)acc.count, (int)(a.count + b.count));
    CHECK_INT((int)acc.emitted, (int)(a.emitted + b.emitted));
    int lit = 0;
    for (int k = 0; k < 200; k++) {
        double x = -0.6 + 0.006 * k, z = -0.2 + 0.002 * k, Ea[3], Eb[3], Ec[3];
        photon_kernel_estimate(&a, 0.05, x, z, Ea);
        photon_kernel_estimate(&b, 0.05, x, z, Eb);
        photon_kernel_estimate(&acc, 0.05, x, z, Ec);
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(Ec[c], 0.75 * Ea[c] + 0.25 * Eb[c], 1e-9 * (1.0 + Ec[c]));
        lit += Ec[1] > 0.0;
    }
    CHECK(lit > 20);
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(acc.landed[c], 0.75 * a.landed[c] + 0.25 * b.landed[c], 1e-9 * acc.landed[c]);
    photon_list_free(&a);
    photon_list_free(&b);
    photon_list_free(&acc);
}

static void radius_rule_and_refusals(void)
{
    struct pathtrace_surface ball = pt_sphere(vec3_make(0, 0, 0), 1.0, 1.5);
    struct pathtrace_scene s = pt_scene(0.0);
    s.surfaces = &ball;
    s.surface_count = 1;
    s.receiver = (struct pathtrace_receiver){true, -1.0, INFINITY, {0.8, 0.8, 0.8}, {0, 0}};
    s.lights[0] = (struct pathtrace_light){
        .kind = PATHTRACE_LIGHT_POINT, .position = {2, 6, 1}, .value = {1, 1, 1}};
    s.light_count = 1;
    double bound = sqrt(3.0) * (1.0 + 1e-6) + 1e-12; /* half the box's diagonal */
    CHECK_NEAR(photon_radius(&s, PHOTON_RADIUS_COUNT, 0.0), PHOTON_RADIUS_SCENE * bound, 1e-12);
    CHECK_NEAR(photon_radius(&s, 64 * PHOTON_RADIUS_COUNT, 0.0), 0.5 * PHOTON_RADIUS_SCENE * bound,
               1e-12);
    CHECK_NEAR(photon_radius(&s, 1000, 0.25), 0.25, 0.0);
    struct photon_list l = {0};
    struct err e;
    ball.medium.sigma_s[1] = 0.5;
    CHECK_INT(photon_trace(&s, 1000, 1, 0, 1, &l, &e), REFRACT_E_CONFLICT);
    CHECK_CONTAINS(e.msg, "scatters");
    ball.medium.sigma_s[1] = 0.0;
    struct pathtrace_surface plane[2] = {ball, ball};
    plane[1].geom.kind = GEOM_PLANE;
    plane[1].geom.center = vec3_make(0, 0.5, 0);
    plane[1].geom.normal = vec3_make(0.3, 0.9, 0.1);
    s.surfaces = plane;
    s.surface_count = 2;
    CHECK_INT(photon_trace(&s, 1000, 1, 0, 1, &l, &e), REFRACT_E_CONFLICT);
    CHECK_CONTAINS(e.msg, "unbounded");
    CHECK_INT((int)l.count, 0);
    photon_list_free(&l);
}

int main(void)
{
    slab_transmits_its_series();
    direct_light_is_not_stored();
    threads_split_and_merge_to_the_same_list();
    ball_focuses_on_its_axis();
    lattice_from_its_points_is_the_same();
    passes_of_a_map();
    passes_accumulate_to_one_estimate();
    lattice_holds_the_kernel_estimate();
    radius_rule_and_refusals();
    return test_summary("test_photon");
}
