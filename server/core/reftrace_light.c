/*
 * reftrace_light.c - the light-dependent terms of the reference tracer; see
 * reftrace_light.h. Line for line the twin of shaders/lighting.glsl.
 */
#include "reftrace_light.h"

#include "photon.h"

#include <math.h>
#include <stddef.h>

#include "bindings.h"
#include "phase.h"
#include "smooth.h"
#include "walter.h"

bool reftrace_light_direct(const struct reftrace_light *l, vec3 x, vec3 *E, vec3 *dir)
{
    *E = (vec3){0, 0, 0};
    *dir = (vec3){0, -1, 0};
    vec3 scale = {l->scale[0], l->scale[1], l->scale[2]};
    if (l->kind == LIGHT_KIND_DIRECTIONAL) {
        *dir = l->direction;
        *E = scale;
        return true;
    }
    vec3 r = vec3_sub(x, l->position);
    double r2 = vec3_dot(r, r);
    if (r2 <= 1e-12)
        return false;
    *dir = vec3_scale(r, 1.0 / sqrt(r2));
    if (l->kind == LIGHT_KIND_SPOT && vec3_dot(*dir, l->direction) < l->cos_spot)
        return false;
    *E = vec3_scale(scale, 1.0 / r2);
    return true;
}

bool reftrace_light_at(const struct reftrace_light *l, vec3 x, vec3 *E, vec3 *dir)
{
    *E = (vec3){0, 0, 0};
    *dir = (vec3){0, -1, 0};
    vec3 scale = {l->scale[0], l->scale[1], l->scale[2]};
    if (l->mode == LIGHT_MODE_OFF)
        return false;
    if (l->mode == LIGHT_MODE_VOLUME) {
        vec3 r = vec3_sub(x, l->bmin);
        double u[3] = {r.x / (l->dims[0] * l->voxel), r.y / (l->dims[1] * l->voxel),
                       r.z / (l->dims[2] * l->voxel)};
        for (int a = 0; a < 3; a++)
            if (u[a] < 0.0 || u[a] > 1.0)
                return false;
        vec3 v = {u[0] * l->dims[0] - 0.5, u[1] * l->dims[1] - 0.5, u[2] * l->dims[2] - 0.5};
        double d[4], e[4];
        voxel_sample_trilinear_f(l->direction_volume, 4, l->dims, v, d);
        double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (len <= 1e-6)
            return false;
        *dir = (vec3){d[0] / len, d[1] / len, d[2] / len};
        voxel_sample_trilinear_f(l->irradiance, 4, l->dims, v, e);
        *E = vec3_mul((vec3){e[0], e[1], e[2]}, scale);
        return true;
    }
    /* Unshadowed direct light (scenes without light simulation; LIGHT_MODE_WALTER outside
     * its in-scattering). */
    return reftrace_light_direct(l, x, E, dir);
}

vec3 reftrace_light_reflected(const struct reftrace_lighting *lt, const struct brdf_params *b,
                              vec3 x, vec3 d, vec3 nrm, double R)
{
    vec3 v = vec3_scale(d, -1.0);
    vec3 n = vec3_dot(nrm, v) < 0.0 ? vec3_scale(nrm, -1.0) : nrm;
    vec3 sum = {0, 0, 0};
    for (int j = 0; j < lt->count && j < MAX_LIGHTS; j++) {
        vec3 E, l;
        if (!reftrace_light_at(&lt->lights[j], x, &E, &l))
            continue;
        vec3 l_in = vec3_scale(l, -1.0);
        double c = vec3_dot(n, l_in);
        if (c <= 0.0)
            continue;
        double f[3];
        brdf_eval(b, v, l_in, n, f);
        sum = vec3_add(sum, vec3_scale(vec3_mul((vec3){f[0], f[1], f[2]}, E), c));
    }
    return vec3_scale(sum, R);
}

/* LIGHT_MODE_WALTER: sum over walter2009's exact paths through the sphere of p_HG E, E the
 * path's irradiance (walter.h); a light inside the sphere shines on x straight, attenuated
 * over the distance (lighting.glsl light_inscatter, walter.glsl). */
static vec3 walter_inscatter(const struct reftrace_walter *w, const struct reftrace_light *l,
                             vec3 x, vec3 toward_eye, double g)
{
    vec3 sum = {0, 0, 0};
    bool at_infinity = l->kind == LIGHT_KIND_DIRECTIONAL;
    vec3 scale = {l->scale[0], l->scale[1], l->scale[2]};
    if (!at_infinity && vec3_length(vec3_sub(l->position, w->center)) < w->radius) {
        vec3 E, dir;
        if (reftrace_light_direct(l, x, &E, &dir)) {
            double r = vec3_length(vec3_sub(x, l->position)),
                   ph = phase_hg(g, vec3_dot(dir, toward_eye));
            for (int c = 0; c < 3; c++)
                vec3_set(&sum, c, ph * vec3_get(E, c) * exp(-w->sigma_t[c] * r));
        }
        return sum;
    }
    vec3 sigma_t = {w->sigma_t[0], w->sigma_t[1], w->sigma_t[2]};
    vec3 e = walter_sphere_inscatter(w->center, w->radius, w->eta,
                                     at_infinity ? l->direction : l->position, at_infinity, x,
                                     vec3_scale(toward_eye, -1.0), g, sigma_t, l->direction,
                                     l->kind == LIGHT_KIND_SPOT ? l->cos_spot : -2.0);
    return vec3_mul(scale, e);
}

vec3 reftrace_light_inscatter(const struct reftrace_lighting *lt, vec3 x, vec3 d, vec3 sigma_s,
                              double g)
{
    vec3 sum = {0, 0, 0};
    vec3 toward_eye = vec3_scale(d, -1.0);
    for (int j = 0; j < lt->count && j < MAX_LIGHTS; j++) {
        if (lt->lights[j].mode == LIGHT_MODE_WALTER && lt->walter.enabled) {
            sum = vec3_add(sum, walter_inscatter(&lt->walter, &lt->lights[j], x, toward_eye, g));
            continue;
        }
        vec3 E, l;
        if (reftrace_light_at(&lt->lights[j], x, &E, &l))
            sum = vec3_madd(sum, E, phase_hg(g, vec3_dot(l, toward_eye)));
    }
    return vec3_mul(sigma_s, sum);
}

double reftrace_light_inscatter_step(const struct reftrace_lighting *lt)
{
    double voxel = 0.0;
    for (int j = 0; lt != NULL && j < lt->count && j < MAX_LIGHTS; j++) {
        double v = lt->lights[j].voxel;
        if (lt->lights[j].mode == LIGHT_MODE_VOLUME && v > 0.0)
            voxel = voxel > 0.0 ? fmin(voxel, v) : v;
    }
    return 0.5 * voxel;
}

bool reftrace_light_receiver(const struct reftrace_lighting *lt, vec3 env_up, vec3 x, vec3 d,
                             vec3 *L)
{
    *L = (vec3){0, 0, 0};
    const struct reftrace_receiver *rc = &lt->receiver;
    if (!rc->enabled || d.y >= 0.0)
        return false;
    double t = (rc->height - x.y) / d.y;
    if (t < 0.0)
        return false;
    vec3 hit = vec3_madd(x, d, t);
    if (fabs(hit.x - rc->center[0]) > rc->half_size || fabs(hit.z - rc->center[1]) > rc->half_size)
        return false;
    vec3 sum = {0, 0, 0};
    vec3 at = {hit.x, rc->height, hit.z};
    for (int j = 0; j < lt->count && j < MAX_LIGHTS; j++) {
        const struct reftrace_light *lj = &lt->lights[j];
        vec3 E, l;
        bool lit;
        if (lt->photon_scene != NULL) { /* docs/photons.md "The receiver" */
            if (reftrace_light_direct(lj, at, &E, &l) &&
                photon_light_visible(lt->photon_scene, j, at))
                sum = vec3_madd(sum, E, fmax(0.0, -l.y));
            if (lj->photons != NULL) {
                double Ep[3];
                photon_irradiance(lj->photons, at.x, at.z, Ep);
                sum = vec3_add(sum, (vec3){Ep[0] * lj->scale[0], Ep[1] * lj->scale[1],
                                           Ep[2] * lj->scale[2]});
            }
            continue;
        }
        if (lj->mode == LIGHT_MODE_VOLUME) {
            /* LIGHT_RECEIVER_INSET voxels inside the grid's x and z faces the volume
             * (shadows, caustics); elsewhere, where no object can shade the plane, the
             * closed form (docs/lightsim.md "Domain"). */
            const double in = LIGHT_RECEIVER_INSET;
            double ux = (at.x - lj->bmin.x) / lj->voxel, uz = (at.z - lj->bmin.z) / lj->voxel;
            bool in_grid = ux >= in && ux <= lj->dims[0] - in && uz >= in && uz <= lj->dims[2] - in;
            lit =
                in_grid ? reftrace_light_at(lj, at, &E, &l) : reftrace_light_direct(lj, at, &E, &l);
        } else {
            lit = reftrace_light_at(lj, at, &E, &l);
        }
        if (lit)
            sum = vec3_madd(sum, E, fmax(0.0, -l.y));
    }
    vec3 albedo = {rc->albedo[0], rc->albedo[1], rc->albedo[2]};
    *L = vec3_add(vec3_scale(vec3_mul(albedo, sum), 1.0 / M_PI), vec3_mul(albedo, env_up));
    return true;
}

bool reftrace_light_emitter(const struct reftrace_lighting *lt, vec3 x, vec3 d, double t_max,
                            bool primary, vec3 *L)
{
    *L = (vec3){0, 0, 0};
    bool hit = false;
    for (int j = 0; lt != NULL && j < lt->count && j < MAX_LIGHTS; j++) {
        const struct reftrace_light *lj = &lt->lights[j];
        double r = lj->radius;
        if (lj->kind != LIGHT_KIND_POINT || !(r > 0.0) || (primary && lj->camera_hidden))
            continue;
        vec3 oc = vec3_sub(x, lj->position);
        double b = vec3_dot(oc, d), c = vec3_dot(oc, oc) - r * r, disc = b * b - c;
        if (disc < 0.0)
            continue;
        double sq = sqrt(disc), t = -b - sq;
        if (t < 0.0)
            t = -b + sq; /* x inside the lamp: its far side */
        if (!(t > 0.0) || t >= t_max)
            continue;
        t_max = t;
        double k = 1.0 / (M_PI * r * r);
        *L = (vec3){lj->scale[0] * k, lj->scale[1] * k, lj->scale[2] * k};
        hit = true;
    }
    return hit;
}
