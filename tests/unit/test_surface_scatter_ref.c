/*
 * test_surface_scatter_ref.c - single scattering in a surface's constant medium in the CPU
 * reference tracer (core/reftrace.c surface_leg, core/medium_step.c; docs/tracing.md
 * "Scattering inside surfaces") against closed forms:
 *
 * - A slab 0 <= z <= D of index 1 (a box surface, wide in x and y: no Fresnel event, no
 *   basic-radiance factor), sigma_a, sigma_s (per channel), Henyey-Greenstein g, lit by a
 *   directional light travelling +z whose irradiance volume holds the exact attenuated
 *   irradiance E(z) = E0 exp(-sigma_t z) inside (the light simulator's job, bounded by
 *   test_lightsim_surfaces.c). A view ray entering the far face z = D at angle a to the
 *   normal, travelling towards -z, sees
 *     L = sigma_s p_HG(g, cos a) E0 int_0^S exp(-sigma_t (D - s cos a)) exp(-sigma_t s) ds
 *       = sigma_s p E0 exp(-sigma_t D) (1 - exp(-sigma_t (1 - cos a) S)) / (sigma_t (1 - cos a))
 *   with S = D / cos a (tevs2007 eqs. 5.4/5.5 with the light's path z and the view's s),
 *   and the transmittance exp(-sigma_t S). Both within 1e-3 relative (measured 1e-5 to
 *   1e-4: the trilinear irradiance of the exponential and the midpoint rule).
 * - Without lights the medium still extinguishes: transmittance exp(-sigma_t S), no light.
 * - The step count (medium_step_count): half the irradiance voxel.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bindings.h"
#include "core/medium_step.h"
#include "core/phase.h"
#include "core/reftrace.h"
#include "core/reftrace_light.h"
#include "test.h"

#define D 1.0 /* slab thickness */

static const double sigma_a[3] = {0.1, 0.05, 0.2};
static const double sigma_s[3] = {0.5, 0.3, 0.8};
static const double g = 0.3;

/* The exact irradiance of a light travelling +z through the slab, on a grid of voxel h
 * whose voxel centres lie on z = 0 and z = D (where E has its kinks: there the trilinear
 * sample is exact on each side); x wide enough for the oblique view rays. */
struct volume {
    int dims[3];
    double voxel;
    vec3 bmin;
    float *E, *dir;
};

static double sigma_t(int c)
{
    return sigma_a[c] + sigma_s[c];
}

static void volume_init(struct volume *v, double h)
{
    v->voxel = h;
    v->dims[0] = (int)ceil(4.0 / h);
    v->dims[1] = 4;
    v->dims[2] = (int)ceil((D + 0.4) / h) + 1;
    v->bmin = vec3_make(-2.0, -2.0 * h, -0.2 - 0.5 * h);
    size_t n = (size_t)v->dims[0] * v->dims[1] * v->dims[2];
    v->E = calloc(4 * n, sizeof *v->E);
    v->dir = calloc(4 * n, sizeof *v->dir);
    for (int k = 0; k < v->dims[2]; k++) {
        double z = v->bmin.z + (k + 0.5) * h, depth = fmin(fmax(z, 0.0), D);
        for (int j = 0; j < v->dims[1]; j++)
            for (int i = 0; i < v->dims[0]; i++) {
                size_t at = 4 * (((size_t)k * v->dims[1] + j) * v->dims[0] + i);
                for (int c = 0; c < 3; c++)
                    v->E[at + c] = (float)exp(-sigma_t(c) * depth);
                v->dir[at + 2] = 1.0f;
                v->dir[at + 3] = 1.0f;
            }
    }
}

static struct reftrace_surface slab_surface(void)
{
    struct reftrace_surface s = {.ior = 1.0, .anisotropy = g};
    s.geom.kind = GEOM_BOX;
    s.geom.xf = xform_identity();
    s.geom.center = vec3_make(0, 0, 0.5 * D);
    s.geom.size = vec3_make(40, 40, D);
    for (int c = 0; c < 3; c++) {
        s.attenuation[c] = sigma_a[c];
        s.scattering[c] = sigma_s[c];
    }
    return s;
}

static struct reftrace_settings settings(const struct reftrace_surface *sf,
                                         const struct reftrace_lighting *lt)
{
    return (struct reftrace_settings){.stepper = REFTRACE_RK4,
                                      .step_voxels = 0.5,
                                      .max_steps = 1000,
                                      .boundary_threshold = 0.02,
                                      .ambient_ior = 1.0,
                                      .env_intensity = 0.0, /* black: only the medium's light */
                                      .lighting = lt,
                                      .min_throughput = -1.0,
                                      .surfaces = sf,
                                      .surface_count = 1};
}

/* The closed form of the header for channel c at view angle a. */
static double closed_form(int c, double a, double E0)
{
    double ca = cos(a), S = D / ca, k = sigma_t(c) * (1.0 - ca);
    double integral =
        k > 0.0 ? exp(-sigma_t(c) * D) * -expm1(-k * S) / k : exp(-sigma_t(c) * D) * S;
    return sigma_s[c] * phase_hg(g, ca) * E0 * integral;
}

/* The slab under the light for view angles a, voxel h: worst relative errors. */
static void test_slab(double h, double tol)
{
    const double E0 = 3.0; /* the light's scale (colour x intensity) */
    struct volume v;
    volume_init(&v, h);
    struct reftrace_light light = {.kind = LIGHT_KIND_DIRECTIONAL,
                                   .mode = LIGHT_MODE_VOLUME,
                                   .direction = vec3_make(0, 0, 1),
                                   .scale = {E0, E0, E0},
                                   .irradiance = v.E,
                                   .direction_volume = v.dir,
                                   .dims = {v.dims[0], v.dims[1], v.dims[2]},
                                   .bmin = v.bmin,
                                   .voxel = v.voxel};
    struct reftrace_lighting lt = {.lights = &light, .count = 1};
    struct reftrace_surface sf = slab_surface();
    struct reftrace_settings st = settings(&sf, &lt);
    CHECK_NEAR(reftrace_light_inscatter_step(&lt), 0.5 * h, 1e-15);
    double worst_L = 0.0, worst_T = 0.0;
    const double angles_deg[] = {0, 20, 45, 60};
    for (size_t i = 0; i < sizeof angles_deg / sizeof angles_deg[0]; i++) {
        double a = angles_deg[i] * M_PI / 180.0;
        vec3 d = vec3_make(sin(a), 0.0, -cos(a));
        /* enters the far face at x = -1 (inside the grid's x range all the way) */
        vec3 o = vec3_madd(vec3_make(-1.0, 0.0, D), d, -2.0);
        struct reftrace_result r;
        reftrace_ray(NULL, 0, &st, o, d, &r);
        double L[3] = {r.radiance.x, r.radiance.y, r.radiance.z};
        double T[3] = {r.transmittance.x, r.transmittance.y, r.transmittance.z};
        for (int c = 0; c < 3; c++) {
            double want = closed_form(c, a, E0), want_T = exp(-sigma_t(c) * D / cos(a));
            double eL = fabs(L[c] - want) / want, eT = fabs(T[c] - want_T) / want_T;
            worst_L = fmax(worst_L, eL);
            worst_T = fmax(worst_T, eT);
            if (c == 0)
                printf("  voxel %.3f, %2.0f deg: L %.6f (closed form %.6f), T %.6f (%.6f)\n", h,
                       angles_deg[i], L[c], want, T[c], want_T);
        }
        CHECK_INT(r.status, RAY_EXITED);
    }
    printf("slab, voxel %.3f: in-scattered radiance worst relative error %.2e, transmittance "
           "%.2e (bound %.0e)\n",
           h, worst_L, worst_T, tol);
    CHECK(worst_L <= tol);
    CHECK(worst_T <= 1e-12);
    free(v.E);
    free(v.dir);
}

/* Without lights: the scattered part still leaves the ray; nothing is added. */
static void test_no_lights(void)
{
    struct reftrace_surface sf = slab_surface();
    struct reftrace_settings st = settings(&sf, NULL);
    st.env_intensity = 1.0;
    struct reftrace_result r, r0;
    reftrace_ray(NULL, 0, &st, vec3_make(0, 0, 3), vec3_make(0, 0, -1), &r);
    struct reftrace_surface clear = sf;
    for (int c = 0; c < 3; c++)
        clear.attenuation[c] = clear.scattering[c] = 0.0;
    st.surfaces = &clear;
    reftrace_ray(NULL, 0, &st, vec3_make(0, 0, 3), vec3_make(0, 0, -1), &r0);
    double T[3] = {r.transmittance.x, r.transmittance.y, r.transmittance.z};
    double L[3] = {r.radiance.x, r.radiance.y, r.radiance.z};
    double L0[3] = {r0.radiance.x, r0.radiance.y, r0.radiance.z};
    for (int c = 0; c < 3; c++) {
        CHECK_NEAR(T[c], exp(-sigma_t(c) * D), 1e-14);
        CHECK_NEAR(L[c], L0[c] * exp(-sigma_t(c) * D), 1e-12); /* the background, extinguished */
    }
}

static void test_step_count(void)
{
    CHECK_INT(medium_step_count(1.0, 0.1), 10);
    CHECK_INT(medium_step_count(1.05, 0.1), 11);
    CHECK_INT(medium_step_count(1.0, 0.0), MEDIUM_DIRECT_STEPS);
    CHECK_INT(medium_step_count(1e9, 0.1), MEDIUM_MAX_STEPS);
    CHECK_INT(medium_step_count(0.0, 0.1), 1);
    CHECK_NEAR(medium_step_weight(0.0, 0.25), 0.25, 0.0);
    CHECK_NEAR(medium_step_weight(2.0, 0.25), (1.0 - exp(-0.5)) / 2.0, 1e-16);
}

int main(void)
{
    test_step_count();
    test_no_lights();
    test_slab(0.02, 1e-3);
    test_slab(0.05, 1e-3);
    return test_summary("test_surface_scatter_ref");
}
