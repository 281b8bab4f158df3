/*
 * test_lightsim_fixture.h - shared set-up of the light-simulator tests
 * (tests/unit/test_lightsim_*.c): a scene from JSON objects, lights and settings filled in
 * C (their JSON parsing is the scene module's and tested there), one run, voxel access.
 * Header-only; not a test itself (the test glob is test_*.c).
 */
#ifndef REFRACT_TEST_LIGHTSIM_FIXTURE_H
#define REFRACT_TEST_LIGHTSIM_FIXTURE_H

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "lightsim/lightsim.h"
#include "scene/scene.h"
#include "test.h"

static inline struct scene *fx_scene(const char *json)
{
    struct scene *s = NULL;
    struct err e = {0};
    if (scene_parse(json, strlen(json), NULL, &s, &e) != REFRACT_E_OK) {
        fprintf(stderr, "scene: %s\n", e.msg);
        test_setup_failed("lightsim", "a fixture scene did not parse");
    }
    return s;
}

/* docs/scenes.md defaults, but coarse: tests run in seconds. */
static inline struct scene_lightsim fx_settings(int resolution, int initial_patches)
{
    return (struct scene_lightsim){
        .resolution = resolution,
        .step_voxels = 0.5,
        .initial_patches = initial_patches,
        .max_level = 6,
        .split_voxels = 1.0,
        .energy_threshold = 1e-4,
        .point_radius = 0.01,
        .deposit = SCENE_DEPOSIT_FLUX,
        .cull_flipped = false,
        .max_patches = 262144,
    };
}

static inline struct scene_light fx_directional(vec3 d)
{
    return (struct scene_light){.kind = SCENE_LIGHT_DIRECTIONAL,
                                .direction = vec3_normalize(d),
                                .color = {1, 1, 1},
                                .intensity = 1};
}

static inline struct scene_light fx_point(vec3 q)
{
    return (struct scene_light){
        .kind = SCENE_LIGHT_POINT, .position = q, .color = {1, 1, 1}, .intensity = 1};
}

static inline double fx_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Builds the fields of s (its uploads found through lookup, which may be NULL) with
 * s->lightsim = *set and runs light l. */
static inline void fx_run_lookup(struct scene *s, scene_volume_lookup_fn lookup, void *ctx,
                                 const struct scene_light *l, const struct scene_lightsim *set,
                                 struct lightsim_fields *f, struct irradiance_volume *v)
{
    struct err e = {0};
    s->lightsim = *set;
    if (lightsim_fields_build(s, lookup, ctx, f, &e) != REFRACT_E_OK) {
        fprintf(stderr, "fields: %s\n", e.msg);
        test_setup_failed("lightsim", "lightsim_fields_build failed");
    }
    if (lightsim_ref_run(f, l, set, v, &e) != REFRACT_E_OK) {
        fprintf(stderr, "run: %s\n", e.msg);
        test_setup_failed("lightsim", "lightsim_ref_run failed");
    }
}

static inline void fx_run(struct scene *s, const struct scene_light *l,
                          const struct scene_lightsim *set, struct lightsim_fields *f,
                          struct irradiance_volume *v)
{
    fx_run_lookup(s, NULL, NULL, l, set, f, v);
}

static inline size_t fx_index(const struct light_grid *g, int i, int j, int k)
{
    return (size_t)i + (size_t)g->dims[0] * ((size_t)j + (size_t)g->dims[1] * (size_t)k);
}

static inline vec3 fx_centre(const struct light_grid *g, int i, int j, int k)
{
    return vec3_add(g->bmin, vec3_scale((vec3){i + 0.5, j + 0.5, k + 0.5}, g->voxel));
}

static inline const float *fx_E(const struct irradiance_volume *v, int i, int j, int k)
{
    return v->irradiance + 4 * fx_index(&v->grid, i, j, k);
}

static inline void fx_print_stats(const char *what, const struct lightsim_stats *s)
{
    printf("%s: in %.6g out %.6g refl %.6g abs %.6g culled %.6g live %.6g | steps %lld "
           "patch_steps %lld splits %lld initial %d peak %d | culled e%lld l%lld f%lld c%lld\n",
           what, s->flux_in[0], s->flux_out[0], s->flux_reflected[0], s->flux_absorbed[0],
           s->flux_culled[0], s->flux_live[0], s->steps, s->patch_steps, s->splits,
           s->patches_initial, s->patches_peak, s->culled_energy, s->culled_level, s->culled_flip,
           s->culled_capacity);
}

#endif
