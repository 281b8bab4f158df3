// volume_bindings.glsl - the resources of the scene-load kernels (smooth_ior, gradient_ior).
#include "bindings.h"
#include "shared_types.h"

layout(std140, binding = BIND_UBO_VOLUME) uniform volume_params_block
{
    volume_params vparams;
};

layout(std430, binding = BIND_SSBO_FIELD_IN) readonly buffer field_in_block
{
    float field_in[];
};

int volume_index(ivec3 v)
{
    ivec3 r = vparams.resolution.xyz;
    v = clamp(v, ivec3(0), r - 1); // clamp to edge (docs/tracing.md "Precomputation")
    return (v.z * r.y + v.y) * r.x + v.x;
}
