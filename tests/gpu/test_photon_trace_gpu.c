/*
 * test_photon_trace_gpu.c - caustic photons traced on the GPU (shaders/photon_trace.comp)
 * against closed forms and against the CPU double tracer (core/photon_trace.c):
 *   - the glass slab under a directional light transmits its series
 *     (1 - R)^2 tau / (1 - R^2 tau^2) per channel (as tests/unit/test_photon.c for the CPU);
 *   - scene A's ball under its spherical lamp: the GPU's and the CPU's kernel estimates at
 *     points over the caustic agree within 4 combined standard errors plus 1 % (the two use
 *     different random numbers: they agree in distribution, not photon for photon), and so
 *     do the landed powers;
 *   - a mesh surface is refused (the caller traces such scenes on the CPU).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/photon.h"
#include "gpu/queue.h"
#include "render/photon_trace_gpu.h"
#include "gpu_test_util.h"
#include "unit/pathtrace_test_util.h"
#include "test.h"

struct trace_work {
    struct gpu_work work;
    const struct pathtrace_scene *scene;
    long count;
    struct photon_list list;
    enum refract_code rc;
};

static void trace_run(struct gpu_work *w, struct gpu *gpu)
{
    (void)gpu;
    struct trace_work *t = w->user;
    t->rc = photon_trace_gpu(t->scene, t->count, 7, &t->list, &w->err);
}

static enum refract_code trace(struct gpu *gpu, const struct pathtrace_scene *s, long count,
                               struct photon_list *out, struct err *e)
{
    struct trace_work t = {.scene = s, .count = count};
    t.work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = trace_run, .user = &t};
    if (gpu_run_sync(gpu, &t.work) != REFRACT_E_OK && t.rc == REFRACT_E_OK)
        t.rc = t.work.err.code;
    if (t.rc != REFRACT_E_OK)
        printf("photon_trace_gpu: %s\n", t.work.err.msg);
    *out = t.list;
    if (e)
        *e = t.work.err;
    return t.rc;
}

static void slab_transmits_its_series(struct gpu *gpu)
{
    const double n = 2.42, h = 0.2, sigma[3] = {0.0, 0.5, 2.0};
    struct pathtrace_surface slab = pt_box(vec3_make(0, 1, 0), vec3_make(4, h, 4), n);
    memcpy(slab.medium.sigma_a, sigma, sizeof sigma);
    struct pathtrace_scene s = pt_scene(0.0);
    s.surfaces = &slab;
    s.surface_count = 1;
    s.receiver = (struct pathtrace_receiver){true, 0.0, INFINITY, {0.8, 0.8, 0.8}, {0, 0}};
    s.lights[0] = (struct pathtrace_light){
        .kind = PATHTRACE_LIGHT_DIRECTIONAL, .direction = {0, -1, 0}, .value = {1, 1, 1}};
    s.light_count = 1;
    struct photon_list l;
    CHECK_INT(trace(gpu, &s, 400000, &l, NULL), REFRACT_E_OK);
    CHECK_INT((int)l.emitted, 400000);
    double E[3], se[3], R = ((n - 1) / (n + 1)) * ((n - 1) / (n + 1));
    photon_kernel_estimate_se(&l, 1.0, 0.0, 0.0, E, se);
    for (int c = 0; c < 3; c++) {
        double tau = exp(-sigma[c] * h);
        double expect = (1 - R) * (1 - R) * tau / (1 - R * R * tau * tau);
        printf("slab n %.2f channel %d: GPU photons E %.5f, series %.5f (se %.1e)\n", n, c, E[c],
               expect, se[c]);
        CHECK_MSG(fabs(E[c] - expect) <= fmin(4.0 * se[c], 0.015 * expect), "channel %d", c);
        CHECK(l.lost[c] <= 1e-6 * l.landed[c]);
    }
    photon_list_free(&l);
}

static void scene_a_agrees_with_the_cpu(struct gpu *gpu)
{
    struct pathtrace_surface ball;
    struct pathtrace_scene s = pt_scene_a(&ball);
    const long count = 1048576;
    struct photon_list g, c = {0};
    struct err e;
    CHECK_INT(trace(gpu, &s, count, &g, NULL), REFRACT_E_OK);
    CHECK_INT(photon_trace(&s, count, 3, 0, 1, &c, &e), REFRACT_E_OK);
    printf("scene A: GPU %zu photons landed, %.4f W; CPU %zu, %.4f W\n", g.count, g.landed[0],
           c.count, c.landed[0]);
    CHECK_MSG(fabs(g.landed[0] - c.landed[0]) <= 0.01 * c.landed[0], "landed power");
    int compared = 0, agree = 0;
    double r = 0.05;
    for (int i = 0; i < 40; i++) {
        double x = -0.75 + 0.02 * i, z = -0.1 - 0.5 * (x + 0.33);
        double Eg[3], sg[3], Ec[3], sc[3];
        photon_kernel_estimate_se(&g, r, x, z, Eg, sg);
        photon_kernel_estimate_se(&c, r, x, z, Ec, sc);
        if (Ec[0] < 1.0)
            continue; /* the caustic only */
        compared++;
        bool ok = fabs(Eg[0] - Ec[0]) <= 4.0 * sqrt(sg[0] * sg[0] + sc[0] * sc[0]) + 0.01 * Ec[0];
        agree += ok;
        if (!ok)
            printf("  (%.2f, %.3f): GPU %.3f +- %.3f, CPU %.3f +- %.3f\n", x, z, Eg[0], sg[0],
                   Ec[0], sc[0]);
    }
    printf("scene A: %d of %d points over the caustic agree\n", agree, compared);
    CHECK(compared >= 10);
    CHECK_MSG(agree >= compared - 1, "%d of %d", agree, compared);
    photon_list_free(&g);
    photon_list_free(&c);
}

static void meshes_are_refused(struct gpu *gpu)
{
    struct pathtrace_surface m = pt_sphere(vec3_make(0, 0, 0), 1.0, 1.5);
    m.geom.kind = GEOM_MESH;
    struct pathtrace_scene s = pt_scene(0.0);
    s.surfaces = &m;
    s.surface_count = 1;
    s.receiver = (struct pathtrace_receiver){true, -1.0, INFINITY, {0.8, 0.8, 0.8}, {0, 0}};
    s.light_count = 1;
    struct photon_list l;
    struct err e;
    CHECK_INT(trace(gpu, &s, 1000, &l, &e), REFRACT_E_CONFLICT);
    CHECK_CONTAINS(e.msg, "mesh");
    photon_list_free(&l);
}

int main(void)
{
    struct gpu *gpu = test_gpu_create("test_photon_trace_gpu");
    slab_transmits_its_series(gpu);
    scene_a_agrees_with_the_cpu(gpu);
    meshes_are_refused(gpu);
    gpu_destroy(gpu, NULL);
    return test_summary("test_photon_trace_gpu");
}
