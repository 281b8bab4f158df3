/*
 * xform.c - similarity transforms; see xform.h for conventions.
 */
#include "xform.h"

#include <math.h>

struct xform xform_identity(void)
{
    struct xform x = {.translate = {0, 0, 0}, .scale = 1.0};
    for (int i = 0; i < 3; i++)
        x.rot[i][i] = 1.0;
    return x;
}

struct xform xform_make(vec3 translate, vec3 axis, double angle_deg, double scale)
{
    struct xform x = xform_identity();
    x.translate = translate;
    x.scale = scale;
    vec3 a = vec3_normalize(axis);
    if (vec3_length(a) == 0.0 || angle_deg == 0.0)
        return x;
    /* Rodrigues' rotation formula. */
    double t = angle_deg * M_PI / 180.0;
    double c = cos(t), s = sin(t), k = 1.0 - c;
    x.rot[0][0] = c + a.x * a.x * k;
    x.rot[0][1] = a.x * a.y * k - a.z * s;
    x.rot[0][2] = a.x * a.z * k + a.y * s;
    x.rot[1][0] = a.y * a.x * k + a.z * s;
    x.rot[1][1] = c + a.y * a.y * k;
    x.rot[1][2] = a.y * a.z * k - a.x * s;
    x.rot[2][0] = a.z * a.x * k - a.y * s;
    x.rot[2][1] = a.z * a.y * k + a.x * s;
    x.rot[2][2] = c + a.z * a.z * k;
    return x;
}

static vec3 rotate(const double r[3][3], vec3 v);

struct xform xform_compose(const struct xform *a, const struct xform *b)
{
    /* a(b(p)) = a.t + a.s a.R (b.t + b.s b.R p) = (a.t + a.s a.R b.t) + a.s b.s (a.R b.R) p */
    struct xform x;
    x.scale = a->scale * b->scale;
    x.translate = vec3_add(a->translate, vec3_scale(rotate(a->rot, b->translate), a->scale));
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            x.rot[i][j] = a->rot[i][0] * b->rot[0][j] + a->rot[i][1] * b->rot[1][j] +
                          a->rot[i][2] * b->rot[2][j];
    return x;
}

static vec3 rotate(const double r[3][3], vec3 v)
{
    return (vec3){r[0][0] * v.x + r[0][1] * v.y + r[0][2] * v.z,
                  r[1][0] * v.x + r[1][1] * v.y + r[1][2] * v.z,
                  r[2][0] * v.x + r[2][1] * v.y + r[2][2] * v.z};
}

static vec3 rotate_transposed(const double r[3][3], vec3 v)
{
    return (vec3){r[0][0] * v.x + r[1][0] * v.y + r[2][0] * v.z,
                  r[0][1] * v.x + r[1][1] * v.y + r[2][1] * v.z,
                  r[0][2] * v.x + r[1][2] * v.y + r[2][2] * v.z};
}

vec3 xform_point_to_world(const struct xform *x, vec3 p)
{
    return vec3_add(x->translate, vec3_scale(rotate(x->rot, p), x->scale));
}

vec3 xform_point_to_object(const struct xform *x, vec3 p)
{
    return vec3_scale(rotate_transposed(x->rot, vec3_sub(p, x->translate)), 1.0 / x->scale);
}

vec3 xform_dir_to_world(const struct xform *x, vec3 d)
{
    return rotate(x->rot, d);
}

vec3 xform_dir_to_object(const struct xform *x, vec3 d)
{
    return rotate_transposed(x->rot, d);
}

vec3 xform_gradient_to_world(const struct xform *x, vec3 g)
{
    return vec3_scale(rotate(x->rot, g), 1.0 / x->scale);
}

void xform_to_gl_mat4(const struct xform *x, float w_from_o[16], float o_from_w[16])
{
    /* Column-major: element (row r, column c) at [c * 4 + r]. */
    for (int i = 0; i < 16; i++) {
        w_from_o[i] = 0.0f;
        o_from_w[i] = 0.0f;
    }
    double inv_s = 1.0 / x->scale;
    double t_obj[3];
    vec3 ti = rotate_transposed(x->rot, x->translate);
    t_obj[0] = -ti.x * inv_s;
    t_obj[1] = -ti.y * inv_s;
    t_obj[2] = -ti.z * inv_s;
    double tw[3] = {x->translate.x, x->translate.y, x->translate.z};
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++) {
            w_from_o[c * 4 + r] = (float)(x->rot[r][c] * x->scale);
            o_from_w[c * 4 + r] = (float)(x->rot[c][r] * inv_s);
        }
        w_from_o[12 + r] = (float)tw[r];
        o_from_w[12 + r] = (float)t_obj[r];
    }
    w_from_o[15] = 1.0f;
    o_from_w[15] = 1.0f;
}
