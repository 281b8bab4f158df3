/*
 * surfaces_gpu.c - a scene's exact surfaces packed for the marching kernels
 * (shared_types.h surface_params, shaders/geom/surface.glsl): one record per surface in
 * priority order, and the lathes' profile points.
 */
#include <stdlib.h>

#include <stdio.h>
#include <string.h>

#include "../core/geom/geom.h"
#include "../mesh/mesh.h"
#include "../mesh/mesh_rt.h"
#include "scene_gpu.h"
#define REFRACT_HOST_C
#include "shared_types.h"

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

/* Finds each mesh surface's mesh and checks that it can bound a medium. */
static enum refract_code find_meshes(const struct render_scene_source *src, struct geom_surface *g,
                                     struct mesh_list *l, ivec4 *first, struct err *e)
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

enum refract_code surfaces_gpu_build(const struct render_scene_source *src, struct scene_gpu *sg,
                                     struct err *e)
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
        const struct scene_medium *m = &s->surfaces[i].medium;
        geom_surface_pack(&g[i], m->ior, m->attenuation, m->emission, m->scattering, m->anisotropy,
                          (int)next, &sp[i]);
        sp[i].mesh = first[i];
        /* The medium "object" form: the object whose fields fill the solid. */
        sp[i].attenuation.w = m->has_object ? (float)m->object : -1.0f;
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
