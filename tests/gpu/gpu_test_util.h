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

#include "core/env.h"
#include "core/pixel_sample.h"
#include "core/reftrace.h"
#include "core/vec3.h"
#include "gpu/queue.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/scene_reference.h"
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

/* The CPU reference's radiance of pixel (col, row) of a w x h image: its centre ray, or for
 * n > 1 the mean of the n jittered rays render_view.comp averages (pixel_sample.c). walter:
 * when not NULL, the lighting in `set` whose walter.step_offset follows each ray's
 * pixel_step_offset (walter scenes shift the in-scattering points per ray). */
static inline vec3 test_reftrace_pixel(const struct scene_reference *ref,
                                       const struct reftrace_settings *set,
                                       const struct scene_camera *cam, int w, int h, int col,
                                       int row, int n, struct reftrace_lighting *walter)
{
    vec3 o, dir, acc = {0, 0, 0};
    struct reftrace_result r;
    if (n <= 1) {
        camera_ray(cam->eye, cam->look_at, cam->up, cam->fov_y_deg, w, h, col, row, &o, &dir);
        reftrace_ray(ref->objects, ref->count, set, o, dir, &r);
        return r.radiance;
    }
    for (int k = 0; k < n; k++) {
        double dx, dy;
        pixel_sample((uint32_t)col, (uint32_t)row, (uint32_t)k, (uint32_t)n, &dx, &dy);
        camera_ray(cam->eye, cam->look_at, cam->up, cam->fov_y_deg, w, h, col + dx - 0.5,
                   row + dy - 0.5, &o, &dir);
        if (walter != NULL)
            walter->walter.step_offset = pixel_step_offset((uint32_t)k);
        reftrace_ray(ref->objects, ref->count, set, o, dir, &r);
        acc = vec3_add(acc, r.radiance);
    }
    if (walter != NULL)
        walter->walter.step_offset = 0.0;
    return vec3_scale(acc, 1.0 / n);
}

#endif
