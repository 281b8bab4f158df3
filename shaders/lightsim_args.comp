#version 450
// lightsim_args.comp - the end of a step, one invocation: folds the step's float sums and
// event counts into the run's double totals, sets the live count (the scan total, capped
// at max_patches: lightsim_emit dropped the rest), the peak, the step count and the
// indirect dispatch arguments of the next step. No CPU round trip per step.
#include "lightsim_common.glsl"

layout(local_size_x = 1) in;

layout(std430, binding = BIND_SSBO_LS_TOTALS) buffer ls_totals_block
{
    double totals[];
};

void main()
{
    int n_in = control.counts.x;
    if (n_in > 0) {
        control.counts.z += 1;
        totals[LS_TOT_PATCH_STEPS] += double(n_in);
    }
    for (int k = 0; k < LS_ACC_LIVE; k++) {
#ifdef GL_NV_shader_atomic_float
        totals[k] += double(ls_accum[k]);
        ls_accum[k] = 0.0;
#else
        totals[k] += double(uintBitsToFloat(ls_accum[k]));
        ls_accum[k] = 0u;
#endif
    }
    if (n_in > 0) {
        for (int k = LS_ACC_LIVE; k < LS_ACC_LIVE + 3; k++) {
#ifdef GL_NV_shader_atomic_float
            totals[k] = double(ls_accum[k]);
            ls_accum[k] = 0.0;
#else
            totals[k] = double(uintBitsToFloat(ls_accum[k]));
            ls_accum[k] = 0u;
#endif
        }
    }
    totals[LS_TOT_SPLITS] += double(control.events.x);
    totals[LS_TOT_CULLED_ENERGY] += double(control.events.y);
    totals[LS_TOT_CULLED_LEVEL] += double(control.events.z);
    totals[LS_TOT_CULLED_FLIP] += double(control.events.w);
    totals[LS_TOT_CULLED_CAPACITY] += double(control.events2.x);
    control.events = ivec4(0);
    control.events2 = ivec4(0);
    int live = n_in > 0 ? min(control.counts.y, ls.limits.y) : 0;
    control.counts.x = live;
    control.counts.y = 0;
    control.counts.w = max(control.counts.w, live);
    control.dispatch_patches = ivec4((live + LS_LOCAL_X - 1) / LS_LOCAL_X, 1, 1, 0);
    control.dispatch_blocks = ivec4((live + LS_SCAN_BLOCK - 1) / LS_SCAN_BLOCK, 1, 1, 0);
}
