/*
 * test_hard_reftrace.c - the CPU reference tracer on the hard cases of docs/tracing.md
 * "Hard cases": rays trapped by total internal reflection in a glass block, a light pipe
 * that reflects a ray dozens of times, grazing incidence (block faces and a sphere's rim),
 * high contrast (n = 2.42; a jump 1 -> 3 at the faces and inside the field), shells one
 * and two voxels thin, very steep gradients (a linear GRIN rising 0.24 per voxel, an
 * unsmoothed step), the camera inside the volume, zero and enormous attenuation, and a
 * ray that reflects between two objects without ever taking a step.
 *
 * Every ray keeps hard_check_hit's invariants (finite, 0 <= T <= 1, steps within the
 * budget, a documented status) and its radiance stays within the environment's. Where a
 * closed form exists it bounds the error:
 *   1e-9 (positions, OPL: relative) and 1e-12 (directions, T): uniform media, where every
 *        stepper is exact and what remains is rounding over a few hundred steps;
 *   the billiard closed form of a ray trapped in a box (unfolding its reflections);
 *   looser bounds, each explained where it is used, for interfaces in the voxel field.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/env.h"
#include "core/fresnel.h"
#include "hard_checks.h"

static const enum reftrace_stepper steppers[3] = {REFTRACE_EULER, REFTRACE_RK4, REFTRACE_ADAPTIVE};
static const char *const stepper_names[3] = {"euler", "rk4", "adaptive"};

/* A scene and its voxel reference; NULL scene when either failed (already reported). */
struct hard_case {
    struct scene *scene;
    struct scene_reference ref;
};

static bool case_open(struct hard_case *c, const char *json)
{
    c->scene = hard_scene(json);
    if (c->scene == NULL)
        return false;
    if (!hard_reference(c->scene, &c->ref)) {
        scene_destroy(c->scene);
        c->scene = NULL;
        return false;
    }
    return true;
}

static void case_close(struct hard_case *c)
{
    if (c->scene == NULL)
        return;
    scene_reference_free(&c->ref);
    scene_destroy(c->scene);
}

/* Traces one ray, checks the invariants and the radiance bound, returns the result. */
static struct reftrace_result trace(const char *what, int ray, const struct hard_case *c,
                                    const struct reftrace_settings *s, vec3 o, vec3 d,
                                    bool allow_pass_cap)
{
    struct reftrace_result r;
    reftrace_ray(c->ref.objects, c->ref.count, s, o, vec3_normalize(d), &r);
    struct hard_hit h = hard_from_ref(&r);
    hard_check_hit(what, ray, &h, s->max_steps, HARD_ENERGY_EPS, allow_pass_cap);
    double L[3] = {r.radiance.x, r.radiance.y, r.radiance.z};
    hard_check_radiance(what, ray, L, s->env_intensity, HARD_ENERGY_EPS);
    return r;
}

static void check_vec(vec3 a, vec3 b, double tol)
{
    CHECK_NEAR(a.x, b.x, tol);
    CHECK_NEAR(a.y, b.y, tol);
    CHECK_NEAR(a.z, b.z, tol);
}

/* The billiard closed form: a straight ray of length s from x0 along d inside the box
 * [lo, hi]^3, reflected at every face, is the unfolded ray folded back into the box, and
 * its direction has flipped along an axis once per reflection on that axis. */
static void billiard(vec3 x0, vec3 d, double lo, double hi, double s, vec3 *x, vec3 *dir)
{
    double w = hi - lo;
    for (int a = 0; a < 3; a++) {
        double u = vec3_get(x0, a) - lo + vec3_get(d, a) * s; /* unfolded, from lo */
        double k = floor(u / w);
        double r = u - k * w;
        bool odd = ((long long)k % 2 + 2) % 2 == 1;
        vec3_set(x, a, lo + (odd ? w - r : r));
        vec3_set(dir, a, odd ? -vec3_get(d, a) : vec3_get(d, a));
    }
}

/* ---- total internal reflection ------------------------------------------------------- */

/* A ray inside a glass block whose direction makes more than the critical angle (41.8 deg)
 * with every face normal reflects off faces for ever: the budget ends it with status
 * max_steps after exactly max_steps steps, losslessly (T = 1, no light gathered), at the
 * billiard position for the path length it travelled (opl / n). */
static void ray_trapped_in_a_block_ends_at_its_budget_where_the_billiard_says(void)
{
    struct hard_case c;
    if (!case_open(&c, HARD_BLOCK))
        return;
    vec3 x0 = {0.1, 0.2, -0.05}, d = vec3_normalize((vec3){1.0, 1.1, 0.9});
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = c.ref.settings;
        s.stepper = steppers[i];
        CHECK_INT(s.max_steps, 400);
        struct reftrace_result r = trace("trapped", i, &c, &s, x0, d, false);
        CHECK_INT(r.status, RAY_MAX_STEPS);
        CHECK_INT(r.steps, 400);
        CHECK_NEAR(r.transmittance.x, 1.0, 1e-12);
        CHECK_NEAR(vec3_length(r.radiance), 0.0, 0.0);
        vec3 x, dir;
        /* 1e-10 further: a ray stopped on a face (a jump over empty space ends on one) has
         * already reflected there, and the direction is the one after the reflection. */
        billiard(x0, d, -0.5, 0.5, r.optical_path_length / 1.5 + 1e-10, &x, &dir);
        /* the adaptive stepper lands on faces by bisection to its tolerance (1e-9) */
        double tol = steppers[i] == REFTRACE_ADAPTIVE ? 1e-7 : 1e-9;
        check_vec(r.exit_origin, x, tol);
        check_vec(r.exit_direction, dir, 1e-9);
        printf("trapped (%s): %d steps, path %.4f (the box is 1 wide)\n", stepper_names[i], r.steps,
               r.optical_path_length / 1.5);
    }
    /* A budget of one step ends the same way after one step. */
    struct reftrace_settings s = c.ref.settings;
    s.max_steps = 1;
    struct reftrace_result r = trace("trapped, 1 step", 0, &c, &s, x0, d, false);
    CHECK_INT(r.status, RAY_MAX_STEPS);
    CHECK_INT(r.steps, 1);
    case_close(&c);
}

/* A glass rod 4 long, 0.2 across: a ray entering its end face at 60 degrees refracts to
 * 35 degrees from the axis and hits the sides at 55 degrees (> 41.8), so it reflects
 * totally 17 times off the y and z sides and leaves through the far end. Closed
 * form by unfolding: the exit point, the exit direction (the entry direction with y and z
 * flipped once per reflection on that axis), T = (1 - R)^2 (the two ends reflect the same,
 * by reciprocity) and OPL. With a budget the same ray stops inside at the unfolded point. */
static void light_pipe_reflects_many_times_and_leaves_per_the_closed_form(void)
{
    struct hard_case c;
    if (!case_open(&c, HARD_ROD))
        return;
    double th = 60.0 * M_PI / 180.0, ph = 25.0 * M_PI / 180.0;
    vec3 d = {cos(th), sin(th) * cos(ph), sin(th) * sin(ph)};
    vec3 entry = {-2.0, 0.03, -0.02};
    vec3 origin = vec3_madd(entry, d, -0.5);
    /* inside: the tangential part of d shrinks by 1 / 1.5 (Snell) */
    vec3 t = {sqrt(1.0 - (d.y * d.y + d.z * d.z) / 2.25), d.y / 1.5, d.z / 1.5};
    CHECK(fabs(t.y) < cos(asin(1.0 / 1.5)) && fabs(t.z) < cos(asin(1.0 / 1.5)));
    double len = 4.0 / t.x;
    double R = fresnel_unpolarized(cos(th), 1.0, 1.5);
    int reflections = (int)(fabs(t.y) * len / 0.2) + (int)(fabs(t.z) * len / 0.2);
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = c.ref.settings;
        s.stepper = steppers[i];
        struct reftrace_result r = trace("light pipe", i, &c, &s, origin, d, false);
        CHECK_INT(r.status, RAY_EXITED);
        /* the unfolded exit: y and z folded into [-0.1, 0.1] */
        vec3 x, dir;
        billiard((vec3){0, entry.y, entry.z}, (vec3){0, t.y, t.z}, -0.1, 0.1, len, &x, &dir);
        vec3 exit = {2.0, x.y, x.z};
        vec3 exit_dir = {d.x, dir.y * t.y > 0.0 ? d.y : -d.y, dir.z * t.z > 0.0 ? d.z : -d.z};
        double tol = steppers[i] == REFTRACE_ADAPTIVE ? 1e-7 : 1e-9;
        check_vec(r.exit_origin, exit, tol);
        check_vec(r.exit_direction, exit_dir, 1e-9);
        CHECK_NEAR(r.transmittance.x, (1.0 - R) * (1.0 - R), 1e-12);
        CHECK_NEAR(r.optical_path_length, 0.5 + 1.5 * len, 1e-8);
        if (i == 1)
            printf("light pipe: %d total reflections, %d steps, T %.6f\n", reflections, r.steps,
                   r.transmittance.x);
    }
    CHECK(reflections >= 15);
    /* The same ray with 20 steps: stopped inside, lossless since the entry face, at the
     * unfolded point for the path it travelled (with empty-space skipping, a jump and a
     * step between reflections, the whole rod takes some 36 steps). */
    struct reftrace_settings s = c.ref.settings;
    s.max_steps = 20;
    struct reftrace_result r = trace("light pipe, 20 steps", 0, &c, &s, origin, d, false);
    CHECK_INT(r.status, RAY_MAX_STEPS);
    CHECK_INT(r.steps, 20);
    CHECK_NEAR(r.transmittance.x, 1.0 - R, 1e-12);
    double inside = (r.optical_path_length - 0.5) / 1.5;
    vec3 x, dir;
    billiard((vec3){0, entry.y, entry.z}, (vec3){0, t.y, t.z}, -0.1, 0.1, inside, &x, &dir);
    check_vec(r.exit_origin, (vec3){-2.0 + t.x * inside, x.y, x.z}, 1e-9);
    case_close(&c);
}

/* Grazing incidence on a block face (80, 89, 89.99 degrees): the ray refracts to just
 * under the critical angle, reflects totally off the side face, and leaves through the
 * far face just under the critical angle again. T = (1 - R)^2 with R -> 1 at grazing;
 * the exit direction is the entry direction mirrored in x (one side reflection). */
static void grazing_rays_enter_a_block_and_keep_energy_bounded(void)
{
    struct hard_case c;
    if (!case_open(&c, HARD_BLOCK))
        return;
    const double angles[3] = {80.0, 89.0, 89.99};
    for (int k = 0; k < 3; k++) {
        double th = angles[k] * M_PI / 180.0;
        vec3 d = {sin(th), 0.0, cos(th)};
        vec3 entry = {0.2, 0.1, -0.5};
        vec3 origin = vec3_madd(entry, d, -0.3);
        double R = fresnel_unpolarized(cos(th), 1.0, 1.5);
        double st = sin(th) / 1.5, ct = sqrt(1.0 - st * st);
        /* to the x = 0.5 face, mirrored, to z = 0.5 */
        double l1 = 0.3 / st, z1 = -0.5 + l1 * ct, l2 = (0.5 - z1) / ct;
        vec3 exit = {0.5 - l2 * st, 0.1, 0.5};
        for (int i = 0; i < 3; i++) {
            struct reftrace_settings s = c.ref.settings;
            s.stepper = steppers[i];
            struct reftrace_result r = trace("grazing block", k * 3 + i, &c, &s, origin, d, false);
            CHECK_INT(r.status, RAY_EXITED);
            CHECK_NEAR(r.transmittance.x, (1.0 - R) * (1.0 - R), 1e-12);
            check_vec(r.exit_direction, (vec3){-d.x, 0.0, d.z}, 1e-9);
            check_vec(r.exit_origin, exit, steppers[i] == REFTRACE_ADAPTIVE ? 1e-7 : 1e-9);
        }
    }
    case_close(&c);
}

/* Rays parallel to z at impact parameters from the centre to past the rim of a smoothed
 * glass sphere (R = 0.8, 24^3 voxels: the interface is a ~3-voxel ramp). Near the rim the
 * ray meets the interface at grazing incidence, where Fresnel reflection -> 1 and the ray
 * equation bends it hardest. Bounded error against exact Snell refraction through a sphere
 * for the paraxial rays (deviation D = 2 (asin(b/R) - asin(b/(nR)))): 0.03 rad, measured
 * 0.0026 (n = 1.5) and 0.022 (n = 2.42; the smoothed, voxelised interface, whose tail
 * reaches the faces 2.4 voxels away). Before the exit face took its index from |w|
 * (docs/tracing.md "The rim") they were 0.014 and 0.009: the clamped rim's error cancelled
 * part of the diamond tail's. At the rim only the invariants. */
static void grazing_rays_on_a_sphere_rim_stay_finite_and_bounded(const char *n_text, double n)
{
    char json[512];
    snprintf(json, sizeof json, HARD_SPHERE("%s"), n_text);
    struct hard_case c;
    if (!case_open(&c, json))
        return;
    const double b[] = {0.0, 0.2, 0.4, 0.7, 0.76, 0.78, 0.79, 0.795, 0.8, 0.805, 0.82, 0.85};
    int nb = (int)(sizeof b / sizeof b[0]);
    double worst = 0.0;
    int exited = 0, statuses[4] = {0};
    for (int k = 0; k < nb; k++) {
        struct reftrace_settings s = c.ref.settings;
        vec3 o = {b[k], 0.05, -3.0};
        struct reftrace_result r = trace("sphere rim", k, &c, &s, o, (vec3){0, 0, 1}, false);
        statuses[r.status]++;
        exited += r.status == RAY_EXITED;
        if (b[k] <= 0.4 && r.status == RAY_EXITED) {
            double si = hypot(b[k], 0.05) / 0.8;
            double D = 2.0 * (asin(si) - asin(si / n));
            double got = acos(fmin(1.0, r.exit_direction.z));
            worst = fmax(worst, fabs(got - D));
            CHECK_NEAR(got, D, 0.03);
        }
    }
    printf("sphere rim n = %s: %d of %d rays exited (absorbed %d, max_steps %d, missed %d); "
           "paraxial deviation error <= %.4f rad\n",
           n_text, exited, nb, statuses[RAY_ABSORBED], statuses[RAY_MAX_STEPS],
           statuses[RAY_MISSED], worst);
    CHECK_INT(statuses[RAY_ABSORBED], 0); /* nothing absorbs here */
    case_close(&c);
}

/* ---- high contrast ---------------------------------------------------------------- */

/* n = 3 filling the bounds: the faces jump 1 -> 3. Normal incidence T = (1 - 0.25)^2, and
 * oblique rays per Snell and Fresnel; the radiance (0.25 of the sky behind, reflected
 * twice, plus the transmitted background) in closed form. */
static void a_jump_from_1_to_3_at_the_faces_matches_fresnel(void)
{
    const char *json = "{\"objects\": [{\"bounds\": {\"min\": [-0.5, -0.5, -0.5], \"max\": [0.5, "
                       "0.5, 0.5]}, \"resolution\": 8, \"ior\": 3}]}";
    struct hard_case c;
    if (!case_open(&c, json))
        return;
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = c.ref.settings;
        s.stepper = steppers[i];
        struct reftrace_result r =
            trace("n = 3 block", i, &c, &s, (vec3){0.1, 0.2, -2}, (vec3){0, 0, 1}, false);
        CHECK_INT(r.status, RAY_EXITED);
        CHECK_NEAR(r.transmittance.y, 0.5625, 1e-12);
        CHECK_NEAR(r.optical_path_length, 1.5 + 3.0, 1e-9);
        vec3 back = env_procedural((vec3){0, 0, -1}), ahead = env_procedural((vec3){0, 0, 1});
        vec3 want = vec3_add(vec3_scale(back, 0.25 + 0.75 * 0.25), vec3_scale(ahead, 0.5625));
        check_vec(r.radiance, want, 1e-12);
        /* 50 degrees: refracts to 14.8 degrees; T = (1 - R)^2 by reciprocity. */
        double th = 50.0 * M_PI / 180.0;
        vec3 d = {sin(th), 0, cos(th)};
        double R = fresnel_unpolarized(cos(th), 1.0, 3.0);
        r = trace("n = 3 block, 50 deg", i, &c, &s, vec3_madd((vec3){-0.2, 0, -0.5}, d, -1.0), d,
                  false);
        CHECK_INT(r.status, RAY_EXITED);
        CHECK_NEAR(r.transmittance.x, (1.0 - R) * (1.0 - R), 1e-12);
        check_vec(r.exit_direction, d, 1e-12);
    }
    case_close(&c);
}

/* The same jump inside the field (a slab n = 3 in air within the bounds, smoothed over a
 * few voxels): one Fresnel event per interface from the zone probes. At normal incidence
 * T = (1 - 0.25)^2 = 0.5625 within 5 % (measured +2.8..4 %: the zone is entered where
 * |grad n| h first exceeds the threshold, a few voxels before the step's middle, so the
 * probe k = 5 voxels further reads the smoothed step before it has settled, n_hi ~ 2.95). */
static void a_jump_from_1_to_3_inside_the_field_matches_fresnel(void)
{
    struct hard_case c;
    if (!case_open(&c, HARD_JUMP3))
        return;
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = c.ref.settings;
        s.stepper = steppers[i];
        struct reftrace_result r =
            trace("n = 3 slab", i, &c, &s, (vec3){0.1, 0.2, -3}, (vec3){0, 0, 1}, false);
        CHECK_INT(r.status, RAY_EXITED);
        CHECK_NEAR(r.transmittance.x, 0.5625, 0.05 * 0.5625);
        check_vec(r.exit_direction, (vec3){0, 0, 1}, 1e-9);
        if (i == 1)
            printf("n = 3 slab in the field: T = %.5f (closed form 0.5625), OPL %.4f (%.4f)\n",
                   r.transmittance.x, r.optical_path_length, 2.0 + 1.0 + 3.0 * 1.0);
    }
    /* Oblique rays, up to grazing the slab: the invariants only. */
    for (int k = 0; k < 9; k++) {
        double th = (10.0 * k + 5.0) * M_PI / 180.0;
        struct reftrace_settings s = c.ref.settings;
        trace("n = 3 slab, oblique", k, &c, &s, (vec3){-0.5, 0, -0.99},
              (vec3){sin(th), 0.1, cos(th)}, false);
    }
    case_close(&c);
}

/* ---- thin shells and steep gradients ------------------------------------------------ */

/* Glass shells 1 and 2 voxels thick (0.08 and 0.16, voxel 0.083): smoothed, their index
 * peaks well below 1.5, but a ray through one must still keep T in [0.8, 1] (four
 * interfaces at most 4 % each give 0.85), and one through the centre keeps its direction. */
static void thin_shells_keep_energy_bounded(void)
{
    const char *const shells[2] = {HARD_SHELL("0.8", "0.72"), HARD_SHELL("0.8", "0.64")};
    for (int k = 0; k < 2; k++) {
        struct hard_case c;
        if (!case_open(&c, shells[k]))
            continue;
        double T_min = 1.0, T_centre = 0.0;
        for (int j = 0; j < 17; j++) {
            double b = 0.05 * j;
            struct reftrace_settings s = c.ref.settings;
            struct reftrace_result r = trace("thin shell", k * 100 + j, &c, &s, (vec3){b, 0.02, -3},
                                             (vec3){0, 0, 1}, false);
            CHECK(r.status == RAY_EXITED);
            CHECK_MSG(r.transmittance.x >= 0.8, "shell %d, b = %.2f: T = %.5f", k, b,
                      r.transmittance.x);
            T_min = fmin(T_min, r.transmittance.x);
            if (j == 0) {
                T_centre = r.transmittance.x;
                CHECK_NEAR(r.exit_direction.z, 1.0, 1e-4); /* 0.02 off the axis */
            }
        }
        printf("shell %d voxel(s) thick: T through the centre %.5f, smallest T %.5f\n", k + 1,
               T_centre, T_min);
        /* the shell is seen: it reflects something */
        CHECK(T_centre < 1.0);
        case_close(&c);
    }
}

/* A linear GRIN n = 1 + 1.9 (y + 1) rising 0.24 per voxel (12x the boundary threshold),
 * unsmoothed: a smooth ramp, so no Fresnel event fires inside; the ray equation alone
 * bends the rays. The medium is stratified, so a ray that enters through the bottom face
 * and leaves through the top one leaves parallel to its entry direction, after a drift
 * along x with a closed form for the voxel field (the linear profile between the outermost
 * voxel centres, clamped to their values in the half voxel beyond):
 * dx = integral c / sqrt(n(y)^2 - c^2) dy, c = sin(incidence).
 *
 * Measured: the drift is off by up to 0.07 at 60-75 degrees: in the half voxel between the
 * outermost voxel centres and the bounds face n is clamped (constant) while grad n, sampled
 * from the clamped gradient volume, is still 1.9, so the path there bends more than the
 * closed form's clamped ends say (docs/tracing.md "Hard cases", known limitation). The exit
 * direction was off by up to 0.1 rad for the same reason until the exit face took its index
 * from |w| instead of n(p') (docs/tracing.md "The rim"): now below 5e-4 rad, since the face keeps
 * w's tangential part, which the stratified field conserves. The bounds below are the
 * measurement with headroom; the drift's shrinks with the voxel size. */
static double stratified_drift(double c, double n_lo, double n_hi, double h_half)
{
    double g = 1.9;
    double linear = c > 0.0 ? c / g * (acosh(n_hi / c) - acosh(n_lo / c)) : 0.0;
    double ends = h_half * (c / sqrt(n_lo * n_lo - c * c) + c / sqrt(n_hi * n_hi - c * c));
    return linear + ends;
}

static void steep_gradient_bends_rays_per_the_stratified_closed_form(void)
{
    struct hard_case c;
    if (!case_open(&c, HARD_STEEP))
        return;
    double h = 2.0 / 16.0;
    double n_lo = 1.0 + 1.9 * (h / 2), n_hi = 1.0 + 1.9 * (2.0 - h / 2);
    double worst = 0.0, worst_dir = 0.0;
    for (int k = 0; k < 6; k++) {
        double a = 15.0 * k * M_PI / 180.0;
        vec3 d = {sin(a), cos(a), 0.0};
        vec3 entry = {-0.8, -1.0, 0.1};
        for (int i = 0; i < 3; i++) {
            struct reftrace_settings s = c.ref.settings;
            s.stepper = steppers[i];
            struct reftrace_result r =
                trace("steep GRIN", k * 3 + i, &c, &s, vec3_madd(entry, d, -1.0), d, false);
            CHECK_INT(r.status, RAY_EXITED);
            double ang = acos(fmin(1.0, vec3_dot(r.exit_direction, d)));
            CHECK_MSG(ang <= 1e-3, "steep ray %d: exit direction %.3g rad off", k, ang);
            CHECK_NEAR(r.exit_origin.y, 1.0, 1e-9);
            double want = entry.x + stratified_drift(d.x, n_lo, n_hi, h / 2);
            worst = fmax(worst, fabs(r.exit_origin.x - want));
            worst_dir = fmax(worst_dir, ang);
            CHECK_NEAR(r.exit_origin.x, want, 0.1);
        }
    }
    printf("steep GRIN: exit drift within %.3f of the closed form, direction within %.3f rad\n",
           worst, worst_dir);
    /* From inside, heading down at a shallow angle: the ray turns around (a mirage) and
     * rises; whatever happens then (it may be trapped by total reflection under the top
     * face, where n = 4.7), it ends within its budget with a documented status. */
    int turned = 0;
    for (int k = 0; k < 6; k++) {
        struct reftrace_settings s = c.ref.settings;
        s.max_steps = 2000;
        vec3 d = vec3_normalize((vec3){1, -0.1 - 0.1 * k, 0.3});
        struct reftrace_result r = trace("mirage", k, &c, &s, (vec3){-0.8, 0.0, -0.5}, d, false);
        turned += r.exit_direction.y > 0.0 || r.status == RAY_MAX_STEPS;
    }
    CHECK_INT(turned, 6);
    case_close(&c);
}

/* An unsmoothed sphere: the index jumps 1 -> 2 between neighbouring voxels, the steepest
 * gradient a scene can make. Invariants on a fan of rays from the centre to past the rim. */
static void unsmoothed_index_step_stays_finite_and_bounded(void)
{
    struct hard_case c;
    if (!case_open(&c, HARD_STEP_SPHERE))
        return;
    for (int k = 0; k < 16; k++) {
        struct reftrace_settings s = c.ref.settings;
        s.stepper = steppers[k % 3];
        trace("step sphere", k, &c, &s, (vec3){0.05 * k, 0.01, -3}, (vec3){0, 0, 1}, false);
    }
    case_close(&c);
}

/* ---- the camera inside the volume ------------------------------------------------------ */

/* A ray that starts inside a glass block: no entry face; it leaves through z = 0.5 per
 * Snell with T = 1 - R, OPL = 1.5 x length, and the radiance R env(reflected inside
 * direction) + (1 - R) env(refracted). */
static void camera_inside_a_block_sees_per_snell_and_fresnel(void)
{
    struct hard_case c;
    if (!case_open(&c, HARD_BLOCK))
        return;
    vec3 o = {0.1, 0.2, 0.0}, d = vec3_normalize((vec3){0.3, 0.2, 1});
    double l = 0.5 / d.z;
    vec3 exit = vec3_madd(o, d, l);
    double R = fresnel_unpolarized(d.z, 1.5, 1.0);
    vec3 out;
    CHECK(snell_refract(d, (vec3){0, 0, -1}, 1.5, 1.0, &out));
    vec3 want = vec3_add(vec3_scale(env_procedural((vec3){d.x, d.y, -d.z}), R),
                         vec3_scale(env_procedural(out), 1.0 - R));
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = c.ref.settings;
        s.stepper = steppers[i];
        struct reftrace_result r = trace("inside block", i, &c, &s, o, d, false);
        CHECK_INT(r.status, RAY_EXITED);
        check_vec(r.exit_origin, exit, steppers[i] == REFTRACE_ADAPTIVE ? 1e-7 : 1e-9);
        check_vec(r.exit_direction, out, 1e-9);
        CHECK_NEAR(r.transmittance.x, 1.0 - R, 1e-12);
        CHECK_NEAR(r.optical_path_length, 1.5 * l, 1e-8);
        check_vec(r.radiance, want, 1e-9);
    }
    case_close(&c);
}

/* From the centre of a smoothed glass sphere every ray meets the interface at normal
 * incidence: it keeps its direction (within 0.01 rad, measured <= 4.7e-3: the voxelised
 * sphere's normals are not exactly radial) and T = 1 - R(normal) = 0.96 within 0.01. */
static void camera_inside_a_sphere_sees_radially_out(void)
{
    struct hard_case c;
    if (!case_open(&c, HARD_SPHERE("1.5")))
        return;
    for (int k = 0; k < 10; k++) {
        double th = 0.6 * k, ph = 1.1 * k;
        vec3 d = {sin(th) * cos(ph), cos(th), sin(th) * sin(ph)};
        struct reftrace_settings s = c.ref.settings;
        struct reftrace_result r = trace("inside sphere", k, &c, &s, (vec3){0, 0, 0}, d, false);
        CHECK_INT(r.status, RAY_EXITED);
        CHECK_MSG(vec3_dot(r.exit_direction, d) >= cos(1e-2), "inside sphere ray %d: %.2e rad", k,
                  acos(fmin(1.0, vec3_dot(r.exit_direction, d))));
        CHECK_NEAR(r.transmittance.x, 0.96, 0.01);
    }
    case_close(&c);
}

/* ---- attenuation ------------------------------------------------------------------------ */

/* sigma = 0: T is the Fresnel factor alone; sigma = 2: exp(-2) more (Beer-Lambert, exact
 * for a constant field); sigma = 1e5 (the scene's largest): absorbed within the first
 * step, T < 1e-6, and the radiance is the entry face's reflection alone. */
static void zero_and_enormous_attenuation(void)
{
    const char *const sigma[3] = {"0", "2", "1e5"};
    for (int k = 0; k < 3; k++) {
        char json[512];
        snprintf(json, sizeof json, HARD_ABSORBER("%s"), sigma[k]);
        struct hard_case c;
        if (!case_open(&c, json))
            continue;
        for (int i = 0; i < 3; i++) {
            struct reftrace_settings s = c.ref.settings;
            s.stepper = steppers[i];
            struct reftrace_result r = trace("attenuation", k * 3 + i, &c, &s, (vec3){0.1, 0.1, -2},
                                             (vec3){0, 0, 1}, false);
            if (k < 2) {
                CHECK_INT(r.status, RAY_EXITED);
                CHECK_NEAR(r.transmittance.x, 0.9216 * exp(-2.0 * k), 1e-9);
                continue;
            }
            CHECK_INT(r.status, RAY_ABSORBED);
            CHECK(r.transmittance.x < 1e-6);
            CHECK(r.steps <= 2);
            CHECK(r.exit_origin.z >= -0.5 && r.exit_origin.z <= -0.3);
            check_vec(r.radiance, vec3_scale(env_procedural((vec3){0, 0, -1}), 0.04), 1e-9);
        }
        case_close(&c);
    }
}

/* ---- termination without steps ------------------------------------------------------------- */

/* In an ambient index 2, a ray at 45 degrees between two index-1 slabs 0.01 apart reflects
 * totally off each face (sin 45 x 2 > 1) and never enters either: no integration step
 * is ever taken, so only the object-entry cap (docs/tracing.md step 1) ends it, with status
 * max_steps, no steps, T = 1 and nothing gathered. */
static void ray_reflecting_between_objects_ends_at_the_entry_cap(void)
{
    struct hard_case c;
    if (!case_open(&c, HARD_MIRRORS))
        return;
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = c.ref.settings;
        s.stepper = steppers[i];
        struct reftrace_result r =
            trace("mirrors", i, &c, &s, (vec3){-0.9, 0, 0.1}, (vec3){1, 1, 0}, true);
        CHECK_INT(r.status, RAY_MAX_STEPS);
        CHECK_INT(r.steps, 0);
        CHECK_NEAR(r.transmittance.x, 1.0, 0.0);
        CHECK(fabs(r.exit_origin.y) <= 0.005 + 1e-12 && r.exit_origin.x < 1.0);
    }
    case_close(&c);
}

int main(void)
{
    ray_trapped_in_a_block_ends_at_its_budget_where_the_billiard_says();
    light_pipe_reflects_many_times_and_leaves_per_the_closed_form();
    grazing_rays_enter_a_block_and_keep_energy_bounded();
    grazing_rays_on_a_sphere_rim_stay_finite_and_bounded("1.5", 1.5);
    grazing_rays_on_a_sphere_rim_stay_finite_and_bounded("2.42", 2.42);
    a_jump_from_1_to_3_at_the_faces_matches_fresnel();
    a_jump_from_1_to_3_inside_the_field_matches_fresnel();
    thin_shells_keep_energy_bounded();
    steep_gradient_bends_rays_per_the_stratified_closed_form();
    unsmoothed_index_step_stays_finite_and_bounded();
    camera_inside_a_block_sees_per_snell_and_fresnel();
    camera_inside_a_sphere_sees_radially_out();
    zero_and_enormous_attenuation();
    ray_reflecting_between_objects_ends_at_the_entry_cap();
    return test_summary("test_hard_reftrace");
}
