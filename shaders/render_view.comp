#version 450
// render_view.comp - view rays through the scene, one or several per pixel (anti-aliasing),
// tevs2007 sect. 6.3 (the view renderer), writing linear radiance. Rows are written top to
// bottom (row 0 = top). One dispatch renders the tile of rows [params.image.z,
// params.image.w) into image_out, whose row 0 is the tile's first row: a pixel's value
// depends only on its place in the whole image (its rays' jitter too), so a render made of
// tiles is the same, bit for bit, as one made at once. The host dispatches a pixel's rays
// one at a time (settings_f2.z: which, .w: how many), each dispatch adding its share to
// image_out: llvmpipe ends a shader invocation's loops after 65535 iterations counted over
// all of them (LP_MAX_TGSI_LOOP_ITERATIONS in Mesa's gallivm), so an invocation that
// marched all of a pixel's rays could silently lose the later ones (docs/tracing.md
// "Anti-aliasing").
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

layout(std430, binding = BIND_SSBO_IMAGE_OUT) buffer image_out_block
{
    vec4 image_out[];
};

void main()
{
    ivec2 px = ivec2(gl_GlobalInvocationID.xy) + ivec2(0, params.image.z);
    if (px.x >= params.image.x || px.y >= params.image.y || px.y >= params.image.w)
        return;
    // Anti-aliasing: n jittered rays in k x k strata, averaged (a box filter).
    uint n = uint(max(params.settings_f2.y, 1.0));
    uint first = uint(params.settings_f2.z), count = uint(params.settings_f2.w);
    if (count == 0u)
        count = n;
    vec3 sum = vec3(0.0);
    for (uint i = first; i < first + count && i < n; i++) {
        vec2 o = pixel_sample(uint(px.x), uint(px.y), i, n);
        vec3 dir = camera_ray_direction(params.forward.xyz, params.right.xyz, params.up.xyz,
                                        params.eye.w, params.forward.w, float(px.x) + o.x - 0.5,
                                        float(px.y) + o.y - 0.5, float(params.image.x),
                                        float(params.image.y));
#if MARCH_SURFACES
        march_defer_ok = true;
        march_deferred = false;
#if MARCH_LIGHTS
        // walter scenes: sample i's inner in-scattering points shifted by the golden ratio
        if (lights.count.w == 1)
            march_step_offset = pixel_step_offset(i);
#endif
#endif
        march_state s = march_ray(params.eye.xyz, dir, uint(params.surfaces.y));
        sum += s.L;
#if MARCH_SURFACES
        if (march_deferred) { // the internal reflection (docs/walter.md)
            march_defer_ok = false;
            march_start_surface = march_defer_surface;
            march_start_prim = march_defer_prim;
            march_second_ray = true;
            march_state r = march_ray(march_defer_x, march_defer_d, march_defer_inside);
            march_second_ray = false;
            sum += march_defer_w * r.L;
            march_start_surface = -1;
            march_start_prim = -1;
        }
#endif
    }
    uint at = uint((px.y - params.image.z) * params.image.x + px.x);
    vec4 part = vec4(sum / float(n), 1.0);
    image_out[at] = first == 0u ? part : image_out[at] + vec4(part.rgb, 0.0);
}
