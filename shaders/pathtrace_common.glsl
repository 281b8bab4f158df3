// pathtrace_common.glsl - what the GPU's Monte Carlo kernels share (pathtrace_render.comp,
// the path tracer; photon_trace.comp, the caustic photons): a 32-bit random number chain
// and the direction samplers of server/core/pathtrace_sample.c.

#include "pixel_sample.glsl" // pixel_hash: lowbias32, the one integer hash of the kernels

#define PT_PI 3.14159265358979

// ---- random numbers: PCG-RXS-M-XS 32 (O'Neill 2014) as a state chain ----
uint rng_state;
float rng_uniform()
{
    rng_state = rng_state * 747796405u + 2891336453u;
    uint w = ((rng_state >> ((rng_state >> 28u) + 4u)) ^ rng_state) * 277803737u;
    w = (w >> 22u) ^ w;
    return float(w >> 8) * (1.0 / 16777216.0);
}

// ---- directions (pathtrace_sample.c) ----
vec3 around(vec3 axis, float cos_t, float phi)
{
    float sgn = axis.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (sgn + axis.z);
    float b = axis.x * axis.y * a;
    vec3 t = vec3(1.0 + sgn * axis.x * axis.x * a, sgn * b, -sgn * axis.x);
    vec3 bb = vec3(b, sgn + axis.y * axis.y * a, -axis.y);
    float sin_t = sqrt(max(0.0, 1.0 - cos_t * cos_t));
    return normalize(axis * cos_t + t * (sin_t * cos(phi)) + bb * (sin_t * sin(phi)));
}
// Uniform in the cone of half angle acos(cos_max) about unit axis (pathtrace_sample_cone).
vec3 sample_cone(vec3 axis, float cos_max)
{
    float u1 = rng_uniform(), u2 = rng_uniform();
    return around(axis, 1.0 - u1 * (1.0 - cos_max), 2.0 * PT_PI * u2);
}
