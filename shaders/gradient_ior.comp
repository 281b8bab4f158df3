#version 450
// gradient_ior.comp - central differences of the smoothed index (tevs2007 eq. 3.1), in
// object units, stored with n as (grad n, n) into the object's box of the ior+grad atlas
// (texture T1 of tevs2007 sect. 6.1). Twin: gradient_central_ref in server/core/smooth.c.
#include "volume_bindings.glsl"

layout(local_size_x = VOLUME_LOCAL_X, local_size_y = VOLUME_LOCAL_Y, local_size_z = VOLUME_LOCAL_Z) in;

layout(rgba32f, binding = IMAGE_IOR_GRAD_OUT) writeonly uniform image3D ior_grad_out;

void main()
{
    ivec3 v = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(v, vparams.resolution.xyz)))
        return;
    vec3 inv2h = 0.5 / vparams.voxel_size.xyz;
    vec3 g;
    g.x = (field_in[volume_index(v + ivec3(1, 0, 0))] - field_in[volume_index(v - ivec3(1, 0, 0))]) * inv2h.x;
    g.y = (field_in[volume_index(v + ivec3(0, 1, 0))] - field_in[volume_index(v - ivec3(0, 1, 0))]) * inv2h.y;
    g.z = (field_in[volume_index(v + ivec3(0, 0, 1))] - field_in[volume_index(v - ivec3(0, 0, 1))]) * inv2h.z;
    imageStore(ior_grad_out, v + vparams.atlas_offset.xyz, vec4(g, field_in[volume_index(v)]));
}
