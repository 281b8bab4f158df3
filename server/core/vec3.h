/*
 * vec3.h - double-precision 3-vectors for the CPU reference code (core/, scene/).
 *
 * The GPU uses float vec3 in GLSL; these are the double twins used by the reference
 * tracer and by field evaluation. Header-only: every function is static inline and
 * pure. Directions are unit length unless a name says otherwise.
 */
#ifndef REFRACT_VEC3_H
#define REFRACT_VEC3_H

#include <math.h>
#include <stdbool.h>

typedef struct {
    double x, y, z;
} vec3;

static inline vec3 vec3_make(double x, double y, double z)
{
    return (vec3){x, y, z};
}
static inline vec3 vec3_add(vec3 a, vec3 b)
{
    return (vec3){a.x + b.x, a.y + b.y, a.z + b.z};
}
static inline vec3 vec3_sub(vec3 a, vec3 b)
{
    return (vec3){a.x - b.x, a.y - b.y, a.z - b.z};
}
static inline vec3 vec3_scale(vec3 a, double s)
{
    return (vec3){a.x * s, a.y * s, a.z * s};
}
/* a + b * s */
static inline vec3 vec3_madd(vec3 a, vec3 b, double s)
{
    return (vec3){a.x + b.x * s, a.y + b.y * s, a.z + b.z * s};
}
static inline vec3 vec3_mul(vec3 a, vec3 b)
{
    return (vec3){a.x * b.x, a.y * b.y, a.z * b.z};
}
static inline double vec3_dot(vec3 a, vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
static inline vec3 vec3_cross(vec3 a, vec3 b)
{
    return (vec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static inline double vec3_length(vec3 a)
{
    return sqrt(vec3_dot(a, a));
}
/* Returns a / |a|; the zero vector stays zero (callers validate directions first). */
static inline vec3 vec3_normalize(vec3 a)
{
    double l = vec3_length(a);
    return l > 0.0 ? vec3_scale(a, 1.0 / l) : a;
}
static inline bool vec3_is_finite(vec3 a)
{
    return isfinite(a.x) && isfinite(a.y) && isfinite(a.z);
}
static inline double vec3_get(vec3 a, int axis)
{
    return axis == 0 ? a.x : (axis == 1 ? a.y : a.z);
}
static inline void vec3_set(vec3 *a, int axis, double v)
{
    if (axis == 0)
        a->x = v;
    else if (axis == 1)
        a->y = v;
    else
        a->z = v;
}
/* Mirror reflection of direction d about unit normal nrm (either orientation). */
static inline vec3 vec3_reflect(vec3 d, vec3 nrm)
{
    return vec3_madd(d, nrm, -2.0 * vec3_dot(d, nrm));
}

#endif
