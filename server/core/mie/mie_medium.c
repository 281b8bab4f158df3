/*
 * mie_medium.c - bulk coefficients of particle populations in a host, per wavelength
 * (frisvad2010 slide "Bulk optical properties of a material").
 *
 * For each population the distribution's relative numbers per bin are scaled to the
 * population's volume fraction, v = 4 pi / 3 integral r^3 N(r) dr (the slide's first
 * formula), or to its number density; then sigma_s = sum C_s(r_i) N_i and likewise sigma_t
 * (the midpoint rule of the slide's integral). The medium's g is the sigma_s-weighted mean
 * of the particles' g. The host's own absorption 4 pi n_h'' / lambda adds to sigma_t, as in
 * Frisvad et al. 2007's milk model (the host is not reduced by the particles' volume; at
 * the volume fractions of milk, at most a few per cent, the difference is below the data's
 * precision).
 */
#include <math.h>
#include <stdlib.h>

#include "mie.h"

#define MAX_BINS 2000

double mie_spectrum_lambda(int i)
{
    return (MIE_SPECTRUM_FIRST_NM + MIE_SPECTRUM_STEP_NM * i) * 1e-9;
}

/* Absolute numbers per m^3 in each bin, in place; false for an invalid population. */
static bool scale_population(const struct mie_population *p, const double *r, double *number,
                             int bins)
{
    double sum = 0.0;
    for (int i = 0; i < bins; i++)
        sum += p->volume_fraction > 0.0 ? number[i] * 4.0 / 3.0 * M_PI * r[i] * r[i] * r[i]
                                        : number[i];
    if (!(sum > 0.0))
        return false;
    double target = p->volume_fraction > 0.0 ? p->volume_fraction : p->number_density;
    for (int i = 0; i < bins; i++)
        number[i] *= target / sum;
    return true;
}

static bool add_population(const struct mie_population *p, const struct mie_medium *m, double *ext,
                           double *sca, double *gsca)
{
    if (p->volume_fraction <= 0.0 && p->number_density <= 0.0)
        return true; /* an empty population (skimmed milk's fat) adds nothing */
    double *r = malloc(2 * MAX_BINS * sizeof *r);
    if (r == NULL)
        return false;
    double *number = r + MAX_BINS;
    int bins = mie_distribution_bins(&p->size, r, number, MAX_BINS);
    bool ok = bins > 0 && scale_population(p, r, number, bins);
    for (int w = 0; ok && w < MIE_SPECTRUM_SAMPLES; w++) {
        double complex n_p = p->per_wavelength ? p->ior[w] : p->ior[0];
        for (int i = 0; ok && i < bins; i++) {
            struct mie_sphere_result s;
            ok = mie_sphere(r[i], mie_spectrum_lambda(w), m->host[w], n_p, &s);
            ext[w] += s.c_ext * number[i];
            sca[w] += s.c_sca * number[i];
            gsca[w] += s.g * s.c_sca * number[i];
        }
    }
    free(r);
    return ok;
}

double mie_medium_work(const struct mie_medium *m)
{
    double work = 0.0, lambda_min = mie_spectrum_lambda(0);
    for (int k = 0; k < m->count; k++) {
        const struct mie_population *p = &m->pop[k];
        if (p->volume_fraction <= 0.0 && p->number_density <= 0.0)
            continue;
        bool mono = p->size.kind == MIE_DIST_MONODISPERSE;
        double bins = mono ? 1.0 : (p->size.bins > 0 ? p->size.bins : 200);
        double r = mono ? p->size.r_vs : p->size.r_max;
        for (int w = 0; w < MIE_SPECTRUM_SAMPLES; w++) {
            double complex n_p = p->per_wavelength ? p->ior[w] : p->ior[0];
            double x = 2.0 * M_PI * r / lambda_min;
            /* the host's terms plus the particle's downward recurrence, and a constant
             * per sphere for its set-up */
            work += bins * ((cabs(m->host[w]) + cabs(n_p)) * x + 20.0);
        }
    }
    return work;
}

bool mie_medium_spectrum(const struct mie_medium *m, struct mie_spectrum *out)
{
    double ext[MIE_SPECTRUM_SAMPLES] = {0}, sca[MIE_SPECTRUM_SAMPLES] = {0};
    double gsca[MIE_SPECTRUM_SAMPLES] = {0};
    if (m->count < 0 || m->count > MIE_MAX_POPULATIONS)
        return false;
    for (int k = 0; k < m->count; k++) {
        if (!add_population(&m->pop[k], m, ext, sca, gsca))
            return false;
    }
    for (int w = 0; w < MIE_SPECTRUM_SAMPLES; w++) {
        double host_abs = 4.0 * M_PI * cimag(m->host[w]) / mie_spectrum_lambda(w);
        out->sigma_s[w] = sca[w];
        out->sigma_a[w] = fmax(ext[w] + host_abs - sca[w], 0.0);
        out->g[w] = sca[w] > 0.0 ? gsca[w] / sca[w] : 0.0;
    }
    return true;
}
