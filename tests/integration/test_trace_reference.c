/*
 * test_trace_reference.c - optical ray queries through a real refractd (/trace, the GPU
 * march) against the CPU double-precision reference tracer (server/core/reftrace.c):
 *
 *   1. on the same voxel fields with the same stepper (scene_reference VOXELS): the
 *      GPU's float32 march must agree closely: this bounds the GPU's deviation;
 *   2. on the exact continuous GRIN profile with an adaptive Dormand-Prince stepper
 *      (scene_reference ANALYTIC): this bounds the discretisation error of the voxel
 *      representation at the resolution used, with closed forms where they exist
 *      (a Luneburg lens focuses a parallel bundle on its far surface; a Maxwell fish-eye
 *      images a surface point to its antipode).
 *
 * Profiles: luneburg, maxwell_fisheye, linear (with face refraction and a mirage turn),
 * gaussian (also with render.ior_filter tricubic, as a scene setting and as a request
 * override); plus a smoothed sharp glass sphere for the Fresnel events.
 */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "daemon.h"
#include "parse_scene.h"
#include "scene/scene_reference.h"
#include "test.h"

#define MAX_RAYS 64

/* How far the GPU's float32 march may drift from the CPU's double march on the same voxels
 * (world units, radians). Mesa's llvmpipe filters float textures with float weights:
 * measured ~2e-5 worst, so 2e-4. Hardware samplers interpolate with ~8-bit fractions
 * (e.g. NVIDIA), which costs ~1e-3 in the gradient: 3e-3 there. Set from /v1/health. */
static double gpu_tol = 2e-4;

struct ray {
    vec3 o, d;
};

struct gpu_hit {
    char status[16];
    vec3 x, d, t;
    double opl;
    int steps;
};

static vec3 json_vec3(const cJSON *a)
{
    return (vec3){cJSON_GetArrayItem(a, 0)->valuedouble, cJSON_GetArrayItem(a, 1)->valuedouble,
                  cJSON_GetArrayItem(a, 2)->valuedouble};
}

/* Traces rays through the daemon; returns how many hits were parsed. */
static int gpu_trace(struct test_daemon *d, const char *id, const struct ray *rays, int n,
                     const char *extra, struct gpu_hit *hits)
{
    char *req = malloc(256 + (size_t)n * 160);
    size_t len = (size_t)sprintf(req, "{%s\"rays\": [", extra);
    for (int i = 0; i < n; i++)
        len += (size_t)sprintf(req + len,
                               "%s{\"origin\": [%.17g, %.17g, %.17g], "
                               "\"direction\": [%.17g, %.17g, %.17g]}",
                               i ? ", " : "", rays[i].o.x, rays[i].o.y, rays[i].o.z, rays[i].d.x,
                               rays[i].d.y, rays[i].d.z);
    sprintf(req + len, "]}");
    char *json = NULL;
    int rc = refract_trace(d->client, id, req, &json);
    free(req);
    if (rc != REFRACT_E_OK) {
        fprintf(stderr, "trace failed: %s\n", refract_errmsg(d->client));
        return 0;
    }
    cJSON *root = cJSON_Parse(json);
    const cJSON *arr = cJSON_GetObjectItemCaseSensitive(root, "rays");
    int count = 0;
    const cJSON *h;
    cJSON_ArrayForEach(h, arr)
    {
        if (count >= n)
            break;
        struct gpu_hit *g = &hits[count++];
        snprintf(g->status, sizeof g->status, "%s",
                 cJSON_GetObjectItemCaseSensitive(h, "status")->valuestring);
        g->x = json_vec3(cJSON_GetObjectItemCaseSensitive(h, "exit_origin"));
        g->d = json_vec3(cJSON_GetObjectItemCaseSensitive(h, "exit_direction"));
        g->t = json_vec3(cJSON_GetObjectItemCaseSensitive(h, "transmittance"));
        g->opl = cJSON_GetObjectItemCaseSensitive(h, "optical_path_length")->valuedouble;
        g->steps = cJSON_GetObjectItemCaseSensitive(h, "steps")->valueint;
    }
    cJSON_Delete(root);
    refract_free(json);
    return count;
}

static double angle_between(vec3 a, vec3 b)
{
    double c = vec3_dot(vec3_normalize(a), vec3_normalize(b));
    return acos(fmax(-1.0, fmin(1.0, c)));
}

struct deviation {
    double pos, dir, opl, trans;
    int status_mismatch;
};

/* GPU hits against the reference for the same rays. */
static struct deviation compare(const struct scene_reference *ref,
                                const struct reftrace_settings *st, const struct ray *rays,
                                const struct gpu_hit *hits, int n, struct reftrace_result *out)
{
    struct deviation dev = {0};
    for (int i = 0; i < n; i++) {
        struct reftrace_result r;
        reftrace_ray(ref->objects, ref->count, st, rays[i].o, rays[i].d, &r);
        if (out)
            out[i] = r;
        if (strcmp(ray_status_json(r.status), hits[i].status) != 0) {
            dev.status_mismatch++;
            fprintf(stderr, "  ray %d: status %s on the GPU, %s in the reference\n", i,
                    hits[i].status, ray_status_json(r.status));
            continue;
        }
        dev.pos = fmax(dev.pos, vec3_length(vec3_sub(r.exit_origin, hits[i].x)));
        dev.dir = fmax(dev.dir, angle_between(r.exit_direction, hits[i].d));
        dev.opl = fmax(dev.opl, fabs(r.optical_path_length - hits[i].opl));
        dev.trans = fmax(dev.trans, fabs(r.transmittance.x - hits[i].t.x));
    }
    return dev;
}

/* Distance from point c to the line through x along d. */
static double miss_distance(vec3 x, vec3 d, vec3 c)
{
    vec3 to = vec3_sub(c, x);
    vec3 u = vec3_normalize(d);
    return vec3_length(vec3_madd(to, u, -vec3_dot(to, u)));
}

static void report(const char *what, struct deviation d)
{
    printf("%-44s pos %.2e  dir %.2e rad  opl %.2e  T %.2e  status mismatches %d\n", what, d.pos,
           d.dir, d.opl, d.trans, d.status_mismatch);
}

/* ---- one GRIN check: the same rays on the GPU and on the CPU --------------------------- */

#define MAX_CHECK_RAYS 32

/* What one scene's rays gave: the GPU hits, the CPU reference on the same voxels and
 * stepper (same_voxels), and the adaptive trace of the exact continuous field
 * (vs_exact, exact_hits) when the scene has an analytic form. */
struct traced {
    struct scene *scene;
    struct scene_reference vox, exact;
    bool has_exact;
    struct gpu_hit hits[MAX_CHECK_RAYS];
    struct reftrace_result voxel_hits[MAX_CHECK_RAYS], exact_hits[MAX_CHECK_RAYS];
    struct deviation same_voxels, vs_exact;
};

/* Creates the scene in the daemon, traces the rays there and on the CPU, and prints the
 * deviations as "<label>: GPU vs ...". Returns false (after a failed CHECK) when the
 * scene or the trace could not be made; traced_free() in any case. */
static bool trace_both_ways(struct test_daemon *d, const char *json, const char *label,
                            bool with_exact, const struct ray *rays, int n, struct traced *t)
{
    memset(t, 0, sizeof *t);
    char id[REFRACT_ID_SIZE];
    t->scene = test_parse_scene(json);
    if (t->scene == NULL || n > MAX_CHECK_RAYS || !test_create_scene(d, json, id)) {
        CHECK(false);
        return false;
    }
    int got = gpu_trace(d, id, rays, n, "", t->hits);
    CHECK_INT(got, n);
    struct err e = {0};
    enum refract_code rc =
        scene_reference_build(t->scene, SCENE_REFERENCE_VOXELS, NULL, NULL, &t->vox, &e);
    CHECK_INT(rc, REFRACT_E_OK);
    if (got != n || rc != REFRACT_E_OK)
        return false;
    char what[96];
    t->same_voxels = compare(&t->vox, &t->vox.settings, rays, t->hits, n, t->voxel_hits);
    snprintf(what, sizeof what, "%s: GPU vs CPU, same voxels", label);
    report(what, t->same_voxels);
    if (!with_exact)
        return true;
    rc = scene_reference_build(t->scene, SCENE_REFERENCE_ANALYTIC, NULL, NULL, &t->exact, &e);
    CHECK_INT(rc, REFRACT_E_OK);
    if (rc != REFRACT_E_OK)
        return false;
    t->has_exact = true;
    struct reftrace_settings adaptive = t->exact.settings;
    adaptive.stepper = REFTRACE_ADAPTIVE;
    adaptive.tolerance = 1e-10;
    t->vs_exact = compare(&t->exact, &adaptive, rays, t->hits, n, t->exact_hits);
    snprintf(what, sizeof what, "%s: GPU vs exact field (adaptive)", label);
    report(what, t->vs_exact);
    return true;
}

static void traced_free(struct traced *t)
{
    scene_reference_free(&t->vox); /* safe on the zeroed struct of a failed build */
    scene_reference_free(&t->exact);
    scene_destroy(t->scene);
}

/* ---- Luneburg ------------------------------------------------------------------------ */

static const char *const luneburg_json =
    "{\"render\": {\"stepper\": \"rk4\", \"step\": 0.5},"
    " \"objects\": [{\"bounds\": {\"min\": [-1.05, -1.05, -1.05], \"max\": [1.05, 1.05, 1.05]},"
    " \"resolution\": 64, \"smoothing_sigma\": 0,"
    " \"ior\": {\"profile\": \"luneburg\", \"center\": [0, 0, 0], \"radius\": 1.0}}]}";

static void luneburg_focuses_parallel_rays_on_far_side(struct test_daemon *d)
{
    struct ray rays[18];
    int n = 0;
    for (int k = 1; k <= 9; k++) {
        double h = 0.1 * k;
        rays[n++] = (struct ray){{0.0, h, -2.0}, {0, 0, 1}};
        rays[n++] = (struct ray){{h * 0.6, -h * 0.8, -2.0}, {0, 0, 1}};
    }
    struct traced t;
    if (trace_both_ways(d, luneburg_json, "luneburg 64^3", true, rays, n, &t)) {
        /* Closed form: the exact reference focuses on (0, 0, 1) within 1e-6, so the lens
         * is right; the GPU focus error is the voxel discretisation error. Rays leave the
         * bounds at z = 1.05 on straight lines (n = 1 outside the lens): their closest
         * approach to the focus (0, 0, 1) measures the focusing error. */
        double worst_exact = 0.0, worst_gpu = 0.0;
        for (int i = 0; i < n; i++) {
            worst_exact =
                fmax(worst_exact, miss_distance(t.exact_hits[i].exit_origin,
                                                t.exact_hits[i].exit_direction, (vec3){0, 0, 1}));
            worst_gpu = fmax(worst_gpu, miss_distance(t.hits[i].x, t.hits[i].d, (vec3){0, 0, 1}));
        }
        printf("luneburg focus: exact reference %.2e R, GPU 64^3 %.2e R\n", worst_exact, worst_gpu);
        CHECK_MSG(worst_exact < 1e-5, "exact focus error %g", worst_exact);
        CHECK_MSG(worst_gpu < 0.03, "GPU focus error %g R", worst_gpu);
        /* GPU float32 vs CPU double on the same voxels and stepper. */
        CHECK_INT(t.same_voxels.status_mismatch, 0);
        CHECK_MSG(t.same_voxels.pos < gpu_tol, "position deviation %g", t.same_voxels.pos);
        CHECK_MSG(t.same_voxels.dir < gpu_tol, "direction deviation %g", t.same_voxels.dir);
        CHECK_MSG(t.same_voxels.opl < gpu_tol, "OPL deviation %g", t.same_voxels.opl);
        /* Discretisation at 64^3: measured ~1e-2; bound it. */
        CHECK_INT(t.vs_exact.status_mismatch, 0);
        CHECK_MSG(t.vs_exact.dir < 0.05, "direction error vs exact %g", t.vs_exact.dir);
        CHECK_MSG(t.vs_exact.opl < 0.02, "OPL error vs exact %g", t.vs_exact.opl);
    }
    traced_free(&t);
}

/* ---- Maxwell fish-eye ---------------------------------------------------------------- */

static const char *const fisheye_json =
    "{\"render\": {\"stepper\": \"rk4\", \"step\": 0.5, \"boundary_threshold\": 1},"
    " \"objects\": [{\"bounds\": {\"min\": [-1.1, -1.1, -1.1], \"max\": [1.1, 1.1, 1.1]},"
    " \"resolution\": 64, \"smoothing_sigma\": 0,"
    " \"ior\": {\"profile\": \"maxwell_fisheye\", \"radius\": 1.0, \"n0\": 2}}]}";

/* Rays from the surface point (0, 0, -1) in many directions: all pass the antipode. */
static void fisheye_images_surface_point_to_antipode(struct test_daemon *d)
{
    struct ray rays[12];
    int n = 0;
    for (int k = 0; k < 12; k++) {
        double a = (k + 0.5) * (M_PI / 2.2) / 12.0, phi = k * 2.4;
        rays[n++] = (struct ray){{0, 0, -1.0}, {sin(a) * cos(phi), sin(a) * sin(phi), cos(a)}};
    }
    struct traced t;
    if (trace_both_ways(d, fisheye_json, "fisheye 64^3", true, rays, n, &t)) {
        /* Outside r = 1 the index is n0/2 = 1, so exit rays are straight lines: their
         * closest approach to the antipode (0, 0, 1) measures the imaging error. */
        double worst = 0.0, worst_exact = 0.0;
        for (int i = 0; i < n; i++) {
            worst = fmax(worst, miss_distance(t.hits[i].x, t.hits[i].d, (vec3){0, 0, 1}));
            worst_exact =
                fmax(worst_exact, miss_distance(t.exact_hits[i].exit_origin,
                                                t.exact_hits[i].exit_direction, (vec3){0, 0, 1}));
        }
        printf("fisheye: rays pass the antipode within %.2e (GPU 64^3), %.2e (exact)\n", worst,
               worst_exact);
        CHECK_MSG(worst_exact < 1e-4, "exact antipode miss %g", worst_exact);
        CHECK_MSG(worst < 0.03, "antipode miss %g", worst);
        CHECK_INT(t.same_voxels.status_mismatch, 0);
        CHECK_MSG(t.same_voxels.pos < gpu_tol && t.same_voxels.dir < gpu_tol, "GPU vs CPU %g %g",
                  t.same_voxels.pos, t.same_voxels.dir);
        /* All rays cross at the antipode, where grad n jumps from 1 to 0 across the
         * sphere (a kink the voxels smooth over one voxel): exit directions there are
         * sensitive, measured ~0.06 rad at 64^3, while the imaging itself (the antipode
         * miss) is 1e-3. */
        CHECK_MSG(t.vs_exact.dir < 0.15, "vs exact %g", t.vs_exact.dir);
    }
    traced_free(&t);
}

/* ---- linear gradient: face refraction, and a mirage ------------------------------------ */

static const char *const linear_json =
    "{\"render\": {\"stepper\": \"rk4\", \"step\": 0.5},"
    " \"objects\": [{\"bounds\": {\"min\": [-1, -2, -2], \"max\": [1, 2, 2]},"
    " \"resolution\": [32, 64, 64], \"smoothing_sigma\": 0,"
    " \"ior\": {\"profile\": \"linear\", \"n0\": 1.3, \"gradient\": [0, 0.2, 0]}}]}";

static void linear_gradient_bends_rays_and_turns_grazing_ones(struct test_daemon *d)
{
    struct ray rays[8];
    int n = 0;
    /* Launched from inside, slightly downwards toward lower n: they turn around (mirage)
     * and leave through the far face going up. */
    for (int k = 0; k < 4; k++)
        rays[n++] = (struct ray){{0, 0.2 * k - 0.3, -1.9}, vec3_normalize((vec3){0, -0.08, 1})};
    /* From outside through the faces (n at the faces differs from the ambient 1). */
    for (int k = 0; k < 4; k++)
        rays[n++] = (struct ray){{-0.3 * k, 0.1, -3}, vec3_normalize((vec3){0.1 * k, 0.05, 1})};
    struct traced t;
    if (trace_both_ways(d, linear_json, "linear", true, rays, n, &t)) {
        for (int i = 0; i < 4; i++) {
            const struct gpu_hit *h = &t.hits[i];
            printf("  mirage ray %d: %s at (%.3f %.3f %.3f) dir (%.3f %.3f %.3f)\n", i, h->status,
                   h->x.x, h->x.y, h->x.z, h->d.x, h->d.y, h->d.z);
            CHECK_MSG(h->d.y > 0.0, "mirage ray %d did not turn upwards (d.y %g)", i, h->d.y);
        }
        CHECK_INT(t.same_voxels.status_mismatch, 0);
        CHECK_MSG(t.same_voxels.pos < gpu_tol && t.same_voxels.dir < gpu_tol, "GPU vs CPU %g %g",
                  t.same_voxels.pos, t.same_voxels.dir);
        /* A linear field is exactly representable by trilinear voxels: only float error. */
        CHECK_INT(t.vs_exact.status_mismatch, 0);
        CHECK_MSG(t.vs_exact.pos < 1e-3 && t.vs_exact.dir < 1e-3, "vs exact %g %g", t.vs_exact.pos,
                  t.vs_exact.dir);
        CHECK_MSG(t.same_voxels.trans < 1e-4, "face Fresnel transmittance deviation %g",
                  t.same_voxels.trans);
    }
    traced_free(&t);
}

/* ---- gaussian lens ---------------------------------------------------------------------- */

static const char *const gaussian_json =
    "{\"render\": {\"stepper\": \"rk4\", \"step\": 0.5, \"boundary_threshold\": 1},"
    " \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]},"
    " \"resolution\": 64, \"smoothing_sigma\": 0,"
    " \"ior\": {\"profile\": \"gaussian\", \"n_peak\": 1.6, \"n_out\": 1.0, \"sigma\": 0.35}}]}";

static void gaussian_lens_matches_reference(struct test_daemon *d)
{
    struct ray rays[10];
    int n = 0;
    for (int k = 0; k < 10; k++)
        rays[n++] = (struct ray){{0.05 * k, 0.08 * k - 0.3, -2}, {0, 0, 1}};
    struct traced t;
    if (trace_both_ways(d, gaussian_json, "gaussian 64^3", true, rays, n, &t)) {
        CHECK_INT(t.same_voxels.status_mismatch, 0);
        CHECK_MSG(t.same_voxels.pos < gpu_tol && t.same_voxels.dir < gpu_tol, "GPU vs CPU %g %g",
                  t.same_voxels.pos, t.same_voxels.dir);
        CHECK_INT(t.vs_exact.status_mismatch, 0);
        CHECK_MSG(t.vs_exact.pos < 0.02 && t.vs_exact.dir < 0.02, "vs exact %g %g", t.vs_exact.pos,
                  t.vs_exact.dir);
    }
    traced_free(&t);
}

/* ---- the tricubic index filter (render.ior_filter) ------------------------------------ */

static const char *const gaussian_tricubic_json =
    "{\"render\": {\"stepper\": \"rk4\", \"step\": 0.5, \"boundary_threshold\": 1,"
    " \"ior_filter\": \"tricubic\"},"
    " \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]},"
    " \"resolution\": 64, \"smoothing_sigma\": 0,"
    " \"ior\": {\"profile\": \"gaussian\", \"n_peak\": 1.6, \"n_out\": 1.0, \"sigma\": 0.35}}]}";

/* The Gaussian lens with Catmull-Rom reconstruction: the GPU agrees with its CPU twin on
 * the same voxels, the interpolating kernel comes closer to the exact field than trilinear
 * on the same grid (docs/accuracy.md: 0.02-0.06x on its strong Gaussian lens), and the
 * per-request override of a trilinear scene gives the same rays as the scene setting. */
static void tricubic_filter_matches_reference(struct test_daemon *d)
{
    struct ray rays[10];
    int n = 0;
    for (int k = 0; k < 10; k++)
        rays[n++] = (struct ray){{0.05 * k, 0.08 * k - 0.3, -2}, {0, 0, 1}};
    struct traced lin, cub;
    bool ok = trace_both_ways(d, gaussian_json, "gaussian 64^3 trilinear", true, rays, n, &lin);
    ok =
        trace_both_ways(d, gaussian_tricubic_json, "gaussian 64^3 tricubic", true, rays, n, &cub) &&
        ok;
    if (ok) {
        CHECK_INT(cub.same_voxels.status_mismatch, 0);
        CHECK_MSG(cub.same_voxels.pos < gpu_tol && cub.same_voxels.dir < gpu_tol,
                  "tricubic GPU vs CPU %g %g", cub.same_voxels.pos, cub.same_voxels.dir);
        CHECK_INT(cub.vs_exact.status_mismatch, 0);
        /* Measured 0.23x in direction and 0.18x in position; half leaves a margin. */
        CHECK_MSG(cub.vs_exact.dir < 0.5 * lin.vs_exact.dir,
                  "tricubic direction error vs exact %g is not below half trilinear's %g",
                  cub.vs_exact.dir, lin.vs_exact.dir);
        CHECK_MSG(cub.vs_exact.pos < 0.5 * lin.vs_exact.pos,
                  "tricubic position error vs exact %g is not below half trilinear's %g",
                  cub.vs_exact.pos, lin.vs_exact.pos);
        char id[REFRACT_ID_SIZE];
        struct gpu_hit over[10];
        if (test_create_scene(d, gaussian_json, id) &&
            gpu_trace(d, id, rays, n, "\"ior_filter\": \"tricubic\", ", over) == n) {
            double worst = 0.0;
            for (int i = 0; i < n; i++)
                worst = fmax(worst, vec3_length(vec3_sub(over[i].x, cub.hits[i].x)) +
                                        angle_between(over[i].d, cub.hits[i].d));
            printf("request override ior_filter tricubic vs scene setting: %.2e\n", worst);
            /* The same program on the same atlas; what remains is the JSON rounding of the
             * hits (seen 2e-8), far below the 1e-3 between the filters. */
            CHECK_MSG(worst < 1e-6, "override differs from the scene setting by %g", worst);
        } else {
            CHECK(false);
        }
    }
    traced_free(&lin);
    traced_free(&cub);
}

/* ---- a sharp glass sphere: Fresnel events agree --------------------------------------- */

static const char *const glass_json =
    "{\"render\": {\"stepper\": \"rk4\", \"step\": 0.5},"
    " \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]},"
    " \"resolution\": 64, \"smoothing_sigma\": 1,"
    " \"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5, \"outside\": 1.0},"
    " \"attenuation\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": [0.1, 0.3, 0.9]}}]}";

static void glass_sphere_fresnel_and_absorption_match_reference(struct test_daemon *d)
{
    struct ray rays[10];
    int n = 0;
    for (int k = 0; k < 10; k++)
        rays[n++] = (struct ray){{0, 0.07 * k, -3}, {0, 0, 1}};
    struct traced t;
    if (trace_both_ways(d, glass_json, "glass sphere 64^3", false, rays, n, &t)) {
        CHECK_INT(t.same_voxels.status_mismatch, 0);
        CHECK_MSG(t.same_voxels.pos < gpu_tol && t.same_voxels.dir < gpu_tol, "GPU vs CPU %g %g",
                  t.same_voxels.pos, t.same_voxels.dir);
        CHECK_MSG(t.same_voxels.trans < gpu_tol, "transmittance deviation %g", t.same_voxels.trans);
        /* The axial ray: two Fresnel events at normal incidence (0.96^2) and Beer-Lambert
         * over the diameter, blue absorbed most. */
        double axial_expected = 0.96 * 0.96 * exp(-0.9 * 1.6);
        printf("axial ray: T_b = %.4f (GPU), %.4f (CPU), closed form %.4f\n", t.hits[0].t.z,
               t.voxel_hits[0].transmittance.z, axial_expected);
        CHECK_NEAR(t.hits[0].t.z, axial_expected, 0.03 * axial_expected);
        CHECK(t.hits[0].t.x > t.hits[0].t.y && t.hits[0].t.y > t.hits[0].t.z);
    }
    traced_free(&t);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_trace_reference", d.why);
    char *health = NULL;
    if (refract_health(d.client, &health) == REFRACT_E_OK && strstr(health, "\"software\"") == NULL)
        gpu_tol = 3e-3;
    printf("GPU vs CPU tolerance %.0e (%s device)\n", gpu_tol,
           gpu_tol < 1e-3 ? "software" : "hardware");
    refract_free(health);
    luneburg_focuses_parallel_rays_on_far_side(&d);
    fisheye_images_surface_point_to_antipode(&d);
    linear_gradient_bends_rays_and_turns_grazing_ones(&d);
    gaussian_lens_matches_reference(&d);
    tricubic_filter_matches_reference(&d);
    glass_sphere_fresnel_and_absorption_match_reference(&d);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_trace_reference");
}
