/*
 * mie_presets.c - media from the course: milk by fat and protein content, clear water.
 *
 * Milk (Frisvad, Christensen and Jensen 2007, sec. 6; parameters as in Frisvad's 02576
 * framework, optprops/milk.h and milk.cpp):
 *   fat globules:   log-normal in r / 1 um, volume-to-surface mean r_vs = 0.475 um,
 *                   standard deviation c_s = 0.285 um, radii 0.005..10 um (200 bins),
 *                   index from Michalski et al. 2001 (mie_data.c);
 *   casein micelles: log-normal in r / (150 nm - r), r_vs = 43 nm, c_s = 0.23, radii
 *                   0..150 nm (150 bins), index 1.503;
 *   volume fractions from weight-%: fat / 0.915 and 0.76 protein / 1.11 (76% of milk
 *                   protein is casein), per 100 / 1.030 ml of milk (densities in g/ml of
 *                   fat, casein and milk);
 *   host: water (Hale and Querry 1973) with riboflavin, 0.17 mg per 100 g by default (Fox
 *                   and McSweeney 1998), molar mass 376.3682 g/mol, absorbing as in
 *                   mie_data.c. A milk diluted in water keeps less: the riboflavin is a
 *                   parameter so that such a mixture can say so.
 */
#include <math.h>
#include <string.h>

#include "mie.h"
#include "mie_data.h"

#define FAT_DENSITY 0.915              /* g/ml */
#define CASEIN_DENSITY 1.11            /* g/ml */
#define MILK_DENSITY 1.030             /* g/ml */
#define CASEIN_SHARE 0.76              /* of milk protein */
#define RIBOFLAVIN_MOLAR_MASS 376.3682 /* g/mol */

void mie_host_water(double complex host[MIE_SPECTRUM_SAMPLES])
{
    for (int i = 0; i < MIE_SPECTRUM_SAMPLES; i++)
        host[i] = mie_data_water_n[i] + I * mie_data_water_k[i];
}

void mie_preset_water(struct mie_medium *out)
{
    memset(out, 0, sizeof *out);
    mie_host_water(out->host);
}

/* Water with riboflavin: sigma_a = ln(10) epsilon c adds lambda sigma_a / (4 pi) to n''. */
static void milk_host(double riboflavin_mg_per_100g, double complex host[MIE_SPECTRUM_SAMPLES])
{
    double ml_per_100g = 100.0 / MILK_DENSITY;
    double molar = (riboflavin_mg_per_100g / RIBOFLAVIN_MOLAR_MASS) / ml_per_100g; /* mol/l */
    double scale = mie_data_riboflavin_molar_absorption / mie_data_riboflavin_reference_absorbance;
    mie_host_water(host);
    for (int i = 0; i < MIE_SPECTRUM_SAMPLES; i++) {
        double sigma_a = log(10.0) * molar * scale * mie_data_riboflavin_absorbance[i];
        host[i] += I * sigma_a * mie_spectrum_lambda(i) / (4.0 * M_PI);
    }
}

bool mie_preset_milk(double fat_percent, double protein_percent, struct mie_medium *out)
{
    return mie_preset_milk_riboflavin(fat_percent, protein_percent, MIE_MILK_RIBOFLAVIN, out);
}

bool mie_preset_milk_riboflavin(double fat_percent, double protein_percent,
                                double riboflavin_mg_per_100g, struct mie_medium *out)
{
    if (!(fat_percent >= 0.0 && fat_percent <= 40.0) ||
        !(protein_percent >= 0.0 && protein_percent <= 15.0) ||
        !(riboflavin_mg_per_100g >= 0.0 && riboflavin_mg_per_100g <= 10.0))
        return false;
    memset(out, 0, sizeof *out);
    milk_host(riboflavin_mg_per_100g, out->host);
    double ml_per_100g = 100.0 / MILK_DENSITY;

    struct mie_population *fat = &out->pop[0];
    fat->size = (struct mie_distribution){.kind = MIE_DIST_LOGNORMAL,
                                          .r_min = 0.005e-6,
                                          .r_max = 10e-6,
                                          .bins = 200,
                                          .r_vs = 0.475e-6,
                                          .c_s = 0.285};
    fat->per_wavelength = true;
    for (int i = 0; i < MIE_SPECTRUM_SAMPLES; i++)
        fat->ior[i] = mie_data_fat_n[i] + I * mie_data_fat_k[i];
    fat->volume_fraction = (fat_percent / FAT_DENSITY) / ml_per_100g;

    struct mie_population *casein = &out->pop[1];
    casein->size = (struct mie_distribution){.kind = MIE_DIST_LOGNORMAL,
                                             .r_min = 0.0,
                                             .r_max = 150e-9,
                                             .bins = 150,
                                             .r_vs = 43e-9,
                                             .c_s = 0.23,
                                             .t_bound = 150e-9};
    casein->ior[0] = 1.503;
    casein->volume_fraction = CASEIN_SHARE * (protein_percent / CASEIN_DENSITY) / ml_per_100g;
    out->count = 2;
    return true;
}
