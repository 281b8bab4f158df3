/*
 * xform.h - similarity transforms (translation, rotation, uniform scale) of scene
 * objects, in double precision.
 *
 * world_from_object(p) = translate + scale * R * p. With a similarity transform the
 * ray equation d/ds(n dx/ds) = grad n (tevs2007 eq. 4.7) keeps its form in object
 * space (lengths scale by 1/scale, gradients by scale), which is why the renderer may
 * integrate in object space; positions go through M^-1 and gradients through
 * (M^-1)^T as in the thesis' pseudo code (sect. 6.3.1).
 *
 * Matrices are row-major 4x4 here; xform_to_gl_mat4 writes column-major floats for
 * GLSL's mat4.
 */
#ifndef REFRACT_XFORM_H
#define REFRACT_XFORM_H

#include "vec3.h"

struct xform {
    vec3 translate;
    double rot[3][3]; /* rotation, row-major; object axes -> world axes */
    double scale;     /* uniform, > 0 */
};

/* Identity transform. */
struct xform xform_identity(void);
/* Rotation of angle_deg about axis (any length > 0), then uniform scale, then translate. */
struct xform xform_make(vec3 translate, vec3 axis, double angle_deg, double scale);
/* a after b: (a o b)(p) = a(b(p)), again a similarity transform. */
struct xform xform_compose(const struct xform *a, const struct xform *b);
/* Point / direction / gradient maps. */
vec3 xform_point_to_world(const struct xform *x, vec3 p_object);
vec3 xform_point_to_object(const struct xform *x, vec3 p_world);
/* Rotation only (unit directions stay unit). */
vec3 xform_dir_to_world(const struct xform *x, vec3 d_object);
vec3 xform_dir_to_object(const struct xform *x, vec3 d_world);
/* grad_world = (M^-1)^T grad_object = R grad_object / scale. */
vec3 xform_gradient_to_world(const struct xform *x, vec3 g_object);
/* Column-major 4x4 float matrices for GLSL: world_from_object and object_from_world. */
void xform_to_gl_mat4(const struct xform *x, float world_from_object[16],
                      float object_from_world[16]);

#endif
