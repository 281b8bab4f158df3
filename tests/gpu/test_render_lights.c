/*
 * test_render_lights.c - the light-dependent terms of the view renderer (render_view.comp
 * with lighting.glsl) against the CPU double-precision reference (reftrace with
 * reftrace_light.c), pixel by pixel, on the same voxels and the same synthetic irradiance
 * volumes (uploaded with irradiance_gpu_upload): in-scattering in a Henyey-Greenstein slab
 * (g = 0.5) lit by a volume whose irradiance varies across it; a receiver plane under a
 * glass ball with a bright spot in the volume (and the ball's GGX reflection of the same
 * volume); a GGX highlight on a glass sphere under an unshadowed direct light (a scene that
 * needs no light simulation); a glass sphere surface filled with a scattering medium in
 * the varying volume (in-scattering along surface segments).
 *
 * The scenes (scattering, anisotropy, receiver, BRDFs) are parsed from JSON; the light
 * and its synthetic volume are set by hand. Values are chosen exactly representable in
 * half floats where the GPU stores RGBA16F (the scattering atlas, the direction volume),
 * so both sides see the same data. scene_reference does not carry the BRDFs (a field of
 * reftrace_object added by this work): the test copies them into the reference objects.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/env.h"
#include "gpu/queue.h"
#include "io/io_image.h"
#include "lightsim/gpu/lightsim_gpu.h"
#include "render/render.h"
#include "scene/scene.h"
#include "scene/scene_reference.h"
#include "gpu_test_util.h"
#include "unit/scene_test_util.h"
#include "test.h"

/* Rounds to the nearest half float (11 significant bits; the values here are normal). */
static float to_half(double x)
{
    if (x == 0.0)
        return 0.0f;
    int e;
    double m = frexp(x, &e);
    return (float)ldexp(round(m * 2048.0) / 2048.0, e);
}

/* A synthetic irradiance volume: E(x) and a fixed direction, on a cubic grid. */
typedef void (*irradiance_fn)(vec3 x, double E[3]);

static void make_volume(struct irradiance_volume *v, vec3 bmin, double voxel, int dims,
                        irradiance_fn fn, vec3 dir)
{
    memset(v, 0, sizeof *v);
    v->grid = (struct light_grid){.dims = {dims, dims, dims}, .bmin = bmin, .voxel = voxel};
    size_t count = (size_t)dims * dims * dims;
    v->irradiance = calloc(count * 4, sizeof(float));
    v->direction = calloc(count * 4, sizeof(float));
    for (int k = 0; k < dims; k++)
        for (int j = 0; j < dims; j++)
            for (int i = 0; i < dims; i++) {
                size_t at = (((size_t)k * dims + j) * dims + i) * 4;
                vec3 x = vec3_add(bmin, vec3_scale((vec3){i + 0.5, j + 0.5, k + 0.5}, voxel));
                double E[3];
                fn(x, E);
                for (int c = 0; c < 3; c++)
                    v->irradiance[at + c] = (float)E[c];
                v->direction[at + 0] = to_half(dir.x);
                v->direction[at + 1] = to_half(dir.y);
                v->direction[at + 2] = to_half(dir.z);
                v->direction[at + 3] = 1.0f;
            }
}

static void ramp_irradiance(vec3 x, double E[3])
{
    E[0] = 0.5 + 0.25 * x.x;
    E[1] = 0.75 + 0.125 * x.y;
    E[2] = 1.0 + 0.25 * x.z * x.z;
}

static void spot_irradiance(vec3 x, double E[3])
{
    double r2 = (x.x - 0.3) * (x.x - 0.3) + (x.z - 0.2) * (x.z - 0.2);
    double b = 0.2 + 5.0 * exp(-r2 / 0.1);
    E[0] = b;
    E[1] = 0.8 * b;
    E[2] = 0.6 * b;
}

struct lit_case {
    const char *name;
    struct scene *scene;
    struct scene_light lights[SCENE_MAX_LIGHTS];
    struct irradiance_volume volumes[SCENE_MAX_LIGHTS]; /* grid.dims[0] == 0: none */
    int light_count;
    double close_fraction, mean_bound; /* bounds of this case */
};

#define TRACE_RAYS 64

struct render_work {
    struct gpu_work work;
    struct lit_case *c;
    struct render_view_result out;
    struct render_trace_ray rays[TRACE_RAYS]; /* the trace kernel on the same scene */
    struct render_trace_hit hits[TRACE_RAYS];
};

static double light_scale(const struct scene_light *l, int c)
{
    return l->color[c] * l->intensity;
}

static void render_run(struct gpu_work *w, struct gpu *gpu)
{
    struct render_work *rw = w->user;
    struct lit_case *c = rw->c;
    struct render_desc desc = {0};
    struct render *r = render_create(gpu, &desc, &w->err);
    if (r == NULL)
        return;
    struct irradiance_gpu vol[SCENE_MAX_LIGHTS];
    memset(vol, 0, sizeof vol);
    struct render_light rl[SCENE_MAX_LIGHTS];
    bool ok = true;
    for (int j = 0; j < c->light_count; j++) {
        const struct scene_light *l = &c->lights[j];
        bool has_volume = c->volumes[j].grid.dims[0] > 0;
        if (has_volume && ok)
            ok = irradiance_gpu_upload(&c->volumes[j], &vol[j], &w->err) == REFRACT_E_OK;
        rl[j] = (struct render_light){
            .kind = l->kind,
            .position = l->position,
            .direction = l->direction,
            .cos_spot = cos(l->spot_angle_deg * M_PI / 180.0),
            .scale = {light_scale(l, 0), light_scale(l, 1), light_scale(l, 2)},
            .volume = has_volume ? &vol[j] : NULL,
            .radius = l->radius,
            .camera_hidden = !l->camera_visible};
    }
    struct render_scene_source src = {.id = c->name, .generation = 1, .scene = c->scene};
    struct render_view_request req = {.camera = c->scene->camera,
                                      .settings = c->scene->render,
                                      .lights = rl,
                                      .light_count = c->light_count};
    if (ok && render_view(r, &src, &req, &rw->out, &w->err) == REFRACT_E_OK) {
        double gpu_ms;
        render_trace(r, &src, &c->scene->render, rw->rays, TRACE_RAYS, rw->hits, &gpu_ms, &w->err);
    }
    for (int j = 0; j < c->light_count; j++)
        irradiance_gpu_free(&vol[j]);
    render_destroy(r);
}

/* REFRACT_TEST_DUMP=dir writes each case's picture as dir/lights_<n>.png, to look at. */
static void dump_png(const struct lit_case *c, const struct render_view_result *out)
{
    static int index;
    const char *dir = getenv("REFRACT_TEST_DUMP");
    if (dir == NULL)
        return;
    uint8_t *px = malloc((size_t)out->width * out->height * 4);
    void *png = NULL;
    size_t len = 0;
    struct err e = {0};
    io_tonemap_srgb8(out->rgba, out->width, out->height, 0.0, IO_TONEMAP_FILMIC, px);
    if (io_encode_png(px, out->width, out->height, &png, &len, &e) == REFRACT_E_OK) {
        char path[512];
        snprintf(path, sizeof path, "%s/lights_%d.png", dir, index++);
        FILE *f = fopen(path, "wb");
        if (f) {
            fwrite(png, 1, len, f);
            fclose(f);
            printf("%s: wrote %s\n", c->name, path);
        }
    }
    free(png);
    free(px);
}

static void compare(struct gpu *gpu, struct lit_case *c)
{
    struct render_work rw = {.c = c};
    /* Trace rays: a fan from the camera towards the scene's centre. */
    for (int i = 0; i < TRACE_RAYS; i++) {
        vec3 o, dir;
        const struct scene_camera *cam = &c->scene->camera;
        camera_ray(cam->eye, cam->look_at, cam->up, cam->fov_y_deg, 8, 8, i % 8, i / 8, &o, &dir);
        rw.rays[i] = (struct render_trace_ray){.origin = {o.x, o.y, o.z},
                                               .direction = {dir.x, dir.y, dir.z}};
    }
    rw.work =
        (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = render_run, .user = &rw};
    CHECK_INT(gpu_run_sync(gpu, &rw.work), REFRACT_E_OK);
    if (rw.out.rgba == NULL) {
        fprintf(stderr, "%s: no image: %s\n", c->name, rw.work.err.msg);
        CHECK(false);
        return;
    }
    dump_png(c, &rw.out);
    const struct scene *s = c->scene;
    struct scene_reference ref;
    struct err e = {0};
    CHECK_INT(scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &ref, &e), REFRACT_E_OK);
    for (int i = 0; i < ref.count; i++) {
        const struct scene_object *o = &s->objects[i];
        ref.objects[i].brdf =
            (struct brdf_params){.kind = (int)o->brdf.kind,
                                 .color = {o->brdf.color[0], o->brdf.color[1], o->brdf.color[2]},
                                 .alpha = o->brdf.roughness * o->brdf.roughness,
                                 .exponent = o->brdf.exponent};
    }
    bool needs_sim = scene_needs_light_simulation(s);
    struct reftrace_light rl[SCENE_MAX_LIGHTS];
    for (int j = 0; j < c->light_count; j++) {
        const struct scene_light *l = &c->lights[j];
        const struct irradiance_volume *v = &c->volumes[j];
        bool has_volume = v->grid.dims[0] > 0;
        rl[j] = (struct reftrace_light){
            .kind = (int)l->kind,
            .mode = has_volume  ? LIGHT_MODE_VOLUME
                    : needs_sim ? LIGHT_MODE_OFF
                                : LIGHT_MODE_DIRECT,
            .position = l->position,
            .direction = l->direction,
            .cos_spot = cos(l->spot_angle_deg * M_PI / 180.0),
            .scale = {light_scale(l, 0), light_scale(l, 1), light_scale(l, 2)},
            .irradiance = v->irradiance,
            .direction_volume = v->direction,
            .dims = {v->grid.dims[0], v->grid.dims[1], v->grid.dims[2]},
            .bmin = v->grid.bmin,
            .voxel = v->grid.voxel,
            .radius = l->radius,
            .camera_hidden = !l->camera_visible};
    }
    struct reftrace_lighting lt = {
        .lights = rl,
        .count = c->light_count,
        .receiver = {
            .enabled = s->receiver.enabled,
            .height = s->receiver.height,
            .half_size = s->receiver.half_size,
            .albedo = {s->receiver.albedo[0], s->receiver.albedo[1], s->receiver.albedo[2]},
            .center = {s->receiver.center[0], s->receiver.center[1]}}};
    ref.settings.lighting = &lt;

    const struct scene_camera *cam = &s->camera;
    int w = rw.out.width, h = rw.out.height, total = w * h, close = 0;
    double sum_diff = 0.0, sum_ref = 0.0, worst = 0.0, sum_light = 0.0;
    struct reftrace_settings dark = ref.settings; /* the same without lights: what they add */
    dark.lighting = NULL;
    for (int row = 0; row < h; row++) {
        for (int col = 0; col < w; col++) {
            vec3 o, dir;
            camera_ray(cam->eye, cam->look_at, cam->up, cam->fov_y_deg, w, h, col, row, &o, &dir);
            struct reftrace_result r, r0;
            reftrace_ray(ref.objects, ref.count, &ref.settings, o, dir, &r);
            reftrace_ray(ref.objects, ref.count, &dark, o, dir, &r0);
            const float *g = &rw.out.rgba[(row * w + col) * 4];
            double want[3] = {r.radiance.x, r.radiance.y, r.radiance.z};
            double base[3] = {r0.radiance.x, r0.radiance.y, r0.radiance.z};
            bool ok = true;
            for (int k = 0; k < 3; k++) {
                double diff = fabs(g[k] - want[k]);
                sum_diff += diff;
                sum_ref += fabs(want[k]);
                sum_light += fabs(want[k] - base[k]);
                worst = fmax(worst, diff);
                ok = ok && diff <= 1e-3;
            }
            close += ok;
            if (!ok && getenv("REFRACT_TEST_VERBOSE"))
                fprintf(stderr, "  %s (%d,%d): gpu %.5f %.5f %.5f ref %.5f %.5f %.5f\n", c->name,
                        col, row, g[0], g[1], g[2], want[0], want[1], want[2]);
        }
    }
    double mean_diff = sum_diff / (3.0 * total);
    printf(
        "%-34s %dx%d, %.1f ms on the GPU: %5.1f%% of pixels within 1e-3 absolute; mean |diff| %.1e "
        "(mean radiance %.3f, of which the lights %.3f); worst %.2e\n",
        c->name, w, h, rw.out.gpu_ms, 100.0 * close / total, mean_diff, sum_ref / (3.0 * total),
        sum_light / (3.0 * total), worst);
    /* The lights must matter in the picture, or the comparison proves nothing. */
    CHECK_MSG(sum_light / (3.0 * total) > 0.01, "%s: the lights add only %g", c->name,
              sum_light / (3.0 * total));
    CHECK_MSG(close >= c->close_fraction * total, "%s: only %d of %d pixels within 1e-3", c->name,
              close, total);
    CHECK_MSG(mean_diff < c->mean_bound, "%s: mean difference %g", c->name, mean_diff);
    /* The trace kernel's transmittance: T_f exp(-alpha) with alpha over sigma_a + sigma_s. */
    double worst_t = 0.0;
    int t_close = 0;
    for (int i = 0; i < TRACE_RAYS; i++) {
        struct reftrace_result r;
        vec3 o = {rw.rays[i].origin[0], rw.rays[i].origin[1], rw.rays[i].origin[2]};
        vec3 dir = {rw.rays[i].direction[0], rw.rays[i].direction[1], rw.rays[i].direction[2]};
        reftrace_ray(ref.objects, ref.count, &ref.settings, o, dir, &r);
        double want[3] = {r.transmittance.x, r.transmittance.y, r.transmittance.z};
        double d = 0.0;
        for (int k = 0; k < 3; k++)
            d = fmax(d, fabs(rw.hits[i].transmittance[k] - want[k]));
        worst_t = fmax(worst_t, d);
        t_close += d <= 1e-4;
    }
    printf("%-34s trace: %d of %d rays' transmittance within 1e-4; worst %.1e\n", c->name, t_close,
           TRACE_RAYS, worst_t);
    CHECK(t_close >= TRACE_RAYS - 2);
    scene_reference_free(&ref);
    free(rw.out.rgba);
}

#define CAMERA_A                                                                                   \
    "\"camera\": {\"eye\": [0.3, 0.8, 3.6], \"look_at\": [0, 0, 0], \"fov_y_deg\": 40, "           \
    "\"width\": 48, \"height\": 36}"
#define CAMERA_B                                                                                   \
    "\"camera\": {\"eye\": [0, 2.5, 3.5], \"look_at\": [0, -0.8, 0], \"fov_y_deg\": 40, "          \
    "\"width\": 48, \"height\": 36}"

int main(void)
{
    struct gpu *gpu = test_gpu_create("test_render_lights");
    /* Bounds measured on llvmpipe (see the printed lines: slab 100% within 1e-3, mean
     * 7e-7; receiver 100%, mean 1.5e-6; GGX sphere 99.4%, mean 3.4e-4); a hardware GPU's
     * arithmetic departs further from double (fused multiply-adds, 8-bit filter weights). */
    bool software = strstr(gpu_info(gpu)->renderer, "llvmpipe") != NULL;
    double close = software ? 0.99 : 0.95, mean = software ? 1e-4 : 1e-3;

    /* 1. A scattering slab n = 1.33, sigma_s (0.75, 0.5, 0.25), sigma_a 0.25, g = 0.5, in a
     * light volume whose irradiance varies across it; GGX faces. */
    struct lit_case slab = {
        .name = "scattering slab, HG g = 0.5", .close_fraction = close, .mean_bound = mean};
    slab.scene =
        parse_ok("{" CAMERA_A ", \"objects\": [{\"bounds\": {\"min\": [-1, -0.6, -1], "
                 "\"max\": [1, 0.6, 1]}, \"resolution\": [20, 12, 20], \"ior\": 1.33, "
                 "\"attenuation\": 0.25, \"scattering\": [0.75, 0.5, 0.25], "
                 "\"anisotropy\": 0.5, \"brdf\": {\"type\": \"ggx\", \"roughness\": 0.3}}]}");
    /* 2. A receiver plane under a glass ball, the volume with a bright spot on it; the ball
     * reflects the same volume with GGX. */
    struct lit_case recv = {
        .name = "receiver with a bright spot", .close_fraction = close, .mean_bound = mean};
    recv.scene =
        parse_ok("{" CAMERA_B ", \"objects\": [{\"bounds\": {\"min\": [-0.8, -0.8, "
                 "-0.8], \"max\": [0.8, 0.8, 0.8]}, \"resolution\": 24, "
                 "\"smoothing_sigma\": 1, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.6, "
                 "\"inside\": 1.5}, \"brdf\": {\"type\": \"ggx\", \"roughness\": 0.2}}], "
                 "\"receiver\": {\"height\": -1.2, \"half_size\": 2, \"center\": [0.25, "
                 "-0.5], \"albedo\": [0.8, 0.75, 0.5]}}");
    /* 2b. The same over an infinite receiver: beyond the volume (LIGHT_RECEIVER_INSET
     * voxels inside its faces) the plane shows the light's closed form, light_direct. */
    struct lit_case recv_inf = {
        .name = "infinite receiver", .close_fraction = close, .mean_bound = mean};
    recv_inf.scene =
        parse_ok("{" CAMERA_B ", \"objects\": [{\"bounds\": {\"min\": [-0.8, -0.8, "
                 "-0.8], \"max\": [0.8, 0.8, 0.8]}, \"resolution\": 24, "
                 "\"smoothing_sigma\": 1, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.6, "
                 "\"inside\": 1.5}, \"brdf\": {\"type\": \"ggx\", \"roughness\": 0.2}}], "
                 "\"receiver\": {\"height\": -1.2, \"half_size\": \"infinite\", \"albedo\": "
                 "[0.8, 0.75, 0.5]}}");
    /* 3. A GGX highlight on a glass sphere under a direct light (no light simulation).
     * Its curved surfaces are where float and double rays part at silhouettes and the
     * environment's grid lines (as in test_render_reference): a few pixels differ by up
     * to 0.5, which lifts the mean to 3.4e-4 on llvmpipe, so its mean bound is 1e-3. */
    struct lit_case ggx = {.name = "GGX highlight, direct light",
                           .close_fraction = close,
                           .mean_bound = software ? 1e-3 : 5e-3};
    ggx.scene = parse_ok("{" CAMERA_A ", \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], "
                         "\"max\": [1, 1, 1]}, \"resolution\": 32, \"smoothing_sigma\": 1, "
                         "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}, "
                         "\"brdf\": {\"type\": \"ggx\", \"color\": [1, 0.9, 0.8], "
                         "\"roughness\": 0.3}}]}");
    if (slab.scene && recv.scene && ggx.scene && recv_inf.scene) {
        CHECK(recv.scene->receiver.enabled && slab.scene->objects[0].brdf.kind == SCENE_BRDF_GGX);
        CHECK(scene_needs_light_simulation(slab.scene) && !scene_needs_light_simulation(ggx.scene));
        slab.light_count = recv.light_count = ggx.light_count = 1;
        slab.lights[0] = (struct scene_light){.kind = SCENE_LIGHT_DIRECTIONAL,
                                              .direction = vec3_normalize((vec3){0.3, -1, 0.2}),
                                              .color = {1, 1, 1},
                                              .intensity = 6};
        make_volume(&slab.volumes[0], (vec3){-1.5, -1.5, -1.5}, 0.25, 12, ramp_irradiance,
                    slab.lights[0].direction);
        recv.lights[0] = (struct scene_light){.kind = SCENE_LIGHT_DIRECTIONAL,
                                              .direction = {0, -1, 0},
                                              .color = {1, 1, 1},
                                              .intensity = 1};
        make_volume(&recv.volumes[0], (vec3){-2.5, -1.5, -2.5}, 0.25, 20, spot_irradiance,
                    vec3_normalize((vec3){0.1, -1, 0.05}));
        ggx.lights[0] = (struct scene_light){.kind = SCENE_LIGHT_DIRECTIONAL,
                                             .direction = vec3_normalize((vec3){-0.2, -0.5, -1}),
                                             .color = {1, 1, 1},
                                             .intensity = 40};
        compare(gpu, &slab);
        compare(gpu, &recv);
        recv_inf.light_count = 1;
        recv_inf.lights[0] = (struct scene_light){.kind = SCENE_LIGHT_POINT,
                                                  .position = {0.5, 3, 0.2},
                                                  .color = {1, 1, 1},
                                                  .intensity = 8};
        make_volume(&recv_inf.volumes[0], (vec3){-2.5, -1.5, -2.5}, 0.25, 20, spot_irradiance,
                    vec3_normalize((vec3){0.1, -1, 0.05}));
        compare(gpu, &recv_inf);
        compare(gpu, &ggx);
    }
    /* 4. Two direct lights, a spot and a point, on a Phong glass block holding an opaque
     * coloured ball (reflections at faces and at the opaque surface). The bottom rows see
     * the checkerboard through the block's edges, where float and double paths part (as in
     * test_render_reference's block with a ball: 96% there): 98.6% within 1e-3 measured. */
    struct lit_case multi = {.name = "spot + point, Phong, opaque",
                             .close_fraction = software ? 0.97 : 0.9,
                             .mean_bound = software ? 1e-3 : 5e-3};
    multi.scene = parse_ok("{" CAMERA_A ", \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], "
                           "\"max\": [1, 1, 1]}, \"resolution\": 24, \"ior\": 1.4, "
                           "\"opaque_ior\": 1.8, \"opaque\": {\"shape\": \"sphere\", \"radius\": "
                           "0.45, \"inside\": [0.8, 0.2, 0.1]}, \"brdf\": {\"type\": \"phong\", "
                           "\"exponent\": 40, \"color\": [1, 1, 0.5]}}]}");
    if (multi.scene) {
        CHECK(!scene_needs_light_simulation(multi.scene));
        multi.light_count = 2;
        multi.lights[0] = (struct scene_light){.kind = SCENE_LIGHT_SPOT,
                                               .position = {1.5, 3, 2.5},
                                               .direction = vec3_normalize((vec3){-1.5, -3, -2.5}),
                                               .spot_angle_deg = 25,
                                               .color = {1, 0.9, 0.7},
                                               .intensity = 600};
        multi.lights[1] = (struct scene_light){.kind = SCENE_LIGHT_POINT,
                                               .position = {-2, 1, 2},
                                               .color = {1, 1, 1},
                                               .intensity = 200};
        compare(gpu, &multi);
    }
    /* 5. Lamps (point lights with a radius, docs/tracing.md "Lamps"): one in view, seen by
     * camera rays, and one behind the glass sphere hidden from the camera but seen through
     * the sphere; GGX highlights of both. (The lamp's radiance against its closed form is
     * test_reftrace_light's; here the GPU against the twin.) */
    struct lit_case lamps = {.name = "lamps: seen, and hidden but refracted",
                             .close_fraction = close,
                             .mean_bound = software ? 1e-3 : 5e-3};
    lamps.scene = parse_ok("{" CAMERA_A ", \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], "
                           "\"max\": [1, 1, 1]}, \"resolution\": 32, \"smoothing_sigma\": 1, "
                           "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}, "
                           "\"brdf\": {\"type\": \"ggx\", \"roughness\": 0.3}}]}");
    if (lamps.scene) {
        lamps.light_count = 2;
        lamps.lights[0] = (struct scene_light){.kind = SCENE_LIGHT_POINT,
                                               .position = {-1.1, 0.7, 0.6},
                                               .color = {1, 0.8, 0.6},
                                               .intensity = 2,
                                               .radius = 0.15,
                                               .camera_visible = true};
        lamps.lights[1] = (struct scene_light){.kind = SCENE_LIGHT_POINT,
                                               .position = {-0.2, -0.1, -2.5},
                                               .color = {1, 1, 1},
                                               .intensity = 3,
                                               .radius = 0.4,
                                               .camera_visible = false};
        compare(gpu, &lamps);
        /* The visible lamp is in the picture: some pixel's ray aims at its centre. */
        const struct scene_camera *cam = &lamps.scene->camera;
        vec3 o, dir;
        int w = cam->width, h = cam->height, hits = 0;
        for (int row = 0; row < h; row++) {
            for (int col = 0; col < w; col++) {
                camera_ray(cam->eye, cam->look_at, cam->up, cam->fov_y_deg, w, h, col, row, &o,
                           &dir);
                vec3 to = vec3_normalize(vec3_sub(lamps.lights[0].position, o));
                hits += vec3_dot(to, dir) > cos(0.5 * M_PI / 180.0);
            }
        }
        CHECK_MSG(hits > 0, "the visible lamp is in view (%d pixels aimed at its centre)", hits);
    }
    /* 5. A glass box surface (n = 1.5) filled with a scattering constant medium (sigma_s
     * (0.75, 0.5, 0.25), sigma_a 0.1, g 0.4) in the ramp volume: in-scattering along the
     * surface segments (docs/tracing.md "Scattering inside surfaces") with refraction,
     * Fresnel and the basic-radiance factor. (A lone scattering sphere would get exact
     * single scattering instead, docs/walter.md: tests/gpu/test_render_walter.c.) */
    struct lit_case ball = {
        .name = "scattering medium in a glass box", .close_fraction = close, .mean_bound = mean};
    ball.scene = parse_ok("{" CAMERA_A ", \"surfaces\": [{\"shape\": \"box\", \"center\": "
                          "[0, 0, 0], \"size\": [1.5, 1.5, 1.5], \"medium\": {\"ior\": 1.5, "
                          "\"attenuation\": [0.1, 0.1, 0.1], \"scattering\": [0.75, 0.5, 0.25], "
                          "\"anisotropy\": 0.4}}]}");
    if (ball.scene) {
        CHECK(scene_needs_light_simulation(ball.scene));
        ball.light_count = 1;
        ball.lights[0] = (struct scene_light){.kind = SCENE_LIGHT_DIRECTIONAL,
                                              .direction = vec3_normalize((vec3){0.3, -1, 0.2}),
                                              .color = {1, 1, 1},
                                              .intensity = 20};
        make_volume(&ball.volumes[0], (vec3){-1.5, -1.5, -1.5}, 0.125, 24, ramp_irradiance,
                    ball.lights[0].direction);
        compare(gpu, &ball);
    }
    struct lit_case *cases[6] = {&slab, &recv, &recv_inf, &ggx, &multi, &ball};
    for (int i = 0; i < 6; i++) {
        for (int j = 0; j < SCENE_MAX_LIGHTS; j++) {
            free(cases[i]->volumes[j].irradiance);
            free(cases[i]->volumes[j].direction);
        }
        scene_destroy(cases[i]->scene);
    }
    gpu_destroy(gpu, NULL);
    return test_summary("test_render_lights");
}
