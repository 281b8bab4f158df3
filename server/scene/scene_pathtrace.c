/*
 * scene_pathtrace.c - struct scene -> struct pathtrace_scene (scene_pathtrace.h).
 */
#include "scene_pathtrace.h"

#include <math.h>
#include <string.h>

void scene_pathtrace_light(enum scene_light_kind kind, vec3 position, vec3 direction,
                           double cos_spot, const double intensity[3], double radius, bool visible,
                           struct pathtrace_light *p)
{
    memset(p, 0, sizeof *p);
    p->position = position;
    p->direction = direction;
    for (int c = 0; c < 3; c++)
        p->value[c] = intensity[c];
    switch (kind) {
    case SCENE_LIGHT_DIRECTIONAL:
        p->kind = PATHTRACE_LIGHT_DIRECTIONAL;
        break;
    case SCENE_LIGHT_POINT:
        p->kind = PATHTRACE_LIGHT_POINT;
        if (radius > 0.0) { /* the same far-field intensity I: L_e = I / (pi r^2) */
            p->kind = PATHTRACE_LIGHT_SPHERE;
            p->radius = radius;
            p->visible = visible;
            for (int c = 0; c < 3; c++)
                p->value[c] /= M_PI * radius * radius;
        }
        break;
    case SCENE_LIGHT_SPOT:
        p->kind = PATHTRACE_LIGHT_SPOT;
        p->cos_spot = cos_spot;
        break;
    }
}

/* Scene light l with intensity I per channel. */
static void convert_light_as(const struct scene_light *l, const double I[3],
                             struct pathtrace_light *p)
{
    scene_pathtrace_light(l->kind, l->position, l->direction, cos(l->spot_angle_deg * M_PI / 180.0),
                          I, l->radius, l->camera_visible, p);
}

static void convert_light(const struct scene_light *l, struct pathtrace_light *p)
{
    double I[3];
    for (int c = 0; c < 3; c++)
        I[c] = l->color[c] * l->intensity;
    convert_light_as(l, I, p);
}

void scene_pathtrace_light_unit(const struct scene_light *l, struct pathtrace_light *p)
{
    static const double unit[3] = {1.0, 1.0, 1.0};
    convert_light_as(l, unit, p);
}

enum refract_code scene_pathtrace_init(const struct scene *s, scene_volume_lookup_fn lookup,
                                       void *ctx, struct scene_pathtrace *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    if (s->object_count > 0)
        return err_set(e, REFRACT_E_CONFLICT,
                       "mode \"reference\": objects[0] (\"%s\") is a volume object; the path "
                       "tracer renders exact surfaces with constant media only (docs/"
                       "pathtracer.md \"Not yet\"); render this scene with \"mode\": \"fast\"",
                       s->objects[0].name);
    if (s->environment.kind != SCENE_ENV_PROCEDURAL)
        return err_set(e, REFRACT_E_CONFLICT,
                       "mode \"reference\": an image environment is not supported yet; use the "
                       "procedural environment (its intensity 0 is black) or \"mode\": \"fast\"");
    for (size_t k = 0; k < s->surface_count; k++) {
        const struct scene_surface *sf = &s->surfaces[k];
        const double *em = sf->medium.emission;
        if (em[0] > 0.0 || em[1] > 0.0 || em[2] > 0.0)
            return err_set(e, REFRACT_E_CONFLICT,
                           "mode \"reference\": surfaces[%d] (\"%s\") has an emitting medium, "
                           "which the path tracer does not render yet (docs/pathtracer.md "
                           "\"Not yet\"); use \"mode\": \"fast\"",
                           sf->document_index, sf->name);
    }
    return scene_pathtrace_geometry(s, lookup, ctx, out, e);
}

enum refract_code scene_pathtrace_geometry(const struct scene *s, scene_volume_lookup_fn lookup,
                                           void *ctx, struct scene_pathtrace *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    struct pathtrace_scene *p = &out->scene;
    p->ambient.ior = s->ambient_ior;
    for (size_t k = 0; k < s->surface_count; k++) {
        const struct scene_surface *sf = &s->surfaces[k];
        struct pathtrace_surface *ps = &out->surfaces[k];
        if (!scene_surface_geom_lookup(sf, lookup, ctx, &ps->geom))
            return err_set(e, REFRACT_E_CONFLICT,
                           "surfaces[%d] (\"%s\"): its mesh is missing; upload it first",
                           sf->document_index, sf->name);
        ps->medium.ior = sf->medium.ior;
        for (int c = 0; c < 3; c++) {
            ps->medium.sigma_a[c] = sf->medium.attenuation[c];
            ps->medium.sigma_s[c] = sf->medium.scattering[c];
        }
        ps->medium.g = sf->medium.anisotropy;
    }
    p->surfaces = s->surface_count > 0 ? out->surfaces : NULL;
    p->surface_count = (int)s->surface_count;
    if (s->receiver.enabled) {
        p->receiver.enabled = true;
        p->receiver.height = s->receiver.height;
        p->receiver.half_size = s->receiver.half_size; /* INFINITY: "infinite" */
        p->receiver.center[0] = s->receiver.center[0];
        p->receiver.center[1] = s->receiver.center[1];
        memcpy(p->receiver.albedo, s->receiver.albedo, sizeof p->receiver.albedo);
    }
    for (size_t k = 0; k < s->light_count && k < PATHTRACE_MAX_LIGHTS; k++)
        convert_light(&s->lights[k], &p->lights[k]);
    p->light_count = (int)s->light_count;
    p->env_kind = PATHTRACE_ENV_PROCEDURAL;
    for (int c = 0; c < 3; c++)
        p->env_radiance[c] = s->environment.intensity;
    struct scene_walter wa;
    if (scene_walter_sphere(s, &wa))
        p->walter =
            (struct pathtrace_walter){true, wa.surface, wa.center, wa.radius, wa.eta, false, 0.02};
    return REFRACT_E_OK;
}
