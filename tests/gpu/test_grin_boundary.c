/*
 * test_grin_boundary.c - the voxel GRIN field up to the bounds faces on the GPU (issue 12
 * item 5; docs/tracing.md "The rim"): a Luneburg lens n = sqrt(2 - r^2), R = 1, at 128^3
 * with default settings, in bounds that touch the sphere (+-1: every ray leaves through
 * the focus, which lies on the exit face) and in bounds with a margin (+-1.05), traced by
 * trace_rays.comp (render_trace) for a parallel bundle from z = -2 along +z over 95% of
 * the aperture, with the index filter trilinear (the default) and tricubic.
 *
 * Checked per layout and filter:
 * - the GPU against its CPU twin (reftrace on scene_reference's voxels) ray by ray: the
 *   same status, exit point within 2e-4 and direction within 5e-4 rad (llvmpipe; ten times
 *   looser on hardware with 8-bit filter weights), as tests/gpu/test_steppers_vs_ref.c;
 * - the GPU against the Dormand-Prince reference on the exact field: the touching
 *   layout's median exit-direction error within 3x of the +-1.05 layout's, both below
 *   0.05 deg, the worst below 0.2 deg. Before the fix (the exit face refracting from the
 *   clamped n(p') instead of |w|, docs/tracing.md "The rim") the touching layout's median
 *   was 0.294 deg against 0.017 (trilinear) and 0.0086 (tricubic): all three checks fail.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "gpu/queue.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/scene_reference.h"
#include "gpu_test_util.h"
#include "unit/scene_test_util.h"
#include "test.h"

#define SIDE 12
#define RAYS (SIDE * SIDE)
#define DEG (180.0 / M_PI)

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

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

/* Shirley's concentric map onto 95% of the aperture, from z = -2 along +z (as
 * bench/accuracy_cases.c). */
static void bundle(struct render_trace_ray *rays)
{
    for (int j = 0; j < SIDE; j++)
        for (int i = 0; i < SIDE; i++) {
            double a = 2.0 * (i + 0.5) / SIDE - 1.0, b = 2.0 * (j + 0.5) / SIDE - 1.0, r, phi;
            if (fabs(a) > fabs(b)) {
                r = a;
                phi = (M_PI / 4.0) * (b / a);
            } else {
                r = b;
                phi = M_PI / 2.0 - (M_PI / 4.0) * (a / b);
            }
            struct render_trace_ray *ray = &rays[j * SIDE + i];
            ray->origin[0] = 0.95 * r * cos(phi);
            ray->origin[1] = 0.95 * r * sin(phi);
            ray->origin[2] = -2.0;
            ray->direction[0] = ray->direction[1] = 0.0;
            ray->direction[2] = 1.0;
        }
}

struct layout_result {
    double median, worst; /* GPU against the exact field, deg */
};

static struct layout_result check_layout(struct gpu *gpu, double half, const char *filter,
                                         double pos_bound, double dir_bound)
{
    struct layout_result out = {INFINITY, INFINITY};
    char doc[512], label[64];
    snprintf(doc, sizeof doc,
             "{\"render\": {\"ior_filter\": \"%s\"}, \"objects\": [{\"bounds\": {\"min\": [%g, "
             "%g, %g], \"max\": [%g, %g, %g]}, \"resolution\": 128, \"ior\": {\"profile\": "
             "\"luneburg\", \"center\": [0, 0, 0], \"radius\": 1.0}}]}",
             filter, -half, -half, -half, half, half, half);
    snprintf(label, sizeof label, "luneburg +-%g %s", half, filter);
    struct scene *s = parse_ok(doc);
    if (s == NULL)
        return out;
    struct trace_work t = {.scene = s, .id = label, .settings = s->render};
    bundle(t.rays);
    t.work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = trace_run, .user = &t};
    CHECK_INT(gpu_run_sync(gpu, &t.work), REFRACT_E_OK);

    struct scene_reference vox, exact;
    struct err e = {0};
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &vox, &e), REFRACT_E_OK);
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_ANALYTIC, NULL, NULL, &exact, &e),
              REFRACT_E_OK);
    struct reftrace_settings st = exact.settings;
    st.stepper = REFTRACE_ADAPTIVE;
    st.tolerance = 1e-10;
    st.step_voxels = 1.0;
    st.max_steps = 10000000;
    double err[RAYS], worst_p = 0.0, worst_d = 0.0, twin_err[RAYS];
    int status_ok = 0;
    for (int k = 0; k < RAYS; k++) {
        vec3 o = v3(t.rays[k].origin), d = v3(t.rays[k].direction);
        struct reftrace_result cpu, x;
        reftrace_ray(vox.objects, vox.count, &vox.settings, o, d, &cpu);
        reftrace_ray(exact.objects, exact.count, &st, o, d, &x);
        vec3 gp = v3(t.hits[k].exit_origin), gd = v3(t.hits[k].exit_direction);
        status_ok += t.hits[k].status == (int)cpu.status && cpu.status == RAY_EXITED &&
                     x.status == RAY_EXITED;
        worst_p = fmax(worst_p, vec3_length(vec3_sub(gp, cpu.exit_origin)));
        worst_d = fmax(worst_d, angle_between(gd, cpu.exit_direction));
        err[k] = angle_between(gd, x.exit_direction) * DEG;
        twin_err[k] = angle_between(cpu.exit_direction, x.exit_direction) * DEG;
    }
    qsort(err, RAYS, sizeof err[0], cmp_double);
    qsort(twin_err, RAYS, sizeof twin_err[0], cmp_double);
    out.median = 0.5 * (err[RAYS / 2 - 1] + err[RAYS / 2]);
    out.worst = err[RAYS - 1];
    printf("%s: GPU vs CPU twin worst position %.3g, direction %.3g rad; against the exact "
           "field: GPU median %.3g deg, worst %.3g; CPU twin median %.3g deg, worst %.3g\n",
           label, worst_p, worst_d, out.median, out.worst,
           0.5 * (twin_err[RAYS / 2 - 1] + twin_err[RAYS / 2]), twin_err[RAYS - 1]);
    CHECK_INT(status_ok, RAYS);
    CHECK_MSG(worst_p <= pos_bound, "%s: position %g > %g", label, worst_p, pos_bound);
    CHECK_MSG(worst_d <= dir_bound, "%s: direction %g > %g", label, worst_d, dir_bound);
    scene_reference_free(&vox);
    scene_reference_free(&exact);
    scene_destroy(s);
    return out;
}

int main(void)
{
    struct gpu *gpu = test_gpu_create("test_grin_boundary");
    bool software = strstr(gpu_info(gpu)->renderer, "llvmpipe") != NULL;
    double pos = software ? 2e-4 : 2e-3, dir = software ? 5e-4 : 5e-3;
    static const char *const filters[2] = {"trilinear", "tricubic"};
    for (int f = 0; f < 2; f++) {
        struct layout_result touch = check_layout(gpu, 1.0, filters[f], pos, dir);
        struct layout_result margin = check_layout(gpu, 1.05, filters[f], pos, dir);
        CHECK_MSG(touch.median <= 3.0 * margin.median, "%s: touching %g deg > 3 x %g", filters[f],
                  touch.median, margin.median);
        CHECK_MSG(touch.median < 0.05 && margin.median < 0.05, "%s: medians %g, %g deg", filters[f],
                  touch.median, margin.median);
        CHECK_MSG(touch.worst < 0.2 && margin.worst < 0.2, "%s: worst %g, %g deg", filters[f],
                  touch.worst, margin.worst);
    }
    gpu_destroy(gpu, NULL);
    return test_summary("test_grin_boundary");
}
