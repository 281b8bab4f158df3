// surface.glsl - a placed exact surface of any kind, the twin of
// server/core/geom/surface.c: the world ray is carried into the surface's object space,
// intersected by the kind's own file, and the hit carried back. Needs geom_hit.glsl and
// the kinds' files included before it (ray_march.glsl does).

layout(std430, binding = BIND_SSBO_SURFACES) readonly buffer surfaces_block
{
    surface_params surfaces[];
};

// sigma_t = sigma_a + sigma_s of surface k's constant medium (tevs2007 eq. 5.9: light
// scattered out of a ray is lost to it); the twin of reftrace_surface_extinction.
vec3 surface_extinction(int k)
{
    return surfaces[k].attenuation.rgb + surfaces[k].scattering.rgb;
}

layout(std430, binding = BIND_SSBO_SURFACE_PROFILES) readonly buffer surface_profiles_block
{
    vec2 lathe_points[];
};
