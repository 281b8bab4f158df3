// ray_equation.glsl - one integration step of the ray equation of geometric optics,
// d/ds (n dx/ds) = grad n (tevs2007 eq. 4.7), as the first-order system
// dx/ds = w / n, dw/ds = grad n (eqs. 4.8, 4.9) with w = n * direction.
// Positions and steps are in object space; the system keeps its form under the
// object's similarity transform. Twins: server/core/reftrace*.c.
//
// Adaptive step control constants (docs/tracing.md "Steppers"); the CPU twin's are in
// server/core/reftrace.c (BS23_*).
const float RAY_BS23_SAFETY = 0.9;
const float RAY_BS23_SHRINK_MIN = 0.2;
const float RAY_BS23_GROW_MAX = 5.0;
const float RAY_BS23_FLOOR = 1e-3; // smallest step, in units of the largest (the step setting)

// Explicit Euler, tevs2007 eqs. 5.11/5.12. s0 = (grad n, n) sampled at p.
void ray_equation_step_euler(int obj, vec4 s0, float h, inout vec3 p, inout vec3 w)
{
    vec3 p1 = p + (h / s0.a) * w;
    w = w + h * s0.rgb;
    p = p1;
}

// Classical fourth-order Runge-Kutta on y = (p, w). s0 = sample at p (the k1 stage);
// three more samples for k2..k4.
void ray_equation_step_rk4(int obj, vec4 s0, float h, inout vec3 p, inout vec3 w)
{
    vec3 k1p = w / s0.a;
    vec3 k1w = s0.rgb;
    vec3 w2 = w + 0.5 * h * k1w;
    vec4 s2 = volume_sample_ior_grad(obj, p + 0.5 * h * k1p);
    vec3 k2p = w2 / s2.a;
    vec3 k2w = s2.rgb;
    vec3 w3 = w + 0.5 * h * k2w;
    vec4 s3 = volume_sample_ior_grad(obj, p + 0.5 * h * k2p);
    vec3 k3p = w3 / s3.a;
    vec3 k3w = s3.rgb;
    vec3 w4 = w + h * k3w;
    vec4 s4 = volume_sample_ior_grad(obj, p + h * k3p);
    vec3 k4p = w4 / s4.a;
    vec3 k4w = s4.rgb;
    p = p + (h / 6.0) * (k1p + 2.0 * k2p + 2.0 * k3p + k4p);
    w = w + (h / 6.0) * (k1w + 2.0 * k2w + 2.0 * k3w + k4w);
}

// Explicit midpoint (RK2): y1 = y + h f(y + h/2 f(y)); one sample more than Euler.
void ray_equation_step_rk2(int obj, vec4 s0, float h, inout vec3 p, inout vec3 w)
{
    vec3 pm = p + (0.5 * h / s0.a) * w;
    vec3 wm = w + 0.5 * h * s0.rgb;
    vec4 sm = volume_sample_ior_grad(obj, pm);
    p = p + (h / sm.a) * wm;
    w = w + h * sm.rgb;
}

// Bogacki-Shampine 3(2) (Bogacki & Shampine 1989): the third-order solution, and the
// difference to the embedded second-order one as the error estimate, returned as
// |e_p| + extent |e_w| / |w| (object units): the position error plus the displacement the
// direction error causes over the object's largest extent. Four samples (the fourth at the
// new point; the CPU twin is reftrace_step_bs23).
float ray_equation_step_bs23(int obj, vec4 s0, float h, float extent, inout vec3 p,
                             inout vec3 w)
{
    vec3 k1p = w / s0.a;
    vec3 k1w = s0.rgb;
    vec3 w2 = w + 0.5 * h * k1w;
    vec4 s2 = volume_sample_ior_grad(obj, p + 0.5 * h * k1p);
    vec3 k2p = w2 / s2.a;
    vec3 k2w = s2.rgb;
    vec3 w3 = w + 0.75 * h * k2w;
    vec4 s3 = volume_sample_ior_grad(obj, p + 0.75 * h * k2p);
    vec3 k3p = w3 / s3.a;
    vec3 k3w = s3.rgb;
    vec3 p1 = p + h * ((2.0 / 9.0) * k1p + (1.0 / 3.0) * k2p + (4.0 / 9.0) * k3p);
    vec3 w1 = w + h * ((2.0 / 9.0) * k1w + (1.0 / 3.0) * k2w + (4.0 / 9.0) * k3w);
    vec4 s4 = volume_sample_ior_grad(obj, p1);
    vec3 k4p = w1 / s4.a;
    vec3 k4w = s4.rgb;
    vec3 ep = h * ((-5.0 / 72.0) * k1p + (1.0 / 12.0) * k2p + (1.0 / 9.0) * k3p - 0.125 * k4p);
    vec3 ew = h * ((-5.0 / 72.0) * k1w + (1.0 / 12.0) * k2w + (1.0 / 9.0) * k3w - 0.125 * k4w);
    float err = length(ep) + extent * length(ew) / max(length(w), 1e-30);
    p = p1;
    w = w1;
    return err;
}

// The step after one of size h with error err against tolerance tol: the usual
// controller h (tol / err)^(1/3) with safety factor, bounded to [0.2, 5] h and to
// [floor, h_max]. Used for the retry after a rejection and for the next step alike.
float ray_equation_next_step(float h, float err, float tol, float h_max)
{
    float fac = err > 0.0 ? RAY_BS23_SAFETY * pow(tol / err, 1.0 / 3.0) : RAY_BS23_GROW_MAX;
    fac = clamp(fac, RAY_BS23_SHRINK_MIN, RAY_BS23_GROW_MAX);
    return clamp(h * fac, RAY_BS23_FLOOR * h_max, h_max);
}
