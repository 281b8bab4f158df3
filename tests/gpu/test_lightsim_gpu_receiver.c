/*
 * test_lightsim_gpu_receiver.c - the GPU light simulator lights the receiver as its CPU
 * twin does (tests/unit/test_lightsim_receiver.c; docs/lightsim.md "Domain"): scene A of
 * shared/peer-scenes/SCENES.md with the ball removed, a point light over the floor. The
 * GPU's volume against lightsim_ref_run's (irradiance relative L1 < 2e-4, the bound of
 * test_lightsim_gpu_vs_ref), and the floor read from the GPU's volume by the receiver
 * shading against the closed form: the check value 0.264553 +-1 %, no rings.
 */
#include "scene/scene.h"
#include "test_lightsim_gpu_support.h"
#include "unit/lightsim_floor.h"

int main(void)
{
    struct gpu *gpu = test_start_gpu("test_lightsim_gpu_receiver");
    struct scene *s = NULL;
    struct err e = {0};
    struct scene_limits lim = scene_limits_default();
    CHECK_INT(scene_parse(FLOOR_SCENE, strlen(FLOOR_SCENE), &lim, &s, &e), REFRACT_E_OK);
    s->lightsim = test_lightsim_settings(32);
    s->lightsim.energy_threshold = 1e-4;
    struct lightsim_fields f;
    CHECK_INT(lightsim_fields_build(s, NULL, NULL, &f, &e), REFRACT_E_OK);
    struct scene_light l = test_point(FLOOR_LIGHT.x, FLOOR_LIGHT.y, FLOOR_LIGHT.z);
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
        printf("grid %d x %d x %d: GPU %.0f ms; irradiance relative L1 GPU - CPU %.2e\n",
               f.grid.dims[0], f.grid.dims[1], f.grid.dims[2], t.ms, l1 / norm);
        CHECK(l1 / norm < 2e-4);
        struct lit_floor lf;
        lit_floor_bind(&lf, &t.out, &s->receiver);
        floor_check("GPU", &lf, f.grid.voxel, 3.5 - 2.0 * f.grid.voxel, 0.015, 0.005);
        irradiance_volume_free(&t.out);
    }
    irradiance_volume_free(&ref);
    lightsim_fields_free(&f);
    scene_destroy(s);
    gpu_destroy(gpu, NULL);
    return test_summary("test_lightsim_gpu_receiver");
}
