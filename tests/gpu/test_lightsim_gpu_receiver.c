/*
 * test_lightsim_gpu_receiver.c - the GPU light simulator lights the receiver as its CPU
 * twin does (tests/unit/test_lightsim_receiver.c; docs/lightsim.md "Domain"): scene A of
 * shared/peer-scenes/SCENES.md with the ball removed, a point light over the floor. The
 * GPU's volume against lightsim_ref_run's (irradiance relative L1 < 2e-4, the bound of
 * test_lightsim_gpu_vs_ref), and the floor read from the GPU's volume by the receiver
 * shading against the closed form: the check value 0.264553 +-1 %, no rings; on a 7 x 7
 * square (the grid over the whole square) and on an infinite floor (the grid over the
 * footprint, the closed form beyond it).
 */
#include "scene/scene.h"
#include "test_lightsim_gpu_support.h"
#include "unit/lightsim_floor.h"

/* One scene: its fields on the light grid of the floor's point light (with_light) or on the
 * whole receiver, the GPU run against the CPU one, the floor from the GPU's volume. */
static void floor_case(struct gpu *gpu, const char *what, const char *json, bool with_light,
                       double edge)
{
    struct scene *s = NULL;
    struct err e = {0};
    struct scene_limits lim = scene_limits_default();
    CHECK_INT(scene_parse(json, strlen(json), &lim, &s, &e), REFRACT_E_OK);
    if (s == NULL)
        return;
    s->lightsim = test_lightsim_settings(32);
    s->lightsim.energy_threshold = 1e-4;
    struct scene_light l = test_point(FLOOR_LIGHT.x, FLOOR_LIGHT.y, FLOOR_LIGHT.z);
    struct lightsim_fields f;
    CHECK_INT(lightsim_fields_build_light(s, with_light ? &l : NULL, NULL, NULL, &f, &e),
              REFRACT_E_OK);
    struct irradiance_volume ref;
    CHECK_INT(lightsim_ref_run(&f, &l, &s->lightsim, &ref, &e), REFRACT_E_OK);
    struct test_gpu_run t = {.fields = &f, .light = l, .set = s->lightsim, .chunk = 64};
    CHECK_INT(test_gpu_simulate(gpu, &t), REFRACT_E_OK);
    if (t.out.irradiance != NULL && ref.irradiance != NULL) {
        size_t n = (size_t)f.grid.dims[0] * f.grid.dims[1] * f.grid.dims[2];
        double l1 = 0, norm = 0;
        for (size_t v = 0; v < 4 * n; v++) {
            l1 += fabs((double)t.out.irradiance[v] - ref.irradiance[v]);
            norm += fabs((double)ref.irradiance[v]);
        }
        printf("%s: grid %d x %d x %d: GPU %.0f ms; irradiance relative L1 GPU - CPU %.2e\n", what,
               f.grid.dims[0], f.grid.dims[1], f.grid.dims[2], t.ms, l1 / norm);
        CHECK(l1 / norm < 2e-4);
        struct lit_floor lf;
        lit_floor_bind(&lf, &t.out, &s->receiver);
        floor_check(what, &lf, f.grid.voxel, edge, 0.015, 0.005);
        irradiance_volume_free(&t.out);
    }
    irradiance_volume_free(&ref);
    lightsim_fields_free(&f);
    scene_destroy(s);
}

int main(void)
{
    struct gpu *gpu = test_start_gpu("test_lightsim_gpu_receiver");
    /* the 7 x 7 square, its whole area in the grid; rows 2 voxels inside it */
    floor_case(gpu, "GPU, square", FLOOR_SCENE, false, 3.5 - 2.0 * 0.25);
    /* the infinite floor: the grid covers the box's footprint as the light sees it, the
     * closed form beyond (rows anywhere) */
    floor_case(gpu, "GPU, infinite floor",
               "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
               "\"resolution\": 8, \"ior\": 1.0}], "
               "\"receiver\": {\"height\": -1, \"half_size\": \"infinite\", \"albedo\": 0.8}}",
               true, 1e30);
    gpu_destroy(gpu, NULL);
    return test_summary("test_lightsim_gpu_receiver");
}
