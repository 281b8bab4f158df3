/*
 * half_float.c - see half_float.h.
 */
#include "half_float.h"

#include <math.h>

double half_float_round(double x)
{
    if (isnan(x))
        return x;
    double ax = fabs(x);
    if (ax >= HALF_FLOAT_MAX)
        return copysign(HALF_FLOAT_MAX, x);
    if (ax < 0x1p-14) /* subnormal halves: multiples of 2^-24 */
        return copysign(round(ax * 0x1p24) * 0x1p-24, x);
    int ex;
    double m = frexp(ax, &ex); /* 0.5 <= m < 1; 11 significant bits: 2048 steps */
    double r = ldexp(round(m * 2048.0) / 2048.0, ex);
    return copysign(fmin(r, HALF_FLOAT_MAX), x);
}
