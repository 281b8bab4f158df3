/*
 * test_lightsim_receiver.c - the receiver plane as the CPU reference of the light
 * simulator lights it and the receiver shading (reftrace_light_receiver, the twin of
 * shaders/lighting.glsl's light_receiver) reads it, against the closed form of a point
 * light over a Lambertian plane, L = albedo / pi I cos(theta) / d^2 (docs/lightsim.md
 * "Domain", docs/tracing.md "Receiver"; the scene and the checks in lightsim_floor.h):
 *
 * - scene A of shared/peer-scenes/SCENES.md with the ball removed: the floor y = -1 at
 *   (-2, -1, 2) under a point light of intensity 79.5775 at (2, 6, 1), albedo 0.8, reads
 *   0.264553 (+-1 %);
 * - rows of floor points through the light's foot, 1/8 voxel apart, follow the closed
 *   form with no rings (a point light's deposits lie on concentric wavefront shells whose
 *   phase against the plane varies with the radius; a deposit kernel cut at the plane
 *   made that phase visible as rings, 7-11 % low; measured before the fix: check value
 *   -5.9 %, rows -4.0 % mean, -9.6 % worst; after: +0.11 %, +0.1 %, +0.56 %);
 * - an infinite receiver: the light grid covers the objects' footprint as the light sees
 *   it (central projection of their box from the point light), not the plane; outside it
 *   the floor is the closed form exactly (reftrace_light_direct), and the seam between
 *   volume and closed form is continuous; a receiver centred off the origin; the transport
 *   hash sees the centre and "infinite"; bad values are refused with their path.
 */
#include "lightsim_floor.h"
#include "test_lightsim_fixture.h"

static void test_check_value_and_no_rings(void)
{
    struct scene *s = fx_scene(FLOOR_SCENE);
    struct scene_lightsim set = fx_settings(32, 32);
    struct scene_light l = fx_point(FLOOR_LIGHT);
    struct lightsim_fields f;
    struct irradiance_volume v;
    double t0 = fx_seconds();
    fx_run(s, &l, &set, &f, &v);
    const struct light_grid *g = &v.grid;
    printf("grid %d x %d x %d, voxel %.4f, bmin (%.4f, %.4f, %.4f); simulated in %.2f s\n",
           g->dims[0], g->dims[1], g->dims[2], g->voxel, g->bmin.x, g->bmin.y, g->bmin.z,
           fx_seconds() - t0);
    fx_print_stats("point light over the floor", &v.stats);
    CHECK(lightsim_stats_imbalance(&v.stats) <= 1e-9);
    struct lit_floor lf;
    lit_floor_bind(&lf, &v, &s->receiver);
    /* rows stop 2 voxels inside the 3.5 square, where its pad begins */
    floor_check("CPU reference", &lf, g->voxel, 3.5 - 2.0 * g->voxel, 0.015, 0.005);
    irradiance_volume_free(&v);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

/* Scene A's box [-1, 1]^3 under the light at (2, 6, 1) over an infinite floor at y = -1:
 * the top corners (y = 1) project by t = 7 / 5 from the light, so the footprint is x in
 * [2 + 1.4 (-1 - 2), 1] = [-2.2, 1], z in [1 + 1.4 (-1 - 1), 1] = [-1.8, 1]. */
static void test_infinite_floor(void)
{
    struct scene *s =
        fx_scene("{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
                 "\"resolution\": 8, \"ior\": 1.0}], "
                 "\"receiver\": {\"height\": -1, \"half_size\": \"infinite\", \"albedo\": 0.8}}");
    CHECK(s->receiver.enabled && isinf(s->receiver.half_size));
    struct scene_lightsim set = fx_settings(32, 32);
    s->lightsim = set;
    struct scene_light l = fx_point(FLOOR_LIGHT);
    struct light_grid g;
    lightsim_domain_light(s, &l, NULL, NULL, &g);
    double voxel = 3.2 / 28.0; /* longest: x from -2.2 to 1 */
    printf("infinite floor: grid %d x %d x %d, voxel %.4f, bmin (%.4f, %.4f, %.4f)\n", g.dims[0],
           g.dims[1], g.dims[2], g.voxel, g.bmin.x, g.bmin.y, g.bmin.z);
    CHECK_NEAR(g.voxel, voxel, 1e-12);
    /* x and z: the 2 pad voxels and the receiver margin; y: the pad */
    const double in = LIGHT_RECEIVER_INSET;
    CHECK_NEAR(g.bmin.x, -2.2 - in * voxel, 1e-12);
    CHECK_NEAR(g.bmin.z, -1.8 - in * voxel, 1e-12);
    CHECK_NEAR(g.bmin.y, -1.0 - 2 * voxel, 1e-12);
    CHECK_INT(g.dims[0], 28 + 2 * (int)in);
    CHECK_INT(g.dims[2], (int)ceil(2.8 / voxel - 1e-9) + 2 * (int)in);
    CHECK_INT(g.dims[1], (int)ceil(2.0 / voxel - 1e-9) + 4);
    /* without a light: the objects' box alone */
    struct light_grid g0;
    lightsim_domain(s, &g0);
    CHECK_NEAR(g0.bmin.x, -1.0 - in * g0.voxel, 1e-12);
    /* a directional light: parallel projection along (1, -2, 0) moves the top by -1 in x */
    struct scene_light dl = fx_directional((vec3){1, -2, 0});
    lightsim_domain_light(s, &dl, NULL, NULL, &g0);
    CHECK_NEAR(g0.bmin.x, -1.0 - in * g0.voxel, 1e-12);
    CHECK_NEAR(g0.bmin.x + (g0.dims[0] - in) * g0.voxel, 2.0, 1e-9); /* (1, 1) -> x = 2 */
    /* a corner at or above the light: clipped to LIGHTSIM_FOOTPRINT_MAX x 2 about (0, 0) */
    struct scene_light low = fx_point((vec3){3, 0.5, 0});
    lightsim_domain_light(s, &low, NULL, NULL, &g0);
    CHECK_NEAR(g0.bmin.x, -2.0 * LIGHTSIM_FOOTPRINT_MAX - in * g0.voxel, 1e-9);

    struct lightsim_fields f;
    struct irradiance_volume v;
    struct err e = {0};
    double t0 = fx_seconds();
    CHECK_INT(lightsim_fields_build_light(s, &l, NULL, NULL, &f, &e), REFRACT_E_OK);
    CHECK(f.grid.voxel == g.voxel && f.grid.dims[0] == g.dims[0]);
    CHECK_INT(lightsim_ref_run(&f, &l, &set, &v, &e), REFRACT_E_OK);
    printf("infinite floor: simulated in %.2f s\n", fx_seconds() - t0);
    struct lit_floor lf;
    lit_floor_bind(&lf, &v, &s->receiver);
    /* The check value lies outside the footprint (z = 2 > 1): the closed form itself. */
    floor_check("infinite floor", &lf, g.voxel, 1e30, 0.015, 0.005);
    double L = 0;
    const double far[][2] = {{-2, 2}, {50, 50}, {-30, 7}, {2, 1e4}};
    for (int i = 0; i < 4; i++) {
        CHECK(floor_radiance(&lf, far[i][0], far[i][1], &L));
        double cf = floor_closed_form(far[i][0], far[i][1]);
        CHECK_MSG(fabs(L / cf - 1.0) <= 1e-9, "far floor (%g, %g): %g, closed form %g", far[i][0],
                  far[i][1], L, cf);
    }
    /* The seam: along z = 0 from inside the grid to beyond it, 1/8 voxel apart; the step
     * across the grid's edge (less its pad) and every point against the closed form. */
    double seam_x = g.bmin.x + (g.dims[0] - in) * g.voxel, worst = 0.0, jump = 0.0, prev = 0.0;
    for (double x = 0.0; x <= seam_x + 1.0; x += g.voxel / 8.0) {
        CHECK(floor_radiance(&lf, x, 0.0, &L));
        double rel = L / floor_closed_form(x, 0.0);
        worst = fmax(worst, fabs(rel - 1.0));
        if (x > seam_x && x - g.voxel / 8.0 <= seam_x) /* the first point beyond the seam */
            jump = fabs(rel - prev);
        prev = rel;
    }
    printf("seam at x = %.4f: step across it %.3f %%, worst deviation on the row %.3f %%\n", seam_x,
           100.0 * jump, 100.0 * worst);
    CHECK_MSG(jump <= 0.01, "seam step %g", jump);
    CHECK_MSG(worst <= 0.015, "seam row worst %g", worst);
    irradiance_volume_free(&v);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

/* A square centred at (5, -3): hits inside it only; its domain holds its footprint part. */
static void test_offset_center(void)
{
    struct scene *s =
        fx_scene("{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
                 "\"resolution\": 8, \"ior\": 1.0}], "
                 "\"receiver\": {\"height\": -1, \"half_size\": 2.5, \"center\": [4, -3]}}");
    CHECK_NEAR(s->receiver.center[0], 4.0, 0);
    CHECK_NEAR(s->receiver.center[1], -3.0, 0);
    struct scene_lightsim set = fx_settings(24, 16);
    s->lightsim = set;
    struct scene_light l = fx_point(FLOOR_LIGHT);
    struct lightsim_fields f;
    struct irradiance_volume v;
    fx_run_lookup(s, NULL, NULL, &l, &set, &f, &v);
    /* fx_run builds without a light: the whole square [1.5, 6.5] x [-5.5, -0.5] with the box */
    CHECK_NEAR(f.grid.bmin.x + (f.grid.dims[0] - LIGHT_RECEIVER_INSET) * f.grid.voxel, 6.5, 1e-9);
    CHECK_NEAR(f.grid.bmin.z, -5.5 - LIGHT_RECEIVER_INSET * f.grid.voxel, 1e-9);
    struct lit_floor lf;
    lit_floor_bind(&lf, &v, &s->receiver);
    double L = 0;
    CHECK(!floor_radiance(&lf, 0.0, 0.0, &L));  /* outside the square */
    CHECK(!floor_radiance(&lf, 6.6, -3.0, &L)); /* beyond its +x edge */
    CHECK(floor_radiance(&lf, 6.4, -3.0, &L));
    CHECK(floor_radiance(&lf, 3.0, -2.0, &L));
    printf("offset square: (3, -1, -2) reads %.6f, closed form %.6f\n", L,
           floor_closed_form(3.0, -2.0));
    CHECK(fabs(L / floor_closed_form(3.0, -2.0) - 1.0) <= 0.015);
    irradiance_volume_free(&v);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

/* The transport hash sees the centre and "infinite"; bad values get their path. */
static void test_parse_and_hash(void)
{
    const char *base = "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, "
                       "1]}, \"resolution\": 8, \"ior\": 1.0}], \"receiver\": {\"height\": -1";
    const char *variants[] = {"}}", ", \"half_size\": \"infinite\"}}", ", \"center\": [0.5, 0]}}",
                              ", \"center\": [0, 0.5]}}"};
    uint64_t h[4];
    for (int i = 0; i < 4; i++) {
        char json[512];
        snprintf(json, sizeof json, "%s%s", base, variants[i]);
        struct scene *s = fx_scene(json);
        h[i] = scene_transport_hash(s);
        scene_destroy(s);
    }
    for (int i = 0; i < 4; i++)
        for (int j = i + 1; j < 4; j++)
            CHECK_MSG(h[i] != h[j], "receiver variants %d and %d hash alike", i, j);
    /* the default centre written out hashes as left away */
    char json[512];
    snprintf(json, sizeof json, "%s%s", base, ", \"center\": [0, 0]}}");
    struct scene *s = fx_scene(json);
    CHECK(scene_transport_hash(s) == h[0]);
    scene_destroy(s);

    struct {
        const char *tail, *want;
    } bad[] = {
        {", \"half_size\": \"huge\"}}", "receiver.half_size"},
        {", \"half_size\": -1}}", "receiver.half_size"},
        {", \"half_size\": null}}", "receiver.half_size"},
        {", \"center\": [1]}}", "receiver.center"},
        {", \"center\": [1, 2, 3]}}", "receiver.center"},
        {", \"center\": [1, \"a\"]}}", "receiver.center[1]"},
        {", \"center\": [2e6, 0]}}", "receiver.center[0]"},
        {", \"center\": {\"x\": 1}}}", "receiver.center"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        snprintf(json, sizeof json, "%s%s", base, bad[i].tail);
        struct scene *t = NULL;
        struct err e = {0};
        CHECK_INT(scene_parse(json, strlen(json), NULL, &t, &e), REFRACT_E_INVALID_FIELD);
        CHECK_MSG(strstr(e.msg, bad[i].want) != NULL, "%s: %s", bad[i].tail, e.msg);
        printf("refused: %s\n", e.msg);
        scene_destroy(t);
    }
}

int main(void)
{
    test_check_value_and_no_rings();
    test_infinite_floor();
    test_offset_center();
    test_parse_and_hash();
    return test_summary("test_lightsim_receiver");
}
