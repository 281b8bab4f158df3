/*
 * mie_sphere.c - one sphere at one wavelength: the Lorenz-Mie coefficients a_n, b_n, the
 * cross sections, the asymmetry parameter, and the amplitude functions S1, S2.
 *
 * Stability (why these recurrences). With z = n x, the Riccati-Bessel functions psi_n(z)
 * and zeta_n(z) over- and underflow for large |z| and large Im z, so the code never forms
 * them. It works with ratios that stay O(1) (Frisvad et al. 2007, sec. 3):
 *   A_n(z) = psi_n'(z) / psi_n(z)     by downward recurrence
 *            A_(n-1) = n/z - 1 / (n/z + A_n), started at N = max(M, |z|) + 16 +
 *            10 |z|^(1/3) with A_N = 0; the recurrence damps the starting error
 *            (Wiscombe 1980; Bohren and Huffman's BHMIE starts at max(x, |mx|) + 15, which
 *            is not enough for nearly real z at x = 1e4), so it is stable for x = 1e4
 *            and m = 1.33 + 1e-5 i or 10 + 10i (tests/unit/test_mie.c);
 *   psi_n zeta_n = psi_(n-1) zeta_(n-1) (n/z - A_(n-1)) (n/z - B_(n-1)),
 *            psi_0 zeta_0 = (1 - e^(2iz)) / 2,
 *   B_n(z) = zeta_n' / zeta_n = A_n + i / (psi_n zeta_n),        B_0 = i,
 *   R_n(z) = psi_n / zeta_n = R_(n-1) (B_n + n/z) / (A_n + n/z), R_0 = (1 - e^(-2iz)) / 2,
 * (the code evaluates the ratios psi_n / psi_(n-1) and zeta_n / zeta_(n-1) in the forms
 * that do not cancel for small z, see the loop),
 * upward, for the host argument only. Then, with n_h, n_p the host and particle indices,
 *   a_n = R_n (n_h A_n(n_p x) - n_p A_n(n_h x)) / (n_h A_n(n_p x) - n_p B_n(n_h x)),
 *   b_n = R_n (n_p A_n(n_p x) - n_h A_n(n_h x)) / (n_p A_n(n_p x) - n_h B_n(n_h x)),
 * which for n_h = 1 are Bohren and Huffman's eq. 4.53 written with these ratios.
 */
#include <math.h>
#include <stdlib.h>

#include "mie.h"

int mie_terms(double abs_z)
{
    return (int)ceil(abs_z + 4.3 * cbrt(abs_z) + 1.0);
}

/* A_n(z) for n = 0..count by downward recurrence; returns a malloc'd array of count + 1
 * entries, or NULL when out of memory. */
static double complex *log_derivative(double complex z, int count)
{
    int start = count;
    double az = cabs(z);
    if (az > start)
        start = (int)ceil(az);
    /* Above n = |z| the error of the guess A_N = 0 shrinks with every step, but only
     * slowly within a few |z|^(1/3) of the turning point n = |z|; nearly real z (weakly
     * absorbing spheres, x = 1e4) needs those steps too (Wiscombe's case 11 is off by 3e-3
     * with the plain + 16). */
    start += 16 + (int)ceil(10.0 * cbrt(az));
    double complex *all = malloc(((size_t)start + 1) * sizeof *all);
    if (all == NULL)
        return NULL;
    all[start] = 0.0;
    for (int n = start; n > 0; n--) {
        double complex nz = (double)n / z;
        all[n - 1] = nz - 1.0 / (nz + all[n]);
    }
    return all; /* only [0..count] is read */
}

/* 1 - e^w without the cancellation of 1 - cexp(w) at small |w|, where R_0 and psi_0 zeta_0
 * of a small sphere (z = 1e-3) would otherwise lose three digits. */
static double complex one_minus_exp(double complex w)
{
    double a = creal(w), b = cimag(w), s = sin(0.5 * b);
    double re = expm1(a) * cos(b) - 2.0 * s * s; /* e^a cos b - 1 */
    return -(re + I * exp(a) * sin(b));
}

bool mie_coefficients(double x, double complex n_h, double complex n_p, int count,
                      double complex *a, double complex *b)
{
    if (!(x > 0.0) || x > MIE_MAX_SIZE_PARAMETER || count < 1 || cimag(n_h) < 0.0 ||
        cimag(n_p) < 0.0 || !(cabs(n_p) > 0.0) || !(creal(n_h) > 0.0))
        return false;
    double complex z_h = n_h * x, z_p = n_p * x;
    /* R_0 = (1 - e^(-2iz)) / 2 grows like e^(2 Im z): refuse before it overflows. */
    if (2.0 * cimag(z_h) > 600.0)
        return false;
    double complex *a_h = log_derivative(z_h, count);
    double complex *a_p = log_derivative(z_p, count);
    if (a_h == NULL || a_p == NULL) {
        free(a_h);
        free(a_p);
        return false;
    }
    double complex psi_zeta = 0.5 * one_minus_exp(2.0 * I * z_h);
    double complex b_prev = I; /* B_0 */
    double complex r = 0.5 * one_minus_exp(-2.0 * I * z_h);
    for (int n = 1; n <= count; n++) {
        double complex nz = (double)n / z_h;
        /* psi_n / psi_(n-1) = 1 / (A_n + n/z) and zeta_n / zeta_(n-1) = n/z - B_(n-1):
         * the equivalent n/z - A_(n-1) and 1 / (B_n + n/z) cancel catastrophically for
         * small z (R_1 lost 4 digits at x = 1e-3 and all of them at 1e-4). */
        double complex psi_ratio = 1.0 / (a_h[n] + nz), zeta_ratio = nz - b_prev;
        psi_zeta *= psi_ratio * zeta_ratio;
        double complex b_n = a_h[n] + I / psi_zeta;
        r *= psi_ratio / zeta_ratio;
        double complex ap = a_p[n], ah = a_h[n];
        a[n] = r * (n_h * ap - n_p * ah) / (n_h * ap - n_p * b_n);
        b[n] = r * (n_p * ap - n_h * ah) / (n_p * ap - n_h * b_n);
        b_prev = b_n;
    }
    free(a_h);
    free(a_p);
    return true;
}

/* e^(-alpha) / gamma with gamma = 2 (1 + (alpha - 1) e^alpha) / alpha^2, the factor by
 * which an absorbing host reduces the scattering cross section measured at the particle
 * (Frisvad et al. 2007); written as alpha^2 e^(-2 alpha) / (2 (e^(-alpha) + alpha - 1))
 * so large alpha cannot overflow, and 1 below alpha = 1e-6 where both forms cancel. */
static double host_absorption_factor(double alpha)
{
    if (alpha < 1e-6)
        return 1.0;
    return alpha * alpha * exp(-2.0 * alpha) / (2.0 * (expm1(-alpha) + alpha));
}

bool mie_sphere(double radius, double lambda, double complex n_h, double complex n_p,
                struct mie_sphere_result *out)
{
    if (!(radius > 0.0) || !(lambda > 0.0))
        return false;
    double x = 2.0 * M_PI * radius / lambda;
    if (x * cabs(n_h) > MIE_MAX_SIZE_PARAMETER)
        return false;
    int m = mie_terms(cabs(n_h) * x);
    double complex *a = malloc(((size_t)m + 1) * sizeof *a);
    double complex *b = malloc(((size_t)m + 1) * sizeof *b);
    bool ok = a != NULL && b != NULL && mie_coefficients(x, n_h, n_p, m, a, b);
    if (!ok) {
        free(a);
        free(b);
        return false;
    }
    /* frisvad2010 "Quantity of scattering": C_s and C_t as sums over (2n + 1) terms; the
     * asymmetry sum is Bohren and Huffman's (p. 120), divided by the same C_s sum. */
    double complex ext = 0.0;
    double sca = 0.0, gsum = 0.0;
    for (int n = 1; n <= m; n++) {
        double w = 2.0 * n + 1.0;
        ext += w * (a[n] + b[n]);
        sca += w * (creal(a[n] * conj(a[n])) + creal(b[n] * conj(b[n])));
        gsum += w / (n * (n + 1.0)) * creal(a[n] * conj(b[n]));
        if (n < m)
            gsum +=
                n * (n + 2.0) / (n + 1.0) * creal(a[n] * conj(a[n + 1]) + b[n] * conj(b[n + 1]));
    }
    free(a);
    free(b);
    double scale = lambda * lambda / (2.0 * M_PI);
    double alpha = 4.0 * M_PI * radius * cimag(n_h) / lambda;
    double nh2 = creal(n_h * conj(n_h));
    out->c_ext = scale * creal(ext / (n_h * n_h));
    out->c_sca = scale * sca * host_absorption_factor(alpha) / nh2;
    out->c_abs = out->c_ext - out->c_sca;
    out->g = sca > 0.0 ? 2.0 * gsum / sca : 0.0;
    double area = M_PI * radius * radius;
    out->q_ext = out->c_ext / area;
    out->q_sca = out->c_sca / area;
    out->q_abs = out->c_abs / area;
    out->terms = m;
    return true;
}

bool mie_efficiencies(double x, double complex m, struct mie_sphere_result *out)
{
    /* lambda = 1 and r = x / (2 pi): the sphere of size parameter x in vacuum. */
    return mie_sphere(x / (2.0 * M_PI), 1.0, 1.0, m, out);
}

void mie_amplitudes(const double complex *a, const double complex *b, int terms, const double *mu,
                    int count, double complex *s1, double complex *s2)
{
    for (int i = 0; i < count; i++) {
        /* pi_n and tau_n by their upward recurrences (Bohren and Huffman eq. 4.47). */
        double pi_prev = 0.0, pi_n = 1.0;
        double complex sum1 = 0.0, sum2 = 0.0;
        for (int n = 1; n <= terms; n++) {
            double tau_n = n * mu[i] * pi_n - (n + 1.0) * pi_prev;
            double w = (2.0 * n + 1.0) / (n * (n + 1.0));
            sum1 += w * (a[n] * pi_n + b[n] * tau_n);
            sum2 += w * (a[n] * tau_n + b[n] * pi_n);
            double pi_next = ((2.0 * n + 1.0) * mu[i] * pi_n - (n + 1.0) * pi_prev) / n;
            pi_prev = pi_n;
            pi_n = pi_next;
        }
        s1[i] = sum1;
        s2[i] = sum2;
    }
}

bool mie_phase_table(double radius, double lambda, double complex n_h, double complex n_p,
                     const double *mu, int count, double *p)
{
    struct mie_sphere_result r;
    if (!mie_sphere(radius, lambda, n_h, n_p, &r) || !(r.c_sca > 0.0))
        return false;
    double x = 2.0 * M_PI * radius / lambda;
    double complex *a = malloc(((size_t)r.terms + 1) * sizeof *a);
    double complex *b = malloc(((size_t)r.terms + 1) * sizeof *b);
    double complex *s = malloc(2 * (size_t)count * sizeof *s);
    bool ok = a != NULL && b != NULL && s != NULL && mie_coefficients(x, n_h, n_p, r.terms, a, b);
    if (ok) {
        mie_amplitudes(a, b, r.terms, mu, count, s, s + count);
        double k = 2.0 * M_PI / lambda;
        double k2 = k * k * creal(n_h * conj(n_h)); /* |k|^2 */
        for (int i = 0; i < count; i++) {
            double s11 = creal(s[i] * conj(s[i])) + creal(s[count + i] * conj(s[count + i]));
            p[i] = s11 / (2.0 * k2 * r.c_sca);
        }
    }
    free(a);
    free(b);
    free(s);
    return ok;
}
