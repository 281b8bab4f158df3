/*
 * gpu_test_util.h - what the GPU tests share, header-only: the GPU thread on the machine's
 * preferred device (hardware, else llvmpipe), or the test reported as not set up (a skip
 * with its reason, tests/test.h) when no EGL/GL 4.5 context can be made; and the small
 * geometry and the lights the GPU-vs-CPU comparisons share. Scenes are parsed with parse_ok
 * (tests/unit/scene_test_util.h).
 */
#ifndef REFRACT_TEST_GPU_UTIL_H
#define REFRACT_TEST_GPU_UTIL_H

#include <math.h>
#include <stdio.h>

#include "core/reftrace.h"
#include "core/vec3.h"
#include "gpu/queue.h"
#include "render/render.h"
#include "scene/scene.h"
#include "test.h"

static inline struct gpu *test_gpu_create(const char *test_name)
{
    struct gpu_desc desc = {.context = {.device_index = -1}};
    struct err e = {0};
    struct gpu *gpu = gpu_create(&desc, &e);
    if (gpu == NULL) {
        fprintf(stderr, "%s\n", e.msg);
        test_setup_failed(test_name, "no EGL/GL 4.5 context could be made");
    }
    return gpu;
}

static inline vec3 v3(const double a[3])
{
    return (vec3){a[0], a[1], a[2]};
}

/* The angle between two directions (radians), safe for rounding past +-1. */
static inline double angle_between(vec3 a, vec3 b)
{
    double c = vec3_dot(vec3_normalize(a), vec3_normalize(b));
    return acos(fmax(-1.0, fmin(1.0, c)));
}

/* A scene's lights as a view request takes them (colour times intensity; the spot's cone
 * as its cosine; the lamp hidden from camera rays unless camera_visible). */
static inline void test_render_lights(const struct scene *s, struct render_light *rl)
{
    for (size_t j = 0; j < s->light_count; j++) {
        const struct scene_light *l = &s->lights[j];
        rl[j] =
            (struct render_light){.kind = l->kind,
                                  .position = l->position,
                                  .direction = l->direction,
                                  .cos_spot = cos(l->spot_angle_deg * M_PI / 180.0),
                                  .scale = {l->color[0] * l->intensity, l->color[1] * l->intensity,
                                            l->color[2] * l->intensity},
                                  .radius = l->radius,
                                  .camera_hidden = !l->camera_visible};
    }
}

/* The same lights as the CPU reference's, in LIGHT_MODE_* `mode`. */
static inline void test_reftrace_lights(const struct scene *s, int mode, struct reftrace_light *rl)
{
    for (size_t j = 0; j < s->light_count; j++) {
        const struct scene_light *l = &s->lights[j];
        rl[j] = (struct reftrace_light){.kind = (int)l->kind,
                                        .mode = mode,
                                        .position = l->position,
                                        .direction = l->direction,
                                        .cos_spot = cos(l->spot_angle_deg * M_PI / 180.0),
                                        .scale = {l->color[0] * l->intensity,
                                                  l->color[1] * l->intensity,
                                                  l->color[2] * l->intensity},
                                        .radius = l->radius,
                                        .camera_hidden = !l->camera_visible};
    }
}

#endif
