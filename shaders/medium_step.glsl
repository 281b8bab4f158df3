// medium_step.glsl - single scattering along a straight segment through a constant medium:
// the step count and the exact transmittance integral of one step. Twin of
// server/core/medium_step.c (same names); docs/tracing.md "Scattering inside surfaces".

const int MEDIUM_MAX_STEPS = 1024;  // most steps one segment is cut into
const int MEDIUM_DIRECT_STEPS = 64; // steps where no light has an irradiance volume

// int_0^h exp(-sigma_t u) du = (1 - exp(-sigma_t h)) / sigma_t; h where sigma_t = 0. Below
// sigma_t h = 1e-3 its series (float's 1 - exp(x) would cancel to 1e-4 relative there).
float medium_step_weight(float sigma_t, float h)
{
    float x = sigma_t * h;
    if (x < 1e-3)
        return h * (1.0 - x * (0.5 - x / 6.0));
    return (1.0 - exp(-x)) / sigma_t;
}

vec3 medium_step_weight(vec3 sigma_t, float h)
{
    return vec3(medium_step_weight(sigma_t.r, h), medium_step_weight(sigma_t.g, h),
                medium_step_weight(sigma_t.b, h));
}

// ceil(t / step) in 1..MEDIUM_MAX_STEPS; step <= 0: MEDIUM_DIRECT_STEPS.
int medium_step_count(float t, float step)
{
    if (!(t > 0.0))
        return 1;
    if (!(step > 0.0))
        return MEDIUM_DIRECT_STEPS;
    return int(clamp(ceil(t / step), 1.0, float(MEDIUM_MAX_STEPS)));
}
