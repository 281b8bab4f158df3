/*
 * test_bound_field_gpu.c - a GRIN field inside an exact surface on the GPU (trace_rays.comp
 * through render_trace; shaders/march_bound.glsl, docs/tracing.md "Fields inside surfaces")
 * against its CPU double twin (reftrace on scene_reference's voxels, reftrace_bound.c):
 * the Luneburg lens n = sqrt(2 - r^2), R = 1, at 64^3, filling its exact sphere
 * ({"medium": {"object": "lens"}}), object bounds +-1 (touching) and +-1.05, a parallel
 * bundle from z = -2 along +z over 95% of the aperture, for the rk4 and adaptive steppers.
 *
 * Checked per layout:
 * - the GPU against its CPU twin ray by ray: the same status, exit point within 2e-4 and
 *   direction within 5e-4 rad on llvmpipe (ten times looser on hardware), the agreement
 *   tests/gpu/test_grin_boundary.c demands of the voxel lens;
 * - the focus: every ray leaves the sphere at (0, 0, 1), GPU median miss below 1.5
 *   voxels, worst below 4, and the two layouts' medians within 3x of each other (the
 *   touching layout was once 200x worse on the voxel lens).
 *
 * And a coloured scene: the lens with attenuation and emission fields in its sphere, and a
 * glass box (constant n = 1.5, straight rays) filled by an object whose attenuation is a
 * sphere layer: random rays traced against the CPU twin (status, exit point, direction,
 * transmittance, optical path within 1e-3, as tests/gpu/test_surfaces_gpu.c's nested media)
 * and the image rendered (render_view.comp) against the twin's radiance per pixel (97% of
 * the pixels within 1e-3 relative, as there). And a cylinder and a lathe (a cone) filled by
 * linear GRIN fields (rays bend inside, the GPU's safe ball uses the cylinder's distance
 * and always tests the lathe): traced against the CPU twin the same way.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/env.h"
#include "gpu/queue.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/scene_reference.h"
#include "gpu_test_util.h"
#include "unit/scene_test_util.h"
#include "test.h"

#define SIDE 10
#define RAYS (SIDE * SIDE)
#define RES 64

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

/* Shirley's concentric map onto 95% of the aperture, from z = -2 along +z. */
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
            memset(ray, 0, sizeof *ray);
            ray->origin[0] = 0.95 * r * cos(phi);
            ray->origin[1] = 0.95 * r * sin(phi);
            ray->origin[2] = -2.0;
            ray->direction[2] = 1.0;
        }
}

/* Distance of the exit ray's line from the focus (0, 0, 1). */
static double focus_miss(vec3 origin, vec3 dir)
{
    vec3 f = vec3_sub(vec3_make(0, 0, 1), origin);
    return vec3_length(vec3_cross(f, vec3_normalize(dir)));
}

/* Returns the GPU's median focus miss. */
static double check_layout(struct gpu *gpu, double half, const char *stepper, double pos_bound,
                           double dir_bound)
{
    char doc[768], label[64];
    snprintf(doc, sizeof doc,
             "{\"render\": {\"stepper\": \"%s\"}, \"objects\": [{\"name\": \"lens\", "
             "\"bounds\": {\"min\": [%g, %g, %g], \"max\": [%g, %g, %g]}, \"resolution\": %d, "
             "\"ior\": {\"profile\": \"luneburg\", \"center\": [0, 0, 0], \"radius\": 1.0}}], "
             "\"surfaces\": [{\"name\": \"ball\", \"shape\": \"sphere\", \"center\": [0, 0, 0], "
             "\"radius\": 1, \"medium\": {\"object\": \"lens\"}}]}",
             stepper, -half, -half, -half, half, half, half, RES);
    snprintf(label, sizeof label, "bounded luneburg +-%g %s", half, stepper);
    struct scene *s = parse_ok(doc);
    if (s == NULL)
        return INFINITY;
    struct trace_work t = {.scene = s, .id = label, .settings = s->render};
    bundle(t.rays);
    t.work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = trace_run, .user = &t};
    CHECK_INT(gpu_run_sync(gpu, &t.work), REFRACT_E_OK);
    struct scene_reference vox;
    struct err e = {0};
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &vox, &e), REFRACT_E_OK);
    double miss[RAYS], worst_p = 0.0, worst_d = 0.0, cpu_miss = 0.0;
    int status_ok = 0;
    for (int k = 0; k < RAYS; k++) {
        struct reftrace_result cpu;
        reftrace_ray(vox.objects, vox.count, &vox.settings, v3(t.rays[k].origin),
                     v3(t.rays[k].direction), &cpu);
        vec3 gp = v3(t.hits[k].exit_origin), gd = v3(t.hits[k].exit_direction);
        status_ok += t.hits[k].status == (int)cpu.status && cpu.status == RAY_EXITED;
        worst_p = fmax(worst_p, vec3_length(vec3_sub(gp, cpu.exit_origin)));
        worst_d = fmax(worst_d, angle_between(gd, cpu.exit_direction));
        miss[k] = focus_miss(gp, gd);
        cpu_miss = fmax(cpu_miss, focus_miss(cpu.exit_origin, cpu.exit_direction));
    }
    qsort(miss, RAYS, sizeof miss[0], cmp_double);
    double median = 0.5 * (miss[RAYS / 2 - 1] + miss[RAYS / 2]), h = 2.0 * half / RES;
    printf("%s: GPU vs CPU twin worst position %.3g, direction %.3g rad; GPU focus miss median "
           "%.3g, worst %.3g (CPU worst %.3g; voxel %.3g)\n",
           label, worst_p, worst_d, median, miss[RAYS - 1], cpu_miss, h);
    CHECK_INT(status_ok, RAYS);
    CHECK_MSG(worst_p <= pos_bound, "%s: position %g > %g", label, worst_p, pos_bound);
    CHECK_MSG(worst_d <= dir_bound, "%s: direction %g > %g", label, worst_d, dir_bound);
    CHECK_MSG(median < 1.5 * h, "%s: median miss %g", label, median);
    CHECK_MSG(miss[RAYS - 1] < 4.0 * h, "%s: worst miss %g", label, miss[RAYS - 1]);
    scene_reference_free(&vox);
    scene_destroy(s);
    return median;
}

struct view_work {
    struct gpu_work work;
    const struct scene *scene;
    struct render_view_result out;
};

static void view_run(struct gpu_work *w, struct gpu *gpu)
{
    struct view_work *v = w->user;
    struct render_desc desc = {0};
    struct render *r = render_create(gpu, &desc, &w->err);
    if (r == NULL)
        return;
    struct render_scene_source src = {.id = "coloured", .generation = 1, .scene = v->scene};
    struct render_view_request req = {.camera = v->scene->camera, .settings = v->scene->render};
    render_view(r, &src, &req, &v->out, &w->err);
    render_destroy(r);
}

static const char coloured_doc[] =
    "{\"camera\": {\"eye\": [0.4, 1.0, 4.2], \"look_at\": [0.6, 0, 0], \"width\": 40, "
    "\"height\": 30, \"fov_y_deg\": 45}, \"objects\": [{\"name\": \"lens\", \"bounds\": "
    "{\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 32, \"ior\": {\"profile\": "
    "\"luneburg\", \"center\": [0, 0, 0], \"radius\": 1.0}, \"attenuation\": {\"shape\": "
    "\"sphere\", \"center\": [0.2, 0, 0], \"radius\": 0.5, \"inside\": [2, 1, 0.5]}, "
    "\"emission\": [0.2, 0.1, 0.05]}, {\"name\": \"glass\", \"bounds\": {\"min\": [-0.5, "
    "-0.5, -0.5], \"max\": [0.5, 0.5, 0.5]}, \"resolution\": 16, \"ior\": 1.5, "
    "\"attenuation\": {\"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 0.3, "
    "\"inside\": [0.5, 3, 3]}, \"transform\": {\"translate\": [1.8, 0, 0]}}], \"surfaces\": "
    "[{\"name\": \"ball\", \"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1, "
    "\"medium\": {\"object\": \"lens\"}}, {\"name\": \"box\", \"shape\": \"box\", "
    "\"center\": [1.8, 0, 0], \"size\": [0.9, 0.9, 0.9], \"medium\": {\"object\": "
    "\"glass\"}}]}";

static const char kinds_doc[] =
    "{\"objects\": [{\"name\": \"rod\", \"bounds\": {\"min\": [-0.5, -1, -0.5], \"max\": "
    "[0.5, 1, 0.5]}, \"resolution\": [16, 32, 16], \"ior\": {\"profile\": \"linear\", "
    "\"center\": [0, 0, 0], \"n0\": 1.5, \"gradient\": [0.3, 0, 0]}}, {\"name\": \"cone\", "
    "\"bounds\": {\"min\": [-0.6, 0, -0.6], \"max\": [0.6, 1.2, 0.6]}, \"resolution\": 24, "
    "\"ior\": {\"profile\": \"linear\", \"center\": [0, 0.6, 0], \"n0\": 1.4, \"gradient\": "
    "[0, -0.25, 0.1]}, \"transform\": {\"translate\": [1.5, -0.6, 0]}}], \"surfaces\": "
    "[{\"shape\": \"cylinder\", \"center\": [0, 0, 0], \"radius\": 0.45, \"height\": 1.8, "
    "\"axis\": \"y\", \"medium\": {\"object\": \"rod\"}}, {\"shape\": \"lathe\", \"base\": "
    "[0, 0, 0], \"axis\": \"y\", \"profile\": [[0, 0], [0.55, 0], [0, 1.1]], \"transform\": "
    "{\"translate\": [1.5, -0.6, 0]}, \"medium\": {\"object\": \"cone\"}}]}";

static unsigned seed = 12345;
static double uniform(void)
{
    seed = seed * 1664525u + 1013904223u;
    return (seed >> 8) * (1.0 / 16777216.0);
}

static void check_image(struct gpu *gpu, const struct scene *s, const struct scene_reference *ref);

/* Random rays through s against the CPU twin; with an image when `image`. */
static void check_scene(struct gpu *gpu, const char *doc, const char *label, bool image)
{
    struct scene *s = parse_ok(doc);
    if (s == NULL)
        return;
    struct scene_reference ref;
    struct err e = {0};
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &ref, &e), REFRACT_E_OK);
    struct trace_work *t = calloc(1, sizeof *t);
    t->scene = s;
    t->id = label;
    t->settings = s->render;
    for (int i = 0; i < RAYS; i++) {
        vec3 aim = {3.0 * uniform() - 1.1, 1.8 * (uniform() - 0.5), 0.6 * (uniform() - 0.5)};
        vec3 o = {2.0 * (uniform() - 0.5), 2.0 * (uniform() - 0.5), -3.0};
        vec3 d = vec3_normalize(vec3_sub(aim, o));
        t->rays[i] =
            (struct render_trace_ray){.origin = {o.x, o.y, o.z}, .direction = {d.x, d.y, d.z}};
    }
    t->work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = trace_run, .user = t};
    CHECK_INT(gpu_run_sync(gpu, &t->work), REFRACT_E_OK);
    int same = 0, close = 0, events = 0;
    for (int i = 0; i < RAYS; i++) {
        struct reftrace_result r;
        reftrace_ray(ref.objects, ref.count, &ref.settings, v3(t->rays[i].origin),
                     v3(t->rays[i].direction), &r);
        events += r.event_count;
        const struct render_trace_hit *g = &t->hits[i];
        if (g->status != (int)r.status)
            continue;
        same++;
        double dd = angle_between(v3(g->exit_direction), r.exit_direction);
        double dx = vec3_length(vec3_sub(v3(g->exit_origin), r.exit_origin));
        double dt = fabs(g->transmittance[0] - r.transmittance.x) +
                    fabs(g->transmittance[1] - r.transmittance.y) +
                    fabs(g->transmittance[2] - r.transmittance.z);
        double dopl =
            fabs(g->optical_path_length - r.optical_path_length) / fmax(1.0, r.optical_path_length);
        close += dd < 1e-3 && dx < 1e-3 && dt < 1e-3 && dopl < 1e-4;
    }
    printf("%s: %d rays, %d surface events on the CPU, same status %d, within 1e-3 %d\n", label,
           RAYS, events, same, close);
    CHECK(events > RAYS / 2); /* the rays do cross the media */
    CHECK_MSG(same >= RAYS - 1, "%d of %d statuses agree", same, RAYS);
    CHECK_MSG(close >= RAYS - 2, "%d of %d rays within 1e-3", close, RAYS);
    free(t);
    if (image)
        check_image(gpu, s, &ref);
    scene_reference_free(&ref);
    scene_destroy(s);
}

static void check_image(struct gpu *gpu, const struct scene *s, const struct scene_reference *ref)
{
    struct view_work v = {.scene = s};
    v.work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = view_run, .user = &v};
    CHECK_INT(gpu_run_sync(gpu, &v.work), REFRACT_E_OK);
    const struct scene_camera *cam = &s->camera;
    int within = 0, total = cam->width * cam->height;
    for (int row = 0; row < cam->height && v.out.rgba; row++)
        for (int col = 0; col < cam->width; col++) {
            vec3 o, dir;
            camera_ray(cam->eye, cam->look_at, cam->up, cam->fov_y_deg, cam->width, cam->height,
                       col, row, &o, &dir);
            struct reftrace_result r;
            reftrace_ray(ref->objects, ref->count, &ref->settings, o, dir, &r);
            const float *px = &v.out.rgba[(row * cam->width + col) * 4];
            double want[3] = {r.radiance.x, r.radiance.y, r.radiance.z};
            bool ok = true;
            for (int c = 0; c < 3; c++)
                ok = ok && fabs(px[c] - want[c]) <= 1e-3 * (fabs(want[c]) + 0.1);
            within += ok;
        }
    printf("coloured image %dx%d: %d of %d pixels within 1e-3 of the CPU twin\n", cam->width,
           cam->height, within, total);
    CHECK_MSG(within >= 0.97 * total, "%d of %d pixels", within, total);
    free(v.out.rgba);
}

int main(void)
{
    struct gpu *gpu = test_gpu_create("test_bound_field_gpu");
    bool software = strstr(gpu_info(gpu)->renderer, "llvmpipe") != NULL;
    double pos = software ? 2e-4 : 2e-3, dir = software ? 5e-4 : 5e-3;
    static const char *const steppers[2] = {"rk4", "adaptive"};
    for (int i = 0; i < (test_sanitized() ? 1 : 2); i++) {
        double touch = check_layout(gpu, 1.0, steppers[i], pos, dir);
        double margin = check_layout(gpu, 1.05, steppers[i], pos, dir);
        CHECK_MSG(touch <= 3.0 * margin + 1e-4 && margin <= 3.0 * touch + 1e-4,
                  "%s: touching %g vs margin %g", steppers[i], touch, margin);
    }
    check_scene(gpu, coloured_doc, "coloured", true);
    check_scene(gpu, kinds_doc, "cylinder and lathe", false);
    gpu_destroy(gpu, NULL);
    return test_summary("test_bound_field_gpu");
}
