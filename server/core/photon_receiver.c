/*
 * photon_receiver.c - the receiver's light in the "photons" caustics mode (photon.h,
 * docs/photons.md "The receiver"): the shadow ray of the direct part, the CPU double twin
 * of shaders/photons.glsl's (reftrace_light_receiver calls it).
 */
#include "photon.h"

#include <math.h>

bool photon_light_visible(const struct pathtrace_scene *s, int j, vec3 at)
{
    const struct pathtrace_light *l = &s->lights[j];
    vec3 to;
    double dist;
    if (l->kind == PATHTRACE_LIGHT_DIRECTIONAL) {
        to = vec3_scale(l->direction, -1.0);
        dist = INFINITY;
    } else {
        vec3 v = vec3_sub(l->position, at);
        dist = vec3_length(v);
        to = vec3_scale(v, 1.0 / dist);
    }
    for (int k = 0; k < s->surface_count; k++) {
        struct geom_hit h;
        if (photon_surface_optical(s, k) &&
            geom_surface_intersect(&s->surfaces[k].geom, at, to, 0.0, dist, -1, &h))
            return false;
    }
    return true;
}
