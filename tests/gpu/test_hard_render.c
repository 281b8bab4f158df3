/*
 * test_hard_render.c - the GPU tracer (trace_rays.comp) and view renderer (render_view.comp)
 * on the hard cases of docs/tracing.md "Hard cases", against the CPU double-precision
 * reference on the same voxels (the scenes of tests/unit/hard_checks.h; the closed forms
 * are checked on the reference in tests/unit/test_hard_reftrace.c).
 *
 * For every case: each GPU hit keeps the invariants (finite, unit direction, 0 <= T <= 1,
 * steps within the budget, a documented status; max_steps exactly when the budget is
 * spent), each pixel of a small view is finite and no brighter than the environment, and
 * the GPU agrees with the reference:
 *   - rays: the same status, T within 1e-4 and exit directions within 1e-3 rad for at least
 *     `ray_fraction` of the rays (float against double: where a ray grazes a rim or meets a
 *     face near the critical angle, the two may take different branches, which is why a
 *     few rays of the rim and step cases may differ; measured fractions are printed);
 *   - pixels: within 1e-3 absolute for at least `pixel_fraction` of the pixels.
 * Images are 32 x 24 and the grids coarse: llvmpipe runs them in seconds.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/env.h"
#include "gpu/queue.h"
#include "render/render.h"
#include "gpu_test_util.h"
#include "test.h"
#include "unit/hard_checks.h"

#define MAX_RAYS 64

struct gpu_case {
    const char *name;
    const char *json;
    struct render_trace_ray rays[MAX_RAYS];
    int ray_count;
    bool allow_pass_cap;                 /* the mirrors: max_steps from the entry cap */
    bool view_inside;                    /* the camera inside the volume */
    double ray_fraction, pixel_fraction; /* agreement bounds, see the header */
    /* filled by the GPU run */
    struct scene *scene;
    struct render_trace_hit hits[MAX_RAYS];
    struct render_view_result view;
    double trace_ms;
};

static void add_ray(struct gpu_case *c, vec3 o, vec3 d)
{
    if (c->ray_count >= MAX_RAYS)
        return;
    d = vec3_normalize(d);
    c->rays[c->ray_count++] =
        (struct render_trace_ray){.origin = {o.x, o.y, o.z}, .direction = {d.x, d.y, d.z}};
}

struct case_work {
    struct gpu_work work;
    struct gpu_case *c;
};

static void case_run(struct gpu_work *w, struct gpu *gpu)
{
    struct case_work *cw = w->user;
    struct gpu_case *c = cw->c;
    struct render_desc desc = {0};
    struct render *r = render_create(gpu, &desc, &w->err);
    if (r == NULL)
        return;
    struct render_scene_source src = {.id = c->name, .generation = 1, .scene = c->scene};
    enum refract_code rc = render_trace(r, &src, &c->scene->render, c->rays, (size_t)c->ray_count,
                                        c->hits, &c->trace_ms, &w->err);
    struct render_view_request req = {.camera = c->scene->camera, .settings = c->scene->render};
    if (rc == REFRACT_E_OK)
        render_view(r, &src, &req, &c->view, &w->err);
    render_destroy(r);
}

static struct hard_hit hard_from_gpu(const struct render_trace_hit *h)
{
    struct hard_hit out = {
        .status = h->status, .optical_path_length = h->optical_path_length, .steps = h->steps};
    for (int k = 0; k < 3; k++) {
        out.origin[k] = h->exit_origin[k];
        out.direction[k] = h->exit_direction[k];
        out.transmittance[k] = h->transmittance[k];
    }
    return out;
}

static void compare_rays(struct gpu_case *c, const struct scene_reference *ref)
{
    int close = 0;
    double worst_t = 0.0, worst_dir = 0.0;
    for (int i = 0; i < c->ray_count; i++) {
        struct hard_hit g = hard_from_gpu(&c->hits[i]);
        hard_check_hit(c->name, i, &g, c->scene->render.max_steps, 1e-5, c->allow_pass_cap);
        const struct render_trace_ray *ray = &c->rays[i];
        vec3 o = {ray->origin[0], ray->origin[1], ray->origin[2]};
        vec3 d = {ray->direction[0], ray->direction[1], ray->direction[2]};
        struct reftrace_result r;
        reftrace_ray(ref->objects, ref->count, &ref->settings, o, d, &r);
        vec3 gd = {g.direction[0], g.direction[1], g.direction[2]};
        double dt = 0.0;
        for (int k = 0; k < 3; k++)
            dt = fmax(dt, fabs(g.transmittance[k] - vec3_get(r.transmittance, k)));
        double ang = acos(fmin(1.0, fmax(-1.0, vec3_dot(gd, r.exit_direction))));
        bool ok = g.status == (int)r.status && dt <= 1e-4 && ang <= 1e-3;
        close += ok;
        worst_t = fmax(worst_t, dt);
        worst_dir = fmax(worst_dir, ang);
        if (!ok && getenv("REFRACT_TEST_VERBOSE"))
            fprintf(stderr,
                    "  %s ray %d: gpu status %d T %.6f dir %.5f %.5f %.5f steps %d | ref status %d "
                    "T %.6f dir %.5f %.5f %.5f steps %d\n",
                    c->name, i, g.status, g.transmittance[0], gd.x, gd.y, gd.z, g.steps, r.status,
                    r.transmittance.x, r.exit_direction.x, r.exit_direction.y, r.exit_direction.z,
                    r.steps);
        /* A spent budget is a spent budget on both sides. */
        if (r.status == RAY_MAX_STEPS && r.steps == ref->settings.max_steps)
            CHECK_MSG(g.status == RAY_MAX_STEPS && g.steps == r.steps,
                      "%s ray %d: the reference spends its budget, the GPU ends with status %d "
                      "after %d steps",
                      c->name, i, g.status, g.steps);
    }
    printf("%-30s trace: %2d of %2d rays agree (status, T 1e-4, direction 1e-3 rad); worst "
           "T %.1e, direction %.1e rad\n",
           c->name, close, c->ray_count, worst_t, worst_dir);
    CHECK_MSG(close >= c->ray_fraction * c->ray_count, "%s: %d of %d rays agree", c->name, close,
              c->ray_count);
}

static void compare_view(struct gpu_case *c, const struct scene_reference *ref)
{
    const struct scene_camera *cam = &c->scene->camera;
    int w = c->view.width, h = c->view.height, close = 0;
    double worst = 0.0;
    for (int row = 0; row < h; row++) {
        for (int col = 0; col < w; col++) {
            const float *px = &c->view.rgba[(row * w + col) * 4];
            double L[3] = {px[0], px[1], px[2]};
            hard_check_radiance(c->name, row * w + col, L, c->scene->environment.intensity, 1e-4);
            vec3 o, d;
            camera_ray(cam->eye, cam->look_at, cam->up, cam->fov_y_deg, w, h, col, row, &o, &d);
            struct reftrace_result r;
            reftrace_ray(ref->objects, ref->count, &ref->settings, o, d, &r);
            double diff = 0.0;
            for (int k = 0; k < 3; k++)
                diff = fmax(diff, fabs(L[k] - vec3_get(r.radiance, k)));
            worst = fmax(worst, diff);
            close += diff <= 1e-3;
        }
    }
    printf("%-30s view %dx%d%s: %5.1f%% of pixels within 1e-3; worst %.2e\n", c->name, w, h,
           c->view_inside ? " (camera inside)" : "", 100.0 * close / (w * h), worst);
    CHECK_MSG(close >= c->pixel_fraction * w * h, "%s: %d of %d pixels within 1e-3", c->name, close,
              w * h);
}

static void run_case(struct gpu *gpu, struct gpu_case *c, const char *camera)
{
    /* The scene's JSON with a small camera put in front of its objects. */
    char json[2048];
    snprintf(json, sizeof json, "{%s, %s", camera, c->json + 1);
    c->scene = hard_scene(json);
    if (c->scene == NULL)
        return;
    struct case_work cw = {.c = c};
    cw.work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = case_run, .user = &cw};
    CHECK_INT(gpu_run_sync(gpu, &cw.work), REFRACT_E_OK);
    struct scene_reference ref;
    if (c->view.rgba == NULL) {
        fprintf(stderr, "%s: %s\n", c->name, cw.work.err.msg);
        CHECK(false);
    } else if (hard_reference(c->scene, &ref)) {
        compare_rays(c, &ref);
        compare_view(c, &ref);
        scene_reference_free(&ref);
    }
    free(c->view.rgba);
    scene_destroy(c->scene);
}

#define CAMERA(eye, at)                                                                            \
    "\"camera\": {\"eye\": " eye ", \"look_at\": " at ", \"fov_y_deg\": 50, \"width\": 32, "       \
    "\"height\": 24}"
#define OUTSIDE CAMERA("[0.6, 0.5, 3]", "[0, 0, 0]")

int main(void)
{
    struct gpu *gpu = test_gpu_create("test_hard_render");

    /* Total internal reflection: a ray trapped in the block (400 steps, from inside), the
     * camera inside the block, and grazing rays from outside. */
    struct gpu_case block = {.name = "glass block, TIR",
                             .json = HARD_BLOCK,
                             .view_inside = true,
                             .ray_fraction = 1.0,
                             .pixel_fraction = 0.95};
    add_ray(&block, (vec3){0.1, 0.2, -0.05}, (vec3){1.0, 1.1, 0.9});
    add_ray(&block, (vec3){-0.3, 0.1, 0.2}, (vec3){-0.9, 1.0, -1.1});
    for (int k = 0; k < 3; k++) {
        double th = (80.0 + 4.9 * k) * M_PI / 180.0;
        vec3 d = {sin(th), 0.0, cos(th)};
        add_ray(&block, vec3_madd((vec3){0.2, 0.1, -0.5}, d, -0.3), d);
    }
    add_ray(&block, (vec3){0.1, 0.2, 0.0}, (vec3){0.3, 0.2, 1});
    run_case(gpu, &block, CAMERA("[0.1, 0.05, 0.3]", "[0, 0, -1]"));

    /* A light pipe: about 17 total reflections, then out of the far end. */
    struct gpu_case rod = {
        .name = "light pipe", .json = HARD_ROD, .ray_fraction = 1.0, .pixel_fraction = 0.95};
    for (int k = 0; k < 4; k++) {
        double th = (45.0 + 5.0 * k) * M_PI / 180.0, ph = (25.0 + 10.0 * k) * M_PI / 180.0;
        vec3 d = {cos(th), sin(th) * cos(ph), sin(th) * sin(ph)};
        add_ray(&rod, vec3_madd((vec3){-2.0, 0.03, -0.02}, d, -0.5), d);
    }
    run_case(gpu, &rod, CAMERA("[-3, 0.4, 0.3]", "[0, 0, 0]"));

    /* Grazing incidence on a sphere's rim, n = 1.5 and 2.42 (high contrast). */
    const char *const sphere_json[2] = {HARD_SPHERE("1.5"), HARD_SPHERE("2.42")};
    const char *const sphere_name[2] = {"sphere rim, n = 1.5", "sphere rim, n = 2.42"};
    for (int s = 0; s < 2; s++) {
        struct gpu_case sph = {.name = sphere_name[s],
                               .json = sphere_json[s],
                               .ray_fraction = 0.9,
                               .pixel_fraction = 0.95};
        for (int k = 0; k < 24; k++)
            add_ray(&sph, (vec3){0.7 + 0.005 * k, 0.05, -3.0}, (vec3){0, 0, 1});
        for (int k = 0; k < 8; k++)
            add_ray(&sph, (vec3){0, 0, 0}, (vec3){sin(0.6 * k), cos(0.6 * k), 0.3});
        run_case(gpu, &sph, OUTSIDE);
    }

    /* A jump 1 -> 3 inside the field, rays from normal incidence to grazing. */
    struct gpu_case jump = {
        .name = "n = 3 slab", .json = HARD_JUMP3, .ray_fraction = 0.9, .pixel_fraction = 0.95};
    for (int k = 0; k < 9; k++) {
        double th = (10.0 * k) * M_PI / 180.0;
        add_ray(&jump, (vec3){-0.5, 0, -0.99}, (vec3){sin(th), 0.1, cos(th)});
    }
    run_case(gpu, &jump, OUTSIDE);

    /* Shells one and two voxels thin. */
    const char *const shell_json[2] = {HARD_SHELL("0.8", "0.72"), HARD_SHELL("0.8", "0.64")};
    const char *const shell_name[2] = {"shell, 1 voxel", "shell, 2 voxels"};
    for (int s = 0; s < 2; s++) {
        struct gpu_case sh = {.name = shell_name[s],
                              .json = shell_json[s],
                              .ray_fraction = 0.9,
                              .pixel_fraction = 0.95};
        for (int k = 0; k < 17; k++)
            add_ray(&sh, (vec3){0.05 * k, 0.02, -3}, (vec3){0, 0, 1});
        run_case(gpu, &sh, OUTSIDE);
    }

    /* Very steep gradients: the linear GRIN (0.24 per voxel) and the unsmoothed step. */
    struct gpu_case steep = {
        .name = "steep GRIN", .json = HARD_STEEP, .ray_fraction = 0.9, .pixel_fraction = 0.95};
    for (int k = 0; k < 6; k++) {
        double a = 15.0 * k * M_PI / 180.0;
        vec3 d = {sin(a), cos(a), 0.0};
        add_ray(&steep, vec3_madd((vec3){-0.8, -1.0, 0.1}, d, -1.0), d);
        add_ray(&steep, (vec3){-0.8, 0.0, -0.5}, (vec3){1, -0.1 - 0.1 * k, 0.3});
    }
    run_case(gpu, &steep, OUTSIDE);
    struct gpu_case step = {.name = "unsmoothed step 1 -> 2",
                            .json = HARD_STEP_SPHERE,
                            .ray_fraction = 0.85,
                            .pixel_fraction = 0.95};
    for (int k = 0; k < 16; k++)
        add_ray(&step, (vec3){0.05 * k, 0.01, -3}, (vec3){0, 0, 1});
    run_case(gpu, &step, OUTSIDE);

    /* Zero, moderate and enormous attenuation (1e5 per unit: absorbed in the first step). */
    const char *const sigma[3] = {"0", "2", "1e5"};
    const char *const absorber_name[3] = {"attenuation 0", "attenuation 2", "attenuation 1e5"};
    for (int s = 0; s < 3; s++) {
        char json[512];
        snprintf(json, sizeof json, HARD_ABSORBER("%s"), sigma[s]);
        struct gpu_case ab = {
            .name = absorber_name[s], .json = json, .ray_fraction = 1.0, .pixel_fraction = 0.95};
        for (int k = 0; k < 8; k++)
            add_ray(&ab, (vec3){-0.4 + 0.1 * k, 0.1, -2}, (vec3){0.05 * k, 0, 1});
        add_ray(&ab, (vec3){0, 0, 0}, (vec3){0.2, 0.1, 1}); /* from inside */
        run_case(gpu, &ab, OUTSIDE);
    }

    /* Reflection between two objects without a single step: the entry cap. */
    struct gpu_case mirrors = {.name = "mirrors, entry cap",
                               .json = HARD_MIRRORS,
                               .allow_pass_cap = true,
                               .ray_fraction = 1.0,
                               .pixel_fraction = 0.95};
    add_ray(&mirrors, (vec3){-0.9, 0, 0.1}, (vec3){1, 1, 0});
    add_ray(&mirrors, (vec3){-0.9, 0, 0.1}, (vec3){1, -1.2, 0.1});
    run_case(gpu, &mirrors, CAMERA("[-3, 0, 0.1]", "[0, 0, 0.1]"));

    gpu_destroy(gpu, NULL);
    return test_summary("test_hard_render");
}
