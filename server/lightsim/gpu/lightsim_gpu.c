/*
 * lightsim_gpu.c - a light-simulation run on the GPU: fields as 3D textures, the patch
 * lists and counters in storage buffers, one chain of dispatches per time step
 * (lightsim_step -> prefix sum -> lightsim_emit -> lightsim_args), all sized by
 * glDispatchComputeIndirect from GPU-written arguments; the host reads the counters back
 * once per lightsim_gpu_advance. See lightsim_gpu.h and docs/lightsim.md.
 */
#include "lightsim_gpu.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "../lightsim_init.h"
#include "lightsim_gpu_programs.h"
#include "lightsim_gpu_surfaces.h"
#include "lightsim_gpu_wavefront.h"

_Static_assert(sizeof(ls_gpu_patch) == 256, "ls_gpu_patch must match std430");
_Static_assert(sizeof(ls_control) == 80, "ls_control must match std430");
_Static_assert(sizeof(lightsim_params) == 96, "lightsim_params must match std140");

/* The run's buffers; DEPOSIT .. DEPOSIT + 5 are the deposit channels (irradiance rgb,
 * direction xyz), one buffer each so that 256^3 fits GL's guaranteed 128 MiB a block. */
enum {
    LIST_A,
    LIST_B,
    COUNTS,
    OFFSETS,
    BLOCK_SUMS,
    CONTROL, /* ls_control, then the step's float sums (LS_ACC_COUNT) */
    TOTALS,
    TWINS,    /* surface events' reflected twins, by live index */
    SURFACES, /* surface_params[] (uploaded, never cleared) */
    PROFILES, /* the lathes' profile points */
    MESHES,   /* the mesh surfaces' BVH nodes, triangles and vertices in one buffer */
    DEPOSIT,
    BUFFER_COUNT = DEPOSIT + LS_DEPOSIT_CHANNELS
};

struct lightsim_gpu_run {
    struct gpu_buffer buf[BUFFER_COUNT];
    struct gpu_buffer params;
    struct gpu_volume ior_grad, extinction;
    struct irradiance_gpu out; /* made when the run ends */
    bool have_out;
    int current; /* LIST_A or LIST_B: the live list */
    bool surfaces; /* the scene has exact surfaces: the LS_SURFACES kernels */
    bool meshes;   /* ... and mesh surfaces among them: the LS_MESHES kernels */
    struct light_grid grid;
    long long max_steps, steps_issued;
    double dt, t_sweep;
    struct lightsim_stats stats;
    double flux_dropped_initial[3];
    int culled_capacity_initial;
    size_t peak_bytes;
};

static enum refract_code upload_fields(struct lightsim_gpu_run *r, const struct lightsim_fields *f,
                                       struct err *e)
{
    const int *d = f->grid.dims;
    size_t n = (size_t)d[0] * d[1] * d[2];
    float *tmp = malloc(n * 4 * sizeof(float));
    if (tmp == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "no host memory to upload the light fields");
    struct gpu_volume_desc desc = {.label = "light grid ior+grad",
                                   .width = d[0],
                                   .height = d[1],
                                   .depth = d[2],
                                   .format = GPU_TEXEL_RGBA32F,
                                   .nearest = 1};
    enum refract_code rc = gpu_volume_create(&desc, &r->ior_grad, e);
    if (rc == REFRACT_E_OK) {
        for (size_t i = 0; i < n * 4; i++)
            tmp[i] = (float)f->ior_grad[i];
        rc = gpu_volume_upload(&r->ior_grad, 0, 0, 0, d[0], d[1], d[2], 4, tmp, e);
    }
    desc.label = "light grid extinction";
    if (rc == REFRACT_E_OK)
        rc = gpu_volume_create(&desc, &r->extinction, e);
    if (rc == REFRACT_E_OK) {
        for (size_t i = 0; i < n * 4; i++)
            tmp[i] = (float)f->extinction[i];
        rc = gpu_volume_upload(&r->extinction, 0, 0, 0, d[0], d[1], d[2], 4, tmp, e);
    }
    free(tmp);
    return rc;
}

static lightsim_params make_params(const struct lightsim_fields *f,
                                   const struct scene_lightsim *set, double dt, double energy_cut)
{
    const struct light_grid *g = &f->grid;
    lightsim_params p;
    memset(&p, 0, sizeof p);
    p.grid_min = (vec4){(float)g->bmin.x, (float)g->bmin.y, (float)g->bmin.z, (float)g->voxel};
    p.grid_max = (vec4){(float)(g->bmin.x + g->dims[0] * g->voxel),
                        (float)(g->bmin.y + g->dims[1] * g->voxel),
                        (float)(g->bmin.z + g->dims[2] * g->voxel), (float)dt};
    p.dims = (ivec4){g->dims[0], g->dims[1], g->dims[2],
                     set->deposit == SCENE_DEPOSIT_MAX ? LS_DEPOSIT_MAX : LS_DEPOSIT_FLUX};
    p.medium = (vec4){(float)f->ambient_ior, (float)f->probe_distance, (float)f->boundary_threshold,
                      (float)(set->split_voxels * g->voxel)};
    vec3 diag = vec3_scale((vec3){g->dims[0], g->dims[1], g->dims[2]}, g->voxel);
    p.cull = (vec4){(float)energy_cut, set->cull_flipped ? 1.0f : 0.0f, (float)vec3_length(diag),
                    0};
    p.limits = (ivec4){set->max_level, set->max_patches, lightsim_deposit_every(set),
                       f->surface_count};
    return p;
}

static enum refract_code finish(struct lightsim_gpu_run *r, const struct lightsim_gpu_programs *p,
                                struct err *e);

static int longest_axis(const struct light_grid *g)
{
    int m = g->dims[0];
    for (int a = 1; a < 3; a++)
        m = g->dims[a] > m ? g->dims[a] : m;
    return m;
}

static void bind_all(const struct lightsim_gpu_run *r)
{
    int in = r->current, out = r->current == LIST_A ? LIST_B : LIST_A;
    glBindBufferBase(GL_UNIFORM_BUFFER, BIND_UBO_LIGHTSIM, r->params.buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_PATCHES_IN, r->buf[in].buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_PATCHES_OUT, r->buf[out].buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_COUNTS, r->buf[COUNTS].buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_OFFSETS, r->buf[OFFSETS].buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_BLOCK_SUMS, r->buf[BLOCK_SUMS].buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_CONTROL, r->buf[CONTROL].buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_TOTALS, r->buf[TOTALS].buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_TWINS, r->buf[TWINS].buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_SURFACES, r->buf[SURFACES].buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_SURFACE_PROFILES, r->buf[PROFILES].buf);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_MESH_NODES, r->buf[MESHES].buf);
    for (int c = 0; c < LS_DEPOSIT_CHANNELS; c++)
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, BIND_SSBO_LS_DEPOSIT + c,
                         r->buf[DEPOSIT + c].buf);
    glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, r->buf[CONTROL].buf);
    glBindTextureUnit(UNIT_LS_IOR_GRAD, r->ior_grad.tex);
    glBindTextureUnit(UNIT_LS_EXTINCTION, r->extinction.tex);
}

enum refract_code lightsim_gpu_begin(struct gpu *gpu, const struct lightsim_fields *f,
                                     const struct scene_light *l, const struct scene_lightsim *set,
                                     struct lightsim_gpu_run **out, struct err *e)
{
    *out = NULL;
    enum refract_code rc = lightsim_gpu_init(gpu, e);
    if (rc != REFRACT_E_OK)
        return rc;
    if (set->max_patches < 1 || set->max_patches > LS_MAX_PATCHES)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "lightsim.max_patches: %d is out of range; use 1..%d", set->max_patches,
                       LS_MAX_PATCHES);
    struct lightsim_gpu_run *r = calloc(1, sizeof *r);
    if (r == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "no host memory for a light simulation run");
    r->grid = f->grid;
    r->current = LIST_A;
    r->surfaces = f->surface_count > 0;
    r->meshes = f->mesh_count > 0;
    struct lightsim_wavefront w;
    rc = lightsim_wavefront_build(f, l, set, &w, e);
    if (rc != REFRACT_E_OK) {
        free(r);
        return rc;
    }
    r->dt = set->step_voxels * f->grid.voxel;
    ls_step_budget(f, r->dt, &r->max_steps, &r->t_sweep);

    size_t cap = (size_t)set->max_patches;
    size_t blocks = (cap + LS_SCAN_BLOCK - 1) / LS_SCAN_BLOCK;
    size_t voxels = (size_t)f->grid.dims[0] * f->grid.dims[1] * f->grid.dims[2];
    struct {
        ls_control c;
        float accum[LS_ACC_COUNT]; /* zero: the sums of the first step */
    } control_block;
    memset(&control_block, 0, sizeof control_block);
    ls_control control;
    memset(&control, 0, sizeof control);
    control.dispatch_patches = (ivec4){(w.count + LS_LOCAL_X - 1) / LS_LOCAL_X, 1, 1, 0};
    control.dispatch_blocks = (ivec4){(w.count + LS_SCAN_BLOCK - 1) / LS_SCAN_BLOCK, 1, 1, 0};
    control.counts = (ivec4){w.count, 0, 0, w.count};
    lightsim_params params = make_params(f, set, r->dt, set->energy_threshold * w.mean_max_power);
    control_block.c = control;
    surface_params *surfs = NULL;
    float *points = NULL;
    size_t point_count = 0;
    void *mesh_data = NULL;
    size_t mesh_records = 0;
    if (!lightsim_gpu_pack_surfaces(f, &surfs, &points, &point_count, &mesh_data,
                                    &mesh_records)) {
        lightsim_wavefront_free(&w);
        free(r);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "no host memory to pack the surfaces");
    }
    size_t twins = f->surface_count > 0 ? cap : 1; /* only surface events make twins */
    struct {
        const char *label;
        size_t bytes;
        const void *data;
    } bufs[BUFFER_COUNT] = {
        [LIST_A] = {"lightsim patches A", cap * sizeof(ls_gpu_patch), NULL},
        [LIST_B] = {"lightsim patches B", cap * sizeof(ls_gpu_patch), NULL},
        [COUNTS] = {"lightsim counts", cap * sizeof(uint32_t), NULL},
        [OFFSETS] = {"lightsim offsets", cap * sizeof(uint32_t), NULL},
        [BLOCK_SUMS] = {"lightsim block sums", blocks * sizeof(uint32_t), NULL},
        [CONTROL] = {"lightsim control and step sums",
                     sizeof control + LS_ACC_COUNT * sizeof(float), &control_block},
        [TOTALS] = {"lightsim totals", LS_TOT_COUNT * sizeof(double), NULL},
        [TWINS] = {"lightsim twins", twins * sizeof(ls_gpu_patch), NULL},
        [SURFACES] = {"lightsim surfaces",
                      (f->surface_count > 0 ? (size_t)f->surface_count : 1) * sizeof *surfs,
                      surfs},
        [PROFILES] = {"lightsim surface profiles",
                      (point_count ? point_count : 1) * 2 * sizeof *points, points},
        [MESHES] = {"lightsim mesh surfaces", mesh_records * 16, mesh_data},
        [DEPOSIT] = {"lightsim deposit irradiance r", voxels * sizeof(float), NULL},
        [DEPOSIT + 1] = {"lightsim deposit irradiance g", voxels * sizeof(float), NULL},
        [DEPOSIT + 2] = {"lightsim deposit irradiance b", voxels * sizeof(float), NULL},
        [DEPOSIT + 3] = {"lightsim deposit direction x", voxels * sizeof(float), NULL},
        [DEPOSIT + 4] = {"lightsim deposit direction y", voxels * sizeof(float), NULL},
        [DEPOSIT + 5] = {"lightsim deposit direction z", voxels * sizeof(float), NULL},
    };
    GLint64 max_block = 0;
    glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &max_block);
    for (int i = 0; i < BUFFER_COUNT; i++) {
        if (max_block <= 0 || bufs[i].bytes <= (size_t)max_block)
            continue;
        if (i == MESHES)
            rc = err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                         "lightsim: the mesh surfaces' hierarchies, triangles and vertices would "
                         "need %zu bytes (about 45 a triangle), more than this GPU's largest "
                         "storage block (%lld bytes); use meshes with fewer triangles",
                         bufs[i].bytes, (long long)max_block);
        else
            rc = err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                         "lightsim: the %s buffer would need %zu bytes, more than this GPU's "
                         "largest storage block (%lld bytes); lower lightsim.resolution (now %d "
                         "voxels on the longest axis) or lightsim.max_patches (now %d)",
                         bufs[i].label, bufs[i].bytes, (long long)max_block, longest_axis(&f->grid),
                         set->max_patches);
    }
    for (int i = 0; i < BUFFER_COUNT && rc == REFRACT_E_OK; i++)
        rc = gpu_buffer_create(bufs[i].label, bufs[i].bytes, bufs[i].data, &r->buf[i], e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("lightsim params", sizeof params, &params, &r->params, e);
    if (rc == REFRACT_E_OK)
        rc = upload_fields(r, f, e);
    if (rc == REFRACT_E_OK) {
        uint32_t zero = 0;
        for (int i = TOTALS; i < BUFFER_COUNT; i++)
            if (i != SURFACES && i != PROFILES && i != MESHES)
                glClearNamedBufferData(r->buf[i].buf, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT,
                                       &zero);
        if (w.count > 0)
            glNamedBufferSubData(r->buf[LIST_A].buf, 0,
                                 (GLsizeiptr)(w.count * sizeof(ls_gpu_patch)), w.patches);
        rc = gpu_check("starting a light simulation", e);
    }
    if (rc == REFRACT_E_OK) {
        struct lightsim_stats *s = &r->stats;
        for (int ch = 0; ch < 3; ch++) {
            s->flux_in[ch] = w.flux_in[ch];
            s->flux_live[ch] = w.flux_in[ch] - w.flux_dropped[ch];
            s->flux_culled[ch] = w.flux_dropped[ch];
            r->flux_dropped_initial[ch] = w.flux_dropped[ch];
        }
        r->culled_capacity_initial = w.kept - w.count;
        s->culled_capacity = r->culled_capacity_initial;
        s->patches_initial = w.kept;
        s->patches_live = w.count;
        s->patches_peak = w.count;
        s->done = w.count == 0;
        s->progress = s->done ? 1 : 0;
    }
    lightsim_wavefront_free(&w);
    free(surfs);
    free(points);
    free(mesh_data);
    r->peak_bytes = lightsim_gpu_run_bytes(r);
    if (rc == REFRACT_E_OK && r->stats.done) /* nothing aimed at the domain: dark volumes */
        rc = finish(r, lightsim_gpu_programs(), e);
    if (rc != REFRACT_E_OK) {
        lightsim_gpu_run_destroy(r);
        return rc;
    }
    *out = r;
    return REFRACT_E_OK;
}

/* Records one time step; its sizes come from the control buffer. */
static void record_step(struct lightsim_gpu_run *r, const struct lightsim_gpu_programs *p)
{
    const GLintptr patches = (GLintptr)offsetof(ls_control, dispatch_patches);
    const GLbitfield barrier = GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT;
    bind_all(r);
    glUseProgram(r->meshes ? p->step_meshes : r->surfaces ? p->step_surfaces : p->step);
    glDispatchComputeIndirect(patches);
    glMemoryBarrier(barrier);
    lightsim_gpu_scan_record(p);
    glUseProgram(r->meshes ? p->emit_meshes : r->surfaces ? p->emit_surfaces : p->emit);
    glDispatchComputeIndirect(patches);
    glMemoryBarrier(barrier);
    glUseProgram(p->args);
    glDispatchCompute(1, 1, 1);
    glMemoryBarrier(barrier);
    r->current = r->current == LIST_A ? LIST_B : LIST_A;
}

/* Reads the counters and totals into r->stats. */
static enum refract_code read_stats(struct lightsim_gpu_run *r, struct err *e)
{
    ls_control control;
    double tot[LS_TOT_COUNT];
    enum refract_code rc = gpu_buffer_read(&r->buf[CONTROL], &control, sizeof control, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_read(&r->buf[TOTALS], tot, sizeof tot, e);
    if (rc != REFRACT_E_OK)
        return rc;
    struct lightsim_stats *s = &r->stats;
    for (int ch = 0; ch < 3; ch++) {
        s->flux_out[ch] = tot[LS_ACC_OUT + ch];
        s->flux_reflected[ch] = tot[LS_ACC_REFLECTED + ch];
        s->flux_absorbed[ch] = tot[LS_ACC_ABSORBED + ch];
        s->flux_culled[ch] = tot[LS_ACC_CULLED + ch] + r->flux_dropped_initial[ch];
        if (control.counts.z > 0) /* else still the initial list's power */
            s->flux_live[ch] = tot[LS_ACC_LIVE + ch];
    }
    s->steps = control.counts.z;
    s->patch_steps = (long long)tot[LS_TOT_PATCH_STEPS];
    s->splits = (long long)tot[LS_TOT_SPLITS];
    s->culled_energy = (long long)tot[LS_TOT_CULLED_ENERGY];
    s->culled_level = (long long)tot[LS_TOT_CULLED_LEVEL];
    s->culled_flip = (long long)tot[LS_TOT_CULLED_FLIP];
    s->culled_capacity = (long long)tot[LS_TOT_CULLED_CAPACITY] + r->culled_capacity_initial;
    s->patches_live = control.counts.x;
    s->patches_peak = control.counts.w;
    return REFRACT_E_OK;
}

/* The deposit buffer into the two output textures. */
static enum refract_code finish(struct lightsim_gpu_run *r, const struct lightsim_gpu_programs *p,
                                struct err *e)
{
    const int *d = r->grid.dims;
    enum refract_code rc = irradiance_gpu_create(&r->grid, &r->out, e);
    if (rc != REFRACT_E_OK)
        return rc;
    bind_all(r);
    glBindImageTexture(IMAGE_LS_IRRADIANCE, r->out.irradiance.tex, 0, GL_TRUE, 0, GL_WRITE_ONLY,
                       GL_RGBA32F);
    glBindImageTexture(IMAGE_LS_DIRECTION, r->out.direction.tex, 0, GL_TRUE, 0, GL_WRITE_ONLY,
                       GL_RGBA16F);
    glUseProgram(p->finish);
    glDispatchCompute(gpu_groups(d[0], VOLUME_LOCAL_X), gpu_groups(d[1], VOLUME_LOCAL_Y),
                      gpu_groups(d[2], VOLUME_LOCAL_Z));
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT |
                    GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    rc = gpu_check("writing the irradiance volume", e);
    if (rc != REFRACT_E_OK) {
        irradiance_gpu_free(&r->out);
        return rc;
    }
    r->peak_bytes = lightsim_gpu_run_bytes(r);
    r->have_out = true;
    /* The deposit and the patch lists are not needed any more. */
    for (int i = 0; i < BUFFER_COUNT; i++)
        if (i != CONTROL && i != TOTALS)
            gpu_buffer_destroy(&r->buf[i]);
    gpu_volume_destroy(&r->ior_grad);
    gpu_volume_destroy(&r->extinction);
    return REFRACT_E_OK;
}

enum refract_code lightsim_gpu_advance(struct lightsim_gpu_run *run, int max_steps, bool *done,
                                       struct err *e)
{
    *done = run->stats.done;
    if (run->stats.done)
        return REFRACT_E_OK;
    const struct lightsim_gpu_programs *p = lightsim_gpu_programs();
    long long steps_now = run->max_steps - run->steps_issued;
    if (max_steps > 0 && max_steps < steps_now)
        steps_now = max_steps;
    for (long long i = 0; i < steps_now; i++)
        record_step(run, p);
    run->steps_issued += steps_now;
    enum refract_code rc = gpu_check("a light simulation step", e);
    if (rc == REFRACT_E_OK)
        rc = read_stats(run, e);
    if (rc != REFRACT_E_OK)
        return rc;
    struct lightsim_stats *s = &run->stats;
    s->done = s->patches_live == 0 || run->steps_issued >= run->max_steps;
    s->progress = s->done ? 1 : fmin(0.99, s->steps * run->dt / run->t_sweep); /* 1 = done */
    if (s->done)
        rc = finish(run, p, e);
    *done = s->done;
    return rc;
}

void lightsim_gpu_stats(const struct lightsim_gpu_run *run, struct lightsim_stats *out)
{
    *out = run->stats;
}

enum refract_code lightsim_gpu_read(struct lightsim_gpu_run *run, struct irradiance_volume *out,
                                    struct err *e)
{
    memset(out, 0, sizeof *out);
    if (!run->have_out)
        return err_set(e, REFRACT_E_CONFLICT,
                       "the light simulation has not finished (or its volumes were taken); "
                       "advance it until done");
    const int *d = run->grid.dims;
    size_t n = (size_t)d[0] * d[1] * d[2] * 4;
    out->grid = run->grid;
    out->stats = run->stats;
    out->irradiance = malloc(n * sizeof(float));
    out->direction = malloc(n * sizeof(float));
    if (out->irradiance == NULL || out->direction == NULL) {
        irradiance_volume_free(out);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "no host memory for an irradiance volume");
    }
    glGetTextureImage(run->out.irradiance.tex, 0, GL_RGBA, GL_FLOAT, (GLsizei)(n * sizeof(float)),
                      out->irradiance);
    glGetTextureImage(run->out.direction.tex, 0, GL_RGBA, GL_FLOAT, (GLsizei)(n * sizeof(float)),
                      out->direction);
    enum refract_code rc = gpu_check("reading an irradiance volume back", e);
    if (rc != REFRACT_E_OK)
        irradiance_volume_free(out);
    return rc;
}

enum refract_code lightsim_gpu_take_textures(struct lightsim_gpu_run *run,
                                             struct irradiance_gpu *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    if (!run->have_out)
        return err_set(e, REFRACT_E_CONFLICT,
                       "the light simulation has not finished (or its volumes were taken); "
                       "advance it until done");
    *out = run->out;
    memset(&run->out, 0, sizeof run->out);
    run->have_out = false;
    return REFRACT_E_OK;
}

size_t lightsim_gpu_run_bytes(const struct lightsim_gpu_run *run)
{
    size_t bytes = run->params.bytes + run->ior_grad.bytes + run->extinction.bytes + run->out.bytes;
    for (int i = 0; i < BUFFER_COUNT; i++)
        bytes += run->buf[i].bytes;
    return bytes;
}

size_t lightsim_gpu_run_peak_bytes(const struct lightsim_gpu_run *run)
{
    return run->peak_bytes;
}

void lightsim_gpu_run_destroy(struct lightsim_gpu_run *run)
{
    if (run == NULL)
        return;
    for (int i = 0; i < BUFFER_COUNT; i++)
        gpu_buffer_destroy(&run->buf[i]);
    gpu_buffer_destroy(&run->params);
    gpu_volume_destroy(&run->ior_grad);
    gpu_volume_destroy(&run->extinction);
    irradiance_gpu_free(&run->out);
    free(run);
}
