// pixel_sample.glsl - where in its pixel view ray s of n goes (docs/tracing.md
// "Anti-aliasing"); twin of server/core/pixel_sample.c, the same integer hash and the same
// float arithmetic, so the CPU reference averages the same rays. The pixel is split into
// k x k equal strata (n = k^2) and each ray is jittered inside its stratum by a hash of
// (col, row, s): stratified sampling under a box filter, every pixel the same weight. One
// ray (n = 1) goes through the pixel's centre, as before anti-aliasing.

// lowbias32 (Chris Wellons' integer hash): full avalanche, two multiplies.
uint pixel_hash(uint x)
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

// Offset of ray s (0 <= s < n) from the pixel's corner, each component in [0, 1).
vec2 pixel_sample(uint col, uint row, uint s, uint n)
{
    if (n <= 1u)
        return vec2(0.5);
    uint k = uint(sqrt(float(n)) + 0.5);
    uint h = pixel_hash(col ^ pixel_hash(row ^ pixel_hash(s)));
    float jx = float(h >> 8) * (1.0 / 16777216.0);
    float jy = float(pixel_hash(h) >> 8) * (1.0 / 16777216.0);
    return vec2((float(s % k) + jx) / float(k), (float(s / k) + jy) / float(k));
}

// Where ray s samples the inner steps of a walter scene's in-scattering (docs/walter.md
// "Steps"): the golden-ratio sequence from the midpoint (pixel_sample.c's twin).
float pixel_step_offset(uint s)
{
    return fract(0.5 + 0.6180339887 * float(s));
}
