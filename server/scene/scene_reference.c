/*
 * scene_reference.c - building reference-tracer objects from a scene; see
 * scene_reference.h. Used by tests and benchmarks, never by the daemon's request path.
 */
#include "scene_reference.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../core/half_float.h"
#include "../core/reftrace_integrate.h"
#include "../core/smooth.h"

static double analytic_profile(void *ctx, vec3 p, vec3 *grad)
{
    return grin_ior(ctx, p, grad);
}

static double analytic_constant(void *ctx, vec3 p, vec3 *grad)
{
    (void)p;
    *grad = (vec3){0, 0, 0};
    return *(const double *)ctx;
}

enum reftrace_stepper scene_reference_stepper(enum scene_stepper i)
{
    switch (i) {
    case SCENE_STEPPER_EULER:
        return REFTRACE_EULER;
    case SCENE_STEPPER_RK2:
        return REFTRACE_RK2;
    case SCENE_STEPPER_ADAPTIVE:
        return REFTRACE_BS23;
    case SCENE_STEPPER_RK4:
        break;
    }
    return REFTRACE_RK4;
}

static void fill_settings(const struct scene *s, struct reftrace_settings *st)
{
    memset(st, 0, sizeof *st);
    st->stepper = scene_reference_stepper(s->render.stepper);
    st->tolerance_voxels = s->render.tolerance_voxels;
    st->step_voxels = s->render.step_voxels;
    st->max_steps = s->render.max_steps;
    st->boundary_threshold = s->render.boundary_threshold;
    st->ambient_ior = s->ambient_ior;
    st->tolerance = 1e-9;
    st->env_intensity = s->environment.intensity;
    st->empty_space_skipping = s->render.empty_space_skipping;
    /* render.min_throughput 0 means never; the reference's 0 means its default. */
    st->min_throughput = s->render.min_throughput > 0.0 ? s->render.min_throughput : -1.0;
}

static const double *texel(const double *channel, size_t v)
{
    return channel ? channel + v * 4 : NULL;
}

/* Object i's empty-space map from its voxel fields (macrocell.h), as scene_gpu.c builds
 * the GPU's from the atlases. */
static enum refract_code build_cells(struct scene_reference *r, int i, int cell, struct err *e)
{
    const struct reftrace_grid *g = &r->grids[i];
    const struct reftrace_object *o = &r->objects[i];
    size_t voxels = (size_t)o->res[0] * o->res[1] * o->res[2];
    vec3 vs = reftrace_voxel_size(o);
    double h_min = fmin(vs.x, fmin(vs.y, vs.z));
    double *n = malloc(voxels * sizeof *n);
    uint8_t *busy = malloc(voxels);
    enum refract_code rc = REFRACT_E_OK;
    macrocell_free(&r->cells[i]);
    if (n == NULL || busy == NULL)
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the empty-space map");
    for (size_t v = 0; rc == REFRACT_E_OK && v < voxels; v++) {
        n[v] = g->ior_grad[v * 4 + 3];
        busy[v] = macrocell_voxel_busy(g->ior_grad + v * 4, h_min, texel(g->attenuation, v),
                                       texel(g->emission, v), texel(g->opaque, v),
                                       texel(g->scattering, v));
    }
    if (rc == REFRACT_E_OK)
        /* The sampling footprint beyond a cell: a tricubic index reads two texels out. */
        rc = macrocell_build(n, busy, o->res, cell,
                             o->ior_filter == REFTRACE_FILTER_TRICUBIC ? MACROCELL_BORDER_TRICUBIC
                                                                       : MACROCELL_BORDER_TRILINEAR,
                             &r->cells[i], e);
    r->objects[i].cells = rc == REFRACT_E_OK ? &r->cells[i] : NULL;
    free(n);
    free(busy);
    return rc;
}

enum refract_code scene_reference_set_cells(struct scene_reference *r, int cell, struct err *e)
{
    enum refract_code rc = REFRACT_E_OK;
    for (int i = 0; rc == REFRACT_E_OK && i < r->count; i++)
        if (r->objects[i].grid != NULL)
            rc = build_cells(r, i, cell, e);
    return rc;
}

static enum refract_code build_analytic(struct scene_reference *r, size_t i,
                                        const struct scene_object *o, double ambient_ior,
                                        struct err *e)
{
    const struct scene_field *f = &o->fields[SCENE_CH_IOR];
    for (int ch = SCENE_CH_ATTENUATION; ch < SCENE_CH_COUNT; ch++) {
        if (o->fields[ch].count > 0)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "objects[%zu]: the analytic reference handles ior only, not %s", i,
                           scene_channel_name((enum scene_channel)ch));
    }
    struct reftrace_object *ro = &r->objects[i];
    if (f->count == 1 && f->layers[0].kind == SCENE_LAYER_PROFILE) {
        r->profiles[i] = f->layers[0].profile;
        ro->ior = analytic_profile;
        ro->ior_ctx = &r->profiles[i];
        return REFRACT_E_OK;
    }
    if (f->count <= 1 && (f->count == 0 || f->layers[0].kind == SCENE_LAYER_CONSTANT)) {
        r->constants[i] = f->count == 0 ? ambient_ior : f->layers[0].inside[0];
        ro->ior = analytic_constant;
        ro->ior_ctx = &r->constants[i];
        return REFRACT_E_OK;
    }
    return err_set(e, REFRACT_E_INVALID_FIELD,
                   "objects[%zu].ior: the analytic reference needs one GRIN profile or a "
                   "constant, not %zu layers",
                   i, f->count);
}

/* Channel floats -> doubles, `comps` per voxel (4, or 1 for anisotropy). */
static double *widen(const float *src, size_t voxels, int comps)
{
    size_t n = voxels * (size_t)comps;
    double *d = malloc(n * sizeof(double));
    if (d)
        for (size_t k = 0; k < n; k++)
            d[k] = src[k];
    return d;
}

static enum refract_code build_voxels(struct scene_reference *r, const struct scene *s, size_t i,
                                      scene_volume_lookup_fn lookup, void *ctx, struct err *e)
{
    const struct scene_object *o = &s->objects[i];
    size_t voxels = (size_t)o->resolution[0] * o->resolution[1] * o->resolution[2];
    float *tmp = malloc(voxels * 4 * sizeof(float));
    double *smooth = malloc(voxels * sizeof(double));
    r->buffers[i][SCENE_CH_IOR] = malloc(voxels * 4 * sizeof(double));
    enum refract_code rc = REFRACT_E_OK;
    if (tmp == NULL || smooth == NULL || r->buffers[i][SCENE_CH_IOR] == NULL)
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the reference fields");
    if (rc == REFRACT_E_OK)
        rc = scene_field_eval(s, o, SCENE_CH_IOR, lookup, ctx, tmp, e);
    if (rc == REFRACT_E_OK) {
        smooth_gaussian_ref(tmp, o->resolution, o->smoothing_sigma_voxels, smooth);
        gradient_central_ref(smooth, o->resolution, scene_object_voxel_size(o),
                             r->buffers[i][SCENE_CH_IOR]);
        if (s->render.ior_texture == SCENE_IOR_FLOAT16)
            for (size_t k = 0; k < voxels * 4; k++)
                r->buffers[i][SCENE_CH_IOR][k] = half_float_round(r->buffers[i][SCENE_CH_IOR][k]);
        r->grids[i].ior_grad = r->buffers[i][SCENE_CH_IOR];
    }
    for (int ch = SCENE_CH_ATTENUATION; rc == REFRACT_E_OK && ch < SCENE_CH_COUNT; ch++) {
        if (!scene_channel_used(o, (enum scene_channel)ch))
            continue;
        rc = scene_field_eval(s, o, (enum scene_channel)ch, lookup, ctx, tmp, e);
        int comps = scene_channel_components((enum scene_channel)ch);
        if (rc == REFRACT_E_OK && (r->buffers[i][ch] = widen(tmp, voxels, comps)) == NULL)
            rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the reference fields");
    }
    r->grids[i].attenuation = r->buffers[i][SCENE_CH_ATTENUATION];
    r->grids[i].emission = r->buffers[i][SCENE_CH_EMISSION];
    r->grids[i].opaque = r->buffers[i][SCENE_CH_OPAQUE];
    r->grids[i].scattering = r->buffers[i][SCENE_CH_SCATTERING];
    r->grids[i].anisotropy = r->buffers[i][SCENE_CH_ANISOTROPY];
    r->objects[i].grid = &r->grids[i];
    r->objects[i].ior_filter = s->render.ior_filter == SCENE_FILTER_TRICUBIC
                                   ? REFTRACE_FILTER_TRICUBIC
                                   : REFTRACE_FILTER_TRILINEAR;
    free(tmp);
    free(smooth);
    if (rc == REFRACT_E_OK)
        rc = build_cells(r, (int)i, MACROCELL_DEFAULT_CELL, e);
    return rc;
}

enum refract_code scene_reference_build(const struct scene *s, enum scene_reference_mode mode,
                                        scene_volume_lookup_fn lookup, void *ctx,
                                        struct scene_reference *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    if (s->object_count > SCENE_REFERENCE_MAX_OBJECTS)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED, "the reference handles %d objects",
                       SCENE_REFERENCE_MAX_OBJECTS);
    fill_settings(s, &out->settings);
    out->count = (int)s->object_count;
    enum refract_code rc = REFRACT_E_OK;
    for (size_t i = 0; rc == REFRACT_E_OK && i < s->object_count; i++) {
        const struct scene_object *o = &s->objects[i];
        struct reftrace_object *ro = &out->objects[i];
        ro->bmin = o->bounds_min;
        ro->bmax = o->bounds_max;
        memcpy(ro->res, o->resolution, sizeof ro->res);
        ro->xf = o->world_from_object;
        ro->smoothing_sigma_voxels = o->smoothing_sigma_voxels;
        ro->opaque_ior = o->opaque_ior;
        /* The same BRDF the GPU gets from render.c (GGX alpha = roughness^2). */
        ro->brdf.kind = (int)o->brdf.kind;
        memcpy(ro->brdf.color, o->brdf.color, sizeof ro->brdf.color);
        ro->brdf.alpha = o->brdf.roughness * o->brdf.roughness;
        ro->brdf.exponent = o->brdf.exponent;
        ro->bound = o->bound;
        ro->ior_constant = scene_ior_constant(o);
        rc = mode == SCENE_REFERENCE_ANALYTIC ? build_analytic(out, i, o, s->ambient_ior, e)
                                              : build_voxels(out, s, i, lookup, ctx, e);
    }
    /* Exact surfaces are the same in both modes: nothing to discretise. */
    for (size_t k = 0; k < s->surface_count && k < SCENE_MAX_SURFACES; k++) {
        struct reftrace_surface *rs = &out->surfaces[k];
        const struct scene_medium *m = &s->surfaces[k].medium;
        if (!scene_surface_geom_lookup(&s->surfaces[k], lookup, ctx, &rs->geom) &&
            rc == REFRACT_E_OK)
            rc = err_set(e, REFRACT_E_CONFLICT,
                         "surfaces[%d] (\"%s\"): mesh \"%s\" was not uploaded; upload it with "
                         "POST /v1/scenes/{id}/meshes/%s",
                         s->surfaces[k].document_index, s->surfaces[k].name,
                         s->surfaces[k].shape.mesh, s->surfaces[k].shape.mesh);
        rs->ior = m->ior;
        memcpy(rs->attenuation, m->attenuation, sizeof rs->attenuation);
        memcpy(rs->emission, m->emission, sizeof rs->emission);
        memcpy(rs->scattering, m->scattering, sizeof rs->scattering);
        rs->anisotropy = m->anisotropy;
        const struct scene_brdf *b = &s->surfaces[k].brdf; /* as render.c fills it */
        rs->brdf.kind = (int)b->kind;
        memcpy(rs->brdf.color, b->color, sizeof rs->brdf.color);
        rs->brdf.alpha = b->roughness * b->roughness;
        rs->brdf.exponent = b->exponent;
        rs->field = m->has_object ? &out->objects[m->object] : NULL;
    }
    out->settings.surfaces = out->surfaces;
    out->settings.surface_count = (int)s->surface_count;
    if (rc != REFRACT_E_OK)
        scene_reference_free(out);
    return rc;
}

void scene_reference_free(struct scene_reference *r)
{
    for (int i = 0; i < SCENE_REFERENCE_MAX_OBJECTS; i++) {
        for (int ch = 0; ch < SCENE_CH_COUNT; ch++) {
            free(r->buffers[i][ch]);
            r->buffers[i][ch] = NULL;
        }
        macrocell_free(&r->cells[i]);
        r->objects[i].cells = NULL;
    }
}
