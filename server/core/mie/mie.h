/*
 * mie.h - Lorenz-Mie theory: light scattered and absorbed by spherical particles in a
 * (possibly absorbing) host, summed over size distributions and wavelengths into the bulk
 * coefficients a scene's voxel object carries (docs/media.md).
 *
 * Sources. frisvad2010 (the course slides, /work/shared/papers) gives the formulas on its
 * slides "Scattering by spherical particles" (phase function, S1, S2), "Quantity of
 * scattering" (C_s, C_t), "Bulk optical properties of a material" (volume fraction,
 * sigma_s = integral C_s N dr) and "Computing scattering properties" (number of terms).
 * The slides carry no equation numbers, so comments name the slide. The recurrences for
 * an absorbing host (A_n, B_n, R_n and the host-absorption factor of C_s) are those of
 * Frisvad, Christensen and Jensen, "Computing the scattering properties of participating
 * media using Lorenz-Mie theory", SIGGRAPH 2007, the paper the slides summarise.
 *
 * Conventions. Refractive indices are n = n' + i n'' with n'' >= 0 for an absorbing
 * material (frisvad2010 slide "Materials"; Bohren and Huffman write m = n + ik the same
 * way, Wiscombe's MIEV0 writes m = n' - i n''). Lengths (radius, wavelength) are in any one
 * unit; cross sections come out in that unit squared. Wavelengths are in vacuum.
 *
 * Thread: any; no globals. Functions that need scratch memory allocate and free it.
 */
#ifndef REFRACT_MIE_H
#define REFRACT_MIE_H

#include <complex.h>
#include <stdbool.h>

/* Size parameters above this are refused (mie_sphere returns false): the brief asks for
 * 1e4 and the tests run Wiscombe's 1e4 cases; beyond 1e5 the O(x) work stops being
 * something a scene upload should wait for. */
#define MIE_MAX_SIZE_PARAMETER 1.0e5

/* One sphere at one wavelength. */
struct mie_sphere_result {
    double c_ext, c_sca, c_abs; /* cross sections, length unit squared */
    double q_ext, q_sca, q_abs; /* efficiencies C / (pi r^2) */
    double g;                   /* asymmetry parameter, mean cosine of scattering */
    int terms;                  /* number of terms M summed */
};

/* Terms to sum for |z| = |n_host| x: M = ceil(|z| + 4.3 |z|^(1/3) + 1), which keeps the
 * truncation error below 1e-8 (frisvad2010 slide "Computing scattering properties",
 * after Wiscombe 1980 and Cachorro and Salcedo 1991). */
int mie_terms(double abs_z);

/* The Lorenz-Mie coefficients a_n, b_n, n = 1..count, of a sphere of size parameter
 * x = 2 pi r / lambda (vacuum wavelength) with index n_p in a host of index n_h. a[0] and
 * b[0] are unused; a and b hold count + 1 entries. Returns false (and writes nothing) when
 * x or an index is out of range (x <= 0, x > MIE_MAX_SIZE_PARAMETER, a host so absorbing
 * that e^(2 Im(n_h) x) overflows) or memory runs out. */
bool mie_coefficients(double x, double complex n_h, double complex n_p, int count,
                      double complex *a, double complex *b);

/* Cross sections, efficiencies and g of a sphere of radius r at vacuum wavelength lambda
 * (same unit) with index n_p in a host of index n_h (frisvad2010 "Quantity of
 * scattering"; Frisvad et al. 2007 for the absorbing host). Returns false as
 * mie_coefficients. */
bool mie_sphere(double radius, double lambda, double complex n_h, double complex n_p,
                struct mie_sphere_result *out);

/* The classic case: host index 1, relative index m (m'' >= 0 absorbs), size parameter x. */
bool mie_efficiencies(double x, double complex m, struct mie_sphere_result *out);

/* The amplitude functions S1(mu), S2(mu) at the count angles mu[i] = cos(theta_i), from
 * the coefficients (frisvad2010 "Scattering by spherical particles"). */
void mie_amplitudes(const double complex *a, const double complex *b, int terms, const double *mu,
                    int count, double complex *s1, double complex *s2);

/* The phase function p(mu) = (|S1|^2 + |S2|^2) / (2 |k|^2 C_s) with k = 2 pi n_h / lambda
 * (frisvad2010 "Scattering by spherical particles"), tabulated at `count` cosines mu[i]
 * (any order). Normalised so that 2 pi * integral p dmu = 1 over [-1, 1] for a
 * non-absorbing host; with an absorbing host the slide's normalisation is kept as it is.
 * Returns false as mie_sphere. */
bool mie_phase_table(double radius, double lambda, double complex n_h, double complex n_p,
                     const double *mu, int count, double *p);

/* ---- size distributions (mie_distribution.c) ---- */

enum mie_distribution_kind {
    MIE_DIST_MONODISPERSE = 0, /* every particle has radius r_vs */
    /* Volume-frequency log-normal in a transformed radius t(r) (Frisvad et al. 2007's milk
     * model): t = r / 1 um when t_bound == 0, else t = r / (t_bound - r). The mean t_vs =
     * t(r_vs) and the standard deviation c_s (in t) give beta^2 = ln(c_s^2 / t_vs^2 + 1),
     * alpha = ln t_vs - beta^2 / 2; the share of volume in [r, r + dr] is proportional to
     * the log-normal density of t at r. */
    MIE_DIST_LOGNORMAL = 1,
    /* Junge power law: number per unit radius proportional to r^-exponent (natural waters,
     * frisvad2010 slide "Particle contents"). */
    MIE_DIST_POWER_LAW = 2,
};

struct mie_distribution {
    enum mie_distribution_kind kind;
    double r_min, r_max; /* radius range, metres (not monodisperse) */
    int bins;            /* midpoint-rule bins over [r_min, r_max]; 0 = 200 */
    double r_vs;         /* monodisperse radius, or the log-normal volume-to-surface mean, m */
    double c_s;          /* log-normal standard deviation in t */
    double t_bound;      /* log-normal transform bound, m (0 = none) */
    double exponent;     /* power-law exponent */
};

/* Fills r[i] (bin midpoints, metres) and number[i] (relative number of particles per unit
 * volume in bin i, any scale) for i < bins (one bin for monodisperse). Returns the number
 * of bins written, or 0 when d is invalid or cap is too small. */
int mie_distribution_bins(const struct mie_distribution *d, double *r, double *number, int cap);

/* ---- media: populations in a host, per wavelength and in RGB (mie_medium.c) ---- */

#define MIE_SPECTRUM_SAMPLES 17 /* 375, 400, ..., 775 nm (Frisvad et al. 2007's grid) */
#define MIE_SPECTRUM_FIRST_NM 375.0
#define MIE_SPECTRUM_STEP_NM 25.0
#define MIE_MAX_POPULATIONS 8

struct mie_population {
    struct mie_distribution size;
    /* Index per spectrum sample, or one index for every wavelength when !per_wavelength. */
    double complex ior[MIE_SPECTRUM_SAMPLES];
    bool per_wavelength;
    /* Exactly one of: the volume fraction (frisvad2010 "Bulk optical properties":
     * v = 4 pi / 3 integral r^3 N(r) dr), or the number density, particles per m^3. */
    double volume_fraction;
    double number_density;
};

struct mie_medium {
    double complex host[MIE_SPECTRUM_SAMPLES]; /* host index per sample */
    struct mie_population pop[MIE_MAX_POPULATIONS];
    int count;
};

/* Bulk coefficients per metre (and g) at each spectrum sample. */
struct mie_spectrum {
    double sigma_a[MIE_SPECTRUM_SAMPLES], sigma_s[MIE_SPECTRUM_SAMPLES];
    double g[MIE_SPECTRUM_SAMPLES];
};

/* RGB coefficients per metre and one scalar g for the scene's Henyey-Greenstein field. */
struct mie_rgb {
    double sigma_a[3], sigma_s[3];
    double g[3];    /* per channel: the scattering-weighted mean of g over the spectrum */
    double g_scene; /* the sigma_s-weighted mean of g[] over the channels */
};

/* An upper bound on the Mie terms mie_medium_spectrum sums (bins x wavelengths x terms per
 * sphere, taking every bin at the largest radius), so that a parser can refuse a medium
 * before spending seconds on it. Milk is about 1.6e6. */
double mie_medium_work(const struct mie_medium *m);
#define MIE_MAX_WORK 1.0e7 /* under a second on one core (0.74 s measured at 9.3e6) */

/* sigma_s, sigma_a and g of the medium at each spectrum sample: sigma = sum over
 * populations of integral C N dr (frisvad2010 "Bulk optical properties"), plus the host's
 * own absorption 4 pi n_h'' / lambda. Returns false when a sphere is out of range. */
bool mie_medium_spectrum(const struct mie_medium *m, struct mie_spectrum *out);

/* The spectrum to RGB (mie_rgb.c): each coefficient spectrum is weighted by the CIE 1931
 * colour matching functions (Wyman, Sloan and Shirley 2013's analytic fit) into XYZ, taken
 * to linear sRGB primaries (IEC 61966-2-1), and divided by the RGB of a flat spectrum, so
 * a grey coefficient stays grey. Negative results (saturated spectra outside the sRGB
 * gamut) are clamped to 0. */
void mie_spectrum_to_rgb(const struct mie_spectrum *s, struct mie_rgb *out);
/* One spectrum to RGB with the same weights (exposed for tests). */
void mie_spectral_rgb(const double v[MIE_SPECTRUM_SAMPLES], double rgb[3]);
double mie_spectrum_lambda(int i); /* metres */

/* ---- presets (mie_presets.c, data in mie_data.c) ---- */

/* Pure water as a host: Hale and Querry 1973, one index per spectrum sample. */
void mie_host_water(double complex host[MIE_SPECTRUM_SAMPLES]);

/* Milk by fat and protein content, weight-% (Frisvad et al. 2007's model: fat globules
 * and casein micelles in water with riboflavin). Returns false unless 0 <= fat <= 40 and
 * 0 <= protein <= 15. */
bool mie_preset_milk(double fat_percent, double protein_percent, struct mie_medium *out);
/* The same with the riboflavin content, mg per 100 g (0..10; whole milk has
 * MIE_MILK_RIBOFLAVIN, Fox and McSweeney 1998), for milk diluted in water. */
#define MIE_MILK_RIBOFLAVIN 0.17
bool mie_preset_milk_riboflavin(double fat_percent, double protein_percent,
                                double riboflavin_mg_per_100g, struct mie_medium *out);

/* Clear water: the host alone (no particles). */
void mie_preset_water(struct mie_medium *out);

#endif
