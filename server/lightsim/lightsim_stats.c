/*
 * lightsim_stats.c - the energy bookkeeping identity of docs/lightsim.md: flux_in =
 * flux_out + flux_reflected + flux_absorbed + flux_culled + flux_live.
 */
#include <math.h>

#include "lightsim.h"

double lightsim_stats_imbalance(const struct lightsim_stats *s)
{
    double worst = 0.0;
    for (int c = 0; c < 3; c++) {
        if (!(s->flux_in[c] > 0.0))
            continue;
        double sum = s->flux_out[c] + s->flux_reflected[c] + s->flux_absorbed[c] +
                     s->flux_culled[c] + s->flux_live[c];
        double r = fabs(s->flux_in[c] - sum) / s->flux_in[c];
        worst = r > worst ? r : worst;
    }
    return worst;
}
