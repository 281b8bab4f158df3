/*
 * scene_surface.c - a scene's exact surfaces as the marches see them (core/geom): the
 * conversion every march shares (the CPU reference, the GPU packing, the eye's and a trace
 * ray's inside set), so that one description of each kind serves all of them.
 */
#include <math.h>

#include "../core/geom/geom.h"
#include "../core/interface.h"
#include "scene.h"

void scene_surface_geom(const struct scene_surface *sf, struct geom_surface *g)
{
    const struct scene_shape *sh = &sf->shape;
    *g = (struct geom_surface){.xf = sf->world_from_object};
    g->center = sh->center;
    g->radius = sh->radius;
    g->size = sh->size;
    g->height = sh->height;
    g->axis = sh->axis;
    g->normal = sh->normal;
    g->base = sh->base;
    switch (sh->kind) {
    case SCENE_SHAPE_SPHERE:
        g->kind = GEOM_SPHERE;
        break;
    case SCENE_SHAPE_BOX:
        g->kind = GEOM_BOX;
        break;
    case SCENE_SHAPE_CYLINDER:
        g->kind = GEOM_CYLINDER;
        break;
    case SCENE_SHAPE_PLANE:
        g->kind = GEOM_PLANE;
        break;
    case SCENE_SHAPE_LATHE:
        g->kind = GEOM_LATHE;
        g->profile = (const double (*)[2])sh->profile;
        g->profile_count = sh->profile_count;
        break;
    default:
        /* Meshes: the mesh is an upload; the caller attaches it (mesh, mesh_ops) and
         * composes the mesh's placement into xf. */
        g->kind = GEOM_MESH;
        g->xf = sf->world_from_object;
        break;
    }
}

uint32_t scene_surfaces_inside(const struct scene *s, vec3 p)
{
    uint32_t set = 0;
    for (size_t k = 0; k < s->surface_count && k < INTERFACE_MAX_SURFACES; k++) {
        struct geom_surface g;
        scene_surface_geom(&s->surfaces[k], &g);
        if (geom_surface_inside(&g, p))
            set |= 1u << k;
    }
    return set;
}
