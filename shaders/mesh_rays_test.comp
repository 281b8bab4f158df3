#version 450
// mesh_rays_test.comp - a test kernel, not used by the renderer: one invocation traces one
// ray with mesh_rt_intersect (geom/mesh.glsl) against the mesh its record names, so that
// tests/gpu/test_mesh_rt_gpu.c can compare every hit with the C double version. Embedded
// like the others because tests compile only embedded shaders; it costs a few KiB.
#include "bindings.h"
#include "geom/mesh.glsl"
// The bare name finds the same file and adds nothing (shader_source.h): kernels written
// before shaders had folders include their geom/ files so.
#include "mesh.glsl"

layout(local_size_x = TRACE_LOCAL_X) in;

struct mesh_ray_in {
    vec4 origin;    // xyz; w: tmin
    vec4 direction; // xyz (need not be unit); w: tmax
    ivec4 mesh;     // xyz: the mesh's first node, triangle, vertex; w: skip_tri (-1: none)
};
struct mesh_hit_out {
    vec4 t_geom;  // x: t; yzw: geometric normal
    vec4 shade;   // xyz: shading normal; w: int bits of the triangle (-1: missed)
};

layout(std430, binding = BIND_SSBO_RAYS_IN) readonly buffer mesh_rays_block
{
    mesh_ray_in mesh_rays[];
};
layout(std430, binding = BIND_SSBO_HITS_OUT) writeonly buffer mesh_hits_block
{
    mesh_hit_out mesh_hits[];
};

uniform int u_ray_count;

void main()
{
    int i = int(gl_GlobalInvocationID.x);
    if (i >= u_ray_count)
        return;
    mesh_ray_in r = mesh_rays[i];
    float t;
    vec3 ng, ns;
    int tri;
    bool hit = mesh_rt_intersect(ivec4(r.mesh.xyz, 0), r.origin.xyz, r.direction.xyz,
                                 r.origin.w, r.direction.w, r.mesh.w, t, ng, ns, tri);
    mesh_hits[i].t_geom = vec4(hit ? t : -1.0, ng);
    mesh_hits[i].shade = vec4(ns, intBitsToFloat(hit ? tri : -1));
}
