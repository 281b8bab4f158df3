/*
 * grin.c - the analytic GRIN profiles of grin.h.
 */
#include "grin.h"

#include <string.h>

static const char *const kind_names[] = {"luneburg", "maxwell_fisheye", "linear", "gaussian"};

const char *grin_kind_name(enum grin_kind k)
{
    return (k >= 0 && k <= GRIN_GAUSSIAN) ? kind_names[k] : "unknown";
}

int grin_kind_parse(const char *name)
{
    for (int i = 0; i <= GRIN_GAUSSIAN; i++) {
        if (strcmp(name, kind_names[i]) == 0)
            return i;
    }
    return -1;
}

double grin_ior(const struct grin_profile *g, vec3 p, vec3 *grad)
{
    vec3 d = vec3_sub(p, g->center);
    double r2 = vec3_dot(d, d);
    vec3 zero = {0, 0, 0};
    switch (g->kind) {
    case GRIN_LUNEBURG: {
        double R2 = g->radius * g->radius;
        if (r2 > R2) {
            if (grad)
                *grad = zero;
            return 1.0;
        }
        double n = sqrt(2.0 - r2 / R2);
        /* dn/dx = -x / (R^2 n) */
        if (grad)
            *grad = vec3_scale(d, -1.0 / (R2 * n));
        return n;
    }
    case GRIN_MAXWELL_FISHEYE: {
        double R2 = g->radius * g->radius;
        if (r2 > R2) {
            if (grad)
                *grad = zero;
            return g->n0 * 0.5;
        }
        double q = 1.0 + r2 / R2;
        /* dn/dx = -n0 * 2x / (R^2 q^2) */
        if (grad)
            *grad = vec3_scale(d, -2.0 * g->n0 / (R2 * q * q));
        return g->n0 / q;
    }
    case GRIN_LINEAR:
        if (grad)
            *grad = g->gradient;
        return g->n0 + vec3_dot(g->gradient, d);
    case GRIN_GAUSSIAN: {
        double s2 = g->sigma * g->sigma;
        double e = exp(-r2 / (2.0 * s2));
        if (grad)
            *grad = vec3_scale(d, -(g->n_peak - g->n_out) * e / s2);
        return g->n_out + (g->n_peak - g->n_out) * e;
    }
    }
    if (grad)
        *grad = zero;
    return 1.0;
}
