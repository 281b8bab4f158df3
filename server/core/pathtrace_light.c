/*
 * pathtrace_light.c - next-event estimation towards the path tracer's lights
 * (pathtrace.h). A point light of intensity I gives radiance-over-pdf I / d^2 from its
 * one direction; a directional light E; a spot light I inside its cone and 0 outside; a
 * spherical light is sampled uniformly in the cone of directions it subtends from p
 * (pbrt-v3 Sphere::Sample(ref, u)), which sees exactly its visible cap, so every sample
 * is useful and the pdf is 1 / (2 pi (1 - cos_max)).
 */
#include <math.h>

#include "pathtrace.h"

double pathtrace_sphere_radiance(double phi_w, double radius)
{
    return phi_w / (4.0 * M_PI * M_PI * radius * radius);
}

/* cos of the half angle the sphere subtends from p; -1 when p is inside it */
static double cone_cos(const struct pathtrace_light *l, vec3 p, double *dist_c)
{
    *dist_c = vec3_length(vec3_sub(l->position, p));
    if (*dist_c <= l->radius)
        return -1.0;
    double s = l->radius / *dist_c;
    return sqrt(fmax(0.0, 1.0 - s * s));
}

double pathtrace_light_pdf(const struct pathtrace_light *l, vec3 p)
{
    if (l->kind != PATHTRACE_LIGHT_SPHERE)
        return 0.0;
    double dc;
    double cos_max = cone_cos(l, p, &dc);
    if (cos_max <= -1.0)
        return 0.0;
    return 1.0 / (2.0 * M_PI * (1.0 - cos_max));
}

bool pathtrace_light_hit(const struct pathtrace_light *l, vec3 o, vec3 d, double tmin, double tmax,
                         double *t)
{
    if (l->kind != PATHTRACE_LIGHT_SPHERE)
        return false;
    struct geom_hit h;
    if (!sphere_intersect(l->position, l->radius, o, d, tmin, tmax, &h))
        return false;
    *t = h.t;
    return true;
}

static void point_sample(const struct pathtrace_light *l, vec3 p,
                         struct pathtrace_light_sample *out)
{
    vec3 v = vec3_sub(l->position, p);
    double d2 = vec3_dot(v, v);
    out->dist = sqrt(d2);
    out->wi = vec3_scale(v, 1.0 / out->dist);
    double k = d2 > 0.0 ? 1.0 / d2 : 0.0;
    if (l->kind == PATHTRACE_LIGHT_SPOT &&
        vec3_dot(vec3_scale(out->wi, -1.0), l->direction) < l->cos_spot)
        k = 0.0;
    for (int c = 0; c < 3; c++)
        out->Li_over_pdf[c] = l->value[c] * k;
}

void pathtrace_light_sample(const struct pathtrace_light *l, vec3 p, struct pathtrace_rng *rng,
                            struct pathtrace_light_sample *out)
{
    out->pdf_sa = 0.0;
    switch (l->kind) {
    case PATHTRACE_LIGHT_POINT:
    case PATHTRACE_LIGHT_SPOT:
        point_sample(l, p, out);
        return;
    case PATHTRACE_LIGHT_DIRECTIONAL:
        out->wi = vec3_scale(l->direction, -1.0);
        out->dist = INFINITY;
        for (int c = 0; c < 3; c++)
            out->Li_over_pdf[c] = l->value[c];
        return;
    case PATHTRACE_LIGHT_SPHERE:
        break;
    }
    double dc;
    double cos_max = cone_cos(l, p, &dc);
    if (cos_max <= -1.0) { /* inside the emitter: no connection */
        out->wi = vec3_make(0.0, 1.0, 0.0);
        out->dist = 0.0;
        for (int c = 0; c < 3; c++)
            out->Li_over_pdf[c] = 0.0;
        return;
    }
    vec3 axis = vec3_scale(vec3_sub(l->position, p), 1.0 / dc);
    out->wi = pathtrace_sample_cone(axis, cos_max, rng);
    /* distance to the near side of the sphere along wi: dc cos - sqrt(r^2 - dc^2 sin^2) */
    double ct = vec3_dot(out->wi, axis);
    double disc = l->radius * l->radius - dc * dc * (1.0 - ct * ct);
    out->dist = dc * ct - sqrt(fmax(0.0, disc));
    out->pdf_sa = 1.0 / (2.0 * M_PI * (1.0 - cos_max));
    for (int c = 0; c < 3; c++)
        out->Li_over_pdf[c] = l->value[c] / out->pdf_sa;
}
