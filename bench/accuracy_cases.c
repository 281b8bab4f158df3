/*
 * accuracy_cases.c - see accuracy_cases.h.
 */
#include "accuracy_cases.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/optics_exact.h"
#include "core/ray_status.h"
#include "scene/scene.h"
#include "scene/scene_reference.h"

#define SPHERE_RADIUS 0.8

const struct accuracy_case accuracy_cases[ACCURACY_CASE_COUNT] = {
    {"luneburg", "Luneburg lens",
     "n = sqrt(2 - r^2), R = 1; a parallel bundle over 95% of the aperture focuses on the far "
     "surface",
     ACCURACY_REF_DOPRI, 0.0, 0.0},
    {"fisheye", "Maxwell fish-eye",
     "n = 2 / (1 + r^2), R = 1; rays from a surface point in a 60-degree cone image to its "
     "antipode",
     ACCURACY_REF_DOPRI, 0.0, 0.0},
    {"mirage", "Linear gradient (mirage)",
     "n = 1.3 + 0.3 y in a cube; rays entering 4-16 degrees downwards turn around and leave "
     "upwards",
     ACCURACY_REF_DOPRI, 0.0, 0.0},
    {"gaussian", "Strong Gaussian lens",
     "n = 1 + exp(-r^2 / (2 * 0.2^2)) (n_peak 2); a parallel bundle over r < 0.6",
     ACCURACY_REF_DOPRI, 0.0, 0.0},
    {"sphere15", "Sharp sphere n = 1.5",
     "homogeneous ball n = 1.5, R = 0.8, smoothed; a parallel bundle over r < 0.8 R, against "
     "Snell's law",
     ACCURACY_REF_SNELL, 1.5, 1.0},
    {"sphere242", "Sharp sphere n = 2.42",
     "homogeneous ball n = 2.42 (diamond), R = 0.8, smoothed; a parallel bundle over r < 0.8 R, "
     "against Snell's law",
     ACCURACY_REF_SNELL, 2.42, 1.0},
};

bool accuracy_case_json(const struct accuracy_case *c, int res, double sigma, bool float16,
                        char *buf, size_t size)
{
    const char *ior;
    double half = 1.05;
    char sphere[160];
    if (!strcmp(c->name, "luneburg")) {
        ior = "{\"profile\": \"luneburg\", \"center\": [0, 0, 0], \"radius\": 1.0}";
    } else if (!strcmp(c->name, "fisheye")) {
        ior = "{\"profile\": \"maxwell_fisheye\", \"center\": [0, 0, 0], \"radius\": 1.0, "
              "\"n0\": 2.0}";
    } else if (!strcmp(c->name, "mirage")) {
        ior = "{\"profile\": \"linear\", \"center\": [0, 0, 0], \"n0\": 1.3, "
              "\"gradient\": [0, 0.3, 0]}";
        half = 1.0;
    } else if (!strcmp(c->name, "gaussian")) {
        ior = "{\"profile\": \"gaussian\", \"center\": [0, 0, 0], \"n_peak\": 2.0, "
              "\"n_out\": 1.0, \"sigma\": 0.2}";
        half = 1.2; /* 6 sigma: n - 1 = 1.5e-8 at the faces */
    } else {
        snprintf(sphere, sizeof sphere,
                 "{\"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": %g, \"inside\": %g}",
                 SPHERE_RADIUS, c->sphere_n);
        ior = sphere;
        half = 1.0;
    }
    int n = snprintf(buf, size,
                     "{\"name\": \"%s\", \"render\": {\"ior_texture\": \"%s\", \"max_steps\": "
                     "100000}, \"objects\": [{\"bounds\": {\"min\": [%g, %g, %g], \"max\": [%g, "
                     "%g, %g]}, \"resolution\": %d, \"smoothing_sigma\": %g, \"ior\": %s}]}",
                     c->name, float16 ? "float16" : "float32", -half, -half, -half, half, half,
                     half, res, sigma, ior);
    return n > 0 && (size_t)n < size;
}

/* Shirley's concentric map of the unit square onto the unit disc: uniform, all inside. */
static void concentric(double u, double v, double *x, double *y)
{
    double a = 2.0 * u - 1.0, b = 2.0 * v - 1.0, r, phi;
    if (a == 0.0 && b == 0.0) {
        *x = *y = 0.0;
        return;
    }
    if (fabs(a) > fabs(b)) {
        r = a;
        phi = (M_PI / 4.0) * (b / a);
    } else {
        r = b;
        phi = M_PI / 2.0 - (M_PI / 4.0) * (a / b);
    }
    *x = r * cos(phi);
    *y = r * sin(phi);
}

static void set_ray(struct render_trace_ray *r, vec3 o, vec3 d)
{
    d = vec3_normalize(d);
    r->origin[0] = o.x;
    r->origin[1] = o.y;
    r->origin[2] = o.z;
    r->direction[0] = d.x;
    r->direction[1] = d.y;
    r->direction[2] = d.z;
}

void accuracy_case_rays(const struct accuracy_case *c, int side, struct render_trace_ray *rays)
{
    for (int j = 0; j < side; j++)
        for (int i = 0; i < side; i++) {
            double u = (i + 0.5) / side, v = (j + 0.5) / side, x, y;
            struct render_trace_ray *r = &rays[j * side + i];
            if (!strcmp(c->name, "fisheye")) {
                /* From P = (0, 0, -1) into a cone of 60 degrees about +z; the origin lies
                 * outside the bounds on the same line (n = 1 there: a straight approach). */
                concentric(u, v, &x, &y);
                double rho = sqrt(x * x + y * y), theta = rho * (M_PI / 3.0);
                double phi = atan2(y, x);
                vec3 d = {sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta)};
                set_ray(r, vec3_madd((vec3){0, 0, -1}, d, -0.5), d);
            } else if (!strcmp(c->name, "mirage")) {
                double y0 = 0.3 + 0.6 * u, theta = (4.0 + 12.0 * v) * M_PI / 180.0;
                double z0 = -0.5 + v; /* spread over z too: not all in one voxel plane */
                set_ray(r, (vec3){-1.5, y0, z0}, (vec3){cos(theta), -sin(theta), 0.0});
            } else {
                double aperture = !strcmp(c->name, "luneburg")   ? 0.95
                                  : !strcmp(c->name, "gaussian") ? 0.6
                                                                 : 0.8 * SPHERE_RADIUS;
                concentric(u, v, &x, &y);
                set_ray(r, (vec3){aperture * x, aperture * y, -1.6}, (vec3){0, 0, 1});
            }
        }
}

bool accuracy_case_reference(const struct accuracy_case *c, const struct render_trace_ray *rays,
                             int count, struct accuracy_exit *out)
{
    if (c->reference == ACCURACY_REF_SNELL) {
        for (int k = 0; k < count; k++) {
            vec3 o = {rays[k].origin[0], rays[k].origin[1], rays[k].origin[2]};
            vec3 d = {rays[k].direction[0], rays[k].direction[1], rays[k].direction[2]};
            out[k].valid = optics_sphere_transmit((vec3){0, 0, 0}, SPHERE_RADIUS, c->sphere_n, 1.0,
                                                  o, d, &out[k].point, &out[k].dir);
        }
        return true;
    }
    char json[1024];
    struct scene *s = NULL;
    struct scene_limits lim = scene_limits_default();
    struct err e = {0};
    if (!accuracy_case_json(c, 128, 0.0, false, json, sizeof json) ||
        scene_parse(json, strlen(json), &lim, &s, &e) != REFRACT_E_OK) {
        fprintf(stderr, "refract-accuracy: %s: %s\n", c->name, e.msg);
        return false;
    }
    struct scene_reference ref;
    if (scene_reference_build(s, SCENE_REFERENCE_ANALYTIC, NULL, NULL, &ref, &e) != REFRACT_E_OK) {
        fprintf(stderr, "refract-accuracy: %s: %s\n", c->name, e.msg);
        scene_destroy(s);
        return false;
    }
    struct reftrace_settings st = ref.settings;
    st.stepper = REFTRACE_ADAPTIVE;
    st.tolerance = 1e-10;
    st.step_voxels = 1.0;
    st.max_steps = 10000000;
    for (int k = 0; k < count; k++) {
        vec3 o = {rays[k].origin[0], rays[k].origin[1], rays[k].origin[2]};
        vec3 d = {rays[k].direction[0], rays[k].direction[1], rays[k].direction[2]};
        struct reftrace_result r;
        reftrace_ray(ref.objects, ref.count, &st, o, d, &r);
        out[k].valid = r.status == RAY_EXITED;
        out[k].point = r.exit_origin;
        out[k].dir = vec3_normalize(r.exit_direction);
    }
    scene_reference_free(&ref);
    scene_destroy(s);
    return true;
}

void accuracy_exit_error(const struct accuracy_exit *ref, const struct render_trace_hit *hit,
                         double *angle, double *distance)
{
    vec3 d = vec3_normalize(
        (vec3){hit->exit_direction[0], hit->exit_direction[1], hit->exit_direction[2]});
    vec3 p = {hit->exit_origin[0], hit->exit_origin[1], hit->exit_origin[2]};
    *angle = acos(fmax(-1.0, fmin(1.0, vec3_dot(d, ref->dir))));
    vec3 rp = vec3_sub(p, ref->point);
    *distance = vec3_length(vec3_sub(rp, vec3_scale(ref->dir, vec3_dot(rp, ref->dir))));
}
