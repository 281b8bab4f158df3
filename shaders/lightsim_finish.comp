#version 450
// lightsim_finish.comp - the deposit buffer into the two volumes the renderer samples
// (docs/lightsim.md "Output"): irradiance rgb (w = 0), and the normalised deposited
// direction with w = 1 where its length is > 0, else 0. Twin: the end of lightsim_ref_run.
#include "lightsim_common.glsl"

layout(local_size_x = VOLUME_LOCAL_X, local_size_y = VOLUME_LOCAL_Y, local_size_z = VOLUME_LOCAL_Z) in;

layout(std430, binding = BIND_SSBO_LS_DEPOSIT) readonly buffer ls_deposit_block
{
    float deposit[];
};
layout(rgba32f, binding = IMAGE_LS_IRRADIANCE) writeonly uniform image3D irradiance_out;
layout(rgba16f, binding = IMAGE_LS_DIRECTION) writeonly uniform image3D direction_out;

void main()
{
    ivec3 v = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(v, ls.dims.xyz)))
        return;
    uint base = uint((v.z * ls.dims.y + v.y) * ls.dims.x + v.x) * LS_DEPOSIT_STRIDE;
    vec3 e = vec3(deposit[base], deposit[base + 1u], deposit[base + 2u]);
    vec3 d = vec3(deposit[base + 3u], deposit[base + 4u], deposit[base + 5u]);
    float len = length(d);
    imageStore(irradiance_out, v, vec4(e, 0.0));
    imageStore(direction_out, v, len > 0.0 ? vec4(d / len, 1.0) : vec4(0.0));
}
