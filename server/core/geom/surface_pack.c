/*
 * surface_pack.c - a placed surface and its medium as the GPU's surface_params record
 * (shaders/shared_types.h, read by shaders/geom/surface_dispatch.glsl): the one packing the
 * view renderer (render/surfaces_gpu.c) and the light simulator
 * (lightsim/gpu/lightsim_gpu_surfaces.c) share.
 */
#include <math.h>

#include "geom.h"
#define REFRACT_HOST_C
#include "shared_types.h"

static vec4 v4(vec3 v, double w)
{
    return (vec4){(float)v.x, (float)v.y, (float)v.z, (float)w};
}

void geom_surface_pack(const struct geom_surface *g, double ior, const double attenuation[3],
                       const double emission[3], const double scattering[3], double anisotropy,
                       int first_point, struct surface_params *sp)
{
    xform_to_gl_mat4(&g->xf, sp->world_from_object.m, sp->object_from_world.m);
    sp->kind = (ivec4){g->kind, g->axis, first_point, (int)g->profile_count};
    sp->mesh = (ivec4){0, 0, 0, 0};
    sp->shape0 = (vec4){0, 0, 0, 0};
    sp->shape1 = (vec4){0, 0, 0, 0};
    switch (g->kind) {
    case GEOM_SPHERE:
        sp->shape0 = v4(g->center, g->radius);
        break;
    case GEOM_BOX:
        sp->shape0 = v4(g->center, 0.0);
        sp->shape1 = v4(g->size, 0.0);
        break;
    case GEOM_ROUNDED_BOX:
        sp->shape0 = v4(g->center, g->radius);
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
    case GEOM_LATHE: {
        /* Orientation and the bounding cylinder that lathe.glsl culls with. */
        double r_max, h_lo, h_hi;
        lathe_extent(g->profile, g->profile_count, &r_max, &h_lo, &h_hi);
        sp->shape0 = v4(g->base, lathe_orientation(g->profile, g->profile_count));
        sp->shape1 = (vec4){(float)r_max, (float)h_lo, (float)h_hi, 0.0f};
        break;
    }
    default: /* GEOM_MESH: the caller sets sp->mesh */
        break;
    }
    /* An endless solid (a half-space) takes all the light when its extinction
     * sigma_a + sigma_s is positive in every channel. */
    bool absorbs = attenuation[0] + scattering[0] > 0 && attenuation[1] + scattering[1] > 0 &&
                   attenuation[2] + scattering[2] > 0;
    sp->medium = (vec4){(float)ior, (float)g->xf.scale,
                        (float)(GEOM_PACK_EPS * geom_surface_size(g)), absorbs ? 1.0f : 0.0f};
    sp->attenuation =
        (vec4){(float)attenuation[0], (float)attenuation[1], (float)attenuation[2], 0.0f};
    sp->emission = (vec4){(float)emission[0], (float)emission[1], (float)emission[2], 0.0f};
    sp->scattering =
        (vec4){(float)scattering[0], (float)scattering[1], (float)scattering[2], (float)anisotropy};
}
