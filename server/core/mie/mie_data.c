/*
 * mie_data.c - measured optical data on the spectrum grid 375, 400, ..., 775 nm
 * (MIE_SPECTRUM_SAMPLES), as tabulated by J. R. Frisvad for the DTU course 02576 rendering
 * framework (optprops/milk.cpp, 2009), which implements the milk model of Frisvad,
 * Christensen and Jensen 2007 that frisvad2010 presents. The primary sources are named
 * per table.
 */
#include "mie_data.h"

/* Water: real part and extinction index n'' (Hale and Querry 1973, Applied Optics 12(3)). */
const double mie_data_water_n[MIE_SPECTRUM_SAMPLES] = {1.341, 1.339, 1.338, 1.337, 1.336, 1.335,
                                                       1.334, 1.333, 1.333, 1.332, 1.332, 1.331,
                                                       1.331, 1.331, 1.330, 1.330, 1.330};
const double mie_data_water_k[MIE_SPECTRUM_SAMPLES] = {
    3.393e-10, 2.110e-10, 1.617e-10, 3.302e-10, 4.309e-10, 8.117e-10, 1.742e-9, 2.473e-9, 3.532e-9,
    1.062e-8,  1.410e-8,  1.759e-8,  2.406e-8,  3.476e-8,  8.591e-8,  1.474e-7, 1.486e-7};

/* Milk fat: n' and n'' (Michalski, Briard and Juaneda 2001). */
const double mie_data_fat_n[MIE_SPECTRUM_SAMPLES] = {1.480, 1.476, 1.473, 1.470, 1.468, 1.466,
                                                     1.464, 1.463, 1.462, 1.461, 1.460, 1.459,
                                                     1.458, 1.457, 1.457, 1.456, 1.456};
const double mie_data_fat_k[MIE_SPECTRUM_SAMPLES] = {
    4.0e-6, 6.4e-6, 8.6e-6, 1.14e-5, 1.10e-5, 1.00e-5, 4.7e-6, 4.6e-6, 4.7e-6,
    4.9e-6, 5.0e-6, 5.0e-6, 5.1e-6,  5.2e-6,  5.2e-6,  5.2e-6, 5.2e-6};

/* Riboflavin (vitamin B2) absorbance, relative (Du et al. 1998, PhotochemCAD), scaled by
 * the molar absorption coefficient 33000 M^-1 cm^-1 at 266.5 nm where the absorbance
 * reads 0.25654 (Koziol 1966). */
const double mie_data_riboflavin_absorbance[MIE_SPECTRUM_SAMPLES] = {
    0.07117, 0.05934, 0.07215, 0.08300, 0.06379, 0.01962, 0.00950, 0.00957, 0.01198,
    0.01047, 0.01046, 0.01061, 0.00671, 0.01034, 0.00589, 0.00886, 0.01015};
const double mie_data_riboflavin_reference_absorbance = 0.25654;
const double mie_data_riboflavin_molar_absorption = 3.3e6; /* M^-1 m^-1 at 266.5 nm */
