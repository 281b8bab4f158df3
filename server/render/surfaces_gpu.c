/*
 * surfaces_gpu.c - a scene's exact surfaces packed for the marching kernels
 * (shared_types.h surface_params, shaders/geom/surface.glsl): one record per surface in
 * priority order, and the lathes' profile points.
 */
#include <math.h>
#include <stdlib.h>

#include "../core/geom/geom.h"
#include "scene_gpu.h"
#define REFRACT_HOST_C
#include "shared_types.h"

/* Self-intersection offset of the surface just left, relative to its size: float hit
 * points are off by about 1e-7 of their coordinates. */
#define SURFACE_GPU_EPS 1e-5

static vec4 v4(vec3 v, double w)
{
    return (vec4){(float)v.x, (float)v.y, (float)v.z, (float)w};
}

static double lathe_orientation(const struct scene_shape *sh)
{
    double area2 = 0.0;
    for (size_t i = 0; i < sh->profile_count; i++) {
        const double *a = sh->profile[i], *b = sh->profile[(i + 1) % sh->profile_count];
        area2 += a[0] * b[1] - b[0] * a[1];
    }
    return area2 >= 0.0 ? 1.0 : -1.0;
}

static void pack(const struct scene_surface *sf, int first_point, surface_params *sp)
{
    struct geom_surface g;
    scene_surface_geom(sf, &g);
    const struct scene_shape *sh = &sf->shape;
    xform_to_gl_mat4(&g.xf, sp->world_from_object.m, sp->object_from_world.m);
    sp->kind = (ivec4){(int)g.kind, sh->axis, first_point, (int)sh->profile_count};
    sp->mesh = (ivec4){0, 0, 0, 0};
    switch (g.kind) {
    case GEOM_SPHERE:
        sp->shape0 = v4(sh->center, sh->radius);
        break;
    case GEOM_BOX:
        sp->shape0 = v4(sh->center, 0.0);
        sp->shape1 = v4(sh->size, 0.0);
        break;
    case GEOM_CYLINDER:
        sp->shape0 = v4(sh->center, sh->radius);
        sp->shape1 = (vec4){(float)sh->height, 0, 0, 0};
        break;
    case GEOM_PLANE:
        sp->shape0 = v4(sh->center, 0.0);
        sp->shape1 = v4(sh->normal, 0.0);
        break;
    case GEOM_LATHE: {
        double r_max = 0.0, h_lo = INFINITY, h_hi = -INFINITY;
        for (size_t i = 0; i < sh->profile_count; i++) {
            r_max = fmax(r_max, sh->profile[i][0]);
            h_lo = fmin(h_lo, sh->profile[i][1]);
            h_hi = fmax(h_hi, sh->profile[i][1]);
        }
        sp->shape0 = v4(sh->base, lathe_orientation(sh));
        sp->shape1 = (vec4){(float)r_max, (float)h_lo, (float)h_hi, 0.0f};
        break;
    }
    case GEOM_MESH:
        break;
    }
    const struct scene_medium *m = &sf->medium;
    bool absorbs = m->attenuation[0] > 0 && m->attenuation[1] > 0 && m->attenuation[2] > 0;
    sp->medium = (vec4){(float)m->ior, (float)g.xf.scale,
                        (float)(SURFACE_GPU_EPS * geom_surface_size(&g)), absorbs ? 1.0f : 0.0f};
    sp->attenuation = (vec4){(float)m->attenuation[0], (float)m->attenuation[1],
                             (float)m->attenuation[2], 0.0f};
    sp->emission =
        (vec4){(float)m->emission[0], (float)m->emission[1], (float)m->emission[2], 0.0f};
}

enum refract_code surfaces_gpu_build(const struct scene *s, struct gpu_buffer *records,
                                     struct gpu_buffer *profiles, struct err *e)
{
    size_t n = s->surface_count, points = 0;
    for (size_t i = 0; i < n; i++)
        if (s->surfaces[i].shape.kind == SCENE_SHAPE_LATHE)
            points += s->surfaces[i].shape.profile_count;
    surface_params *sp = calloc(n ? n : 1, sizeof *sp);
    float *pts = calloc(points ? 2 * points : 2, sizeof *pts);
    if (sp == NULL || pts == NULL) {
        free(sp);
        free(pts);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory packing the surfaces");
    }
    size_t next = 0;
    for (size_t i = 0; i < n; i++) {
        const struct scene_shape *sh = &s->surfaces[i].shape;
        pack(&s->surfaces[i], (int)next, &sp[i]);
        if (sh->kind == SCENE_SHAPE_LATHE)
            for (size_t j = 0; j < sh->profile_count; j++, next++) {
                pts[2 * next] = (float)sh->profile[j][0];
                pts[2 * next + 1] = (float)sh->profile[j][1];
            }
    }
    enum refract_code rc =
        gpu_buffer_create("surfaces", (n ? n : 1) * sizeof *sp, sp, records, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("surface profiles", (points ? points : 1) * 2 * sizeof *pts, pts,
                               profiles, e);
    free(sp);
    free(pts);
    return rc;
}
