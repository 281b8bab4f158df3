// ray_equation.glsl - one integration step of the ray equation of geometric optics,
// d/ds (n dx/ds) = grad n (tevs2007 eq. 4.7), as the first-order system
// dx/ds = w / n, dw/ds = grad n (eqs. 4.8, 4.9) with w = n * direction.
// Positions and steps are in object space; the system keeps its form under the
// object's similarity transform. Twins: server/core/reftrace*.c.

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
