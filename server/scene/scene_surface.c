/*
 * scene_surface.c - a scene's exact surfaces as the marches see them (core/geom): the
 * conversion every march shares (the CPU reference, the GPU packing, the eye's and a trace
 * ray's inside set), so that one description of each kind serves all of them.
 */
#include <math.h>

#include "../core/geom/geom.h"
#include "../core/interface.h"
#include "../mesh/mesh.h"
#include "../mesh/mesh_rt.h"
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
    case SCENE_SHAPE_ROUNDED_BOX:
        g->kind = GEOM_ROUNDED_BOX;
        break;
    case SCENE_SHAPE_CYLINDER:
        g->kind = GEOM_CYLINDER;
        break;
    case SCENE_SHAPE_PLANE:
        g->kind = GEOM_PLANE;
        break;
    case SCENE_SHAPE_LATHE:
        g->kind = GEOM_LATHE;
        g->profile = (const double(*)[2])sh->profile;
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

/* ---- mesh surfaces: mesh_rt for the crossings, the winding number for inside ---- */

static bool mesh_intersect_op(const void *mesh, vec3 o, vec3 d, double tmin, double tmax,
                              int64_t skip_prim, struct geom_hit *h)
{
    const struct mesh *m = mesh;
    struct mesh_rt_hit r;
    if (!mesh_rt_intersect(m->rt, o, d, tmin, tmax, skip_prim, &r))
        return false;
    h->t = r.t;
    h->normal = r.n_geom;
    h->shading = r.n_shade;
    h->prim = (int64_t)r.tri;
    return true;
}

/* |w| >= 1/2: inside whichever way the mesh is wound (mesh.h). */
static bool mesh_inside_op(const void *mesh, vec3 p)
{
    return fabs(mesh_winding_number(mesh, p)) >= 0.5;
}

static const struct geom_mesh_ops scene_mesh_ops = {.intersect = mesh_intersect_op,
                                                    .inside = mesh_inside_op};

void scene_surface_geom_mesh(const struct scene_surface *sf, const struct mesh *m,
                             struct geom_surface *g)
{
    scene_surface_geom(sf, g);
    g->kind = GEOM_MESH;
    /* The surface's object space is the mesh's own: its placement (centre, scale, rotate)
     * composed into the transform. */
    g->xf = xform_compose(&sf->world_from_object, &sf->shape.object_from_mesh);
    g->mesh = m;
    g->mesh_ops = &scene_mesh_ops;
    g->mesh_lo = m->lo;
    g->mesh_hi = m->hi;
}

bool scene_surface_geom_lookup(const struct scene_surface *sf, scene_volume_lookup_fn lookup,
                               void *ctx, struct geom_surface *g)
{
    if (sf->shape.kind != SCENE_SHAPE_MESH) {
        scene_surface_geom(sf, g);
        return true;
    }
    const struct mesh *m = lookup ? scene_mesh_lookup(lookup, ctx, sf->shape.mesh) : NULL;
    if (m == NULL) {
        scene_surface_geom(sf, g); /* traced as nothing (mesh_ops NULL) */
        return false;
    }
    scene_surface_geom_mesh(sf, m, g);
    return true;
}

uint32_t scene_surfaces_inside(const struct scene *s, scene_volume_lookup_fn lookup, void *ctx,
                               vec3 p)
{
    uint32_t set = 0;
    for (size_t k = 0; k < s->surface_count && k < INTERFACE_MAX_SURFACES; k++) {
        struct geom_surface g;
        if (scene_surface_geom_lookup(&s->surfaces[k], lookup, ctx, &g) &&
            geom_surface_inside(&g, p))
            set |= 1u << k;
    }
    return set;
}
