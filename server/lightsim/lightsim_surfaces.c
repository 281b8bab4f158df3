/*
 * lightsim_surfaces.c - the simulator's copy of the exact surfaces and the queries on
 * them; see lightsim_surfaces.h and docs/lightsim.md "Surfaces".
 */
#include "lightsim_surfaces.h"

#include <stdlib.h>
#include <string.h>

#include "../core/interface.h"
#include "../mesh/mesh.h"
#include "lightsim_sample.h"

/* A copy of m that the fields own (mesh_create from copies of its arrays: the hierarchies
 * are rebuilt, which costs about what the upload's parse did). */
static enum refract_code copy_mesh(const struct mesh *m, struct mesh **out, struct err *e)
{
    double(*v)[3] = malloc(m->vertex_count * sizeof *v);
    uint32_t(*t)[3] = malloc(m->triangle_count * sizeof *t);
    if (v == NULL || t == NULL) {
        free(v);
        free(t);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory copying a mesh surface's mesh");
    }
    memcpy(v, m->vertices, m->vertex_count * sizeof *v);
    memcpy(t, m->triangles, m->triangle_count * sizeof *t);
    struct mesh_limits lim = {.max_triangles = m->triangle_count};
    return mesh_create(v, m->vertex_count, t, m->triangle_count, &lim, out, e);
}

/* Surface k's mesh (a copy the fields own, one per distinct upload); its checks are the
 * view renderer's (render/surfaces_gpu.c), and a receiver must not cut it (the parser's
 * rule for the other kinds, which it cannot check for a mesh before the upload). */
static enum refract_code attach_mesh(const struct scene *s, size_t k, scene_volume_lookup_fn lookup,
                                     void *ctx, const struct mesh **sources,
                                     struct lightsim_fields *f, struct err *e)
{
    const struct scene_surface *sf = &s->surfaces[k];
    const struct mesh *m = lookup ? scene_mesh_lookup(lookup, ctx, sf->shape.mesh) : NULL;
    if (m == NULL)
        return err_set(e, REFRACT_E_CONFLICT,
                       "surfaces[%d] (\"%s\"): mesh \"%s\" was not uploaded; upload it with "
                       "POST /v1/scenes/{id}/meshes/%s",
                       sf->document_index, sf->name, sf->shape.mesh, sf->shape.mesh);
    if (!m->solid)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "surfaces[%d] (\"%s\"): mesh \"%s\" cannot bound a medium: %s",
                       sf->document_index, sf->name, sf->shape.mesh, m->solid_error);
    int i = 0;
    while (i < f->mesh_count && sources[i] != m)
        i++;
    if (i == f->mesh_count) {
        enum refract_code rc = copy_mesh(m, &f->meshes[i], e);
        if (rc != REFRACT_E_OK)
            return rc;
        sources[i] = m;
        f->mesh_count++;
    }
    struct geom_surface *g = &f->surfaces[k].geom;
    scene_surface_geom_mesh(sf, f->meshes[i], g);
    vec3 lo, hi;
    geom_surface_bounds(g, &lo, &hi);
    const struct scene_receiver *r = &s->receiver;
    if (r->enabled && r->height > lo.y + 1e-9)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "receiver.height: %g is above the bottom of surfaces[%d] (\"%s\")'s mesh "
                       "\"%s\" (y = %g in world space); put the plane at or below y = %g",
                       r->height, sf->document_index, sf->name, sf->shape.mesh, lo.y, lo.y);
    return REFRACT_E_OK;
}

enum refract_code ls_surfaces_build(const struct scene *s, scene_volume_lookup_fn lookup,
                                    void *ctx, struct lightsim_fields *f, struct err *e)
{
    size_t n = s->surface_count < SCENE_MAX_SURFACES ? s->surface_count : SCENE_MAX_SURFACES;
    f->surfaces = NULL;
    f->surface_count = 0;
    f->profile_points = NULL;
    f->meshes = NULL;
    f->mesh_count = 0;
    if (n == 0)
        return REFRACT_E_OK;
    size_t points = 0;
    for (size_t k = 0; k < n; k++) {
        const struct scene_shape *sh = &s->surfaces[k].shape;
        if (sh->kind == SCENE_SHAPE_LATHE)
            points += sh->profile_count;
    }
    f->surfaces = calloc(n, sizeof *f->surfaces);
    f->profile_points = calloc(points ? points : 1, sizeof *f->profile_points);
    f->meshes = calloc(n, sizeof *f->meshes);
    if (f->surfaces == NULL || f->profile_points == NULL || f->meshes == NULL) {
        ls_surfaces_free(f);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the light fields' surfaces");
    }
    const struct mesh *sources[SCENE_MAX_SURFACES];
    size_t next = 0;
    for (size_t k = 0; k < n; k++) {
        const struct scene_surface *sf = &s->surfaces[k];
        struct reftrace_surface *rs = &f->surfaces[k];
        scene_surface_geom(sf, &rs->geom);
        if (sf->shape.kind == SCENE_SHAPE_LATHE) {
            /* the fields outlive the scene (irradiance cache): own the profile */
            memcpy(f->profile_points + next, sf->shape.profile,
                   sf->shape.profile_count * sizeof *f->profile_points);
            rs->geom.profile = (const double (*)[2])(f->profile_points + next);
            next += sf->shape.profile_count;
        } else if (sf->shape.kind == SCENE_SHAPE_MESH) {
            enum refract_code rc = attach_mesh(s, k, lookup, ctx, sources, f, e);
            if (rc != REFRACT_E_OK) {
                ls_surfaces_free(f);
                return rc;
            }
        }
        rs->ior = sf->medium.ior;
        for (int c = 0; c < 3; c++) {
            rs->attenuation[c] = sf->medium.attenuation[c];
            rs->emission[c] = sf->medium.emission[c];
            rs->scattering[c] = sf->medium.scattering[c]; /* extinction: ls_corner_move */
        }
        rs->anisotropy = sf->medium.anisotropy;
    }
    f->surface_count = (int)n;
    return REFRACT_E_OK;
}

void ls_surfaces_free(struct lightsim_fields *f)
{
    for (int i = 0; f->meshes != NULL && i < f->mesh_count; i++)
        mesh_destroy(f->meshes[i]);
    free(f->meshes);
    free(f->surfaces);
    free(f->profile_points);
    f->meshes = NULL;
    f->mesh_count = 0;
    f->surfaces = NULL;
    f->profile_points = NULL;
    f->surface_count = 0;
}

uint32_t ls_surfaces_inside(const struct lightsim_fields *f, vec3 p)
{
    return reftrace_inside_set(f->surfaces, f->surface_count, p);
}

double ls_medium_ior(const struct lightsim_fields *f, int medium, vec3 x)
{
    if (medium >= 0)
        return f->surfaces[medium].ior;
    double n;
    vec3 g;
    ls_sample_ior(f, x, &n, &g);
    return n;
}

bool ls_surface_hit(const struct lightsim_fields *f, int k, vec3 o, vec3 d, int last, double tmax,
                    struct geom_hit *hit)
{
    const struct geom_surface *g = &f->surfaces[k].geom;
    double tmin = (k == last ? LS_SURFACE_EPS_SAME : LS_SURFACE_EPS_OTHER) * geom_surface_size(g);
    return geom_surface_intersect(g, o, d, tmin, tmax, -1, hit);
}

int ls_next_surface(const struct lightsim_fields *f, vec3 o, vec3 d, int last, double tmax,
                    struct geom_hit *hit)
{
    int best = -1;
    for (int k = 0; k < f->surface_count; k++) {
        struct geom_hit h;
        if (ls_surface_hit(f, k, o, d, last, tmax, &h)) {
            tmax = h.t;
            *hit = h;
            best = k;
        }
    }
    return best;
}
