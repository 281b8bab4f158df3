/*
 * lightsim_surfaces.c - the simulator's copy of the exact surfaces and the queries on
 * them; see lightsim_surfaces.h and docs/lightsim.md "Surfaces".
 */
#include "lightsim_surfaces.h"

#include <stdlib.h>
#include <string.h>

#include "../core/interface.h"
#include "lightsim_sample.h"

enum refract_code ls_surfaces_build(const struct scene *s, struct lightsim_fields *f,
                                    struct err *e)
{
    size_t n = s->surface_count < SCENE_MAX_SURFACES ? s->surface_count : SCENE_MAX_SURFACES;
    f->surfaces = NULL;
    f->surface_count = 0;
    f->profile_points = NULL;
    if (n == 0)
        return REFRACT_E_OK;
    size_t points = 0;
    for (size_t k = 0; k < n; k++) {
        const struct scene_shape *sh = &s->surfaces[k].shape;
        if (sh->kind == SCENE_SHAPE_MESH)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "surfaces[%d]: the light simulator does not trace mesh surfaces yet",
                           s->surfaces[k].document_index);
        if (sh->kind == SCENE_SHAPE_LATHE)
            points += sh->profile_count;
    }
    f->surfaces = calloc(n, sizeof *f->surfaces);
    f->profile_points = calloc(points ? points : 1, sizeof *f->profile_points);
    if (f->surfaces == NULL || f->profile_points == NULL) {
        ls_surfaces_free(f);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the light fields' surfaces");
    }
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
        }
        rs->ior = sf->medium.ior;
        for (int c = 0; c < 3; c++) {
            rs->attenuation[c] = sf->medium.attenuation[c];
            rs->emission[c] = sf->medium.emission[c];
        }
    }
    f->surface_count = (int)n;
    return REFRACT_E_OK;
}

void ls_surfaces_free(struct lightsim_fields *f)
{
    free(f->surfaces);
    free(f->profile_points);
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
