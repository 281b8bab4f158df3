// lightsim_patches.glsl - the two patch lists (ping-pong), the per-patch output counts and
// their prefix sum, shared by lightsim_step.comp and lightsim_emit.comp.

layout(std430, binding = BIND_SSBO_LS_PATCHES_IN) buffer ls_patches_in_block
{
    ls_gpu_patch patches_in[];
};

layout(std430, binding = BIND_SSBO_LS_PATCHES_OUT) writeonly buffer ls_patches_out_block
{
    ls_gpu_patch patches_out[];
};

layout(std430, binding = BIND_SSBO_LS_COUNTS) buffer ls_counts_block
{
    uint out_count[];
};

layout(std430, binding = BIND_SSBO_LS_OFFSETS) readonly buffer ls_offsets_block
{
    uint out_offset[];
};
