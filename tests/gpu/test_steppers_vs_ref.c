/*
 * test_steppers_vs_ref.c - every stepper of the march (euler, rk2, rk4, adaptive)
 * and the float16 index atlas on the GPU (trace_rays.comp through render_trace) against
 * their double-precision CPU twins (reftrace: REFTRACE_EULER, _RK2, _RK4, _BS23) on the
 * same voxels (scene_reference, which rounds the atlas to half floats for float16), ray
 * by ray: exit point and exit direction.
 *
 * Each case also checks that the GPU's exit lies closer to its own twin than to the other
 * steppers' CPU exits, and closer to it than to the twin reconstructing the same voxels
 * with the other index filter (render.ior_filter trilinear / tricubic): a kernel variant
 * that silently ran another stepper or filter would fail there even when all of them
 * land close to each other. Every stepper runs with both filters; tricubic (Catmull-Rom
 * of n and its exact gradient, 64 texel fetches on the GPU, the same 64 taps in double on
 * the CPU) has the same bounds (seen: 8e-6 in position, 3e-6 rad with fixed steps; 4e-4
 * and 2e-4 adaptive).
 *
 * Scenes: a Luneburg lens and a strong Gaussian lens (n_peak 1.8) at 32^3, a parallel
 * bundle of 8 x 8 rays. Bounds, measured on llvmpipe (printed): the fixed-step
 * steppers 2e-4 (seen: 3e-6), the float arithmetic of the GPU against double over some
 * 100 steps; 2e-4 rad in direction. The adaptive stepper 1e-3 in position and
 * 2.5e-3 rad in direction (seen: 2e-4 and 6e-4): where an error estimate lies near
 * the tolerance (1e-3 voxels here), float and double accept or reject differently, and the
 * two step sequences then differ by about the error the tolerance allows. A hardware GPU
 * filters with 8-bit weights, hence ten times looser bounds there.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "gpu/queue.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/scene_reference.h"
#include "gpu_test_util.h"
#include "unit/scene_test_util.h"
#include "test.h"

#define SIDE 8
#define RAYS (SIDE * SIDE)

struct trace_work {
    struct gpu_work work;
    const struct scene *scene;
    const char *id;
    struct scene_render_settings settings;
    struct render_trace_ray rays[RAYS];
    struct render_trace_hit hits[RAYS];
};

static void trace_run(struct gpu_work *w, struct gpu *gpu)
{
    struct trace_work *t = w->user;
    struct render_desc desc = {0};
    struct render *r = render_create(gpu, &desc, &w->err);
    if (r == NULL)
        return;
    struct render_scene_source src = {.id = t->id, .generation = 1, .scene = t->scene};
    render_trace(r, &src, &t->settings, t->rays, RAYS, t->hits, NULL, &w->err);
    render_destroy(r);
}

static const enum scene_stepper steppers[4] = {SCENE_STEPPER_EULER, SCENE_STEPPER_RK2,
                                               SCENE_STEPPER_RK4, SCENE_STEPPER_ADAPTIVE};
static const char *const names[4] = {"euler", "rk2", "rk4", "adaptive"};

/* Traces the bundle with stepper `which` on the GPU and all four on the CPU; checks the
 * GPU against its twin within (pos_bound, dir_bound) and closer to it than to the others. */
static void check_case(struct gpu *gpu, const char *label, const struct scene *s, int which,
                       double step, double pos_bound, double dir_bound)
{
    struct trace_work t = {.scene = s, .id = label, .settings = s->render};
    t.settings.stepper = steppers[which];
    t.settings.step_voxels = step;
    t.settings.tolerance_voxels = 1e-3;
    vec3 lo = s->objects[0].bounds_min, hi = s->objects[0].bounds_max;
    for (int j = 0; j < SIDE; j++)
        for (int i = 0; i < SIDE; i++) {
            struct render_trace_ray *r = &t.rays[j * SIDE + i];
            r->origin[0] = lo.x + (hi.x - lo.x) * (0.1 + 0.8 * (i + 0.5) / SIDE);
            r->origin[1] = lo.y + (hi.y - lo.y) * (0.1 + 0.8 * (j + 0.37) / SIDE);
            r->origin[2] = lo.z - 1.0;
            r->direction[0] = 0.0;
            r->direction[1] = 0.0;
            r->direction[2] = 1.0;
        }
    t.work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = trace_run, .user = &t};
    CHECK_INT(gpu_run_sync(gpu, &t.work), REFRACT_E_OK);
    struct scene_reference ref;
    struct err e = {0};
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &ref, &e), REFRACT_E_OK);
    /* The same voxels reconstructed with the other index filter (render.ior_filter). */
    struct reftrace_object swapped[SCENE_REFERENCE_MAX_OBJECTS];
    for (int i = 0; i < ref.count; i++) {
        swapped[i] = ref.objects[i];
        swapped[i].ior_filter = ref.objects[i].ior_filter == REFTRACE_FILTER_TRICUBIC
                                    ? REFTRACE_FILTER_TRILINEAR
                                    : REFTRACE_FILTER_TRICUBIC;
    }
    double worst_p = 0.0, worst_d = 0.0, nearest_other = INFINITY;
    int status_ok = 0, own_closest = 0, own_filter_closest = 0;
    for (int k = 0; k < RAYS; k++) {
        vec3 o = v3(t.rays[k].origin), d = v3(t.rays[k].direction);
        vec3 gp = v3(t.hits[k].exit_origin), gd = v3(t.hits[k].exit_direction);
        double own = INFINITY, other = INFINITY;
        for (int m = 0; m < 4; m++) {
            struct reftrace_settings st = ref.settings;
            st.stepper = scene_reference_stepper(steppers[m]);
            st.step_voxels = step;
            st.tolerance_voxels = 1e-3;
            struct reftrace_result cpu;
            reftrace_ray(ref.objects, ref.count, &st, o, d, &cpu);
            double dp = vec3_length(vec3_sub(gp, cpu.exit_origin));
            double da = angle_between(gd, cpu.exit_direction);
            if (m == which) {
                worst_p = fmax(worst_p, dp);
                worst_d = fmax(worst_d, da);
                own = dp + da;
                status_ok += t.hits[k].status == (int)cpu.status;
                struct reftrace_result alt;
                reftrace_ray(swapped, ref.count, &st, o, d, &alt);
                own_filter_closest += own < vec3_length(vec3_sub(gp, alt.exit_origin)) +
                                                angle_between(gd, alt.exit_direction);
            } else {
                other = fmin(other, dp + da);
            }
        }
        own_closest += own < other;
        nearest_other = fmin(nearest_other, other);
    }
    printf("%s %s step %.2f: GPU vs CPU twin worst position %.3g, direction %.3g rad; rays "
           "closest to their twin %d/%d, closer to their filter's twin than to the other "
           "filter's %d/%d\n",
           label, names[which], step, worst_p, worst_d, own_closest, RAYS, own_filter_closest,
           RAYS);
    CHECK_INT(status_ok, RAYS);
    CHECK_MSG(worst_p <= pos_bound, "%s %s: position %g > %g", label, names[which], worst_p,
              pos_bound);
    CHECK_MSG(worst_d <= dir_bound, "%s %s: direction %g > %g", label, names[which], worst_d,
              dir_bound);
    /* Rays through the lens centre are nearly straight for every stepper; the rest
     * tell the steppers apart. */
    CHECK_MSG(own_closest >= RAYS * 3 / 4, "%s %s: only %d of %d rays closest to their twin", label,
              names[which], own_closest, RAYS);
    /* A variant that silently sampled with the other filter fails here. */
    CHECK_MSG(own_filter_closest >= RAYS * 3 / 4,
              "%s %s: only %d of %d rays closer to their filter's twin than to the other's", label,
              names[which], own_filter_closest, RAYS);
    scene_reference_free(&ref);
}

#define LENS(RES, EXTRA)                                                                           \
    "{\"name\": \"t\", " EXTRA "\"objects\": [{\"bounds\": {\"min\": [-1.05, -1.05, -1.05], "      \
    "\"max\": [1.05, 1.05, 1.05]}, \"resolution\": " #RES ", \"smoothing_sigma\": 0, "             \
    "\"ior\": {\"profile\": \"luneburg\", \"center\": [0, 0, 0], \"radius\": 1.0}}]}"
#define GAUSS(RES, EXTRA)                                                                          \
    "{\"name\": \"t\", " EXTRA "\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], "               \
    "\"max\": [1, 1, 1]}, \"resolution\": " #RES ", \"smoothing_sigma\": 0, "                      \
    "\"ior\": {\"profile\": \"gaussian\", \"center\": [0, 0, 0], \"n_peak\": 1.8, "                \
    "\"n_out\": 1.0, \"sigma\": 0.3}}]}"

int main(void)
{
    struct gpu *gpu = test_gpu_create("test_steppers_vs_ref");
    bool software = strstr(gpu_info(gpu)->renderer, "llvmpipe") != NULL;
    double pos = software ? 2e-4 : 2e-3, dir = software ? 2e-4 : 2e-3;
    struct scene *lens = parse_ok(LENS(32, ""));
    struct scene *gauss = parse_ok(GAUSS(32, ""));
    struct scene *lens16 = parse_ok(LENS(32, "\"render\": {\"ior_texture\": \"float16\"}, "));
    struct scene *lens3 = parse_ok(LENS(32, "\"render\": {\"ior_filter\": \"tricubic\"}, "));
    struct scene *gauss3 = parse_ok(GAUSS(32, "\"render\": {\"ior_filter\": \"tricubic\"}, "));
    for (int m = 0; m < 4 && lens && gauss; m++) {
        bool adaptive = steppers[m] == SCENE_STEPPER_ADAPTIVE;
        double step = adaptive ? 2.0 : 0.5, loose = adaptive ? 5.0 : 1.0;
        check_case(gpu, "luneburg", lens, m, step, loose * pos, 2.5 * loose * dir);
        check_case(gpu, "gaussian", gauss, m, step, loose * pos, 2.5 * loose * dir);
    }
    if (lens16) {
        check_case(gpu, "luneburg-float16", lens16, 2, 0.5, pos, dir);
        check_case(gpu, "luneburg-float16", lens16, 3, 2.0, 5.0 * pos, 12.5 * dir);
    }
    scene_destroy(lens);
    scene_destroy(gauss);
    for (int m = 0; m < 4 && lens3 && gauss3; m++) {
        bool adaptive = steppers[m] == SCENE_STEPPER_ADAPTIVE;
        double step = adaptive ? 2.0 : 0.5, loose = adaptive ? 5.0 : 1.0;
        check_case(gpu, "luneburg-tricubic", lens3, m, step, loose * pos, 2.5 * loose * dir);
        check_case(gpu, "gaussian-tricubic", gauss3, m, step, loose * pos, 2.5 * loose * dir);
    }
    scene_destroy(lens16);
    scene_destroy(lens3);
    scene_destroy(gauss3);
    gpu_destroy(gpu, NULL);
    return test_summary("test_steppers_vs_ref");
}
