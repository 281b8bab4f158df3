/*
 * lightsim_floor.h - what the receiver tests share (tests/unit/test_lightsim_receiver.c,
 * tests/gpu/test_lightsim_gpu_receiver.c): scene A of shared/peer-scenes/SCENES.md with
 * the ball removed, i.e. a Lambertian floor y = -1 (albedo 0.8) under a point light of
 * intensity 79.5775 at (2, 6, 1); the closed form L = albedo / pi I cos(theta) / d^2;
 * the receiver shading (reftrace_light_receiver, the twin of shaders/lighting.glsl's
 * light_receiver) reading an irradiance volume from either simulator; and the two checks:
 * the check value 0.264553 at (-2, -1, 2), and rows of floor points 1/8 voxel apart
 * through the light's foot (no rings). Header-only; not a test itself.
 */
#ifndef REFRACT_TEST_LIGHTSIM_FLOOR_H
#define REFRACT_TEST_LIGHTSIM_FLOOR_H

#include <math.h>
#include <stdio.h>

#include "bindings.h"
#include "core/reftrace_light.h"
#include "lightsim/lightsim.h"
#include "scene/scene.h"
#include "test.h"

static const double FLOOR_INTENSITY = 79.5775; /* 1000 W / (4 pi), SCENES.md */
static const double FLOOR_Y = -1.0;
static const vec3 FLOOR_LIGHT = {2, 6, 1};

/* The scene: an index-matched box (n = 1: no effect on the light) standing on the floor,
 * so that the scene has an object, over a 7 x 7 receiver. */
static const char *const FLOOR_SCENE =
    "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
    "\"resolution\": 8, \"ior\": 1.0}], "
    "\"receiver\": {\"height\": -1, \"half_size\": 3.5, \"albedo\": 0.8}}";

/* albedo / pi * I cos / d^2 at floor point (x, FLOOR_Y, z), albedo 0.8 */
static inline double floor_closed_form(double x, double z)
{
    vec3 r = vec3_sub((vec3){x, FLOOR_Y, z}, FLOOR_LIGHT);
    double d2 = vec3_dot(r, r);
    double cos_t = -r.y / sqrt(d2);
    return 0.8 / M_PI * FLOOR_INTENSITY * cos_t / d2;
}

struct lit_floor {
    struct reftrace_light light;
    struct reftrace_lighting lt;
};

/* The shading's view of volume v (borrowed) of the floor's point light, under receiver r. */
static inline void lit_floor_bind(struct lit_floor *lf, const struct irradiance_volume *v,
                                  const struct scene_receiver *r)
{
    const struct light_grid *g = &v->grid;
    lf->light =
        (struct reftrace_light){.kind = LIGHT_KIND_POINT,
                                .mode = LIGHT_MODE_VOLUME,
                                .position = FLOOR_LIGHT,
                                .direction = {0, -1, 0},
                                .scale = {FLOOR_INTENSITY, FLOOR_INTENSITY, FLOOR_INTENSITY},
                                .irradiance = v->irradiance,
                                .direction_volume = v->direction,
                                .dims = {g->dims[0], g->dims[1], g->dims[2]},
                                .bmin = g->bmin,
                                .voxel = g->voxel};
    lf->lt = (struct reftrace_lighting){
        .lights = &lf->light,
        .count = 1,
        .receiver = {.enabled = true,
                     .height = r->height,
                     .half_size = r->half_size,
                     .albedo = {r->albedo[0], r->albedo[1], r->albedo[2]},
                     .center = {r->center[0], r->center[1]}}};
}

/* The receiver's radiance at floor point (x, z), seen straight down from above (no
 * environment: env_up = 0). false where the ray misses the receiver. */
static inline bool floor_radiance(const struct lit_floor *lf, double x, double z, double *L)
{
    vec3 out;
    if (!reftrace_light_receiver(&lf->lt, (vec3){0, 0, 0}, (vec3){x, FLOOR_Y + 3.0, z},
                                 (vec3){0, -1, 0}, &out))
        return false;
    *L = out.x;
    return true;
}

/* The check value and the rows through the light's foot (2, -1, 1) along x and along a
 * diagonal, 1/8 voxel apart, up to 3 from the foot, within `edge` of x = z = 0. Checks:
 * the check value within 1 %, every row point within `worst_bound`, their mean within
 * `mean_bound`. */
static inline void floor_check(const char *what, const struct lit_floor *lf, double voxel,
                               double edge, double worst_bound, double mean_bound)
{
    double L = 0;
    CHECK(floor_radiance(lf, -2.0, 2.0, &L));
    printf("%s: the floor at (-2, -1, 2) reads %.6f, closed form %.6f (%+.3f %%)\n", what, L,
           floor_closed_form(-2.0, 2.0), 100.0 * (L / floor_closed_form(-2.0, 2.0) - 1.0));
    CHECK_NEAR(floor_closed_form(-2.0, 2.0), 0.264553, 1e-6); /* SCENES.md's number */
    CHECK_MSG(fabs(L / 0.264553 - 1.0) <= 0.01, "%s: floor reads %g, not 0.264553 +-1 %%", what, L);
    double worst = 0.0, worst_at = 0.0, sum = 0.0;
    int n = 0;
    double h = voxel / 8.0;
    for (int row = 0; row < 2; row++) {
        for (double t = -3.0; t <= 3.0; t += h) {
            double x = FLOOR_LIGHT.x + t, z = FLOOR_LIGHT.z + (row == 1 ? t : 0.0);
            if (fabs(x) > edge || fabs(z) > edge)
                continue;
            CHECK(floor_radiance(lf, x, z, &L));
            double dev = L / floor_closed_form(x, z) - 1.0;
            sum += dev;
            n++;
            if (fabs(dev) > fabs(worst)) {
                worst = dev;
                worst_at = t;
            }
        }
    }
    printf("%s: %d floor points, mean deviation from the closed form %+.3f %%, worst %+.3f %% "
           "(at %.3f from the foot)\n",
           what, n, 100.0 * sum / n, 100.0 * worst, worst_at);
    CHECK(n > 200);
    CHECK_MSG(fabs(worst) <= worst_bound, "%s: rings: worst deviation %g", what, worst);
    CHECK_MSG(fabs(sum / n) <= mean_bound, "%s: mean deviation %g", what, sum / n);
}

#endif
