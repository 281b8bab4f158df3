/*
 * mie_distribution.c - particle size distributions, discretised for the midpoint rule
 * sigma = sum_i C(r_i) N(r_i) dr (frisvad2010 slide "Bulk optical properties of a
 * material": sigma_s = integral from r_min to r_max of C_s(r) N(r) dr).
 *
 * The weights are relative numbers of particles per bin; mie_medium.c scales them to the
 * population's volume fraction or number density, so no distribution here needs its own
 * normalisation constant.
 */
#include <math.h>

#include "mie.h"

#define DEFAULT_BINS 200

/* t(r): the radius the log-normal is written in (see mie.h). */
static double lognormal_t(const struct mie_distribution *d, double r)
{
    return d->t_bound > 0.0 ? r / (d->t_bound - r) : r * 1e6;
}

int mie_distribution_bins(const struct mie_distribution *d, double *r, double *number, int cap)
{
    if (d->kind == MIE_DIST_MONODISPERSE) {
        if (cap < 1 || !(d->r_vs > 0.0))
            return 0;
        r[0] = d->r_vs;
        number[0] = 1.0;
        return 1;
    }
    int bins = d->bins > 0 ? d->bins : DEFAULT_BINS;
    if (bins > cap || !(d->r_min >= 0.0) || !(d->r_max > d->r_min))
        return 0;
    double dr = (d->r_max - d->r_min) / bins;
    if (d->kind == MIE_DIST_LOGNORMAL) {
        if (!(d->r_vs > d->r_min) || !(d->r_vs < d->r_max) || !(d->c_s > 0.0))
            return 0;
        if (d->t_bound > 0.0 && d->r_max > d->t_bound)
            return 0;
        double t_vs = lognormal_t(d, d->r_vs);
        double beta2 = log(d->c_s * d->c_s / (t_vs * t_vs) + 1.0);
        double alpha = log(t_vs) - 0.5 * beta2, beta = sqrt(beta2);
        for (int i = 0; i < bins; i++) {
            r[i] = d->r_min + (i + 0.5) * dr;
            double t = lognormal_t(d, r[i]);
            double u = (log(t) - alpha) / beta;
            double volume_share = exp(-0.5 * u * u) / (t * beta * sqrt(2.0 * M_PI));
            /* A share of volume in a bin is that many spheres of volume 4/3 pi r^3. */
            number[i] = volume_share / (4.0 / 3.0 * M_PI * r[i] * r[i] * r[i]);
        }
        return bins;
    }
    if (d->kind == MIE_DIST_POWER_LAW) {
        if (!(d->r_min > 0.0) || !isfinite(d->exponent))
            return 0;
        for (int i = 0; i < bins; i++) {
            r[i] = d->r_min + (i + 0.5) * dr;
            number[i] = pow(r[i] / d->r_min, -d->exponent);
        }
        return bins;
    }
    return 0;
}
