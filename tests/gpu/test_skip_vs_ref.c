/*
 * test_skip_vs_ref.c - empty-space skipping (docs/tracing.md "Empty space") on the GPU
 * (trace_rays.comp through render_trace) against its CPU double-precision twin
 * (reftrace with the same macro-cell maps, scene_reference), and the error skipping
 * introduces against the march without it, on scenes with lots of empty space:
 *
 *   - a small absorbing glass sphere (radius 0.2) in a large box: the empty cells around
 *     it and inside it (constant n, but absorbing: those must not be skipped);
 *   - a Gaussian GRIN lens (sigma 0.15) in the same box, whose index decays to the
 *     ambient value: empty cells only where the gradient is below MACROCELL_GRAD_EPS;
 *   - a uniform glass block with an opaque ball (camera rays from above: jumps that end
 *     on the bounds, total internal reflection at the faces, opaque hits);
 *   - a strong absorber with render.min_throughput 1e-2 (rays end absorbed inside it alike
 *     on both sides), and at 0 (none does);
 *   - rays that start inside the box (a camera inside), in empty space and in the lens;
 *   - each scene also as a 48x36 image (render_view.comp, radiance) against the CPU twin.
 *
 * Checks, ray by ray: the GPU with skipping against the CPU with skipping (same status,
 * exit point, direction, optical path, steps), and skipping against no skipping on each
 * side (the error it introduces); and that skipping takes far fewer steps. Bounds,
 * measured on llvmpipe (printed): GPU vs CPU 2e-4 in position and direction as
 * test_steppers_vs_ref (adaptive 5x, as there). Skip vs no skip: a jump is a whole
 * number of fixed steps, so the fixed-step march after it samples the same points: 1e-7 on
 * the CPU for the sphere (seen: 1e-10, and acos's 1.5e-8 in direction), 1e-6 for the GRIN
 * lens, whose tails below MACROCELL_GRAD_EPS a jump ignores (seen: 1.7e-7), 1e-5 in its
 * direction (seen: 3.3e-6: the exit face refracts from |w|, docs/tracing.md "The rim", and
 * the ignored tails change |w| too); the GPU's float
 * rounding on the GPU (2e-4; seen: 1e-5). The
 * adaptive stepper restarts at its largest step after a jump and takes other steps
 * than without: 1e-3 (seen: 1.6e-4), the error its tolerance allows.
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
#define INSIDE 16
#define EYE 64
#define RAYS (SIDE * SIDE + INSIDE + EYE)

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

struct view_work {
    struct gpu_work work;
    const struct scene *scene;
    bool skip;
    struct render_view_result out;
};

static void view_run(struct gpu_work *w, struct gpu *gpu)
{
    struct view_work *v = w->user;
    struct render_desc desc = {0};
    struct render *r = render_create(gpu, &desc, &w->err);
    if (r == NULL)
        return;
    struct render_scene_source src = {.id = "view", .generation = 1, .scene = v->scene};
    struct render_view_request req = {.camera = v->scene->camera, .settings = v->scene->render};
    req.settings.empty_space_skipping = v->skip;
    render_view(r, &src, &req, &v->out, &w->err);
    render_destroy(r);
}

/* The image (render_view.comp) with and without skipping on the GPU, and the CPU twin's
 * radiance per pixel (camera_ray, as tests/integration/test_render_reference.c): the
 * largest difference of each pair relative to |L| + 0.1, and the pixels within 1e-3. */
static void check_view(struct gpu *gpu, const char *label, const struct scene *s,
                       const struct scene_reference *ref, bool adaptive)
{
    struct view_work v[2];
    for (int k = 0; k < 2; k++) {
        v[k] = (struct view_work){.scene = s, .skip = k == 0};
        v[k].work =
            (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = view_run, .user = &v[k]};
        CHECK_INT(gpu_run_sync(gpu, &v[k].work), REFRACT_E_OK);
    }
    const struct scene_camera *cam = &s->camera;
    double gpu_gap = 0.0, cpu_gap = 0.0, twin_gap = 0.0;
    int gpu_close = 0, twin_close = 0, total = cam->width * cam->height;
    for (int row = 0; row < cam->height && v[0].out.rgba && v[1].out.rgba; row++) {
        for (int col = 0; col < cam->width; col++) {
            vec3 o, dir;
            camera_ray(cam->eye, cam->look_at, cam->up, cam->fov_y_deg, cam->width, cam->height,
                       col, row, &o, &dir);
            struct reftrace_result cs, cp;
            struct reftrace_settings st = ref->settings;
            st.empty_space_skipping = true;
            reftrace_ray(ref->objects, ref->count, &st, o, dir, &cs);
            st.empty_space_skipping = false;
            reftrace_ray(ref->objects, ref->count, &st, o, dir, &cp);
            const float *gs = &v[0].out.rgba[(row * cam->width + col) * 4];
            const float *gp = &v[1].out.rgba[(row * cam->width + col) * 4];
            double want_s[3] = {cs.radiance.x, cs.radiance.y, cs.radiance.z};
            double want_p[3] = {cp.radiance.x, cp.radiance.y, cp.radiance.z};
            bool gpu_ok = true, twin_ok = true;
            for (int c = 0; c < 3; c++) {
                double scale = fabs(want_p[c]) + 0.1; /* test_render_reference's 1e-4 at 1e-3 */
                gpu_gap = fmax(gpu_gap, fabs(gs[c] - gp[c]) / scale);
                cpu_gap = fmax(cpu_gap, fabs(want_s[c] - want_p[c]) / scale);
                twin_gap = fmax(twin_gap, fabs(gs[c] - want_s[c]) / scale);
                gpu_ok = gpu_ok && fabs(gs[c] - gp[c]) <= 1e-3 * scale;
                twin_ok = twin_ok && fabs(gs[c] - want_s[c]) <= 1e-3 * scale;
            }
            gpu_close += gpu_ok;
            twin_close += twin_ok;
        }
    }
    printf("%s image %dx%d: skip vs no skip: GPU worst %.3g, %.1f%% of pixels within 1e-3; CPU "
           "worst %.3g; GPU vs CPU with skipping: worst %.3g, %.1f%% within 1e-3\n",
           label, cam->width, cam->height, gpu_gap, 100.0 * gpu_close / total, cpu_gap, twin_gap,
           100.0 * twin_close / total);
    /* Bounds (seen: GPU 99.5-100%, CPU worst 3.4e-3 adaptive, 2.3e-4 otherwise; GPU vs CPU
     * 98.3-100%, test_render_reference allows 96%). */
    CHECK_MSG(gpu_close >= (adaptive ? 0.97 : 0.99) * total,
              "%s: GPU image with skipping: %d "
              "of %d pixels within 1e-3 of the image without",
              label, gpu_close, total);
    CHECK_MSG(cpu_gap <= (adaptive ? 1e-2 : 1e-3), "%s: CPU radiance with skipping off by %g",
              label, cpu_gap);
    CHECK_MSG(twin_close >= 0.96 * total,
              "%s: GPU image with skipping: %d of %d pixels within "
              "1e-3 of the CPU twin",
              label, twin_close, total);
    free(v[0].out.rgba);
    free(v[1].out.rgba);
}

/* An oblique bundle from outside the box, and rays from points inside it. */
static void make_rays(struct render_trace_ray *rays)
{
    for (int j = 0; j < SIDE; j++)
        for (int i = 0; i < SIDE; i++) {
            struct render_trace_ray *r = &rays[j * SIDE + i];
            vec3 o = {-0.6 + 1.2 * (i + 0.5) / SIDE, -0.6 + 1.2 * (j + 0.37) / SIDE, -2.0};
            vec3 d = vec3_normalize((vec3){0.13, -0.07, 1.0});
            memcpy(r->origin, &o, sizeof r->origin);
            memcpy(r->direction, &d, sizeof r->direction);
        }
    for (int k = 0; k < INSIDE; k++) {
        struct render_trace_ray *r = &rays[SIDE * SIDE + k];
        double a = 2.0 * M_PI * k / INSIDE;
        vec3 o = {0.6 * cos(a), 0.3 * sin(3.0 * a), 0.6 * sin(a)};
        vec3 d = vec3_normalize(vec3_sub((vec3){0.05, 0.02, -0.03}, o)); /* towards the centre */
        memcpy(r->origin, &o, sizeof r->origin);
        memcpy(r->direction, &d, sizeof r->direction);
    }
    for (int k = 0; k < EYE; k++) { /* a camera above and in front, looking down at the box */
        struct render_trace_ray *r = &rays[SIDE * SIDE + INSIDE + k];
        vec3 o = {0.3, 0.8, 3.6};
        vec3 at = {-0.9 + 1.8 * (k % 8 + 0.5) / 8, -0.9 + 1.8 * (k / 8 + 0.5) / 8, 0.0};
        vec3 d = vec3_normalize(vec3_sub(at, o));
        memcpy(r->origin, &o, sizeof r->origin);
        memcpy(r->direction, &d, sizeof r->direction);
    }
}

struct side {
    struct reftrace_result r[RAYS];
};

static double min_throughput_override = -1.0; /* >= 0: replaces render.min_throughput */

static void gpu_trace(struct gpu *gpu, const char *id, const struct scene *s, bool skip,
                      struct side *out, double *steps)
{
    static struct trace_work t;
    memset(&t, 0, sizeof t);
    t.scene = s;
    t.id = id;
    t.settings = s->render;
    t.settings.empty_space_skipping = skip;
    if (min_throughput_override >= 0.0)
        t.settings.min_throughput = min_throughput_override;
    make_rays(t.rays);
    t.work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = trace_run, .user = &t};
    CHECK_INT(gpu_run_sync(gpu, &t.work), REFRACT_E_OK);
    *steps = 0.0;
    for (int k = 0; k < RAYS; k++) {
        const struct render_trace_hit *h = &t.hits[k];
        out->r[k] = (struct reftrace_result){.status = (enum ray_status)h->status,
                                             .exit_origin = v3(h->exit_origin),
                                             .exit_direction = v3(h->exit_direction),
                                             .transmittance = v3(h->transmittance),
                                             .optical_path_length = h->optical_path_length,
                                             .steps = h->steps};
        *steps += h->steps;
    }
    *steps /= RAYS;
}

static void cpu_trace(const struct scene_reference *ref, bool skip, struct side *out, double *steps)
{
    struct render_trace_ray rays[RAYS];
    make_rays(rays);
    struct reftrace_settings st = ref->settings;
    st.empty_space_skipping = skip;
    *steps = 0.0;
    for (int k = 0; k < RAYS; k++) {
        reftrace_ray(ref->objects, ref->count, &st, v3(rays[k].origin), v3(rays[k].direction),
                     &out->r[k]);
        *steps += out->r[k].steps;
    }
    *steps /= RAYS;
}

struct deviation {
    double pos, dir, opl, trans;
    int status_diff, steps_diff;
};

static int count_status(const struct side *a, enum ray_status st)
{
    int n = 0;
    for (int k = 0; k < RAYS; k++)
        n += a->r[k].status == st;
    return n;
}

/* render.min_throughput: at 1e-2 rays through the strong absorber end as absorbed on both
 * sides alike (check_scene compares them ray by ray); at 0 none does, and the throughput
 * they report is below the cut-off the default would have applied. */
static void check_cutoff(struct gpu *gpu, const struct scene *s)
{
    struct scene_reference ref;
    struct err e = {0};
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &ref, &e), REFRACT_E_OK);
    static struct side g, c;
    double gs, cs;
    min_throughput_override = 0.0;
    gpu_trace(gpu, "absorber-never", s, true, &g, &gs);
    min_throughput_override = -1.0;
    ref.settings.min_throughput = -1.0; /* never */
    cpu_trace(&ref, true, &c, &cs);
    double darkest = 1.0;
    for (int k = 0; k < RAYS; k++)
        darkest = fmin(darkest, g.r[k].transmittance.x);
    printf("absorber, min_throughput 0: absorbed GPU %d, CPU %d; darkest transmittance %.3g\n",
           count_status(&g, RAY_ABSORBED), count_status(&c, RAY_ABSORBED), darkest);
    CHECK_INT(count_status(&g, RAY_ABSORBED), 0);
    CHECK_INT(count_status(&c, RAY_ABSORBED), 0);
    CHECK(darkest < 1e-2);
    scene_reference_free(&ref);
}

static struct deviation compare(const struct side *a, const struct side *b)
{
    struct deviation d = {0};
    for (int k = 0; k < RAYS; k++) {
        const struct reftrace_result *x = &a->r[k], *y = &b->r[k];
        d.status_diff += x->status != y->status;
        d.steps_diff += x->steps != y->steps;
        d.pos = fmax(d.pos, vec3_length(vec3_sub(x->exit_origin, y->exit_origin)));
        d.dir = fmax(d.dir, angle_between(x->exit_direction, y->exit_direction));
        d.opl = fmax(d.opl, fabs(x->optical_path_length - y->optical_path_length));
        d.trans = fmax(d.trans, vec3_length(vec3_sub(x->transmittance, y->transmittance)));
    }
    return d;
}

static void report(const char *label, const char *what, struct deviation d)
{
    printf("%s %s: position %.3g, direction %.3g rad, opl %.3g, transmittance %.3g; status "
           "differs on %d, steps on %d of %d rays\n",
           label, what, d.pos, d.dir, d.opl, d.trans, d.status_diff, d.steps_diff, RAYS);
}

static void check_within(const char *label, const char *what, struct deviation d, double pos,
                         double dir, double trans)
{
    report(label, what, d);
    CHECK_MSG(d.status_diff == 0, "%s %s: %d statuses differ", label, what, d.status_diff);
    CHECK_MSG(d.pos <= pos, "%s %s: position %g > %g", label, what, d.pos, pos);
    CHECK_MSG(d.dir <= dir, "%s %s: direction %g > %g", label, what, d.dir, dir);
    CHECK_MSG(d.opl <= 10.0 * pos, "%s %s: optical path %g > %g", label, what, d.opl, 10.0 * pos);
    CHECK_MSG(d.trans <= trans, "%s %s: transmittance %g > %g", label, what, d.trans, trans);
}

/* bound: GPU vs CPU and GPU skip vs no skip; cpu_bound: CPU skip vs no skip. */
static void check_scene(struct gpu *gpu, const char *label, const struct scene *s, double bound,
                        double cpu_bound, double max_step_ratio)
{
    struct scene_reference ref;
    struct err e = {0};
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &ref, &e), REFRACT_E_OK);
    CHECK_MSG(ref.cells[0].empty_count > 0, "%s: no empty cells", label);
    printf("%s: %zu of %zu macro cells empty\n", label, ref.cells[0].empty_count,
           macrocell_count(&ref.cells[0]));
    static struct side gpu_skip, gpu_plain, cpu_skip, cpu_plain;
    double gs, gp, cs, cp;
    gpu_trace(gpu, label, s, true, &gpu_skip, &gs);
    gpu_trace(gpu, label, s, false, &gpu_plain, &gp);
    cpu_trace(&ref, true, &cpu_skip, &cs);
    cpu_trace(&ref, false, &cpu_plain, &cp);
    printf("%s: mean steps per ray GPU %.1f with skipping, %.1f without; CPU %.1f, %.1f; absorbed "
           "%d, %d, %d, %d\n",
           label, gs, gp, cs, cp, count_status(&gpu_skip, RAY_ABSORBED),
           count_status(&gpu_plain, RAY_ABSORBED), count_status(&cpu_skip, RAY_ABSORBED),
           count_status(&cpu_plain, RAY_ABSORBED));
    if (s->render.min_throughput > 1e-3)
        CHECK_MSG(count_status(&gpu_skip, RAY_ABSORBED) > 0, "%s: no ray absorbed", label);
    struct deviation twin = compare(&gpu_skip, &cpu_skip);
    struct deviation twin_plain = compare(&gpu_plain, &cpu_plain);
    /* Transmittance GPU vs CPU: the GPU's attenuation atlas holds half floats (11 bits;
     * seen: 2.4e-4 through the strong absorber, with or without skipping). */
    check_within(label, "GPU vs CPU, skipping", twin, bound, bound, 1e-3);
    check_within(label, "GPU vs CPU, no skipping", twin_plain, bound, bound, 1e-3);
    /* The same step counts where the plain march has them (adaptive: float and double
     * accept or reject differently near the tolerance, with or without skipping). */
    CHECK_MSG(twin.steps_diff <= twin_plain.steps_diff + RAYS / 20, "%s: steps differ on %d rays",
              label, twin.steps_diff);
    /* Direction 10x the position's bound: the exit face refracts from |w| (see above). */
    check_within(label, "CPU skip vs no skip", compare(&cpu_skip, &cpu_plain), cpu_bound,
                 10.0 * cpu_bound, cpu_bound);
    check_within(label, "GPU skip vs no skip", compare(&gpu_skip, &gpu_plain), bound, bound, bound);
    CHECK_MSG(gs <= max_step_ratio * gp, "%s: %.1f steps with skipping, %.1f without", label, gs,
              gp);
    CHECK_MSG(cs <= max_step_ratio * cp, "%s: CPU %.1f steps with skipping, %.1f without", label,
              cs, cp);
    check_view(gpu, label, s, &ref, s->render.stepper == SCENE_STEPPER_ADAPTIVE);
    scene_reference_free(&ref);
}

#define CAM                                                                                        \
    "\"camera\": {\"eye\": [0.3, 0.8, 3.6], \"look_at\": [0, 0, 0], \"fov_y_deg\": 40, "           \
    "\"width\": 48, \"height\": 36}, "
#define BOX "\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 48"
#define SPHERE                                                                                     \
    "{\"name\": \"t\", " CAM "\"objects\": [{" BOX                                                 \
    ", \"ior\": {\"shape\": \"sphere\", \"center\": "                                              \
    "[0.1, 0, 0], \"radius\": 0.2, \"inside\": 1.5}, \"attenuation\": {\"shape\": \"sphere\", "    \
    "\"center\": [0.1, 0, 0], \"radius\": 0.2, \"inside\": [0.5, 1.0, 2.0]}}]}"
#define GRIN                                                                                       \
    "{\"name\": \"t\", " CAM "\"objects\": [{" BOX                                                 \
    ", \"smoothing_sigma\": 0, \"ior\": {\"profile\": "                                            \
    "\"gaussian\", \"center\": [0, 0, 0], \"n_peak\": 1.5, \"n_out\": 1.0, \"sigma\": 0.15}}]}"
#define GRIN_ADAPTIVE                                                                              \
    "{\"name\": \"t\", " CAM                                                                       \
    "\"render\": {\"stepper\": \"adaptive\", \"step\": 2}, \"objects\": [{" BOX                    \
    ", \"smoothing_sigma\": 0, \"ior\": {\"profile\": \"gaussian\", \"center\": [0, 0, 0], "       \
    "\"n_peak\": 1.5, \"n_out\": 1.0, \"sigma\": 0.15}}]}"
#define GRIN_TRICUBIC                                                                              \
    "{\"name\": \"t\", " CAM "\"render\": {\"ior_filter\": \"tricubic\"}, \"objects\": [{" BOX     \
    ", \"smoothing_sigma\": 0, \"ior\": {\"profile\": \"gaussian\", \"center\": [0, 0, 0], "       \
    "\"n_peak\": 1.5, \"n_out\": 1.0, \"sigma\": 0.15}}]}"
#define SPHERE16                                                                                   \
    "{\"name\": \"t\", " CAM "\"render\": {\"ior_texture\": \"float16\"}, \"objects\": [{" BOX     \
    ", \"ior\": {\"shape\": \"sphere\", \"center\": [0.1, 0, 0], \"radius\": 0.2, \"inside\": "    \
    "1.5}}]}"

#define BLOCK                                                                                      \
    "{\"name\": \"t\", " CAM "\"objects\": [{" BOX                                                 \
    ", \"ior\": 1.4, \"opaque_ior\": 1.8, \"opaque\": "                                            \
    "{\"shape\": \"sphere\", \"radius\": 0.45, \"inside\": [0.8, 0.2, 0.1]}}]}"

#define ABSORBER                                                                                   \
    "{\"name\": \"t\", " CAM "\"render\": {\"min_throughput\": 0.01}, \"objects\": [{" BOX         \
    ", \"ior\": {\"shape\": \"sphere\", \"center\": [0.1, 0, 0], \"radius\": 0.3, \"inside\": "    \
    "1.5}, \"attenuation\": {\"shape\": \"sphere\", \"center\": [0.1, 0, 0], \"radius\": 0.3, "    \
    "\"inside\": [20, 40, 80]}}]}"

int main(void)
{
    struct err e = {0};
    struct gpu *gpu = test_gpu_create("test_skip_vs_ref");
    bool software = strstr(gpu_info(gpu)->renderer, "llvmpipe") != NULL;
    double bound = software ? 2e-4 : 2e-3;
    /* grin-tricubic: the map allows for the tricubic footprint (two texels beyond a cell),
     * and GPU and CPU skip the same cells. */
    const char *docs[] = {SPHERE, GRIN, GRIN_ADAPTIVE, SPHERE16, BLOCK, ABSORBER, GRIN_TRICUBIC};
    const char *labels[] = {"sphere", "grin",     "grin-adaptive", "sphere-float16",
                            "block",  "absorber", "grin-tricubic"};
    /* Steps with skipping / without, at most (seen: 0.31, 0.72, 0.91, 0.31): the adaptive
     * stepper already takes 2-voxel steps in empty space. */
    const double ratio[] = {0.5, 0.8, 0.95, 0.5, 0.5, 0.5, 0.9};
    const double loose[] = {1.0, 1.0, 5.0, 1.0,
                            1.0, 1.0, 1.0}; /* adaptive: as test_steppers_vs_ref */
    const double cpu_bound[] = {1e-7, 1e-6, 1e-3, 1e-7, 1e-7, 1e-7, 1e-6};
    for (int k = 0; k < 7; k++) {
        struct scene *s = parse_ok(docs[k]);
        if (s)
            check_scene(gpu, labels[k], s, loose[k] * bound, cpu_bound[k], ratio[k]);
        if (s && k == 5)
            check_cutoff(gpu, s);
        scene_destroy(s);
    }
    /* The same field: the tricubic map marks fewer cells empty (its footprint is wider). */
    struct scene *lin = parse_ok(GRIN), *cub = parse_ok(GRIN_TRICUBIC);
    struct scene_reference rl, rc;
    if (lin && cub &&
        scene_reference_build(lin, SCENE_REFERENCE_VOXELS, NULL, NULL, &rl, &e) == REFRACT_E_OK) {
        if (scene_reference_build(cub, SCENE_REFERENCE_VOXELS, NULL, NULL, &rc, &e) ==
            REFRACT_E_OK) {
            printf("empty cells: trilinear %zu, tricubic %zu\n", rl.cells[0].empty_count,
                   rc.cells[0].empty_count);
            CHECK(rc.cells[0].empty_count < rl.cells[0].empty_count);
            CHECK(rc.cells[0].empty_count > 0);
            scene_reference_free(&rc);
        }
        scene_reference_free(&rl);
    }
    scene_destroy(lin);
    scene_destroy(cub);
    gpu_destroy(gpu, NULL);
    return test_summary("test_skip_vs_ref");
}
