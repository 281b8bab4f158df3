#version 450
// render_view.comp - one view ray per pixel through the scene (tevs2007 sect. 6.3, the view
// renderer), writing linear radiance. Rows are written top to bottom (row 0 = top). One
// dispatch renders the tile of rows [params.image.z, params.image.w) into image_out, whose
// row 0 is the tile's first row: a pixel's value depends only on its place in the whole
// image, so a render made of tiles is the same, bit for bit, as one made at once.
#define MARCH_RADIANCE 1
#include "march_bindings.glsl"
#include "fresnel.glsl"
#include "camera.glsl"
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
    ivec2 px = ivec2(gl_GlobalInvocationID.xy) + ivec2(0, params.image.z);
    if (px.x >= params.image.x || px.y >= params.image.y || px.y >= params.image.w)
        return;
    vec3 dir = camera_ray_direction(params.forward.xyz, params.right.xyz, params.up.xyz,
                                    params.eye.w, params.forward.w, float(px.x), float(px.y),
                                    float(params.image.x), float(params.image.y));
    march_state s = march_ray(params.eye.xyz, dir, uint(params.surfaces.y));
    image_out[(px.y - params.image.z) * params.image.x + px.x] = vec4(s.L, 1.0);
}
