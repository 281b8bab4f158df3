/*
 * test_scene_scattering.c - the channels and the shape issue 3 added, evaluated:
 * scattering (RGB sigma_s, 4 floats per voxel) and anisotropy (g, 1 float per voxel) from
 * constant, shape and volume layers, with their ranges and component rules; the
 * bumpy_sphere's SDF and bounds against its closed-form radius r(theta, phi); and the CPU
 * reference grids that carry both channels.
 */
#include <string.h>

#include "scene/scene.h"
#include "scene_test_util.h"
#include "scene/scene_reference.h"
#include "test.h"

/* OBJ at resolution 8. */
#define OBJ8(fields) OBJ("\"resolution\": 8, " fields)

static void channel_table_covers_the_new_channels(void)
{
    CHECK_STR(scene_channel_name(SCENE_CH_SCATTERING), "scattering");
    CHECK_STR(scene_channel_name(SCENE_CH_ANISOTROPY), "anisotropy");
    CHECK_STR(scene_channel_name(SCENE_CH_COUNT), "unknown");
    CHECK_INT(scene_channel_components(SCENE_CH_SCATTERING), 4);
    CHECK_INT(scene_channel_components(SCENE_CH_ANISOTROPY), 1);
    CHECK_INT(scene_channel_components(SCENE_CH_IOR), 1);
}

static void unused_channels_evaluate_to_zero(void)
{
    struct scene *s = parse_ok(OBJ8("\"ior\": 1.5"));
    if (s == NULL)
        return;
    float *sc = eval(s, SCENE_CH_SCATTERING, NULL, NULL);
    float *g = eval(s, SCENE_CH_ANISOTROPY, NULL, NULL);
    size_t nonzero = 0;
    for (size_t v = 0; v < voxels(&s->objects[0]); v++) {
        nonzero += g[v] != 0.0f;
        for (int c = 0; c < 4; c++)
            nonzero += sc[v * 4 + (size_t)c] != 0.0f;
    }
    CHECK_INT(nonzero, 0);
    free(sc);
    free(g);
    scene_destroy(s);
}

/* Smoke: an object of scattering only, a constant RGB with a sphere of another value. */
static void scattering_layers_give_rgb_and_zero(void)
{
    struct scene *s = parse_ok(OBJ8("\"scattering\": [[0.1, 0.2, 0.3], {\"shape\": \"sphere\", "
                                    "\"radius\": 0.5, \"inside\": 7}]"));
    if (s == NULL)
        return;
    const struct scene_object *o = &s->objects[0];
    float *sc = eval(s, SCENE_CH_SCATTERING, NULL, NULL);
    const float *corner = sc + 4 * voxel_index(o, 0, 0, 0), *mid = sc + 4 * voxel_index(o, 4, 4, 4);
    CHECK_NEAR(corner[0], 0.1, 1e-7);
    CHECK_NEAR(corner[1], 0.2, 1e-7);
    CHECK_NEAR(corner[2], 0.3, 1e-7);
    CHECK_NEAR(corner[3], 0.0, 0);
    /* Voxel (4, 4, 4) has its centre at 0.125 on each axis: well inside. */
    for (int c = 0; c < 3; c++)
        CHECK_NEAR(mid[c], 7.0, 1e-6);
    CHECK_NEAR(mid[3], 0.0, 0);
    free(sc);
    scene_destroy(s);
}

/* g, one float per voxel: a constant base and a shape whose inside and outside differ.
 * The sphere's boundary is anti-aliased over one voxel, as for every channel. */
static void anisotropy_is_one_float_per_voxel_with_shape_coverage(void)
{
    struct scene *s = parse_ok(OBJ8("\"scattering\": 1, \"anisotropy\": [0.3, {\"shape\": "
                                    "\"sphere\", \"radius\": 0.6, \"inside\": -0.8, \"outside\": "
                                    "0.9}]"));
    if (s == NULL)
        return;
    const struct scene_object *o = &s->objects[0];
    float *g = eval(s, SCENE_CH_ANISOTROPY, NULL, NULL);
    double h = scene_object_min_voxel(o);
    size_t bad = 0;
    for (int k = 0; k < 8; k++) {
        for (int j = 0; j < 8; j++) {
            for (int i = 0; i < 8; i++) {
                double d = vec3_length(centre(o, i, j, k)) - 0.6;
                double c = fmin(fmax(0.5 - d / h, 0.0), 1.0);
                double want = c * -0.8 + (1 - c) * 0.9;
                bad += fabs(g[voxel_index(o, i, j, k)] - want) > 1e-6;
            }
        }
    }
    CHECK_INT(bad, 0);
    free(g);
    scene_destroy(s);
}

struct one_volume {
    const char *name;
    const struct scene_volume *vol;
};

static const struct scene_volume *lookup(void *ctx, const char *name)
{
    const struct one_volume *v = ctx;
    return strcmp(v->name, name) == 0 ? v->vol : NULL;
}

static void volumes_fill_scattering_and_clamp_anisotropy(void)
{
    struct scene *s = parse_ok("{\"objects\": [{" BOUNDS ", \"resolution\": 2, \"scattering\": "
                               "{\"volume\": \"v\", \"scale\": 2}, \"anisotropy\": {\"volume\": "
                               "\"v\", \"offset\": -1}}]}");
    if (s == NULL)
        return;
    /* A 2^3 volume: x fastest; values 0.25 .. 1.75 along the voxels, so g = v - 1. */
    float grey[8] = {0.25f, 0.5f, 0.75f, 1.0f, 1.25f, 1.5f, 1.75f, 3.0f};
    struct scene_volume vol = {.dims = {2, 2, 2}, .components = 1, .data = grey};
    struct one_volume ctx = {"v", &vol};
    float *sc = eval(s, SCENE_CH_SCATTERING, lookup, &ctx);
    float *g = eval(s, SCENE_CH_ANISOTROPY, lookup, &ctx);
    for (int v = 0; v < 8; v++) {
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(sc[4 * v + c], 2.0 * grey[v], 1e-6);
        CHECK_NEAR(sc[4 * v + 3], 0.0, 0);
        /* g = v - 1, clamped to -0.99..0.99 (the first and last voxel). */
        CHECK_NEAR(g[v], fmin(fmax(grey[v] - 1.0, -0.99), 0.99), 1e-6);
    }
    free(sc);
    free(g);

    /* RGB scattering from 3 components is fine; anisotropy takes 1 only. */
    float rgb[24];
    for (int i = 0; i < 24; i++)
        rgb[i] = 0.01f * (float)i;
    struct scene_volume vrgb = {.dims = {2, 2, 2}, .components = 3, .data = rgb};
    ctx.vol = &vrgb;
    sc = eval(s, SCENE_CH_SCATTERING, lookup, &ctx);
    CHECK_NEAR(sc[4 * 7 + 2], 2.0 * rgb[23], 1e-6);
    free(sc);
    float out[8];
    struct err e;
    err_clear(&e);
    CHECK_INT(scene_field_eval(s, &s->objects[0], SCENE_CH_ANISOTROPY, lookup, &ctx, out, &e),
              REFRACT_E_CONFLICT);
    CHECK_MSG(strstr(e.msg, "objects[0].anisotropy: volume \"v\" has 3 components but "
                            "anisotropy takes 1") != NULL,
              "%s", e.msg);
    char missing[64];
    CHECK_INT(scene_missing_volumes(s, NULL, NULL, missing, sizeof missing), 1);
    CHECK_STR(missing, "v");
    scene_destroy(s);
}

/* ---- bumpy sphere ---- */

static double bumpy_radius(const struct scene_shape *sh, vec3 d)
{
    double len = vec3_length(d);
    double theta = acos(d.y / len), phi = atan2(d.z, d.x);
    int f = sh->bump_frequency;
    return sh->radius + sh->bump_amplitude * sin(f * theta) * sin(f * phi);
}

static vec3 spherical(double r, double theta, double phi)
{
    return vec3_make(r * sin(theta) * cos(phi), r * cos(theta), r * sin(theta) * sin(phi));
}

static struct scene_shape bumpy(double radius, double amplitude, int frequency)
{
    return (struct scene_shape){.kind = SCENE_SHAPE_BUMPY_SPHERE,
                                .center = vec3_make(0.1, -0.2, 0.05),
                                .radius = radius,
                                .bump_amplitude = amplitude,
                                .bump_frequency = frequency};
}

static void bumpy_sphere_bulges_and_dents_where_its_radius_says(void)
{
    struct scene_shape sh = bumpy(0.5, 0.1, 4);
    double t = M_PI / (2 * 4);
    /* sin(4 theta) sin(4 phi) = 1 at theta = phi = pi / 8: r = 0.6 there ... */
    vec3 out_bulge = vec3_add(sh.center, spherical(0.59, t, t));
    vec3 beyond = vec3_add(sh.center, spherical(0.61, t, t));
    CHECK(scene_shape_sdf(&sh, out_bulge) < 0.0);
    CHECK(scene_shape_sdf(&sh, beyond) > 0.0);
    /* ... and = -1 at phi = 3 pi / 8: r = 0.4, so 0.45 is outside, which a plain sphere of
     * radius 0.5 would have inside. */
    CHECK(scene_shape_sdf(&sh, vec3_add(sh.center, spherical(0.45, t, 3 * t))) > 0.0);
    CHECK(scene_shape_sdf(&sh, vec3_add(sh.center, spherical(0.39, t, 3 * t))) < 0.0);
    CHECK(scene_shape_sdf(&sh, sh.center) < 0.0);
    /* Every point: the sign is that of |d| - r(theta, phi), the value never exceeds the
     * radial distance to the surface, and beyond R + a or within R - a it is safely off. */
    unsigned st = 12345;
    size_t wrong_sign = 0, too_far = 0;
    for (int n = 0; n < 20000; n++) {
        st = st * 1664525u + 1013904223u;
        double r = 0.8 * (double)(st >> 8) / (double)(1u << 24);
        st = st * 1664525u + 1013904223u;
        double theta = M_PI * (double)(st >> 8) / (double)(1u << 24);
        st = st * 1664525u + 1013904223u;
        double phi = 2 * M_PI * (double)(st >> 8) / (double)(1u << 24);
        vec3 d = spherical(r, theta, phi);
        if (r < 1e-6)
            continue;
        double sdf = scene_shape_sdf(&sh, vec3_add(sh.center, d));
        double radial = r - bumpy_radius(&sh, d);
        wrong_sign += (radial > 1e-12 && !(sdf > 0)) || (radial < -1e-12 && !(sdf < 0));
        too_far += fabs(sdf) > fabs(radial) + 1e-12;
    }
    CHECK_INT(wrong_sign, 0);
    CHECK_INT(too_far, 0);
}

static void bumpy_sphere_bounds_hold_the_whole_solid(void)
{
    struct scene_shape sh = bumpy(0.5, 0.2, 3);
    vec3 lo, hi;
    CHECK(scene_shape_bounds(&sh, &lo, &hi));
    CHECK_NEAR(hi.x - sh.center.x, 0.7, 1e-12);
    CHECK_NEAR(sh.center.y - lo.y, 0.7, 1e-12);
    /* Dense samples on the surface r(theta, phi) all lie in the box, and the box is tight:
     * the bulges reach R + a along +-x (theta = pi/2 gives sin(3 theta) = -1, phi = pi/2
     * ... any direction where the product is 1). */
    size_t outside = 0;
    double reach = 0.0;
    for (int a = 0; a <= 180; a++) {
        for (int b = 0; b < 360; b++) {
            double theta = a * M_PI / 180, phi = b * M_PI / 180;
            vec3 u = spherical(1.0, theta, phi);
            vec3 p = vec3_add(sh.center, vec3_scale(u, bumpy_radius(&sh, u)));
            outside +=
                p.x < lo.x || p.y < lo.y || p.z < lo.z || p.x > hi.x || p.y > hi.y || p.z > hi.z;
            reach = fmax(reach, vec3_length(vec3_sub(p, sh.center)));
        }
    }
    CHECK_INT(outside, 0);
    CHECK_NEAR(reach, 0.7, 1e-3);
}

/* Field evaluation skips runs of voxels using the SDF as a distance bound; the result must
 * equal the coverage computed voxel by voxel from the SDF. */
static void bumpy_sphere_field_equals_voxelwise_coverage(void)
{
    struct scene *s =
        parse_ok("{\"objects\": [{" BOUNDS ", \"resolution\": 40, \"ior\": {\"shape\": "
                 "\"bumpy_sphere\", \"radius\": 0.6, \"bump_amplitude\": 0.3, "
                 "\"bump_frequency\": 5, \"inside\": 1.5}}]}");
    if (s == NULL)
        return;
    const struct scene_object *o = &s->objects[0];
    const struct scene_shape *sh = &o->fields[SCENE_CH_IOR].layers[0].shape;
    float *n = eval(s, SCENE_CH_IOR, NULL, NULL);
    double h = scene_object_min_voxel(o);
    size_t bad = 0, inside = 0;
    for (int k = 0; k < 40; k++) {
        for (int j = 0; j < 40; j++) {
            for (int i = 0; i < 40; i++) {
                double c = fmin(fmax(0.5 - scene_shape_sdf(sh, centre(o, i, j, k)) / h, 0), 1);
                double want = c * 1.5 + (1 - c) * 1.0;
                bad += fabs(n[voxel_index(o, i, j, k)] - want) > 1e-6;
                inside += c == 1.0;
            }
        }
    }
    CHECK_INT(bad, 0);
    CHECK(inside > 1000);
    free(n);
    scene_destroy(s);
}

/* ---- reference grids ---- */

static void reference_grids_carry_scattering_and_anisotropy(void)
{
    struct scene *s = parse_ok(OBJ8("\"ior\": 1.33, \"scattering\": [0.5, 0.25, 0.125], "
                                    "\"anisotropy\": 0.3"));
    if (s == NULL)
        return;
    struct scene_reference r;
    struct err e;
    err_clear(&e);
    enum refract_code rc = scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &r, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "%s", e.msg);
    if (rc == REFRACT_E_OK) {
        const struct reftrace_grid *g = r.objects[0].grid;
        CHECK(g->scattering != NULL && g->anisotropy != NULL);
        CHECK(g->attenuation == NULL && g->emission == NULL && g->opaque == NULL);
        if (g->scattering != NULL && g->anisotropy != NULL) {
            size_t last = voxels(&s->objects[0]) - 1;
            CHECK_NEAR(g->scattering[4 * last + 0], 0.5, 0);
            CHECK_NEAR(g->scattering[4 * last + 2], 0.125, 0);
            CHECK_NEAR(g->scattering[4 * last + 3], 0.0, 0);
            CHECK_NEAR(g->anisotropy[last], 0.3, 1e-7);
        }
        scene_reference_free(&r);
    }
    scene_destroy(s);

    s = parse_ok(OBJ8("\"ior\": 1.33"));
    if (s != NULL &&
        scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &r, &e) == REFRACT_E_OK) {
        CHECK(r.objects[0].grid->scattering == NULL);
        CHECK(r.objects[0].grid->anisotropy == NULL);
        scene_reference_free(&r);
    }
    scene_destroy(s);
}

int main(void)
{
    channel_table_covers_the_new_channels();
    unused_channels_evaluate_to_zero();
    scattering_layers_give_rgb_and_zero();
    anisotropy_is_one_float_per_voxel_with_shape_coverage();
    volumes_fill_scattering_and_clamp_anisotropy();
    bumpy_sphere_bulges_and_dents_where_its_radius_says();
    bumpy_sphere_bounds_hold_the_whole_solid();
    bumpy_sphere_field_equals_voxelwise_coverage();
    reference_grids_carry_scattering_and_anisotropy();
    return test_summary("test_scene_scattering");
}
