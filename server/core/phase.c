/*
 * phase.c - Henyey-Greenstein phase function; see phase.h.
 */
#include "phase.h"

#include <math.h>

double phase_hg(double g, double cos_theta)
{
    double d = 1.0 + g * g - 2.0 * g * cos_theta;
    return (1.0 - g * g) / (4.0 * M_PI * d * sqrt(d));
}
