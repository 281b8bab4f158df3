#version 450
// trace_rays.comp - optical ray queries for /v1/scenes/{id}/trace: the same march as the
// view renderer without radiance, one invocation per ray.
#include "march_bindings.glsl"
#include "fresnel.glsl"
#include "environment.glsl"
#include "volume_sample.glsl"
#include "ray_equation.glsl"
#include "ray_march.glsl"

layout(local_size_x = TRACE_LOCAL_X) in;

layout(std430, binding = BIND_SSBO_RAYS_IN) readonly buffer rays_in_block
{
    trace_ray_in rays_in[];
};

layout(std430, binding = BIND_SSBO_HITS_OUT) writeonly buffer hits_out_block
{
    trace_hit_out hits_out[];
};

void main()
{
    int i = int(gl_GlobalInvocationID.x);
    if (i >= params.image.z)
        return;
    march_state s = march_ray(rays_in[i].origin.xyz, rays_in[i].direction.xyz,
                              floatBitsToUint(rays_in[i].origin.w));
    hits_out[i].exit_origin = vec4(s.x, float(s.status));
    hits_out[i].exit_direction = vec4(s.d, float(s.steps));
    hits_out[i].transmittance = vec4(s.t_f * exp(-s.alpha), s.opl);
}
