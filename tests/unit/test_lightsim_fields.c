/*
 * test_lightsim_fields.c - lightsim_fields_build against the scene (docs/lightsim.md
 * "Fields"): a rotated, scaled, translated linear GRIN object gives n and grad n on the
 * light grid in world units; overlapping objects resolve to the first; sigma_t and the
 * opaque coverage are the object's; the probe distance scales with the object.
 *
 * Tolerances: 1e-6 relative: the scene module evaluates fields in float (scene_field_eval),
 * and trilinear sampling and central differences of a linear field are otherwise exact.
 */
#include "test_lightsim_fixture.h"

static size_t vidx(const struct light_grid *g, int i, int j, int k)
{
    return fx_index(g, i, j, k);
}

static void test_linear_grin(void)
{
    /* world = (1, 0, 0) + 2 R_z(90) object; n = 1.3 + g . p (object units) */
    struct scene *s = fx_scene(
        "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": "
        "16, \"smoothing_sigma\": 0, \"transform\": {\"translate\": [1, 0, 0], \"scale\": 2, "
        "\"rotate\": {\"axis\": [0, 0, 1], \"angle_deg\": 90}}, \"ior\": {\"profile\": \"linear\", "
        "\"n0\": 1.3, \"gradient\": [0.1, -0.05, 0.02]}}]}");
    s->lightsim = fx_settings(24, 16);
    struct lightsim_fields f;
    struct err e = {0};
    CHECK_INT(lightsim_fields_build(s, NULL, NULL, &f, &e), REFRACT_E_OK);
    const struct light_grid *g = &f.grid;
    /* the world box is [-1, 3] x [-2, 2] x [-2, 2] */
    CHECK_NEAR(g->voxel, 4.0 / 20.0, 1e-12);
    CHECK_NEAR(g->bmin.x, -1.0 - 2.0 * g->voxel, 1e-9);
    const struct xform *xf = &s->objects[0].world_from_object;
    vec3 grad_obj = {0.1, -0.05, 0.02};
    vec3 grad_world = xform_gradient_to_world(xf, grad_obj); /* R g / scale */
    double worst_n = 0.0, worst_g = 0.0;
    int checked = 0;
    for (int k = 0; k < g->dims[2]; k++)
        for (int j = 0; j < g->dims[1]; j++)
            for (int i = 0; i < g->dims[0]; i++) {
                vec3 x = fx_centre(g, i, j, k);
                vec3 p = xform_point_to_object(xf, x);
                /* 2 light voxels (0.4 world = 0.2 object) inside the bounds: both central
                 * difference neighbours sample the object's interior */
                if (fabs(p.x) > 0.75 || fabs(p.y) > 0.75 || fabs(p.z) > 0.75)
                    continue;
                const double *v = f.ior_grad + 4 * vidx(g, i, j, k);
                worst_n = fmax(worst_n, fabs(v[3] - (1.3 + vec3_dot(grad_obj, p))));
                worst_g =
                    fmax(worst_g, vec3_length(vec3_sub((vec3){v[0], v[1], v[2]}, grad_world)));
                checked++;
            }
    printf("linear GRIN: %d voxels, worst n error %.3g, gradient error %.3g\n", checked, worst_n,
           worst_g);
    CHECK(checked > 500);
    CHECK(worst_n <= 1e-6);
    CHECK(worst_g <= 1e-5);
    /* outside the object (the pad): ambient, no gradient two voxels out */
    const double *corner = f.ior_grad + 4 * vidx(g, 0, 0, 0);
    CHECK_NEAR(corner[3], 1.0, 0.0);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

static void test_overlap_and_channels(void)
{
    struct scene *s = fx_scene(
        "{\"objects\": ["
        "{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [0.2, 1, 1]}, \"resolution\": 16, "
        "\"smoothing_sigma\": 2, \"ior\": 1.2},"
        "{\"bounds\": {\"min\": [-0.2, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, "
        "\"ior\": 1.7, \"attenuation\": [1, 2, 3], \"scattering\": [0.5, 0.5, 0.5], "
        "\"opaque\": {\"shape\": \"box\", \"center\": [0.6, 0, 0], \"size\": [0.4, 0.4, 0.4], "
        "\"inside\": 0.3}}]}");
    s->lightsim = fx_settings(24, 16);
    struct lightsim_fields f;
    struct err e = {0};
    CHECK_INT(lightsim_fields_build(s, NULL, NULL, &f, &e), REFRACT_E_OK);
    const struct light_grid *g = &f.grid;
    int j = g->dims[1] / 2, k = g->dims[2] / 2;
    bool first_wins = true, second = true, opaque = true;
    for (int i = 0; i < g->dims[0]; i++) {
        vec3 x = fx_centre(g, i, j, k);
        const double *n = f.ior_grad + 4 * vidx(g, i, j, k);
        const double *ex = f.extinction + 4 * vidx(g, i, j, k);
        if (x.x > -0.15 && x.x < 0.15) /* in both boxes: the first object's */
            first_wins = first_wins && fabs(n[3] - 1.2) < 1e-6 && ex[0] == 0.0;
        if (x.x > 0.3 && x.x < 0.9) /* the second only: sigma_a + sigma_s */
            second = second && fabs(n[3] - 1.7) < 1e-6 && fabs(ex[0] - 1.5) < 1e-6 &&
                     fabs(ex[1] - 2.5) < 1e-6 && fabs(ex[2] - 3.5) < 1e-6;
        if (x.x > 0.5 && x.x < 0.7) /* inside the opaque box (1.5 light voxels in) */
            opaque = opaque && ex[3] > 0.99;
        if (x.x > 0.9 && x.x < 1.0)
            opaque = opaque && ex[3] < 0.01;
    }
    CHECK(first_wins);
    CHECK(second);
    CHECK(opaque);
    /* probe distance: 3 x the largest smoothing width (2 voxels of 1.2 / 16) + 2 voxels */
    CHECK_NEAR(f.probe_distance, 3.0 * 2.0 * (1.2 / 16.0) + 2.0 * g->voxel, 1e-12);
    CHECK_NEAR(f.boundary_threshold, s->render.boundary_threshold, 0.0);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

int main(void)
{
    test_linear_grin();
    test_overlap_and_channels();
    return test_summary("test_lightsim_fields");
}
