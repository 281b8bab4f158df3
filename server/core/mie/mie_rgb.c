/*
 * mie_rgb.c - from the 17-sample spectrum to the RGB a voxel object carries.
 *
 * frisvad2010's "Path tracing volumes" slide notes that its procedure works only for
 * monochromatic rays; this renderer traces RGB, so each coefficient spectrum is reduced to
 * three numbers: weighted by the CIE 1931 2-degree colour matching functions into XYZ
 * (the analytic multi-lobe Gaussian fit of Wyman, Sloan and Shirley, JCGT 2(2), 2013, eq.
 * 2, within the fit's 1% of the tabulated functions), then taken to linear sRGB (the
 * XYZ-to-sRGB matrix of IEC 61966-2-1), and divided channel by channel by the RGB of a
 * flat spectrum so that a wavelength-independent coefficient keeps its value in all three
 * channels. The equal-energy weighting (no illuminant) is deliberate: a coefficient is
 * not a colour, and this keeps the map linear and grey-preserving.
 */
#include <math.h>

#include "mie.h"

/* One lobe of the fit: exp(-t^2 / 2), t = (lambda - mu) / sigma1 below mu, / sigma2 above. */
static double lobe(double nm, double mu, double sigma1, double sigma2)
{
    double t = (nm - mu) / (nm < mu ? sigma1 : sigma2);
    return exp(-0.5 * t * t);
}

static void cie_xyz(double nm, double xyz[3])
{
    xyz[0] = 1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7) -
             0.065 * lobe(nm, 501.1, 20.4, 26.2);
    xyz[1] = 0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1);
    xyz[2] = 1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8);
}

static void spectral_rgb_raw(const double v[MIE_SPECTRUM_SAMPLES], double rgb[3])
{
    static const double to_srgb[3][3] = {
        {3.2406, -1.5372, -0.4986}, {-0.9689, 1.8758, 0.0415}, {0.0557, -0.2040, 1.0570}};
    double xyz[3] = {0, 0, 0};
    for (int i = 0; i < MIE_SPECTRUM_SAMPLES; i++) {
        double c[3];
        cie_xyz(MIE_SPECTRUM_FIRST_NM + MIE_SPECTRUM_STEP_NM * i, c);
        for (int k = 0; k < 3; k++)
            xyz[k] += v[i] * c[k];
    }
    for (int k = 0; k < 3; k++)
        rgb[k] = to_srgb[k][0] * xyz[0] + to_srgb[k][1] * xyz[1] + to_srgb[k][2] * xyz[2];
}

void mie_spectral_rgb(const double v[MIE_SPECTRUM_SAMPLES], double rgb[3])
{
    double ones[MIE_SPECTRUM_SAMPLES], white[3];
    for (int i = 0; i < MIE_SPECTRUM_SAMPLES; i++)
        ones[i] = 1.0;
    spectral_rgb_raw(ones, white);
    spectral_rgb_raw(v, rgb);
    for (int k = 0; k < 3; k++)
        rgb[k] = fmax(rgb[k] / white[k], 0.0);
}

void mie_spectrum_to_rgb(const struct mie_spectrum *s, struct mie_rgb *out)
{
    double gs[MIE_SPECTRUM_SAMPLES], gsum[3];
    for (int i = 0; i < MIE_SPECTRUM_SAMPLES; i++)
        gs[i] = s->g[i] * s->sigma_s[i];
    mie_spectral_rgb(s->sigma_a, out->sigma_a);
    mie_spectral_rgb(s->sigma_s, out->sigma_s);
    mie_spectral_rgb(gs, gsum);
    double num = 0.0, den = 0.0;
    for (int k = 0; k < 3; k++) {
        out->g[k] = out->sigma_s[k] > 0.0 ? gsum[k] / out->sigma_s[k] : 0.0;
        num += out->g[k] * out->sigma_s[k];
        den += out->sigma_s[k];
    }
    out->g_scene = den > 0.0 ? num / den : 0.0;
}
