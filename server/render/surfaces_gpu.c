/*
 * surfaces_gpu.c - a scene's exact surfaces packed for the marching kernels
 * (shared_types.h surface_params, shaders/geom/surface.glsl): one record per surface in
 * priority order, and the lathes' profile points.
 */
#include <math.h>
#include <stdlib.h>

#include <stdio.h>
#include <string.h>

#include "../core/geom/geom.h"
#include "../mesh/mesh.h"
#include "../mesh/mesh_rt.h"
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

/* The mesh surfaces' meshes, each once, and where each begins in the shared arrays. */
struct mesh_list {
    const struct mesh *mesh[MAX_SURFACES];
    ivec4 first[MAX_SURFACES]; /* x node, y triangle, z vertex */
    int count;
    size_t nodes, tris, verts;
};

static ivec4 mesh_slot(struct mesh_list *l, const struct mesh *m)
{
    for (int i = 0; i < l->count; i++)
        if (l->mesh[i] == m)
            return l->first[i];
    struct mesh_rt_gpu a = mesh_rt_gpu_arrays(m->rt);
    ivec4 f = {(int)l->nodes, (int)l->tris, (int)l->verts, 0};
    l->mesh[l->count] = m;
    l->first[l->count++] = f;
    l->nodes += a.node_count;
    l->tris += a.tri_count;
    l->verts += a.vertex_count;
    return f;
}

static void pack(const struct scene_surface *sf, const struct geom_surface *gs, int first_point,
                 surface_params *sp)
{
    struct geom_surface g = *gs;
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

/* Finds each mesh surface's mesh and checks that it can bound a medium. */
static enum refract_code find_meshes(const struct render_scene_source *src,
                                     struct geom_surface *g, struct mesh_list *l,
                                     ivec4 *first, struct err *e)
{
    const struct scene *s = src->scene;
    for (size_t i = 0; i < s->surface_count; i++) {
        const struct scene_surface *sf = &s->surfaces[i];
        bool found = scene_surface_geom_lookup(sf, src->lookup, src->lookup_ctx, &g[i]);
        first[i] = (ivec4){0, 0, 0, 0};
        if (sf->shape.kind != SCENE_SHAPE_MESH)
            continue;
        if (!found)
            return err_set(e, REFRACT_E_CONFLICT,
                           "surfaces[%d] (\"%s\"): mesh \"%s\" was not uploaded; upload it "
                           "with POST /v1/scenes/%s/meshes/%s",
                           sf->document_index, sf->name, sf->shape.mesh, src->id, sf->shape.mesh);
        const struct mesh *m = g[i].mesh;
        if (!m->solid)
            return err_set(e, REFRACT_E_INVALID_MESH,
                           "surfaces[%d] (\"%s\"): mesh \"%s\" cannot bound a medium: %s",
                           sf->document_index, sf->name, sf->shape.mesh, m->solid_error);
        first[i] = mesh_slot(l, m);
    }
    return REFRACT_E_OK;
}

static enum refract_code upload_meshes(const struct mesh_list *l, struct scene_gpu *sg,
                                       struct err *e)
{
    size_t rec = 16;
    void *nodes = calloc(l->nodes ? 2 * l->nodes : 1, rec);
    void *tris = calloc(l->tris ? l->tris : 1, rec);
    void *verts = calloc(l->verts ? l->verts : 1, rec);
    enum refract_code rc = REFRACT_E_OK;
    if (nodes == NULL || tris == NULL || verts == NULL)
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory packing the mesh surfaces");
    for (int i = 0; rc == REFRACT_E_OK && i < l->count; i++) {
        struct mesh_rt_gpu a = mesh_rt_gpu_arrays(l->mesh[i]->rt);
        memcpy((char *)nodes + (size_t)l->first[i].x * 2 * rec, a.nodes, a.node_bytes);
        memcpy((char *)tris + (size_t)l->first[i].y * rec, a.tris, a.tri_bytes);
        memcpy((char *)verts + (size_t)l->first[i].z * rec, a.verts, a.vertex_bytes);
    }
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("mesh nodes", (l->nodes ? 2 * l->nodes : 1) * rec, nodes,
                               &sg->mesh_nodes, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("mesh triangles", (l->tris ? l->tris : 1) * rec, tris,
                               &sg->mesh_tris, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("mesh vertices", (l->verts ? l->verts : 1) * rec, verts,
                               &sg->mesh_verts, e);
    free(nodes);
    free(tris);
    free(verts);
    return rc;
}

enum refract_code surfaces_gpu_build(const struct render_scene_source *src,
                                     struct scene_gpu *sg, struct err *e)
{
    const struct scene *s = src->scene;
    struct gpu_buffer *records = &sg->surfaces, *profiles = &sg->surface_profiles;
    struct geom_surface g[MAX_SURFACES];
    ivec4 first[MAX_SURFACES];
    struct mesh_list meshes = {.count = 0};
    enum refract_code rc = find_meshes(src, g, &meshes, first, e);
    if (rc == REFRACT_E_OK)
        rc = upload_meshes(&meshes, sg, e);
    if (rc != REFRACT_E_OK)
        return rc;
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
        pack(&s->surfaces[i], &g[i], (int)next, &sp[i]);
        sp[i].mesh = first[i];
        if (sh->kind == SCENE_SHAPE_LATHE)
            for (size_t j = 0; j < sh->profile_count; j++, next++) {
                pts[2 * next] = (float)sh->profile[j][0];
                pts[2 * next + 1] = (float)sh->profile[j][1];
            }
    }
    rc = gpu_buffer_create("surfaces", (n ? n : 1) * sizeof *sp, sp, records, e);
    if (rc == REFRACT_E_OK)
        rc = gpu_buffer_create("surface profiles", (points ? points : 1) * 2 * sizeof *pts, pts,
                               profiles, e);
    free(sp);
    free(pts);
    return rc;
}
