/*
 * lightsim_gpu_surfaces.c - packing the light fields' surfaces for the GPU; see
 * lightsim_gpu_surfaces.h. Same layout and offsets as server/render/surfaces_gpu.c.
 */
#include <stdlib.h>

#include "../../core/geom/geom.h"
#include "../../core/reftrace.h"
/* after geom.h: shaders/bindings.h names the kinds as macros */
#include "lightsim_gpu_surfaces.h"

/* Self-intersection offset of the surface just left, relative to its size (float hit
 * points are off by about 1e-7 of their coordinates): surfaces_gpu.c's SURFACE_GPU_EPS. */
#define LS_SURFACE_GPU_EPS 1e-5

static vec4 v4(vec3 v, double w)
{
    return (vec4){(float)v.x, (float)v.y, (float)v.z, (float)w};
}

/* +1 for a counter-clockwise profile in (r, h), -1 otherwise (lathe.glsl's orientation). */
static double orientation(const struct geom_surface *g)
{
    double area2 = 0.0;
    for (size_t i = 0; i < g->profile_count; i++) {
        const double *a = g->profile[i], *b = g->profile[(i + 1) % g->profile_count];
        area2 += a[0] * b[1] - b[0] * a[1];
    }
    return area2 >= 0.0 ? 1.0 : -1.0;
}

static void pack(const struct reftrace_surface *rs, int first_point, surface_params *sp)
{
    const struct geom_surface *g = &rs->geom;
    xform_to_gl_mat4(&g->xf, sp->world_from_object.m, sp->object_from_world.m);
    sp->kind = (ivec4){(int)g->kind, g->axis, first_point, (int)g->profile_count};
    sp->mesh = (ivec4){0, 0, 0, 0};
    switch (g->kind) {
    case GEOM_SPHERE:
        sp->shape0 = v4(g->center, g->radius);
        break;
    case GEOM_BOX:
        sp->shape0 = v4(g->center, 0.0);
        sp->shape1 = v4(g->size, 0.0);
        break;
    case GEOM_CYLINDER:
        sp->shape0 = v4(g->center, g->radius);
        sp->shape1 = (vec4){(float)g->height, 0, 0, 0};
        break;
    case GEOM_PLANE:
        sp->shape0 = v4(g->center, 0.0);
        sp->shape1 = v4(g->normal, 0.0);
        break;
    case GEOM_LATHE:
        sp->shape0 = v4(g->base, orientation(g));
        break;
    case GEOM_MESH:
        break;
    }
    const double *a = rs->attenuation;
    bool absorbs = a[0] > 0 && a[1] > 0 && a[2] > 0;
    sp->medium = (vec4){(float)rs->ior, (float)g->xf.scale,
                        (float)(LS_SURFACE_GPU_EPS * geom_surface_size(g)), absorbs ? 1.0f : 0.0f};
    sp->attenuation = (vec4){(float)a[0], (float)a[1], (float)a[2], 0.0f};
    sp->emission = (vec4){(float)rs->emission[0], (float)rs->emission[1],
                          (float)rs->emission[2], 0.0f};
}

bool lightsim_gpu_pack_surfaces(const struct lightsim_fields *f, surface_params **records,
                                float **points, size_t *point_count)
{
    size_t n = (size_t)f->surface_count, count = 0;
    for (size_t k = 0; k < n; k++)
        if (f->surfaces[k].geom.kind == GEOM_LATHE)
            count += f->surfaces[k].geom.profile_count;
    *records = calloc(n ? n : 1, sizeof **records);
    *points = calloc(count ? 2 * count : 2, sizeof **points);
    *point_count = count;
    if (*records == NULL || *points == NULL) {
        free(*records);
        free(*points);
        return false;
    }
    size_t next = 0;
    for (size_t k = 0; k < n; k++) {
        const struct geom_surface *g = &f->surfaces[k].geom;
        pack(&f->surfaces[k], (int)next, &(*records)[k]);
        if (g->kind == GEOM_LATHE)
            for (size_t j = 0; j < g->profile_count; j++, next++) {
                (*points)[2 * next] = (float)g->profile[j][0];
                (*points)[2 * next + 1] = (float)g->profile[j][1];
            }
    }
    return true;
}
