// lightsim_patches.glsl - the two patch lists (ping-pong), the per-patch output counts and
// their prefix sum, shared by lightsim_step.comp and lightsim_emit.comp.

layout(std430, binding = BIND_SSBO_LS_PATCHES_IN) buffer ls_patches_in_block
{
    ls_gpu_patch patches_in[];
};

// lightsim_step.comp (LS_STEP_KERNEL) declares neither the next list nor the offsets: a
// compute shader may have 16 storage blocks (llvmpipe and many GPUs), and the step's
// deposit channels, twins and surfaces take the rest.
#ifndef LS_STEP_KERNEL
layout(std430, binding = BIND_SSBO_LS_PATCHES_OUT) writeonly buffer ls_patches_out_block
{
    ls_gpu_patch patches_out[];
};
#endif

layout(std430, binding = BIND_SSBO_LS_COUNTS) buffer ls_counts_block
{
    uint out_count[];
};

#ifndef LS_STEP_KERNEL
layout(std430, binding = BIND_SSBO_LS_OFFSETS) readonly buffer ls_offsets_block
{
    uint out_offset[];
};
#endif
