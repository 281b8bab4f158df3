/*
 * pathtrace_medium.c - free flights in a homogeneous medium (pathtrace.h).
 *
 * A medium whose sigma_t differs between channels is sampled with one channel chosen
 * uniformly per flight and the estimator weighted by the mean of the three channels'
 * pdfs: the one-sample balance heuristic over channels (pbrt-v3,
 * HomogeneousMedium::Sample). For a grey medium the weight is exactly sigma_s / sigma_t
 * (the single-scattering albedo) at a collision and 1 past the segment.
 */
#include <math.h>

#include "pathtrace.h"

bool pathtrace_medium_scatters(const struct pathtrace_medium *m)
{
    return m->sigma_s[0] > 0.0 || m->sigma_s[1] > 0.0 || m->sigma_s[2] > 0.0;
}

void pathtrace_medium_transmittance(const struct pathtrace_medium *m, double d, double tr[3])
{
    for (int c = 0; c < 3; c++) {
        double st = m->sigma_a[c] + m->sigma_s[c];
        if (st > 0.0)
            tr[c] *= isinf(d) ? 0.0 : exp(-st * d);
    }
}

bool pathtrace_medium_sample(const struct pathtrace_medium *m, double t_max,
                             struct pathtrace_rng *rng, double weight[3], double *t)
{
    if (!pathtrace_medium_scatters(m)) {
        pathtrace_medium_transmittance(m, t_max, weight);
        return false;
    }
    double st[3];
    for (int c = 0; c < 3; c++)
        st[c] = m->sigma_a[c] + m->sigma_s[c];
    int ch = (int)(pathtrace_rng_uniform(rng) * 3.0);
    if (ch > 2)
        ch = 2;
    double tt = st[ch] > 0.0 ? -log(1.0 - pathtrace_rng_uniform(rng)) / st[ch] : INFINITY;
    bool collide = tt < t_max;
    double d = collide ? tt : t_max;
    double tr[3], pdf = 0.0;
    for (int c = 0; c < 3; c++) {
        tr[c] = isinf(d) ? (st[c] > 0.0 ? 0.0 : 1.0) : exp(-st[c] * d);
        /* collision: density sigma_t T; crossing: probability T */
        pdf += (collide ? st[c] * tr[c] : tr[c]) / 3.0;
    }
    for (int c = 0; c < 3; c++)
        weight[c] *= pdf > 0.0 ? (collide ? tr[c] * m->sigma_s[c] : tr[c]) / pdf : 0.0;
    *t = d;
    return collide;
}
