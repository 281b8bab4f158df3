/*
 * reftrace_integrate.c - field sampling and the three steppers of the reference
 * tracer: explicit Euler (tevs2007 eqs. 5.11/5.12), classical RK4, and Dormand-Prince
 * 5(4) for the adaptive "exact" reference. The march itself (objects, faces, events,
 * statuses) is reftrace.c; this file knows nothing about bounds or Fresnel.
 *
 * Euler and RK4 integrate only y = (p, w), exactly as shaders/ray_equation.glsl does;
 * the march accumulates OPL, absorption and emission with the trapezoid rule as
 * docs/tracing.md says. The adaptive stepper instead carries those integrals in its
 * state, so they get the same fifth-order accuracy as the path: a trapezoid over steps
 * of a few hundredths of the object would not be a reference.
 */
#include "reftrace_integrate.h"

#include <math.h>
#include <stddef.h>

#include "smooth.h"
#include "voxel_tricubic.h"

vec3 reftrace_voxel_size(const struct reftrace_object *o)
{
    vec3 e = vec3_sub(o->bmax, o->bmin);
    return (vec3){e.x / o->res[0], e.y / o->res[1], e.z / o->res[2]};
}

/* docs/tracing.md "Conventions": continuous voxel coordinates, voxel centres at
 * integers. */
static vec3 voxel_coord(const struct reftrace_object *o, vec3 p)
{
    vec3 vs = reftrace_voxel_size(o);
    vec3 r = vec3_sub(p, o->bmin);
    return (vec3){r.x / vs.x - 0.5, r.y / vs.y - 0.5, r.z / vs.z - 0.5};
}

double reftrace_sample_ior(const struct reftrace_object *o, vec3 p, vec3 *grad)
{
    if (o->grid == NULL)
        return o->ior(o->ior_ctx, p, grad);
    if (o->ior_filter == REFTRACE_FILTER_TRICUBIC) {
        /* n and the exact gradient of its interpolant (the stored gradient is unused). */
        vec3 g, vs = reftrace_voxel_size(o);
        double n =
            voxel_tricubic_value_grad(o->grid->ior_grad, 4, 3, o->res, voxel_coord(o, p), &g);
        *grad = (vec3){g.x / vs.x, g.y / vs.y, g.z / vs.z};
        return n;
    }
    double s[4];
    voxel_sample_trilinear(o->grid->ior_grad, 4, o->res, voxel_coord(o, p), s);
    *grad = (vec3){s[0], s[1], s[2]};
    return s[3];
}

void reftrace_sample_field(const struct reftrace_object *o, vec3 p, struct reftrace_field *f)
{
    f->sigma_a = (vec3){0, 0, 0};
    f->emission = (vec3){0, 0, 0};
    f->sigma_s = (vec3){0, 0, 0};
    f->g = 0.0;
    f->n = reftrace_sample_ior(o, p, &f->grad);
    if (o->grid == NULL)
        return;
    vec3 v = voxel_coord(o, p);
    double s[4];
    if (o->grid->attenuation != NULL) {
        voxel_sample_trilinear(o->grid->attenuation, 4, o->res, v, s);
        f->sigma_a = (vec3){s[0], s[1], s[2]};
    }
    if (o->grid->emission != NULL) {
        voxel_sample_trilinear(o->grid->emission, 4, o->res, v, s);
        f->emission = (vec3){s[0], s[1], s[2]};
    }
    if (o->grid->scattering != NULL) {
        voxel_sample_trilinear(o->grid->scattering, 4, o->res, v, s);
        f->sigma_s = (vec3){s[0], s[1], s[2]};
        if (o->grid->anisotropy != NULL) {
            voxel_sample_trilinear(o->grid->anisotropy, 1, o->res, v, s);
            f->g = s[0];
        }
    }
}

bool reftrace_sample_opaque(const struct reftrace_object *o, vec3 p, vec3 *colour, double *coverage)
{
    if (o->grid == NULL || o->grid->opaque == NULL)
        return false;
    double s[4];
    voxel_sample_trilinear(o->grid->opaque, 4, o->res, voxel_coord(o, p), s);
    *colour = (vec3){s[0], s[1], s[2]};
    *coverage = s[3];
    return true;
}

/* tevs2007 eqs. 5.11/5.12: x' = x + (h / n) w, w' = w + h grad n, both at the old x. */
void reftrace_step_euler(const struct reftrace_object *o, double h, vec3 *p, vec3 *w)
{
    vec3 g;
    double n = reftrace_sample_ior(o, *p, &g);
    *p = vec3_madd(*p, *w, h / n);
    *w = vec3_madd(*w, g, h);
}

/* Classical RK4 on y = (p, w) with dy/ds = (w / n(p), grad n(p)) (eqs. 4.8, 4.9). */
void reftrace_step_rk4(const struct reftrace_object *o, double h, vec3 *p, vec3 *w)
{
    vec3 p0 = *p, w0 = *w, g;
    double n = reftrace_sample_ior(o, p0, &g);
    vec3 k1p = vec3_scale(w0, 1.0 / n), k1w = g;

    vec3 w2 = vec3_madd(w0, k1w, 0.5 * h);
    n = reftrace_sample_ior(o, vec3_madd(p0, k1p, 0.5 * h), &g);
    vec3 k2p = vec3_scale(w2, 1.0 / n), k2w = g;

    vec3 w3 = vec3_madd(w0, k2w, 0.5 * h);
    n = reftrace_sample_ior(o, vec3_madd(p0, k2p, 0.5 * h), &g);
    vec3 k3p = vec3_scale(w3, 1.0 / n), k3w = g;

    vec3 w4 = vec3_madd(w0, k3w, h);
    n = reftrace_sample_ior(o, vec3_madd(p0, k3p, h), &g);
    vec3 k4p = vec3_scale(w4, 1.0 / n), k4w = g;

    vec3 sp = vec3_add(vec3_add(k1p, k4p), vec3_scale(vec3_add(k2p, k3p), 2.0));
    vec3 sw = vec3_add(vec3_add(k1w, k4w), vec3_scale(vec3_add(k2w, k3w), 2.0));
    *p = vec3_madd(p0, sp, h / 6.0);
    *w = vec3_madd(w0, sw, h / 6.0);
}

/* Explicit midpoint: y1 = y + h f(y + h/2 f(y)). */
void reftrace_step_rk2(const struct reftrace_object *o, double h, vec3 *p, vec3 *w)
{
    vec3 g;
    double n = reftrace_sample_ior(o, *p, &g);
    vec3 pm = vec3_madd(*p, *w, 0.5 * h / n);
    vec3 wm = vec3_madd(*w, g, 0.5 * h);
    n = reftrace_sample_ior(o, pm, &g);
    *p = vec3_madd(*p, wm, h / n);
    *w = vec3_madd(*w, g, h);
}

/* Bogacki & Shampine (1989): c = (0, 1/2, 3/4, 1), b = (2/9, 1/3, 4/9, 0), and b - b* =
 * (-5/72, 1/12, 1/9, -1/8) for the error of the embedded second-order solution. */
double reftrace_step_bs23(const struct reftrace_object *o, double h, double extent, vec3 *p,
                          vec3 *w)
{
    vec3 p0 = *p, w0 = *w, g;
    double n = reftrace_sample_ior(o, p0, &g);
    vec3 k1p = vec3_scale(w0, 1.0 / n), k1w = g;
    vec3 w2 = vec3_madd(w0, k1w, 0.5 * h);
    n = reftrace_sample_ior(o, vec3_madd(p0, k1p, 0.5 * h), &g);
    vec3 k2p = vec3_scale(w2, 1.0 / n), k2w = g;
    vec3 w3 = vec3_madd(w0, k2w, 0.75 * h);
    n = reftrace_sample_ior(o, vec3_madd(p0, k2p, 0.75 * h), &g);
    vec3 k3p = vec3_scale(w3, 1.0 / n), k3w = g;
    vec3 sp = vec3_add(vec3_add(vec3_scale(k1p, 2.0 / 9.0), vec3_scale(k2p, 1.0 / 3.0)),
                       vec3_scale(k3p, 4.0 / 9.0));
    vec3 sw = vec3_add(vec3_add(vec3_scale(k1w, 2.0 / 9.0), vec3_scale(k2w, 1.0 / 3.0)),
                       vec3_scale(k3w, 4.0 / 9.0));
    vec3 p1 = vec3_madd(p0, sp, h), w1 = vec3_madd(w0, sw, h);
    n = reftrace_sample_ior(o, p1, &g);
    vec3 k4p = vec3_scale(w1, 1.0 / n), k4w = g;
    vec3 ep = vec3_add(vec3_add(vec3_scale(k1p, -5.0 / 72.0), vec3_scale(k2p, 1.0 / 12.0)),
                       vec3_add(vec3_scale(k3p, 1.0 / 9.0), vec3_scale(k4p, -0.125)));
    vec3 ew = vec3_add(vec3_add(vec3_scale(k1w, -5.0 / 72.0), vec3_scale(k2w, 1.0 / 12.0)),
                       vec3_add(vec3_scale(k3w, 1.0 / 9.0), vec3_scale(k4w, -0.125)));
    *p = p1;
    *w = w1;
    return h * vec3_length(ep) + extent * h * vec3_length(ew) / fmax(vec3_length(w0), 1e-300);
}

/* ---- Dormand-Prince 5(4) --------------------------------------------------------- */

/* p(3), w(3), opl(1), alpha(3), emit(3) */
#define ODE_DIM 13

/* Dormand & Prince (1980), the tableau of RK5(4)7M. Row s holds a_{s,0..s-1}; the last
 * row equals the fifth-order weights (first same as last). */
static const double dp_a[7][6] = {
    {0, 0, 0, 0, 0, 0},
    {1.0 / 5.0, 0, 0, 0, 0, 0},
    {3.0 / 40.0, 9.0 / 40.0, 0, 0, 0, 0},
    {44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0, 0, 0},
    {19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0, 0},
    {9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0},
    {35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0},
};
/* b5 - b4: the embedded error estimate's weights. */
static const double dp_e[7] = {
    35.0 / 384.0 - 5179.0 / 57600.0,
    0.0,
    500.0 / 1113.0 - 7571.0 / 16695.0,
    125.0 / 192.0 - 393.0 / 640.0,
    -2187.0 / 6784.0 + 92097.0 / 339200.0,
    11.0 / 84.0 - 187.0 / 2100.0,
    -1.0 / 40.0,
};

static vec3 triple(const double *a)
{
    return (vec3){a[0], a[1], a[2]};
}

static void put_triple(double *a, vec3 v)
{
    a[0] = v.x;
    a[1] = v.y;
    a[2] = v.z;
}

/* Layout of the packed state: p 0-2, w 3-5, opl 6, alpha 7-9, emit 10-12. */
static void ode_to_array(const struct reftrace_ode *y, double a[ODE_DIM])
{
    put_triple(a + 0, y->p);
    put_triple(a + 3, y->w);
    a[6] = y->opl;
    put_triple(a + 7, y->alpha);
    put_triple(a + 10, y->emit);
}

static void ode_from_array(const double a[ODE_DIM], struct reftrace_ode *y)
{
    y->p = triple(a + 0);
    y->w = triple(a + 3);
    y->opl = a[6];
    y->alpha = triple(a + 7);
    y->emit = triple(a + 10);
}

/* dy/ds, s in object units: (w / n, grad n, n scale, sigma_t scale,
 * exp(-alpha) L_e / n^2 scale). alpha here is the optical depth gathered since the step began;
 * the march multiplies the step's emission by the transmittance at its start. */
static void ode_deriv(const struct reftrace_object *o, double scale, const double y[ODE_DIM],
                      double dy[ODE_DIM])
{
    struct reftrace_field f;
    reftrace_sample_field(o, triple(y), &f);
    const double sig[3] = {f.sigma_a.x + f.sigma_s.x, f.sigma_a.y + f.sigma_s.y,
                           f.sigma_a.z + f.sigma_s.z};
    const double inv_n2 = 1.0 / (f.n * f.n);
    const double em[3] = {f.emission.x * inv_n2, f.emission.y * inv_n2, f.emission.z * inv_n2};
    const double g[3] = {f.grad.x, f.grad.y, f.grad.z};
    for (int c = 0; c < 3; c++) {
        dy[c] = y[3 + c] / f.n;
        dy[3 + c] = g[c];
        dy[7 + c] = sig[c] * scale;
        dy[10 + c] = exp(-y[7 + c]) * em[c] * scale;
    }
    dy[6] = f.n * scale;
}

void reftrace_step_dopri(const struct reftrace_object *o, double scale, double h,
                         const struct reftrace_ode *y0, struct reftrace_ode *y1, double err[3])
{
    double y[ODE_DIM], k[7][ODE_DIM], tmp[ODE_DIM];
    ode_to_array(y0, y);
    ode_deriv(o, scale, y, k[0]);
    for (int s = 1; s < 7; s++) {
        for (int i = 0; i < ODE_DIM; i++) {
            double acc = 0.0;
            for (int j = 0; j < s; j++)
                acc += dp_a[s][j] * k[j][i];
            tmp[i] = y[i] + h * acc;
        }
        ode_deriv(o, scale, tmp, k[s]);
    }
    /* Stage 7 was evaluated at the fifth-order solution, which is therefore tmp. */
    ode_from_array(tmp, y1);
    /* Components 0-2 are p, 3-5 w, 6 the optical path length. */
    double e2[3] = {0.0, 0.0, 0.0};
    for (int i = 0; i < 7; i++) {
        double e = 0.0;
        for (int s = 0; s < 7; s++)
            e += dp_e[s] * k[s][i];
        e *= h;
        e2[i / 3] += e * e;
    }
    for (int i = 0; i < 3; i++)
        err[i] = sqrt(e2[i]);
}
