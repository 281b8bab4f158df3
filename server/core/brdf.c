/*
 * brdf.c - Lambert, normalised Phong and GGX; see brdf.h.
 */
#include "brdf.h"

#include <math.h>

#include "bindings.h"

double brdf_ggx_d(double alpha, double cos_h)
{
    double a2 = alpha * alpha;
    double t = cos_h * cos_h * (a2 - 1.0) + 1.0;
    return a2 / (M_PI * t * t);
}

static double smith_g1(double a2, double c)
{
    return 2.0 * c / (c + sqrt(a2 + (1.0 - a2) * c * c));
}

void brdf_eval(const struct brdf_params *b, vec3 v, vec3 l_in, vec3 n, double out[3])
{
    out[0] = out[1] = out[2] = 0.0;
    double cos_i = vec3_dot(n, l_in), cos_o = vec3_dot(n, v);
    if (b->kind == BRDF_NONE || cos_i <= 0.0 || cos_o <= 0.0)
        return;
    double f;
    if (b->kind == BRDF_LAMBERT) {
        f = 1.0 / M_PI;
    } else if (b->kind == BRDF_PHONG) {
        double c = fmax(vec3_dot(vec3_reflect(vec3_scale(l_in, -1.0), n), v), 0.0);
        f = (b->exponent + 2.0) / (2.0 * M_PI) * pow(c, b->exponent);
    } else {
        double a2 = b->alpha * b->alpha;
        vec3 h = vec3_normalize(vec3_add(v, l_in));
        double D = brdf_ggx_d(b->alpha, fmax(vec3_dot(n, h), 0.0));
        f = D * smith_g1(a2, cos_i) * smith_g1(a2, cos_o) / (4.0 * cos_i * cos_o);
    }
    for (int c = 0; c < 3; c++)
        out[c] = b->color[c] * f;
}
