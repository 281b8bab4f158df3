/*
 * scene_walter.c - when a scene's single scattering comes from walter2009's exact paths
 * (docs/walter.md "When"): the one place that decides it, for the view renderer (its
 * lights' LIGHT_MODE_WALTER), the CPU reference, the light-simulation rule and the scene
 * status.
 */
#include "../core/xform.h"
#include "scene.h"

bool scene_walter_sphere(const struct scene *s, struct scene_walter *w)
{
    if (s->object_count != 0 || s->surface_count != 1 || s->receiver.enabled)
        return false;
    const struct scene_surface *sf = &s->surfaces[0];
    if (sf->shape.kind != SCENE_SHAPE_SPHERE || sf->medium.has_object ||
        !scene_surface_scatters(sf))
        return false;
    if (w != NULL) {
        w->surface = 0;
        w->center = xform_point_to_world(&sf->world_from_object, sf->shape.center);
        w->radius = sf->shape.radius * sf->world_from_object.scale;
        w->eta = sf->medium.ior / s->ambient_ior;
        for (int c = 0; c < 3; c++)
            w->sigma_t[c] = sf->medium.attenuation[c] + sf->medium.scattering[c];
    }
    return true;
}

const char *scene_single_scattering_method(const struct scene *s)
{
    return scene_walter_sphere(s, NULL) ? "walter" : scene_scatters(s) ? "volume" : "none";
}
