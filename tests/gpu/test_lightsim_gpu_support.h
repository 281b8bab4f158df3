/*
 * test_lightsim_gpu_support.h - what the light-simulator GPU tests share: analytic light
 * fields built by hand on a struct lightsim_fields (index and extinction at the voxel
 * centres, the gradient by docs/lightsim.md "Fields" step 3), the GPU thread, and one
 * whole GPU run as a work item. Header-only (static functions) for the test executables.
 */
#ifndef REFRACT_TEST_LIGHTSIM_GPU_SUPPORT_H
#define REFRACT_TEST_LIGHTSIM_GPU_SUPPORT_H

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "gpu/queue.h"
#include "lightsim/gpu/lightsim_gpu.h"
#include "test.h"

/* n and (sigma_t rgb, coverage) at a world point. */
typedef void (*test_field_fn)(vec3 x, const void *ctx, double *n, double ext[4]);

/* A cubic grid of `res` voxels per axis centred at the origin, `voxel` world units each. */
static inline void test_fields_make(struct lightsim_fields *f, const int dims[3], double voxel,
                                    double ambient, test_field_fn fn, const void *ctx)
{
    memset(f, 0, sizeof *f);
    f->grid.dims[0] = dims[0];
    f->grid.dims[1] = dims[1];
    f->grid.dims[2] = dims[2];
    f->grid.voxel = voxel;
    f->grid.bmin =
        vec3_make(-0.5 * dims[0] * voxel, -0.5 * dims[1] * voxel, -0.5 * dims[2] * voxel);
    f->ambient_ior = ambient;
    f->boundary_threshold = 0.02;
    f->probe_distance = 3 * voxel + 2 * voxel; /* sigma = 1 voxel of smoothing */
    size_t n = (size_t)dims[0] * dims[1] * dims[2];
    f->ior_grad = calloc(n * 4, sizeof(double));
    f->extinction = calloc(n * 4, sizeof(double));
    for (int k = 0; k < dims[2]; k++)
        for (int j = 0; j < dims[1]; j++)
            for (int i = 0; i < dims[0]; i++) {
                size_t v = ((size_t)k * dims[1] + j) * dims[0] + i;
                vec3 x = vec3_madd(f->grid.bmin, vec3_make(i + 0.5, j + 0.5, k + 0.5), voxel);
                fn(x, ctx, &f->ior_grad[4 * v + 3], &f->extinction[4 * v]);
            }
    /* Central differences, one-sided at the faces, world units. */
    for (int k = 0; k < dims[2]; k++)
        for (int j = 0; j < dims[1]; j++)
            for (int i = 0; i < dims[0]; i++) {
                int c[3] = {i, j, k};
                size_t v = ((size_t)k * dims[1] + j) * dims[0] + i;
                for (int a = 0; a < 3; a++) {
                    int lo[3] = {i, j, k}, hi[3] = {i, j, k};
                    lo[a] = c[a] > 0 ? c[a] - 1 : 0;
                    hi[a] = c[a] < dims[a] - 1 ? c[a] + 1 : dims[a] - 1;
                    int span = hi[a] - lo[a];
                    size_t vl = ((size_t)lo[2] * dims[1] + lo[1]) * dims[0] + lo[0];
                    size_t vh = ((size_t)hi[2] * dims[1] + hi[1]) * dims[0] + hi[0];
                    f->ior_grad[4 * v + a] =
                        span > 0
                            ? (f->ior_grad[4 * vh + 3] - f->ior_grad[4 * vl + 3]) / (span * voxel)
                            : 0;
                }
            }
}

static inline void test_fields_free(struct lightsim_fields *f)
{
    free(f->ior_grad);
    free(f->extinction);
    f->ior_grad = f->extinction = NULL;
}

/* Settings for tests: the scene defaults with the closed forms' needs. */
static inline struct scene_lightsim test_lightsim_settings(int initial_patches)
{
    struct scene_lightsim s = {.resolution = 32,
                               .step_voxels = 0.5,
                               .initial_patches = initial_patches,
                               .max_level = 6,
                               .split_voxels = 1,
                               .energy_threshold = 0,
                               .point_radius = 0.01,
                               .deposit = SCENE_DEPOSIT_FLUX,
                               .cull_flipped = false,
                               .max_patches = 262144};
    return s;
}

static inline struct gpu *test_start_gpu(const char *name)
{
    struct gpu_desc desc = {.context = {.device = GPU_DEVICE_AUTO, .device_index = -1}};
    struct err e = {0};
    struct gpu *g = gpu_create(&desc, &e);
    if (g == NULL) {
        fprintf(stderr, "gpu_create failed: %s\n", e.msg);
        test_setup_failed(name, "no EGL/GL 4.5 context could be made on this machine");
    }
    return g;
}

/* One whole run on the GPU thread: begin, advance in chunks until done, read back. */
struct test_gpu_run {
    struct gpu_work work;
    const struct lightsim_fields *fields;
    struct scene_light light;
    struct scene_lightsim set;
    int chunk; /* steps per advance */
    struct irradiance_volume out;
    size_t peak_bytes;
    double ms; /* wall time of the run, glFinish included */
    int chunks;
};

static inline void test_gpu_run_work(struct gpu_work *w, struct gpu *gpu)
{
    struct test_gpu_run *t = w->user;
    if (lightsim_gpu_init(gpu, &w->err) != REFRACT_E_OK)
        return;
    glFinish();
    double t0 = gpu_time_ms();
    struct lightsim_gpu_run *run = NULL;
    if (lightsim_gpu_begin(gpu, t->fields, &t->light, &t->set, &run, &w->err) != REFRACT_E_OK)
        return;
    bool done = false;
    while (!done) {
        t->chunks++;
        if (lightsim_gpu_advance(run, t->chunk, &done, &w->err) != REFRACT_E_OK)
            break;
    }
    glFinish();
    t->ms = gpu_time_ms() - t0;
    t->peak_bytes = lightsim_gpu_run_peak_bytes(run);
    if (done)
        lightsim_gpu_read(run, &t->out, &w->err);
    lightsim_gpu_run_destroy(run);
}

static inline enum refract_code test_gpu_simulate(struct gpu *g, struct test_gpu_run *t)
{
    t->work.priority = GPU_PRIORITY_LIGHTSIM;
    t->work.label = "lightsim test run";
    t->work.run = test_gpu_run_work;
    t->work.user = t;
    if (t->chunk == 0)
        t->chunk = 64;
    enum refract_code rc = gpu_run_sync(g, &t->work);
    if (rc != REFRACT_E_OK)
        fprintf(stderr, "GPU light simulation failed: %s\n", t->work.err.msg);
    return rc;
}

static inline struct scene_light test_directional(double x, double y, double z)
{
    struct scene_light l = {.kind = SCENE_LIGHT_DIRECTIONAL, .color = {1, 1, 1}, .intensity = 1};
    l.direction = vec3_normalize(vec3_make(x, y, z));
    return l;
}

static inline struct scene_light test_point(double x, double y, double z)
{
    struct scene_light l = {.kind = SCENE_LIGHT_POINT, .color = {1, 1, 1}, .intensity = 1};
    l.position = vec3_make(x, y, z);
    l.direction = vec3_make(0, -1, 0);
    return l;
}

/* flux_in - (out + reflected + absorbed + culled + live), relative to flux_in, channel r. */
static inline double test_bookkeeping_residual(const struct lightsim_stats *s, int ch)
{
    double sum = s->flux_out[ch] + s->flux_reflected[ch] + s->flux_absorbed[ch] +
                 s->flux_culled[ch] + s->flux_live[ch];
    return fabs(s->flux_in[ch] - sum) / s->flux_in[ch];
}

#endif
