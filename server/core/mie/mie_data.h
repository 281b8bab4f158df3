/*
 * mie_data.h - measured optical data for the presets (sources in mie_data.c). Private to
 * server/core/mie.
 */
#ifndef REFRACT_MIE_DATA_H
#define REFRACT_MIE_DATA_H

#include "mie.h"

extern const double mie_data_water_n[MIE_SPECTRUM_SAMPLES];
extern const double mie_data_water_k[MIE_SPECTRUM_SAMPLES];
extern const double mie_data_fat_n[MIE_SPECTRUM_SAMPLES];
extern const double mie_data_fat_k[MIE_SPECTRUM_SAMPLES];
extern const double mie_data_riboflavin_absorbance[MIE_SPECTRUM_SAMPLES];
extern const double mie_data_riboflavin_reference_absorbance;
extern const double mie_data_riboflavin_molar_absorption;

#endif
