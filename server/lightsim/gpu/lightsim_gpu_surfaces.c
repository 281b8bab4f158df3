/*
 * lightsim_gpu_surfaces.c - packing the light fields' surfaces for the GPU; see
 * lightsim_gpu_surfaces.h. The records are core/geom's geom_surface_pack, as the view
 * renderer's (server/render/surfaces_gpu.c); the meshes' arrays are mesh_rt's, in one
 * buffer (shaders/geom/mesh.glsl, MESH_RT_PACKED).
 */
#include <stdlib.h>
#include <string.h>

#include "../../core/geom/geom.h"
#include "../../core/reftrace.h"
#include "../../mesh/mesh.h"
#include "../../mesh/mesh_rt.h"
/* after geom.h: shaders/bindings.h names the kinds as macros */
#include "lightsim_gpu_surfaces.h"

#define RECORD 16 /* bytes of one packed mesh record (a vec4) */

/* The fields' meshes concatenated: every node of every mesh, then every triangle, then
 * every vertex; first[i] = mesh i's first node (in nodes), first triangle and first vertex
 * (in records). NULL (and *records 0) when there are none; false: out of memory. */
static bool pack_meshes(const struct lightsim_fields *f, ivec4 *first, void **out, size_t *records)
{
    size_t nodes = 0, tris = 0, verts = 0;
    for (int i = 0; i < f->mesh_count; i++) {
        struct mesh_rt_gpu a = mesh_rt_gpu_arrays(f->meshes[i]->rt);
        nodes += a.node_count;
        tris += a.tri_count;
        verts += a.vertex_count;
    }
    *records = 2 * nodes + tris + verts;
    *out = calloc(*records ? *records : 1, RECORD);
    if (*out == NULL)
        return false;
    if (*records == 0)
        *records = 1;
    size_t n = 0, t = 2 * nodes, v = 2 * nodes + tris;
    for (int i = 0; i < f->mesh_count; i++) {
        struct mesh_rt_gpu a = mesh_rt_gpu_arrays(f->meshes[i]->rt);
        first[i] = (ivec4){(int)n, (int)t, (int)v, 0};
        memcpy((char *)*out + 2 * n * RECORD, a.nodes, a.node_bytes);
        memcpy((char *)*out + t * RECORD, a.tris, a.tri_bytes);
        memcpy((char *)*out + v * RECORD, a.verts, a.vertex_bytes);
        n += a.node_count;
        t += a.tri_count;
        v += a.vertex_count;
    }
    return true;
}

bool lightsim_gpu_pack_surfaces(const struct lightsim_fields *f, surface_params **records,
                                float **points, size_t *point_count, void **meshes,
                                size_t *mesh_records)
{
    size_t n = (size_t)f->surface_count, count = 0;
    for (size_t k = 0; k < n; k++)
        if (f->surfaces[k].geom.kind == GEOM_LATHE)
            count += f->surfaces[k].geom.profile_count;
    ivec4 first[SCENE_MAX_SURFACES];
    *records = calloc(n ? n : 1, sizeof **records);
    *points = calloc(count ? 2 * count : 2, sizeof **points);
    *point_count = count;
    *meshes = NULL;
    bool packed = pack_meshes(f, first, meshes, mesh_records);
    if (*records == NULL || *points == NULL || !packed) {
        free(*records);
        free(*points);
        free(*meshes);
        return false;
    }
    size_t next = 0;
    for (size_t k = 0; k < n; k++) {
        const struct geom_surface *g = &f->surfaces[k].geom;
        const struct reftrace_surface *rs = &f->surfaces[k];
        geom_surface_pack(g, rs->ior, rs->attenuation, rs->emission, rs->scattering, rs->anisotropy,
                          (int)next, &(*records)[k]);
        if (g->kind == GEOM_MESH)
            for (int i = 0; i < f->mesh_count; i++)
                if (g->mesh == f->meshes[i])
                    (*records)[k].mesh = first[i];
        if (g->kind == GEOM_LATHE)
            for (size_t j = 0; j < g->profile_count; j++, next++) {
                (*points)[2 * next] = (float)g->profile[j][0];
                (*points)[2 * next + 1] = (float)g->profile[j][1];
            }
    }
    return true;
}
