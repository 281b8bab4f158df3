/*
 * interface.c - the interface event and the medium rule (interface.h). Twin:
 * shaders/interface.glsl.
 */
#include "interface.h"

#include "fresnel.h"

struct interface_event interface_cross(vec3 d, vec3 N, double n_i, double n_t)
{
    struct interface_event ev;
    double cos_i = vec3_dot(d, N);
    ev.R = fresnel_unpolarized(cos_i < 0.0 ? -cos_i : cos_i, n_i, n_t);
    ev.reflected = vec3_reflect(d, N);
    ev.tir = ev.R >= 1.0 || !snell_refract(d, N, n_i, n_t, &ev.refracted);
    if (ev.tir) {
        ev.R = 1.0;
        ev.refracted = ev.reflected;
    }
    return ev;
}

int interface_medium(uint32_t inside)
{
    if (inside == 0)
        return -1;
    int k = 0;
    while (!(inside & 1u)) {
        inside >>= 1;
        k++;
    }
    return k;
}
