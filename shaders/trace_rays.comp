#version 450
// trace_rays.comp - optical ray queries for /v1/scenes/{id}/trace: the same march as the
// view renderer without radiance, one invocation per ray.
#include "march_bindings.glsl"

// Surface events ("events": true, params.image.w = 1): TRACE_MAX_EVENTS slots per ray.
layout(std430, binding = BIND_SSBO_TRACE_EVENTS) writeonly buffer trace_events_block
{
    trace_event_out trace_events[];
};

void march_trace_event(int index, vec3 x, vec3 d, vec3 N, bool tir, float R, int k, int from,
                       int to, float n_from, float n_to)
{
    if (params.image.w != 1 || index >= TRACE_MAX_EVENTS)
        return;
    int slot = int(gl_GlobalInvocationID.x) * TRACE_MAX_EVENTS + index;
    trace_events[slot].point = vec4(x, tir ? float(TRACE_EVENT_REFLECTED) : float(TRACE_EVENT_REFRACTED));
    trace_events[slot].normal = vec4(dot(N, d) > 0.0 ? -N : N, R);
    trace_events[slot].media = ivec4(k, from, to, 0);
    trace_events[slot].ior = vec4(n_from, n_to, 0.0, 0.0);
}
#define MARCH_TRACE_EVENTS 1
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
    hits_out[i].events = ivec4(s.events, 0, 0, 0);
}
