// camera.glsl - the pinhole camera of frisvad2010 ("Ray casting"); twin of camera_ray in
// server/core/env.c. Pixel (col, row) with row 0 at the top; docs/tracing.md "Camera".

vec3 camera_ray_direction(vec3 forward, vec3 right, vec3 up, float tan_half_fov, float aspect,
                          float col, float row, float width, float height)
{
    float sx = (2.0 * (col + 0.5) / width - 1.0) * tan_half_fov * aspect;
    float sy = (1.0 - 2.0 * (row + 0.5) / height) * tan_half_fov;
    return normalize(forward + sx * right + sy * up);
}
