/*
 * lightsim_gpu_wavefront.c - the GPU's first patch list from the CPU reference's initial
 * wavefront; see lightsim_gpu_wavefront.h.
 */
#include "lightsim_gpu_wavefront.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../lightsim_init.h"

static ls_gpu_patch to_gpu(const struct ls_patch *p)
{
    ls_gpu_patch g;
    memset(&g, 0, sizeof g);
    for (int k = 0; k < 4; k++) {
        g.x[k] = (vec4){(float)p->x[k].x, (float)p->x[k].y, (float)p->x[k].z, 0};
        g.w[k] = (vec4){(float)p->w[k].x, (float)p->w[k].y, (float)p->w[k].z, 0};
    }
    g.power = (vec4){(float)p->P[0], (float)p->P[1], (float)p->P[2], 0};
    g.zone = (vec4){(float)p->n_lo, (float)p->n_hi, 0, 0};
    g.state = (ivec4){p->level, p->in_zone ? 1 : 0, p->crossed ? 1 : 0, 0};
    g.inside = (ivec4){(int)p->inside[0], (int)p->inside[1], (int)p->inside[2], (int)p->inside[3]};
    g.last = (ivec4){p->last[0], p->last[1], p->last[2], p->last[3]};
    g.event = (ivec4){p->ev_surface, p->ev_mask, p->ev_reflect ? 1 : 0, 0};
    return g;
}

enum refract_code lightsim_wavefront_build(const struct lightsim_fields *f,
                                           const struct scene_light *l,
                                           const struct scene_lightsim *set,
                                           struct lightsim_wavefront *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    struct ls_patch *init = NULL;
    size_t n0 = 0;
    enum refract_code rc = ls_initial_wavefront(f, l, set, &init, &n0, e);
    if (rc != REFRACT_E_OK)
        return rc;
    size_t keep = n0 < (size_t)set->max_patches ? n0 : (size_t)set->max_patches;
    out->patches = malloc((keep > 0 ? keep : 1) * sizeof *out->patches);
    if (out->patches == NULL) {
        free(init);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "no host memory for the initial wavefront (%zu patches)", keep);
    }
    double sum_max = 0;
    for (size_t i = 0; i < n0; i++) {
        const double *P = init[i].P;
        sum_max += fmax(P[0], fmax(P[1], P[2]));
        for (int ch = 0; ch < 3; ch++) {
            out->flux_in[ch] += P[ch];
            if (i >= keep)
                out->flux_dropped[ch] += P[ch];
        }
        if (i < keep)
            out->patches[i] = to_gpu(&init[i]);
    }
    out->kept = (int)n0;
    out->count = (int)keep;
    out->mean_max_power = n0 > 0 ? sum_max / (double)n0 : 0;
    free(init);
    return REFRACT_E_OK;
}

void lightsim_wavefront_free(struct lightsim_wavefront *w)
{
    free(w->patches);
    w->patches = NULL;
    w->count = 0;
}
