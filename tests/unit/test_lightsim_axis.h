/*
 * test_lightsim_axis.h - reading a ball lens's focus off an irradiance volume (the light
 * simulator tests on the CPU and the GPU): E on the axis x = z = 0, and its maximum refined
 * by a least-squares parabola. Header-only; not a test itself.
 */
#ifndef REFRACT_TEST_LIGHTSIM_AXIS_H
#define REFRACT_TEST_LIGHTSIM_AXIS_H

#include <math.h>
#include <stdio.h>

#include "lightsim/lightsim.h"

/* E on the axis x = z = 0 at height y: trilinear in the float volume. */
static inline double axis_E(const struct irradiance_volume *v, double y)
{
    const struct light_grid *g = &v->grid;
    vec3 c = vec3_sub(vec3_scale(vec3_sub((vec3){0, y, 0}, g->bmin), 1.0 / g->voxel),
                      (vec3){0.5, 0.5, 0.5});
    int i0 = (int)floor(c.x), j0 = (int)floor(c.y), k0 = (int)floor(c.z);
    double fx = c.x - i0, fy = c.y - j0, fz = c.z - k0, E = 0.0;
    for (int q = 0; q < 8; q++) {
        int a = q & 1, b = (q >> 1) & 1, d = q >> 2;
        E += (a ? fx : 1 - fx) * (b ? fy : 1 - fy) * (d ? fz : 1 - fz) *
             v->irradiance[4 * ((size_t)(i0 + a) + (size_t)g->dims[0] * ((size_t)(j0 + b) + (size_t)g->dims[1] * (size_t)(k0 + d)))];
    }
    return E;
}

/* The axis maximum between y_hi and y_lo: the largest sample (steps of a tenth of a
 * voxel), refined by the least-squares parabola through the samples within half_width of
 * it. Returns the refined y; *E_max the largest sample. */
static inline double axis_focus(const struct irradiance_volume *v, double y_hi, double y_lo,
                         double half_width, double *E_max)
{
    double dy = 0.1 * v->grid.voxel, y_best = y_hi;
    *E_max = 0.0;
    for (double y = y_hi; y >= y_lo; y -= dy) {
        double E = axis_E(v, y);
        if (E > *E_max) {
            *E_max = E;
            y_best = y;
        }
    }
    /* fit E = a + b u + c u^2, u = y - y_best: normal equations */
    double S[5] = {0}, T[3] = {0};
    for (double u = -half_width; u <= half_width + 1e-12; u += dy) {
        double E = axis_E(v, y_best + u), p = 1.0;
        for (int k = 0; k < 5; k++, p *= u)
            S[k] += p;
        T[0] += E;
        T[1] += E * u;
        T[2] += E * u * u;
    }
    double m[3][4] = {{S[0], S[1], S[2], T[0]}, {S[1], S[2], S[3], T[1]}, {S[2], S[3], S[4], T[2]}};
    for (int i = 0; i < 3; i++)
        for (int r = i + 1; r < 3; r++) {
            double q = m[r][i] / m[i][i];
            for (int col = i; col < 4; col++)
                m[r][col] -= q * m[i][col];
        }
    double c = m[2][3] / m[2][2];
    double b = (m[1][3] - m[1][2] * c) / m[1][1];
    if (!(c < 0.0))
        return y_best; /* not a maximum: keep the sample */
    double u0 = -b / (2.0 * c);
    return fabs(u0) <= half_width ? y_best + u0 : y_best;
}

/* The ball lens scene of issue 12's acceptance: a ball of radius R and index n at the
 * origin, stopped down by an absorbing plate (a box surface of index 1, sigma 2000) with a
 * cylinder of air of higher priority as its hole of radius a, over a receiver 0.12 below
 * the paraxial focus n R / (2 (n - 1)). No voxel object. ball: the ball surface's shape
 * keys (ball_lens_json: the exact sphere; a mesh of the unit sphere scaled by R works
 * too). */
static inline void ball_lens_json_shape(char *json, size_t size, const char *ball, double R,
                                        double n, double a)
{
    double f_eff = n * R / (2.0 * (n - 1.0));
    snprintf(json, size,
             "{\"surfaces\": ["
             "{\"name\": \"ball\", %s, \"medium\": {\"ior\": %.17g}},"
             "{\"name\": \"stop\", \"shape\": \"box\", \"center\": [0, %.17g, 0], "
             "\"size\": [%.17g, 0.03, %.17g], \"priority\": 1, "
             "\"medium\": {\"ior\": 1, \"attenuation\": [2000, 2000, 2000]}},"
             "{\"name\": \"hole\", \"shape\": \"cylinder\", \"center\": [0, %.17g, 0], "
             "\"radius\": %g, \"height\": 0.06, \"axis\": \"y\", \"priority\": 2, "
             "\"medium\": {\"ior\": 1}}],"
             " \"receiver\": {\"height\": %.17g, \"half_size\": %.17g}}",
             ball, n, R + 0.07, 2.0 * R + 0.04, 2.0 * R + 0.04, R + 0.07, a, -f_eff - 0.12, R + 0.02);
}

static inline void ball_lens_json(char *json, size_t size, double R, double n, double a)
{
    char ball[128];
    snprintf(ball, sizeof ball, "\"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": %g",
             R);
    ball_lens_json_shape(json, size, ball, R, n, a);
}

#endif
