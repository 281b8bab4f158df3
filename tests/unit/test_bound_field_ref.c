/*
 * test_bound_field_ref.c - a voxel object's field inside an exact surface (docs/scenes.md
 * "Surfaces", the medium "object" form; docs/tracing.md "Fields inside surfaces") in the
 * CPU double reference:
 *   - luneburg_bounded_by_sphere_focuses_on_far_side: a Luneburg lens n = sqrt(2 - r^2),
 *     R = 1, filling its exact sphere, object bounds +-1 (touching) and +-1.05; a parallel
 *     bundle from z = -2 along +z over 95% of the aperture leaves the sphere at (0, 0, 1).
 *     The focus error of the two layouts must agree (within 3x and 0.01 absolute: the
 *     touching layout once was 200x worse on the voxel lens) and stay below the voxel-only
 *     lens's (proto/examples/luneburg_lens.json) plus its rim error; the exit directions
 *     agree with Dormand-Prince on the exact field in the exact sphere;
 *   - field_continued_beyond_surface_helps: the same bundle with the bound object's field
 *     left as the layers give it (n = 1 outside R) focuses worse, median and worst;
 * The lens has no smoothing (smoothing_sigma 0, as proto/examples/luneburg_lens.json), so
 * the voxels hold the profile and the errors are those of the boundary treatment.
 *   - step_cut_lands_on_surface: every surface event of a field-filled sphere lies on the
 *     sphere to 1e-12 and within 1e-6 of the step of the end of the ray-equation step cut
 *     there (reftrace_event.step_gap), for every stepper;
 *   - constant_n_attenuation_field_is_straight_beer_lambert: a box surface filled by an
 *     object with n = 1.5 and a linear attenuation ramp: straight rays (exit direction =
 *     entry direction through parallel faces), transmittance = Fresnel x exp(-integral of
 *     sigma along the refracted chord), closed form;
 *   - constant_object_medium_equals_constant_medium: a box filled by an object with constant
 *     ior, attenuation and emission traces as the constant medium does.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fresnel.h"
#include "core/reftrace.h"
#include "scene/scene.h"
#include "scene/scene_reference.h"
#include "scene_test_util.h"
#include "test.h"

#define SIDE 10
#define RAYS (SIDE * SIDE)
#define DEG (180.0 / M_PI)

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double angle(vec3 a, vec3 b)
{
    double c = vec3_dot(vec3_normalize(a), vec3_normalize(b));
    return acos(fmax(-1.0, fmin(1.0, c)));
}

/* Shirley's concentric map onto 95% of the aperture (as tests/gpu/test_grin_boundary.c). */
static vec3 bundle_origin(int k)
{
    int i = k % SIDE, j = k / SIDE;
    double a = 2.0 * (i + 0.5) / SIDE - 1.0, b = 2.0 * (j + 0.5) / SIDE - 1.0, r, phi;
    if (fabs(a) > fabs(b)) {
        r = a;
        phi = (M_PI / 4.0) * (b / a);
    } else {
        r = b;
        phi = M_PI / 2.0 - (M_PI / 4.0) * (a / b);
    }
    return vec3_make(0.95 * r * cos(phi), 0.95 * r * sin(phi), -2.0);
}

static int resolution(void)
{
    return test_sanitized() ? 48 : 96;
}

static struct scene *lens_scene(double half, bool bounded)
{
    char doc[768];
    snprintf(doc, sizeof doc,
             "{\"objects\": [{\"name\": \"lens\", \"bounds\": {\"min\": [%g, %g, %g], \"max\": "
             "[%g, %g, %g]}, \"resolution\": %d, \"smoothing_sigma\": 0, \"ior\": "
             "{\"profile\": \"luneburg\", \"center\": [0, 0, 0], \"radius\": 1.0}}]%s}",
             -half, -half, -half, half, half, half, resolution(),
             bounded ? ", \"surfaces\": [{\"name\": \"ball\", \"shape\": \"sphere\", \"center\": "
                       "[0, 0, 0], \"radius\": 1, \"medium\": {\"object\": \"lens\"}}]"
                     : "");
    return parse_ok(doc);
}

/* How far the exit ray's line passes from the focus (0, 0, 1): the exit point's distance
 * when the ray leaves the exact sphere there, and a fair measure for the voxel-only lens,
 * whose rays leave through its bounds beyond the focus. */
static double focus_miss(const struct reftrace_result *r)
{
    vec3 f = vec3_sub(vec3_make(0, 0, 1), r->exit_origin);
    return vec3_length(vec3_cross(f, vec3_normalize(r->exit_direction)));
}

struct focus {
    double median, worst; /* |exit point - (0, 0, 1)| */
    double dir_median;    /* exit direction against the exact reference, deg */
};

/* Traces the bundle through the reference of s; exact: the analytic field's reference to
 * compare directions with (NULL: none). */
static struct focus measure(const char *label, struct scene *s, bool against_exact)
{
    struct focus f = {INFINITY, INFINITY, INFINITY};
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
    double err[RAYS], dir[RAYS];
    int exited = 0;
    for (int k = 0; k < RAYS; k++) {
        vec3 o = bundle_origin(k), d = vec3_make(0, 0, 1);
        struct reftrace_result r, x;
        reftrace_ray(vox.objects, vox.count, &vox.settings, o, d, &r);
        exited += r.status == RAY_EXITED;
        err[k] = focus_miss(&r);
        dir[k] = 0.0;
        if (against_exact) {
            reftrace_ray(exact.objects, exact.count, &st, o, d, &x);
            dir[k] = angle(r.exit_direction, x.exit_direction) * DEG;
        }
    }
    CHECK_INT(exited, RAYS);
    qsort(err, RAYS, sizeof err[0], cmp_double);
    qsort(dir, RAYS, sizeof dir[0], cmp_double);
    f.median = 0.5 * (err[RAYS / 2 - 1] + err[RAYS / 2]);
    f.worst = err[RAYS - 1];
    f.dir_median = 0.5 * (dir[RAYS / 2 - 1] + dir[RAYS / 2]);
    printf("%s: focus error median %.3g, worst %.3g; exit direction vs exact median %.3g deg\n",
           label, f.median, f.worst, f.dir_median);
    scene_reference_free(&vox);
    scene_reference_free(&exact);
    return f;
}

static void test_luneburg_bounded_by_sphere_focuses_on_far_side(void)
{
    struct scene *touch_s = lens_scene(1.0, true), *margin_s = lens_scene(1.05, true);
    struct scene *voxel_s = lens_scene(1.05, false);
    if (touch_s == NULL || margin_s == NULL || voxel_s == NULL)
        return;
    struct focus touch = measure("bounded +-1", touch_s, true);
    struct focus margin = measure("bounded +-1.05", margin_s, true);
    struct focus voxel = measure("voxel-only +-1.05", voxel_s, false);
    /* A voxel and a half at 48^3 (ASan), under one at 96^3. */
    double h = 2.1 / resolution();
    CHECK_MSG(touch.median < 1.5 * h && margin.median < 1.5 * h, "medians %g, %g (voxel %g)",
              touch.median, margin.median, h);
    CHECK_MSG(touch.worst < 4.0 * h && margin.worst < 4.0 * h, "worst %g, %g", touch.worst,
              margin.worst);
    CHECK_MSG(touch.median <= 3.0 * margin.median + 1e-3 &&
                  margin.median <= 3.0 * touch.median + 1e-3,
              "layouts disagree: %g vs %g", touch.median, margin.median);
    /* The exact surface removes the voxel lens's staircase rim: not worse than it. */
    CHECK_MSG(margin.median <= 1.5 * voxel.median + 1e-3, "bounded %g vs voxel-only %g",
              margin.median, voxel.median);
    /* 0.02 deg at 96^3, twice that at 48^3 (first order in the voxel size). */
    double dir_bound = 0.02 * 96.0 / resolution();
    CHECK_MSG(touch.dir_median < dir_bound && margin.dir_median < dir_bound,
              "directions %g, %g deg", touch.dir_median, margin.dir_median);
    CHECK_MSG(touch.dir_median <= 3.0 * margin.dir_median + 1e-3 &&
                  margin.dir_median <= 3.0 * touch.dir_median + 1e-3,
              "layouts' directions disagree: %g vs %g deg", touch.dir_median, margin.dir_median);
    scene_destroy(touch_s);
    scene_destroy(margin_s);
    scene_destroy(voxel_s);
}

static void test_field_continued_beyond_surface_helps(void)
{
    struct scene *s = lens_scene(1.0, true);
    if (s == NULL)
        return;
    struct focus with = measure("touching, field continued", s, false);
    /* The scene's own field, as the layers give it: n = 1 beyond R (the binding stays with
     * the surface's medium; only the continuation looks at objects[0].bound). */
    s->objects[0].bound = false;
    struct scene_reference raw;
    struct err e = {0};
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &raw, &e), REFRACT_E_OK);
    raw.objects[0].bound = true;
    double err[RAYS];
    for (int k = 0; k < RAYS; k++) {
        struct reftrace_result r;
        reftrace_ray(raw.objects, raw.count, &raw.settings, bundle_origin(k), vec3_make(0, 0, 1),
                     &r);
        err[k] = focus_miss(&r);
    }
    qsort(err, RAYS, sizeof err[0], cmp_double);
    double median = 0.5 * (err[RAYS / 2 - 1] + err[RAYS / 2]);
    printf("touching, field as the layers give it: focus error median %.3g, worst %.3g\n", median,
           err[RAYS - 1]);
    CHECK_MSG(with.median < median && with.worst < err[RAYS - 1],
              "continued %g, worst %g vs raw %g, worst %g", with.median, with.worst, median,
              err[RAYS - 1]);
    scene_reference_free(&raw);
    scene_destroy(s);
}

static void test_step_cut_lands_on_surface(void)
{
    struct scene *s = lens_scene(1.0, true);
    if (s == NULL)
        return;
    struct scene_reference ref;
    struct err e = {0};
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &ref, &e), REFRACT_E_OK);
    static const enum reftrace_stepper steppers[] = {REFTRACE_EULER, REFTRACE_RK2, REFTRACE_RK4,
                                                        REFTRACE_BS23, REFTRACE_ADAPTIVE};
    double h_world = ref.settings.step_voxels * 2.0 / resolution();
    for (size_t i = 0; i < sizeof steppers / sizeof steppers[0]; i++) {
        struct reftrace_settings st = ref.settings;
        st.stepper = steppers[i];
        st.tolerance = 1e-8;
        double worst_gap = 0.0, worst_r = 0.0;
        int events = 0;
        for (int k = 0; k < RAYS; k += 7) {
            /* Oblique rays too: the cut must work where the path curves across the step. */
            vec3 d = vec3_normalize(vec3_make(0.3 * (k % 3 - 1), 0.2, 1.0));
            vec3 aim = bundle_origin(k);
            aim.z = 0.0;
            struct reftrace_result r;
            reftrace_ray(ref.objects, ref.count, &st, vec3_madd(aim, d, -2.0), d, &r);
            for (int j = 0; j < r.event_count && j < REFTRACE_MAX_EVENTS; j++) {
                events++;
                worst_gap = fmax(worst_gap, r.events[j].step_gap);
                worst_r = fmax(worst_r, fabs(vec3_length(r.events[j].point) - 1.0));
            }
        }
        printf("stepper %d: %d events, worst |r - 1| %.3g, worst step gap %.3g (step %.3g)\n",
               (int)steppers[i], events, worst_r, worst_gap, h_world);
        CHECK(events >= 2 * (RAYS / 7));
        CHECK_MSG(worst_r < 1e-12, "stepper %d: |r - 1| %g", (int)steppers[i], worst_r);
        CHECK_MSG(worst_gap <= 1e-6 * h_world, "stepper %d: gap %g > 1e-6 x %g", (int)steppers[i],
                  worst_gap, h_world);
    }
    scene_reference_free(&ref);
    scene_destroy(s);
}

/* sigma_a(x) = A + B x (object = world space) at every voxel centre; n = 1.5, grad 0. */
#define SIG_A 0.8
#define SIG_B 0.5

static void test_constant_n_attenuation_field_is_straight_beer_lambert(void)
{
    enum { N = 16 };
    static double ior[N * N * N * 4], att[N * N * N * 4];
    for (int k = 0; k < N; k++)
        for (int j = 0; j < N; j++)
            for (int i = 0; i < N; i++) {
                size_t v = ((size_t)k * N + j) * N + i;
                double x = -1.0 + (i + 0.5) * 2.0 / N;
                ior[v * 4 + 0] = ior[v * 4 + 1] = ior[v * 4 + 2] = 0.0;
                ior[v * 4 + 3] = 1.5;
                for (int c = 0; c < 3; c++)
                    att[v * 4 + c] = SIG_A + (c + 1) * SIG_B * x;
                att[v * 4 + 3] = 0.0;
            }
    struct reftrace_grid grid = {.ior_grad = ior, .attenuation = att};
    struct reftrace_object obj = {
        .bmin = {-1, -1, -1},
        .bmax = {1, 1, 1},
        .res = {N, N, N},
        .xf = xform_identity(),
        .grid = &grid,
        .bound = true,
        .ior_constant = true,
    };
    struct reftrace_surface box = {.field = &obj};
    box.geom.kind = GEOM_BOX;
    box.geom.xf = xform_identity();
    box.geom.center = vec3_make(0, 0, 0);
    box.geom.size = vec3_make(1.6, 1.6, 1.6); /* inside the voxel centres' hull: exact */
    struct reftrace_settings st = {
        .stepper = REFTRACE_RK4,
        .step_voxels = 0.5,
        .max_steps = 100000,
        .ambient_ior = 1.0,
        .env_intensity = 1.0,
        .min_throughput = -1.0,
        .surfaces = &box,
        .surface_count = 1,
    };
    for (int t = 0; t < 5; t++) {
        double tilt = 0.1 * t;
        vec3 d = vec3_normalize(vec3_make(tilt, 0.05 * t, 1.0));
        vec3 o = vec3_make(-0.3, 0.1, -2.0);
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &st, o, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        CHECK_INT(r.event_count, 2);
        /* Straight: through parallel faces the exit direction is the entry direction, and
         * inside the ray is the Snell-refracted chord between the two event points. */
        CHECK_NEAR(angle(r.exit_direction, d), 0.0, 1e-12);
        vec3 p0 = r.events[0].point, p1 = r.events[1].point;
        vec3 chord = vec3_sub(p1, p0);
        double cos_i = d.z, sin_t = sqrt(1.0 - cos_i * cos_i) / 1.5;
        CHECK_NEAR(vec3_normalize(chord).z, sqrt(1.0 - sin_t * sin_t), 1e-12);
        CHECK_NEAR(p1.z, 0.8, 1e-12);
        /* Beer-Lambert along the chord: sigma is linear, so its integral is the length times
         * sigma at the chord's middle; Fresnel at both faces (frisvad2010). */
        double L = vec3_length(chord), xm = 0.5 * (p0.x + p1.x);
        double R_in = fresnel_unpolarized(cos_i, 1.0, 1.5);
        double R_out = fresnel_unpolarized(sqrt(1.0 - sin_t * sin_t), 1.5, 1.0);
        double tf = (1.0 - R_in) * (1.0 - R_out);
        double T[3] = {r.transmittance.x, r.transmittance.y, r.transmittance.z};
        for (int c = 0; c < 3; c++)
            CHECK_NEAR(T[c], tf * exp(-L * (SIG_A + (c + 1) * SIG_B * xm)), 1e-12);
        CHECK_NEAR(r.optical_path_length,
                   vec3_length(vec3_sub(p0, o)) + 1.5 * L + 0.0 /* exits at the face */, 1e-12);
    }
}

static void test_constant_object_medium_equals_constant_medium(void)
{
    const char *with_object =
        "{\"objects\": [{\"name\": \"glass\", \"bounds\": {\"min\": [-0.5, -0.5, -0.5], \"max\": "
        "[0.5, 0.5, 0.5]}, \"resolution\": 16, \"ior\": 1.5, \"attenuation\": [0.3, 0.6, 0.9], "
        "\"emission\": [0.2, 0.1, 0.05]}], \"surfaces\": [{\"shape\": \"box\", \"center\": [0, 0, "
        "0], \"size\": [1, 1, 1], \"medium\": {\"object\": \"glass\"}}]}";
    const char *with_constants =
        "{\"surfaces\": [{\"shape\": \"box\", \"center\": [0, 0, 0], \"size\": [1, 1, 1], "
        "\"medium\": {\"ior\": 1.5, \"attenuation\": [0.3, 0.6, 0.9], \"emission\": [0.2, 0.1, "
        "0.05]}}]}";
    struct scene *a = parse_ok(with_object), *b = parse_ok(with_constants);
    if (a == NULL || b == NULL)
        return;
    CHECK(a->objects[0].bound);
    struct scene_reference ra, rb;
    struct err e = {0};
    CHECK_INT(scene_reference_build(a, SCENE_REFERENCE_VOXELS, NULL, NULL, &ra, &e), REFRACT_E_OK);
    CHECK_INT(scene_reference_build(b, SCENE_REFERENCE_VOXELS, NULL, NULL, &rb, &e), REFRACT_E_OK);
    CHECK(ra.objects[0].ior_constant);
    for (int k = 0; k < 6; k++) {
        vec3 o = vec3_make(-0.2 + 0.08 * k, 0.1, -2.0);
        vec3 d = vec3_normalize(vec3_make(0.1 * k, -0.05, 1.0));
        struct reftrace_result x, y;
        reftrace_ray(ra.objects, ra.count, &ra.settings, o, d, &x);
        reftrace_ray(rb.objects, rb.count, &rb.settings, o, d, &y);
        CHECK_INT(x.status, y.status);
        CHECK_INT(x.event_count, y.event_count);
        /* Within float rounding: the object's fields are stored as floats. */
        CHECK_NEAR(vec3_length(vec3_sub(x.exit_origin, y.exit_origin)), 0.0, 1e-6);
        CHECK_NEAR(angle(x.exit_direction, y.exit_direction), 0.0, 1e-6);
        CHECK_NEAR(x.optical_path_length, y.optical_path_length, 1e-6);
        CHECK_NEAR(x.transmittance.x, y.transmittance.x, 1e-6);
        CHECK_NEAR(x.transmittance.z, y.transmittance.z, 1e-6);
        /* The emission is a sum of steps in the field, the closed form for constants:
         * within the rectangle rule's error at half-voxel steps. */
        CHECK_NEAR(x.radiance.x, y.radiance.x, 0.02 * y.radiance.x + 1e-9);
    }
    scene_reference_free(&ra);
    scene_reference_free(&rb);
    scene_destroy(a);
    scene_destroy(b);
}

int main(void)
{
    test_luneburg_bounded_by_sphere_focuses_on_far_side();
    test_field_continued_beyond_surface_helps();
    test_step_cut_lands_on_surface();
    test_constant_n_attenuation_field_is_straight_beer_lambert();
    test_constant_object_medium_equals_constant_medium();
    return test_summary("test_bound_field_ref");
}
