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
    // Central differences inside; one-sided at the grid's edges (the clamped neighbour is
    // the voxel itself and the difference spans one voxel), so linear fields keep their
    // slope up to the bounds.
    ivec3 r = vparams.resolution.xyz;
    ivec3 lo = max(v - 1, ivec3(0));
    ivec3 hi = min(v + 1, r - 1);
    vec3 span = vec3(max(hi - lo, ivec3(1))) * vparams.voxel_size.xyz;
    vec3 g;
    g.x = (field_in[volume_index(ivec3(hi.x, v.y, v.z))] - field_in[volume_index(ivec3(lo.x, v.y, v.z))]) / span.x;
    g.y = (field_in[volume_index(ivec3(v.x, hi.y, v.z))] - field_in[volume_index(ivec3(v.x, lo.y, v.z))]) / span.y;
    g.z = (field_in[volume_index(ivec3(v.x, v.y, hi.z))] - field_in[volume_index(ivec3(v.x, v.y, lo.z))]) / span.z;
    imageStore(ior_grad_out, v + vparams.atlas_offset.xyz, vec4(g, field_in[volume_index(v)]));
}
