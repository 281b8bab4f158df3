// lightsim_common.glsl - what every light-simulator kernel shares (docs/lightsim.md): the
// parameter block, the patch lists, the control counters, field sampling on the light
// grid and atomic float addition. Twin: server/lightsim/lightsim_ref.c (double).
// Include it first: the #extension line must precede every declaration.
#extension GL_NV_shader_atomic_float : enable
// LS_CAS_ATOMICS (a preamble #define, REFRACT_LIGHTSIM_CAS_ATOMICS=1 at start-up) forces
// the portable compare-and-swap path where the extension exists, so tests run both.
#if defined(GL_NV_shader_atomic_float) && !defined(LS_CAS_ATOMICS)
#define LS_NATIVE_FLOAT_ATOMICS 1
#endif
#include "bindings.h"
#include "shared_types.h"

layout(std140, binding = BIND_UBO_LIGHTSIM) uniform lightsim_params_block
{
    lightsim_params ls;
};

// The control counters and one step's flux sums (ls_accum, LS_ACC_COUNT floats after
// control: one storage block for both, so that the step kernel among mesh surfaces stays
// within the 16 a compute shader is guaranteed). With GL_NV_shader_atomic_float the sums
// are added natively, else by a compare-and-swap loop on their bits (both give the same
// sums up to the order of the additions).
#ifdef LS_NATIVE_FLOAT_ATOMICS
layout(std430, binding = BIND_SSBO_LS_CONTROL) buffer ls_control_block
{
    ls_control control;
    float ls_accum[LS_ACC_COUNT];
};
void accum_add(int slot, float v)
{
    atomicAdd(ls_accum[slot], v);
}
#else
layout(std430, binding = BIND_SSBO_LS_CONTROL) buffer ls_control_block
{
    ls_control control;
    uint ls_accum[LS_ACC_COUNT];
};
void accum_add(int slot, float v)
{
    uint seen = ls_accum[slot];
    for (;;) {
        uint expected = seen;
        seen = atomicCompSwap(ls_accum[slot], expected, floatBitsToUint(uintBitsToFloat(expected) + v));
        if (seen == expected)
            break;
    }
}
#endif

layout(binding = UNIT_LS_IOR_GRAD) uniform sampler3D ls_ior_grad;
layout(binding = UNIT_LS_EXTINCTION) uniform sampler3D ls_extinction;

bool ls_inside_box(vec3 x)
{
    return all(greaterThanEqual(x, ls.grid_min.xyz)) && all(lessThanEqual(x, ls.grid_max.xyz));
}

// Trilinear sample at world point x in voxel coordinates v = (x - bmin) / voxel - 0.5,
// clamped to [0, dims - 1] (docs/lightsim.md "Fields"), from texelFetch. Measured on
// llvmpipe, hardware filtering (textureLod) was neither faster nor less accurate (it
// filters float textures in float), but GPUs filter with 8-bit fixed-point weights (as
// in the OpenGL spec's minimum), which would move the ray equation's gradient off the CPU
// reference's by up to 1/512 of a voxel's change in n.
vec4 ls_trilinear(sampler3D tex, vec3 x)
{
    ivec3 dims = ls.dims.xyz;
    vec3 v = clamp((x - ls.grid_min.xyz) / ls.grid_min.w - 0.5, vec3(0.0), vec3(dims - 1));
    ivec3 i0 = min(ivec3(floor(v)), max(dims - 2, ivec3(0)));
    vec3 f = v - vec3(i0);
    ivec3 i1 = min(i0 + 1, dims - 1);
    vec4 c000 = texelFetch(tex, ivec3(i0.x, i0.y, i0.z), 0);
    vec4 c100 = texelFetch(tex, ivec3(i1.x, i0.y, i0.z), 0);
    vec4 c010 = texelFetch(tex, ivec3(i0.x, i1.y, i0.z), 0);
    vec4 c110 = texelFetch(tex, ivec3(i1.x, i1.y, i0.z), 0);
    vec4 c001 = texelFetch(tex, ivec3(i0.x, i0.y, i1.z), 0);
    vec4 c101 = texelFetch(tex, ivec3(i1.x, i0.y, i1.z), 0);
    vec4 c011 = texelFetch(tex, ivec3(i0.x, i1.y, i1.z), 0);
    vec4 c111 = texelFetch(tex, ivec3(i1.x, i1.y, i1.z), 0);
    vec4 c00 = mix(c000, c100, f.x), c10 = mix(c010, c110, f.x);
    vec4 c01 = mix(c001, c101, f.x), c11 = mix(c011, c111, f.x);
    return mix(mix(c00, c10, f.y), mix(c01, c11, f.y), f.z);
}

// (grad n, n); outside the grid box (0, ambient n).
vec4 ls_ior_grad_at(vec3 x)
{
    return ls_inside_box(x) ? ls_trilinear(ls_ior_grad, x) : vec4(0.0, 0.0, 0.0, ls.medium.x);
}

// (sigma_t rgb, coverage); outside the grid box 0.
vec4 ls_extinction_at(vec3 x)
{
    return ls_inside_box(x) ? ls_trilinear(ls_extinction, x) : vec4(0.0);
}

// Does the half-line x + t d, t >= 0, meet the box [lo, hi]? (slab test)
bool ls_ray_meets_box(vec3 x, vec3 d, vec3 lo, vec3 hi)
{
    float t0 = 0.0, t1 = 3.0e38;
    for (int a = 0; a < 3; a++) {
        if (abs(d[a]) < 1e-30) {
            if (x[a] < lo[a] || x[a] > hi[a])
                return false;
            continue;
        }
        float ta = (lo[a] - x[a]) / d[a], tb = (hi[a] - x[a]) / d[a];
        t0 = max(t0, min(ta, tb));
        t1 = min(t1, max(ta, tb));
    }
    return t0 <= t1;
}

// The patch's area |D| / 2, D = (x11 - x00) x (x01 - x10) (docs/lightsim.md "Patches").
vec3 ls_diagonal_cross(vec3 x00, vec3 x10, vec3 x11, vec3 x01)
{
    return cross(x11 - x00, x01 - x10);
}
