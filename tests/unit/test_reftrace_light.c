/*
 * test_reftrace_light.c - the light-dependent terms of the CPU reference tracer
 * (core/reftrace.c, reftrace_light.c; docs/tracing.md "Light", "Basic radiance") against
 * closed forms:
 * - basic radiance (frisvad2010): a uniform emitting medium n = 1.5 seen through its
 *   boundary gives T_f L_e length / n^2;
 * - single scattering in a uniform slab lit by a uniform irradiance volume (E = 1, fixed
 *   direction): T_f sigma_s p_HG(g, cos) E (1 - exp(-sigma_t len)) / sigma_t (n_amb/n)^2,
 *   and the transmittance exp(-sigma_t len) (extinction includes sigma_s);
 * - the lights' reflected light at the faces of a glass cube under the unshadowed direct
 *   light (Lambert), with the basic-radiance factor on the inner face;
 * - the volume lookup convention (trilinear, clamp to edge, 0 outside the grid) and the
 *   direct point and spot lights;
 * - the receiver: Lambertian plane lit by a volume, ambient albedo * env(up), misses.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "bindings.h"
#include "core/env.h"
#include "core/fresnel.h"
#include "core/phase.h"
#include "core/reftrace.h"
#include "core/reftrace_light.h"
#include "test.h"

/* A uniform grid of res^3 voxels; owns its arrays. */
struct slab {
    int res;
    double *ior_grad, *attenuation, *emission, *scattering, *anisotropy;
    struct reftrace_grid grid;
};

static void fill4(double *a, size_t count, double x, double y, double z, double w)
{
    for (size_t i = 0; i < count; i++) {
        a[4 * i + 0] = x;
        a[4 * i + 1] = y;
        a[4 * i + 2] = z;
        a[4 * i + 3] = w;
    }
}

static void slab_init(struct slab *u, int res, double n, vec3 sigma_a, vec3 le, vec3 sigma_s,
                      double g)
{
    size_t count = (size_t)res * res * res;
    u->res = res;
    u->ior_grad = malloc(sizeof(double) * 4 * count);
    u->attenuation = malloc(sizeof(double) * 4 * count);
    u->emission = malloc(sizeof(double) * 4 * count);
    u->scattering = malloc(sizeof(double) * 4 * count);
    u->anisotropy = malloc(sizeof(double) * count);
    fill4(u->ior_grad, count, 0, 0, 0, n);
    fill4(u->attenuation, count, sigma_a.x, sigma_a.y, sigma_a.z, 0);
    fill4(u->emission, count, le.x, le.y, le.z, 0);
    fill4(u->scattering, count, sigma_s.x, sigma_s.y, sigma_s.z, 0);
    for (size_t i = 0; i < count; i++)
        u->anisotropy[i] = g;
    u->grid = (struct reftrace_grid){.ior_grad = u->ior_grad,
                                     .attenuation = u->attenuation,
                                     .emission = u->emission,
                                     .scattering = u->scattering,
                                     .anisotropy = u->anisotropy};
}

static void slab_fini(struct slab *u)
{
    free(u->ior_grad);
    free(u->attenuation);
    free(u->emission);
    free(u->scattering);
    free(u->anisotropy);
}

static struct reftrace_object slab_object(vec3 bmin, vec3 bmax, const struct slab *u)
{
    return (struct reftrace_object){.bmin = bmin,
                                    .bmax = bmax,
                                    .res = {u->res, u->res, u->res},
                                    .xf = xform_identity(),
                                    .opaque_ior = 1.5,
                                    .grid = &u->grid};
}

static struct reftrace_settings settings(enum reftrace_stepper integ, double step)
{
    return (struct reftrace_settings){.stepper = integ,
                                      .step_voxels = step,
                                      .max_steps = 1000000,
                                      .boundary_threshold = 0.02,
                                      .ambient_ior = 1.0,
                                      .tolerance = 1e-10,
                                      .env_intensity = 0.0};
}

/* Refraction into the slab's z = 0 face from air: the direction inside and T = 1 - R. */
static vec3 enter(vec3 d, double n, double *T)
{
    vec3 nrm = {0, 0, -1}, t;
    *T = 1.0 - fresnel_unpolarized(fabs(d.z), 1.0, n);
    CHECK(snell_refract(d, nrm, 1.0, n, &t));
    return t;
}

static void emitting_medium_is_seen_with_basic_radiance(void)
{
    const double n = 1.5;
    vec3 le = {0.2, 0.3, 0.4};
    struct slab u;
    slab_init(&u, 8, n, (vec3){0, 0, 0}, le, (vec3){0, 0, 0}, 0.0);
    struct reftrace_object obj = slab_object((vec3){-2, -2, 0}, (vec3){2, 2, 2}, &u);
    vec3 d = vec3_normalize((vec3){0, 0.3, 1});
    double T;
    vec3 t = enter(d, n, &T);
    double len = 2.0 / t.z;
    const enum reftrace_stepper integ[3] = {REFTRACE_EULER, REFTRACE_RK4, REFTRACE_ADAPTIVE};
    for (int i = 0; i < 3; i++) {
        struct reftrace_settings s = settings(integ[i], 0.5);
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &s, (vec3){0, 0, -1}, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        vec3 expect = vec3_scale(le, T * len / (n * n));
        printf("basic radiance (stepper %d): L = %.9f, T_f L_e len / n^2 = %.9f\n", i, r.radiance.x,
               expect.x);
        CHECK_NEAR(r.radiance.x, expect.x, 1e-9);
        CHECK_NEAR(r.radiance.y, expect.y, 1e-9);
        CHECK_NEAR(r.radiance.z, expect.z, 1e-9);
    }
    slab_fini(&u);
}

/* A light grid of dims^3 cubic voxels at bmin with uniform E and direction. */
struct volume {
    float *irradiance, *direction;
    struct reftrace_light light;
};

static void volume_init(struct volume *v, int dims, vec3 bmin, double voxel, vec3 E, vec3 dir)
{
    size_t count = (size_t)dims * dims * dims;
    v->irradiance = malloc(count * 4 * sizeof(float));
    v->direction = malloc(count * 4 * sizeof(float));
    for (size_t i = 0; i < count; i++) {
        float *e = v->irradiance + 4 * i, *d = v->direction + 4 * i;
        e[0] = (float)E.x, e[1] = (float)E.y, e[2] = (float)E.z, e[3] = 0.0f;
        d[0] = (float)dir.x, d[1] = (float)dir.y, d[2] = (float)dir.z, d[3] = 1.0f;
    }
    v->light = (struct reftrace_light){.kind = LIGHT_KIND_DIRECTIONAL,
                                       .mode = LIGHT_MODE_VOLUME,
                                       .direction = dir,
                                       .scale = {1, 1, 1},
                                       .irradiance = v->irradiance,
                                       .direction_volume = v->direction,
                                       .dims = {dims, dims, dims},
                                       .bmin = bmin,
                                       .voxel = voxel};
}

static void volume_fini(struct volume *v)
{
    free(v->irradiance);
    free(v->direction);
}

static void slab_single_scattering_matches_the_closed_form(void)
{
    const double n = 1.33, g = 0.5;
    vec3 sa = {0.4, 0.2, 0.1}, ss = {0.6, 0.3, 0.9};
    struct slab u;
    slab_init(&u, 32, n, sa, (vec3){0, 0, 0}, ss, g);
    struct reftrace_object obj = slab_object((vec3){-2, -2, 0}, (vec3){2, 2, 1}, &u);
    struct volume vol;
    /* float-exact direction components, so the volume's copy is the same vector */
    vec3 l = vec3_normalize((vec3){0.25, -1.0, 0.5});
    volume_init(&vol, 16, (vec3){-3, -3, -2}, 0.375, (vec3){1, 1, 1}, l);
    for (int c = 0; c < 3; c++)
        vol.light.scale[c] = 1.0;
    struct reftrace_lighting lt = {.lights = &vol.light, .count = 1};
    vec3 d = vec3_normalize((vec3){0.2, 0.1, 1});
    double T;
    vec3 t = enter(d, n, &T);
    double len = 1.0 / t.z;
    vec3 lf = vec3_normalize((vec3){vol.direction[0], vol.direction[1], vol.direction[2]});
    double p = phase_hg(g, vec3_dot(lf, vec3_scale(t, -1.0)));
    const enum reftrace_stepper integ[2] = {REFTRACE_EULER, REFTRACE_RK4};
    for (int i = 0; i < 2; i++) {
        struct reftrace_settings s = settings(integ[i], 0.02);
        s.lighting = &lt;
        struct reftrace_result r;
        reftrace_ray(&obj, 1, &s, (vec3){0, 0, -1}, d, &r);
        CHECK_INT(r.status, RAY_EXITED);
        double sig_a[3] = {sa.x, sa.y, sa.z}, sig_s[3] = {ss.x, ss.y, ss.z};
        double got[3] = {r.radiance.x, r.radiance.y, r.radiance.z};
        double tr[3] = {r.transmittance.x, r.transmittance.y, r.transmittance.z};
        double T_out = 1.0 - fresnel_unpolarized(fabs(t.z), n, 1.0);
        for (int c = 0; c < 3; c++) {
            double st = sig_a[c] + sig_s[c];
            double expect = T * sig_s[c] * p * (1.0 - exp(-st * len)) / st / (n * n);
            printf("single scattering (stepper %d, channel %d): L = %.7f, closed form %.7f "
                   "(rel %.1e)\n",
                   i, c, got[c], expect, fabs(got[c] / expect - 1.0));
            CHECK(fabs(got[c] / expect - 1.0) < 1e-3);
            CHECK_NEAR(tr[c], T * T_out * exp(-st * len), 1e-9);
        }
    }
    /* With the light grid moved away the slab is outside it: E = 0, no in-scattering. */
    vol.light.bmin = (vec3){10, 10, 10};
    struct reftrace_settings s = settings(REFTRACE_RK4, 0.5);
    s.lighting = &lt;
    struct reftrace_result r;
    reftrace_ray(&obj, 1, &s, (vec3){0, 0, -1}, d, &r);
    CHECK(r.radiance.x == 0.0 && r.radiance.y == 0.0);
    volume_fini(&vol);
    slab_fini(&u);
}

/* A glass cube (n = 1.5) with a white Lambert BRDF, viewed along +z at normal incidence,
 * a directional light travelling +z with no light simulation (direct, unshadowed light):
 * the entry face reflects R / pi, the inner exit face, seen from inside, T R / pi times
 * (1 / n)^2; with the environment dark nothing else reaches the eye. */
static void faces_reflect_the_direct_light_with_their_brdf(void)
{
    const double n = 1.5;
    struct slab u;
    slab_init(&u, 8, n, (vec3){0, 0, 0}, (vec3){0, 0, 0}, (vec3){0, 0, 0}, 0.0);
    u.grid.scattering = NULL;
    struct reftrace_object obj = slab_object((vec3){-1, -1, 0}, (vec3){1, 1, 2}, &u);
    obj.brdf = (struct brdf_params){.kind = BRDF_LAMBERT, .color = {1, 0.5, 0.25}};
    struct reftrace_light light = {.kind = LIGHT_KIND_DIRECTIONAL,
                                   .mode = LIGHT_MODE_DIRECT,
                                   .direction = {0, 0, 1},
                                   .scale = {2, 2, 2}};
    struct reftrace_lighting lt = {.lights = &light, .count = 1};
    struct reftrace_settings s = settings(REFTRACE_RK4, 0.5);
    s.lighting = &lt;
    struct reftrace_result r;
    reftrace_ray(&obj, 1, &s, (vec3){0.1, 0.2, -1}, (vec3){0, 0, 1}, &r);
    double R = fresnel_unpolarized(1.0, 1.0, n);
    double expect = 2.0 * R / M_PI * (1.0 + (1.0 - R) / (n * n));
    printf("Lambert faces under a direct light: L = %.9f, closed form %.9f\n", r.radiance.x,
           expect);
    CHECK_NEAR(r.radiance.x, expect, 1e-12);
    CHECK_NEAR(r.radiance.y, 0.5 * expect, 1e-12);
    /* A light from behind the viewer lights neither face from the viewer's side... */
    light.direction = (vec3){0, 0, -1};
    reftrace_ray(&obj, 1, &s, (vec3){0.1, 0.2, -1}, (vec3){0, 0, 1}, &r);
    CHECK_NEAR(r.radiance.x, 0.0, 1e-15);
    /* ...and a light with no volume in a scene that needs simulation adds nothing. */
    light.direction = (vec3){0, 0, 1};
    light.mode = LIGHT_MODE_OFF;
    reftrace_ray(&obj, 1, &s, (vec3){0.1, 0.2, -1}, (vec3){0, 0, 1}, &r);
    CHECK(r.radiance.x == 0.0);
    slab_fini(&u);
}

static void volume_lookup_is_trilinear_clamped_and_zero_outside(void)
{
    struct volume vol;
    volume_init(&vol, 4, (vec3){0, 0, 0}, 0.5, (vec3){0, 0, 0}, (vec3){0, -1, 0});
    for (int k = 0; k < 4; k++)
        for (int j = 0; j < 4; j++)
            for (int i = 0; i < 4; i++)
                vol.irradiance[((k * 4 + j) * 4 + i) * 4] = (float)(i + 10 * j + 100 * k);
    vec3 E, l;
    /* v = x / 0.5 - 0.5: x = 0.6 -> 0.7; y = 0.25 -> 0 (centre of voxel 0); z = 1.9 -> 3.3,
     * clamped to 3. */
    CHECK(reftrace_light_at(&vol.light, (vec3){0.6, 0.25, 1.9}, &E, &l));
    CHECK_NEAR(E.x, 0.7 + 0 + 300, 1e-6);
    CHECK_NEAR(l.y, -1.0, 1e-15);
    CHECK(reftrace_light_at(&vol.light, (vec3){0.0, 2.0, 0.1}, &E, &l)); /* on the faces */
    CHECK_NEAR(E.x, 0 + 30 + 0, 1e-6);
    CHECK(!reftrace_light_at(&vol.light, (vec3){-0.01, 1, 1}, &E, &l));
    CHECK(!reftrace_light_at(&vol.light, (vec3){1, 2.01, 1}, &E, &l));
    volume_fini(&vol);

    struct reftrace_light pt = {.kind = LIGHT_KIND_POINT,
                                .mode = LIGHT_MODE_DIRECT,
                                .position = {0, 2, 0},
                                .scale = {4, 4, 4}};
    CHECK(reftrace_light_at(&pt, (vec3){0, 0, 0}, &E, &l));
    CHECK_NEAR(E.x, 1.0, 1e-15); /* 4 / 2^2 */
    CHECK_NEAR(l.y, -1.0, 1e-15);
    pt.kind = LIGHT_KIND_SPOT;
    pt.direction = (vec3){0, -1, 0};
    pt.cos_spot = cos(25.0 * M_PI / 180.0);
    CHECK(reftrace_light_at(&pt, (vec3){0.5, 0, 0}, &E, &l));  /* 14 deg off the axis */
    CHECK(!reftrace_light_at(&pt, (vec3){1.5, 0, 0}, &E, &l)); /* 37 deg */
}

static void receiver_shows_the_volume_and_the_ambient_term(void)
{
    struct volume vol;
    vec3 l = vec3_normalize((vec3){0, -1, 0.5});
    /* 16 voxels of 0.5 from -4: the volume is read LIGHT_RECEIVER_INSET (4) voxels inside
     * the x, z faces, on [-2, 2] */
    volume_init(&vol, 16, (vec3){-4, -1.5, -4}, 0.5, (vec3){3, 2, 1}, l);
    struct reftrace_lighting lt = {
        .lights = &vol.light,
        .count = 1,
        .receiver = {.enabled = true, .height = -1, .half_size = 1.5, .albedo = {0.8, 0.5, 0.2}}};
    struct reftrace_settings s = settings(REFTRACE_RK4, 0.5);
    s.env_intensity = 1.0;
    s.lighting = &lt;
    struct reftrace_result r;
    vec3 d = vec3_normalize((vec3){0.2, -1, 0.1});
    reftrace_ray(NULL, 0, &s, (vec3){0, 1, 0}, d, &r);
    CHECK_INT(r.status, RAY_MISSED);
    vec3 lf = vec3_normalize((vec3){vol.direction[0], vol.direction[1], vol.direction[2]});
    vec3 up = env_procedural((vec3){0, 1, 0});
    double expect = 0.8 / M_PI * 3.0 * -lf.y + 0.8 * up.x;
    printf("receiver: L = %.9f, closed form %.9f\n", r.radiance.x, expect);
    CHECK_NEAR(r.radiance.x, expect, 1e-6);
    CHECK_NEAR(r.radiance.z, 0.2 / M_PI * 1.0 * -lf.y + 0.2 * up.z, 1e-6);
    /* Beyond the volume's inset region, still on the square: the light's closed form
     * (reftrace_light_direct: E = scale = 1 along its direction). */
    lt.receiver.half_size = 3.0; /* hit at (2.2, -1, 0.6) */
    d = vec3_normalize((vec3){1.1, -1, 0.3});
    reftrace_ray(NULL, 0, &s, (vec3){0, 1, 0}, d, &r);
    printf("receiver beyond the volume: L = %.9f\n", r.radiance.x);
    CHECK_NEAR(r.radiance.x, 0.8 / M_PI * 1.0 * -lf.y + 0.8 * up.x, 1e-6);
    /* An infinite plane centred anywhere: hit far away, the closed form. */
    lt.receiver.half_size = INFINITY;
    lt.receiver.center[0] = 40.0;
    d = vec3_normalize((vec3){30.0, -1, 0});
    reftrace_ray(NULL, 0, &s, (vec3){0, 1, 0}, d, &r);
    CHECK_NEAR(r.radiance.x, 0.8 / M_PI * 1.0 * -lf.y + 0.8 * up.x, 1e-6);
    lt.receiver.half_size = 1.5;
    /* A square centred at (40, 0): (0, -1, 0) is off it. */
    d = (vec3){0, -1, 0};
    reftrace_ray(NULL, 0, &s, (vec3){0, 1, 0}, d, &r);
    CHECK_NEAR(r.radiance.x, env_procedural(d).x, 1e-12);
    lt.receiver.center[0] = 0.0;
    /* Beyond the square: the environment. */
    d = vec3_normalize((vec3){1.0, -1, 0});
    reftrace_ray(NULL, 0, &s, (vec3){0, 1, 0}, d, &r);
    CHECK_NEAR(r.radiance.x, env_procedural(d).x, 1e-12);
    volume_fini(&vol);
}

/* The receiver seen in a glass's reflection (issue 14 item 4): a view ray meets an opaque-
 * black glass ball (sigma_a 1e3: nothing comes through) at cos_i = 0.6, and the reflected
 * ray goes down to the floor, lit by an unshadowed directional light straight down:
 * L = R(0.6) * albedo / pi * E (no environment, no BRDF). */
static void receiver_seen_in_a_reflection(void)
{
    struct reftrace_light sun = {.kind = LIGHT_KIND_DIRECTIONAL,
                                 .mode = LIGHT_MODE_DIRECT,
                                 .direction = {0, -1, 0},
                                 .scale = {1, 1, 1}};
    struct reftrace_lighting lt = {
        .lights = &sun,
        .count = 1,
        .receiver = {
            .enabled = true, .height = -1, .half_size = INFINITY, .albedo = {0.8, 0.8, 0.8}}};
    struct reftrace_surface ball = {.ior = 1.5, .attenuation = {1e3, 1e3, 1e3}};
    ball.geom.kind = GEOM_SPHERE;
    ball.geom.xf = xform_identity();
    ball.geom.center = (vec3){0, 0, 0};
    ball.geom.radius = 1.0;
    struct reftrace_settings s = settings(REFTRACE_RK4, 0.5);
    s.env_intensity = 0.0;
    s.lighting = &lt;
    s.surfaces = &ball;
    s.surface_count = 1;
    struct reftrace_result r;
    /* hits (0, -0.8, 0.6), normal (0, -0.8, 0.6); reflected (0, -0.96, -0.28) meets the
     * floor at (0, -1, 0.54), outside the ball */
    reftrace_ray(NULL, 0, &s, (vec3){0, -0.8, 5}, (vec3){0, 0, -1}, &r);
    double expect = fresnel_unpolarized(0.6, 1.0, 1.5) * 0.8 / M_PI;
    printf("receiver in a reflection: L = %.9f, closed form %.9f\n", r.radiance.x, expect);
    CHECK_NEAR(r.radiance.x, expect, 1e-9);
    /* without the receiver the reflection sees the (black) environment */
    lt.receiver.enabled = false;
    reftrace_ray(NULL, 0, &s, (vec3){0, -0.8, 5}, (vec3){0, 0, -1}, &r);
    CHECK_NEAR(r.radiance.x, 0.0, 1e-12);
}

/* Lamps (docs/tracing.md "Lamps"): a point light of radius r is a sphere of radiance
 * intensity / (pi r^2) to rays leaving the scene, the nearest one first, behind the
 * receiver where the receiver is nearer, and hidden from camera rays that met nothing
 * when camera_visible is false. */
static void lamps_are_seen_by_rays_leaving_the_scene(void)
{
    struct reftrace_light l[2] = {
        {.kind = LIGHT_KIND_POINT, .position = {0, 0, -5}, .scale = {2, 4, 6}, .radius = 0.5},
        {.kind = LIGHT_KIND_POINT, .position = {0, 0, -9}, .scale = {1, 1, 1}, .radius = 2}};
    struct reftrace_lighting lt = {.lights = l, .count = 2};
    vec3 L;
    const double k = 1.0 / (M_PI * 0.25);
    CHECK(reftrace_light_emitter(&lt, (vec3){0.1, 0.2, 0}, (vec3){0, 0, -1}, INFINITY, true, &L));
    CHECK_NEAR(L.x, 2 * k, 1e-12); /* the nearer lamp, though the far one is larger */
    CHECK_NEAR(L.z, 6 * k, 1e-12);
    /* past the near lamp's edge: the far one */
    CHECK(reftrace_light_emitter(&lt, (vec3){0.6, 0, 0}, (vec3){0, 0, -1}, INFINITY, true, &L));
    CHECK_NEAR(L.x, 1.0 / (M_PI * 4.0), 1e-12);
    /* a nearer receiver (t_max) hides both; a ray going away sees none */
    CHECK(!reftrace_light_emitter(&lt, (vec3){0, 0, 0}, (vec3){0, 0, -1}, 4.0, true, &L));
    CHECK(!reftrace_light_emitter(&lt, (vec3){0, 0, 0}, (vec3){0, 0, 1}, INFINITY, false, &L));
    /* hidden from the camera: skipped for primary rays only */
    l[0].camera_hidden = true;
    CHECK(reftrace_light_emitter(&lt, (vec3){0, 0, 0}, (vec3){0, 0, -1}, INFINITY, true, &L));
    CHECK_NEAR(L.x, 1.0 / (M_PI * 4.0), 1e-12);
    CHECK(reftrace_light_emitter(&lt, (vec3){0, 0, 0}, (vec3){0, 0, -1}, INFINITY, false, &L));
    CHECK_NEAR(L.x, 2 * k, 1e-12);
    /* a point (radius 0) and other kinds are never seen */
    l[0].radius = 0.0;
    l[1].kind = LIGHT_KIND_SPOT;
    CHECK(!reftrace_light_emitter(&lt, (vec3){0, 0, 0}, (vec3){0, 0, -1}, INFINITY, false, &L));
    /* Through the tracer: a camera ray that meets nothing sees the lamp; hidden, the
     * environment (black here). */
    l[0] = (struct reftrace_light){
        .kind = LIGHT_KIND_POINT, .position = {0, 0, -5}, .scale = {2, 4, 6}, .radius = 0.5};
    lt.count = 1;
    struct reftrace_settings st = settings(REFTRACE_RK4, 0.5);
    st.env_intensity = 0.0;
    st.lighting = &lt;
    struct reftrace_result r;
    reftrace_ray(NULL, 0, &st, (vec3){0, 0, 0}, (vec3){0, 0, -1}, &r);
    CHECK_NEAR(r.radiance.y, 4 * k, 1e-9);
    l[0].camera_hidden = true;
    reftrace_ray(NULL, 0, &st, (vec3){0, 0, 0}, (vec3){0, 0, -1}, &r);
    CHECK_NEAR(r.radiance.y, 0.0, 1e-12);
}

int main(void)
{
    lamps_are_seen_by_rays_leaving_the_scene();
    emitting_medium_is_seen_with_basic_radiance();
    slab_single_scattering_matches_the_closed_form();
    faces_reflect_the_direct_light_with_their_brdf();
    volume_lookup_is_trilinear_clamped_and_zero_outside();
    receiver_shows_the_volume_and_the_ambient_term();
    receiver_seen_in_a_reflection();
    return test_summary("test_reftrace_light");
}
