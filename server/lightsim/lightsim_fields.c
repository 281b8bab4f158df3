/*
 * lightsim_fields.c - the simulator's input fields on the light grid (docs/lightsim.md
 * "Fields"): each object's smoothed index, extinction and opaque coverage, exactly as the
 * reference tracer sees them (scene_reference_build, voxel mode), resampled at the light
 * voxel centres; the gradient is then taken on the light grid itself.
 */
#include <stdlib.h>
#include <string.h>

#include "../core/smooth.h"
#include "../scene/scene_reference.h"
#include "lightsim.h"
#include "lightsim_surfaces.h"

/* Trilinear sample of one object's grid at object-space point p (tracing.md's voxel
 * coordinates, clamp to edge). */
static void sample_object(const struct reftrace_object *o, const double *grid, vec3 p,
                          double out[4])
{
    vec3 vs = {(o->bmax.x - o->bmin.x) / o->res[0], (o->bmax.y - o->bmin.y) / o->res[1],
               (o->bmax.z - o->bmin.z) / o->res[2]};
    vec3 v = {(p.x - o->bmin.x) / vs.x - 0.5, (p.y - o->bmin.y) / vs.y - 0.5,
              (p.z - o->bmin.z) / vs.z - 0.5};
    voxel_sample_trilinear(grid, 4, o->res, v, out);
}

static bool object_contains(const struct reftrace_object *o, vec3 p)
{
    return p.x >= o->bmin.x && p.x <= o->bmax.x && p.y >= o->bmin.y && p.y <= o->bmax.y &&
           p.z >= o->bmin.z && p.z <= o->bmax.z;
}

/* n, sigma_t and coverage at world point x: the first object (scene order) whose bounds
 * contain M^-1 x, else the ambient medium. */
static void voxel_value(const struct scene_reference *r, double ambient, vec3 x, double *n,
                        double ext[4])
{
    *n = ambient;
    memset(ext, 0, 4 * sizeof(double));
    for (int i = 0; i < r->count; i++) {
        const struct reftrace_object *o = &r->objects[i];
        vec3 p = xform_point_to_object(&o->xf, x);
        if (!object_contains(o, p))
            continue;
        double s[4];
        sample_object(o, o->grid->ior_grad, p, s);
        *n = s[3];
        if (o->grid->attenuation) {
            sample_object(o, o->grid->attenuation, p, s);
            for (int c = 0; c < 3; c++)
                ext[c] += s[c];
        }
        if (o->grid->scattering) {
            sample_object(o, o->grid->scattering, p, s);
            for (int c = 0; c < 3; c++)
                ext[c] += s[c];
        }
        if (o->grid->opaque) {
            sample_object(o, o->grid->opaque, p, s);
            ext[3] = s[3];
        }
        return;
    }
}

enum refract_code lightsim_fields_build(const struct scene *s, scene_volume_lookup_fn lookup,
                                        void *ctx, struct lightsim_fields *out, struct err *e)
{
    return lightsim_fields_build_light(s, NULL, lookup, ctx, out, e);
}

enum refract_code lightsim_fields_build_light(const struct scene *s, const struct scene_light *l,
                                              scene_volume_lookup_fn lookup, void *ctx,
                                              struct lightsim_fields *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    lightsim_domain_light(s, l, lookup, ctx, &out->grid);
    out->ambient_ior = s->ambient_ior;
    out->boundary_threshold = s->render.boundary_threshold;
    double sigma_max = 0.0;
    for (size_t i = 0; i < s->object_count; i++) {
        const struct scene_object *o = &s->objects[i];
        double sg =
            o->smoothing_sigma_voxels * scene_object_min_voxel(o) * o->world_from_object.scale;
        sigma_max = sg > sigma_max ? sg : sigma_max;
    }
    out->probe_distance = 3.0 * sigma_max + 2.0 * out->grid.voxel;

    struct scene_reference *ref = malloc(sizeof *ref);
    if (ref == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the light fields");
    enum refract_code rc = scene_reference_build(s, SCENE_REFERENCE_VOXELS, lookup, ctx, ref, e);
    if (rc != REFRACT_E_OK) {
        free(ref);
        return rc;
    }
    const struct light_grid *g = &out->grid;
    size_t voxels = (size_t)g->dims[0] * g->dims[1] * g->dims[2];
    double *n = malloc(voxels * sizeof(double));
    out->ior_grad = malloc(voxels * 4 * sizeof(double));
    out->extinction = malloc(voxels * 4 * sizeof(double));
    if (n == NULL || out->ior_grad == NULL || out->extinction == NULL) {
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY,
                     "out of memory for the light fields (%d x %d x %d voxels); lower "
                     "lightsim.resolution",
                     g->dims[0], g->dims[1], g->dims[2]);
    } else {
        for (int k = 0; k < g->dims[2]; k++)
            for (int j = 0; j < g->dims[1]; j++)
                for (int i = 0; i < g->dims[0]; i++) {
                    size_t idx = (size_t)i + (size_t)g->dims[0] * (j + (size_t)g->dims[1] * k);
                    vec3 x =
                        vec3_add(g->bmin, vec3_scale((vec3){i + 0.5, j + 0.5, k + 0.5}, g->voxel));
                    voxel_value(ref, s->ambient_ior, x, &n[idx], &out->extinction[4 * idx]);
                }
        /* tracing.md "Precomputation" step 3, on the light grid, world units */
        gradient_central_ref(n, g->dims, (vec3){g->voxel, g->voxel, g->voxel}, out->ior_grad);
    }
    free(n);
    scene_reference_free(ref);
    free(ref);
    if (rc == REFRACT_E_OK)
        rc = ls_surfaces_build(s, lookup, ctx, out, e);
    if (rc != REFRACT_E_OK)
        lightsim_fields_free(out);
    return rc;
}

void lightsim_fields_free(struct lightsim_fields *f)
{
    if (f == NULL)
        return;
    free(f->ior_grad);
    free(f->extinction);
    ls_surfaces_free(f);
    f->ior_grad = NULL;
    f->extinction = NULL;
}
