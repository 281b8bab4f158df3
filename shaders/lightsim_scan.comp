#version 450
// lightsim_scan.comp - exclusive prefix sum of the patches' output counts, in three
// stages chosen by LS_SCAN_STAGE (a preamble #define):
//   0: each block of LS_SCAN_BLOCK counts is scanned in shared memory into out_offset,
//      its total into block_sums[block];
//   1: one work group scans block_sums in place and writes the grand total into
//      control.counts.y (at most LS_SCAN_BLOCK blocks: LS_MAX_PATCHES elements);
//   2: each block adds its block's offset.
// The element count is control.counts.x. Twin: the CPU scan in the test
// (tests/gpu/test_lightsim_gpu_scan.c); the reference simulator appends in list order.
#include "lightsim_common.glsl"

layout(local_size_x = LS_SCAN_LOCAL) in;

layout(std430, binding = BIND_SSBO_LS_COUNTS) readonly buffer ls_counts_block
{
    uint out_count[];
};
layout(std430, binding = BIND_SSBO_LS_OFFSETS) buffer ls_offsets_block
{
    uint out_offset[];
};
layout(std430, binding = BIND_SSBO_LS_BLOCK_SUMS) buffer ls_block_sums_block
{
    uint block_sums[];
};

shared uint partial[LS_SCAN_LOCAL];

// Exclusive scan of the invocations' values in shared memory (Hillis-Steele); returns
// this invocation's exclusive prefix, and the group total through `total`.
uint scan_group(uint value, out uint total)
{
    uint lid = gl_LocalInvocationID.x;
    partial[lid] = value;
    barrier();
    for (uint s = 1u; s < LS_SCAN_LOCAL; s <<= 1u) {
        uint add = lid >= s ? partial[lid - s] : 0u;
        barrier();
        partial[lid] += add;
        barrier();
    }
    total = partial[LS_SCAN_LOCAL - 1];
    return partial[lid] - value;
}

void main()
{
    uint n = uint(control.counts.x);
    uint lid = gl_LocalInvocationID.x;
    const uint per = LS_SCAN_BLOCK / LS_SCAN_LOCAL;
#if LS_SCAN_STAGE == 0
    uint base = gl_WorkGroupID.x * LS_SCAN_BLOCK + lid * per;
    uint v[per];
    uint sum = 0u;
    for (uint k = 0u; k < per; k++) {
        v[k] = base + k < n ? out_count[base + k] : 0u;
        sum += v[k];
    }
    uint total;
    uint run = scan_group(sum, total);
    for (uint k = 0u; k < per; k++) {
        if (base + k < n)
            out_offset[base + k] = run;
        run += v[k];
    }
    if (lid == 0u)
        block_sums[gl_WorkGroupID.x] = total;
#elif LS_SCAN_STAGE == 1
    uint blocks = (n + LS_SCAN_BLOCK - 1u) / LS_SCAN_BLOCK;
    uint base = lid * per;
    uint v[per];
    uint sum = 0u;
    for (uint k = 0u; k < per; k++) {
        v[k] = base + k < blocks ? block_sums[base + k] : 0u;
        sum += v[k];
    }
    uint total;
    uint run = scan_group(sum, total);
    for (uint k = 0u; k < per; k++) {
        if (base + k < blocks)
            block_sums[base + k] = run;
        run += v[k];
    }
    if (lid == 0u)
        control.counts.y = int(total);
#else
    uint add = block_sums[gl_WorkGroupID.x];
    uint base = gl_WorkGroupID.x * LS_SCAN_BLOCK + lid * per;
    for (uint k = 0u; k < per; k++)
        if (base + k < n)
            out_offset[base + k] += add;
#endif
}
