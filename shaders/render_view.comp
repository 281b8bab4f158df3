#version 450
// render_view.comp - view rays through the scene, one or several per pixel (anti-aliasing),
// tevs2007 sect. 6.3 (the view renderer), writing linear radiance. Rows are written top to
// bottom (row 0 = top).
#define MARCH_RADIANCE 1
#include "march_bindings.glsl"
#include "fresnel.glsl"
#include "camera.glsl"
#include "pixel_sample.glsl"
#include "environment.glsl"
#include "volume_sample.glsl"
#include "ray_equation.glsl"
#include "lighting.glsl"
#include "ray_march.glsl"

layout(local_size_x = RENDER_LOCAL_X, local_size_y = RENDER_LOCAL_Y) in;

layout(std430, binding = BIND_SSBO_IMAGE_OUT) writeonly buffer image_out_block
{
    vec4 image_out[];
};

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy);
    if (px.x >= params.image.x || px.y >= params.image.y)
        return;
    // Anti-aliasing: n jittered rays in k x k strata, averaged (a box filter).
    uint n = uint(max(params.settings_f2.y, 1.0));
    vec3 sum = vec3(0.0);
    for (uint i = 0u; i < n; i++) {
        vec2 o = pixel_sample(uint(px.x), uint(px.y), i, n);
        vec3 dir = camera_ray_direction(params.forward.xyz, params.right.xyz, params.up.xyz,
                                        params.eye.w, params.forward.w, float(px.x) + o.x - 0.5,
                                        float(px.y) + o.y - 0.5, float(params.image.x),
                                        float(params.image.y));
        march_state s = march_ray(params.eye.xyz, dir, uint(params.surfaces.y));
        sum += s.L;
    }
    image_out[px.y * params.image.x + px.x] = vec4(sum / float(n), 1.0);
}
