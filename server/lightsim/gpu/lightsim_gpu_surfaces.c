/*
 * lightsim_gpu_surfaces.c - packing the light fields' surfaces for the GPU; see
 * lightsim_gpu_surfaces.h. The records are core/geom's geom_surface_pack, as the view
 * renderer's (server/render/surfaces_gpu.c).
 */
#include <stdlib.h>

#include "../../core/geom/geom.h"
#include "../../core/reftrace.h"
/* after geom.h: shaders/bindings.h names the kinds as macros */
#include "lightsim_gpu_surfaces.h"

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
        const struct reftrace_surface *rs = &f->surfaces[k];
        geom_surface_pack(g, rs->ior, rs->attenuation, rs->emission, (int)next, &(*records)[k]);
        if (g->kind == GEOM_LATHE)
            for (size_t j = 0; j < g->profile_count; j++, next++) {
                (*points)[2 * next] = (float)g->profile[j][0];
                (*points)[2 * next + 1] = (float)g->profile[j][1];
            }
    }
    return true;
}
