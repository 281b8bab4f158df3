/*
 * medium_step.c - see medium_step.h. Twin of shaders/medium_step.glsl.
 */
#include "medium_step.h"

#include <math.h>

double medium_step_weight(double sigma_t, double h)
{
    return sigma_t > 0.0 ? -expm1(-sigma_t * h) / sigma_t : h; /* expm1: no cancellation */
}

int medium_step_count(double t, double step)
{
    if (!(t > 0.0))
        return 1;
    if (!(step > 0.0))
        return MEDIUM_DIRECT_STEPS;
    double n = ceil(t / step);
    return n < 1.0 ? 1 : n > MEDIUM_MAX_STEPS ? MEDIUM_MAX_STEPS : (int)n;
}
