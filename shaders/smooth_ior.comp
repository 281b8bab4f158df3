#version 450
// smooth_ior.comp - one pass of the separable Gaussian pre-smoothing of the refractive index
// (tevs2007 sect. 3.1, eq. 3.2 with a standard deviation; docs/tracing.md). Run three times
// with vparams.resolution.w = 0, 1, 2. Twin: smooth_gaussian_ref in server/core/smooth.c.
#include "volume_bindings.glsl"

layout(local_size_x = VOLUME_LOCAL_X, local_size_y = VOLUME_LOCAL_Y, local_size_z = VOLUME_LOCAL_Z) in;

layout(std430, binding = BIND_SSBO_FIELD_OUT) writeonly buffer field_out_block
{
    float field_out[];
};

float smooth_ior_weight(int k)
{
    return vparams.weights[k / 4][k % 4];
}

void main()
{
    ivec3 v = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(v, vparams.resolution.xyz)))
        return;
    ivec3 axis = ivec3(0);
    axis[vparams.resolution.w] = 1;
    int radius = vparams.atlas_offset.w;
    float sum = smooth_ior_weight(0) * field_in[volume_index(v)];
    for (int k = 1; k <= radius; k++) {
        float w = smooth_ior_weight(k);
        sum += w * (field_in[volume_index(v + k * axis)] + field_in[volume_index(v - k * axis)]);
    }
    field_out[volume_index(v)] = sum;
}
