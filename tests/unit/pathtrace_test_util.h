/*
 * pathtrace_test_util.h - scenes and estimates shared by the path tracer's tests
 * (test_pathtrace_*.c). Header-only.
 */
#ifndef REFRACT_PATHTRACE_TEST_UTIL_H
#define REFRACT_PATHTRACE_TEST_UTIL_H

#include <math.h>
#include <string.h>

#include "core/pathtrace.h"

static inline struct pathtrace_surface pt_sphere(vec3 c, double r, double ior)
{
    struct pathtrace_surface s;
    memset(&s, 0, sizeof s);
    s.geom.kind = GEOM_SPHERE;
    s.geom.xf = xform_identity();
    s.geom.center = c;
    s.geom.radius = r;
    s.medium.ior = ior;
    return s;
}

static inline struct pathtrace_surface pt_box(vec3 c, vec3 size, double ior)
{
    struct pathtrace_surface s;
    memset(&s, 0, sizeof s);
    s.geom.kind = GEOM_BOX;
    s.geom.xf = xform_identity();
    s.geom.center = c;
    s.geom.size = size;
    s.medium.ior = ior;
    return s;
}

/* An empty scene in vacuum under a uniform environment of radiance env. */
static inline struct pathtrace_scene pt_scene(double env)
{
    struct pathtrace_scene s;
    memset(&s, 0, sizeof s);
    s.ambient.ior = 1.0;
    s.env_kind = PATHTRACE_ENV_UNIFORM;
    for (int c = 0; c < 3; c++)
        s.env_radiance[c] = env;
    return s;
}

/* Scene A of ../shared/peer-scenes/SCENES.md: the glass ball (radius 1, n = 1.5, stored in
 * *ball) on the infinite floor y = -1 (albedo 0.8) under the spherical lamp of radius 0.1
 * and 1000 W at (2, 6, 1), black sky. */
static inline struct pathtrace_scene pt_scene_a(struct pathtrace_surface *ball)
{
    *ball = pt_sphere(vec3_make(0, 0, 0), 1.0, 1.5);
    struct pathtrace_scene s = pt_scene(0.0);
    s.surfaces = ball;
    s.surface_count = 1;
    s.receiver = (struct pathtrace_receiver){true, -1.0, INFINITY, {0.8, 0.8, 0.8}, {0, 0}};
    s.lights[0] = (struct pathtrace_light){
        .kind = PATHTRACE_LIGHT_SPHERE, .position = {2, 6, 1}, .radius = 0.1, .visible = false};
    for (int c = 0; c < 3; c++)
        s.lights[0].value[c] = pathtrace_sphere_radiance(1000.0, 0.1);
    s.light_count = 1;
    return s;
}

/* Mean and standard error of n samples of the ray o + t d, per channel. */
struct pt_estimate {
    double mean[3], stderr_[3];
};

static inline struct pt_estimate pt_estimate_ray(const struct pathtrace_scene *s, vec3 o, vec3 d,
                                                 int n, uint64_t seed)
{
    double sum[3] = {0}, sq[3] = {0};
    uint32_t inside = pathtrace_inside_set(s, o);
    for (int i = 0; i < n; i++) {
        struct pathtrace_rng rng;
        pathtrace_rng_init(&rng, seed, 0, (uint64_t)i);
        double L[3];
        pathtrace_radiance(s, o, vec3_normalize(d), inside, true, &rng, L);
        for (int c = 0; c < 3; c++) {
            sum[c] += L[c];
            sq[c] += L[c] * L[c];
        }
    }
    struct pt_estimate e;
    for (int c = 0; c < 3; c++) {
        e.mean[c] = sum[c] / n;
        double var = (sq[c] - n * e.mean[c] * e.mean[c]) / (n - 1);
        e.stderr_[c] = sqrt(fmax(var, 0.0) / n);
    }
    return e;
}

#endif
