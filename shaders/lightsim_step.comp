#version 450
// lightsim_step.comp - one wavefront time step of every live patch (docs/lightsim.md "A
// time step", items 1-6; tevs2007 eqs. 4.12/4.13, 6.1/6.2): propagate the four corners,
// extinction, interface (Fresnel) test, opaque test, deposit into the light grid, fate.
// Writes the patch back in place and its output count (0, 1 or 4) for the prefix sum;
// among exact surfaces (docs/lightsim.md "Surfaces") a Fresnel event that begins in the
// step also makes the reflected twin, stepped here too and written to twins[i]; its output
// (0 or 1) adds to the count, and the patch record's event.w says it is there.
// Twin: the step of lightsim_ref_run (server/lightsim/lightsim_ref.c, lightsim_step.c).
#include "lightsim_common.glsl"
#define LS_STEP_KERNEL 1
#include "lightsim_patches.glsl"
#include "fresnel.glsl"

// LS_SURFACES (a preamble #define, the "(surfaces)" programs): scenes with exact
// surfaces. The voxel scenes' programs leave the surface code out: though never entered,
// it made llvmpipe run their steps 2-4x slower.
#if LS_SURFACES
layout(std430, binding = BIND_SSBO_LS_TWINS) writeonly buffer ls_twins_block
{
    ls_gpu_patch twins[];
};
#endif

layout(local_size_x = LS_LOCAL_X) in;

// Deposits: one float buffer per channel (irradiance rgb, direction xyz), added
// atomically (native float add or a compare-and-swap loop); max mode keeps the largest
// irradiance with atomicMax on the bits (positive floats order as their bits do). The
// channel index is a constant at every call (blocks of an array need a uniform index).
#ifdef LS_NATIVE_FLOAT_ATOMICS
#define LS_BITS_BLOCKS 3 /* only max mode's irradiance channels */
layout(std430, binding = BIND_SSBO_LS_DEPOSIT) buffer ls_deposit_block
{
    float v[];
} deposit[LS_DEPOSIT_CHANNELS];
#else
#define LS_BITS_BLOCKS LS_DEPOSIT_CHANNELS
#endif
layout(std430, binding = BIND_SSBO_LS_DEPOSIT) buffer ls_deposit_bits_block
{
    uint v[];
} deposit_bits[LS_BITS_BLOCKS];

#ifdef LS_NATIVE_FLOAT_ATOMICS
#define deposit_add(ch, i, value) atomicAdd(deposit[ch].v[i], value)
#else
#define deposit_add(ch, i, value) deposit_add_cas(ch, i, value)
void deposit_add_cas(int ch, uint i, float value)
{
    uint seen = deposit_bits[ch].v[i];
    for (;;) {
        uint expected = seen;
        seen = atomicCompSwap(deposit_bits[ch].v[i], expected,
                              floatBitsToUint(uintBitsToFloat(expected) + value));
        if (seen == expected)
            break;
    }
}
#endif

uint voxel_index(ivec3 v)
{
    return uint((v.z * ls.dims.y + v.y) * ls.dims.x + v.x);
}

// Cubic B-spline weights of the four voxels i0 - 1 .. i0 + 2 along one axis (f = v - i0).
vec4 bspline_weights(float f)
{
    float g = 1.0 - f;
    return vec4(g * g * g / 6.0, 2.0 / 3.0 - f * f + 0.5 * f * f * f,
                2.0 / 3.0 - g * g + 0.5 * g * g * g, f * f * f / 6.0);
}

// Splat of q (rgb) into the 4 x 4 x 4 voxels around m with cubic B-spline weights
// (docs/lightsim.md step 5, "flux": a lattice of tent splats ripples by up to 12% per
// axis, the B-spline's by 0.45%) and of q_lum * d into the 2 x 2 x 2 voxels around m
// with trilinear weights (only the direction's normalised mean is used, so it needs no
// ripple-free amplitude); voxels outside the grid are skipped. The loops run over the
// stencil's part inside the grid, so the 64 voxels need no per-voxel bounds tests.
void splat(vec3 m, vec3 q, vec3 d)
{
    vec3 v = (m - ls.grid_min.xyz) / ls.grid_min.w - 0.5;
    vec3 fl = floor(v);
    if (!all(greaterThan(fl, vec3(-3.0))) || !all(lessThan(fl, vec3(ls.dims.xyz) + 1.0)))
        return; // all 64 voxels outside (or NaN)
    ivec3 i1 = ivec3(fl); // the trilinear stencil's first voxel
    vec3 f = v - fl;
    // direction: trilinear over i1 .. i1 + 1
    float q_lum = (q.r + q.g + q.b) / 3.0;
    vec3 qd = q_lum * d;
    ivec3 lo = max(-i1, ivec3(0)), hi = min(ls.dims.xyz - i1, ivec3(2));
    for (int kz = lo.z; kz < hi.z; kz++) {
        float wz = kz == 0 ? 1.0 - f.z : f.z;
        for (int ky = lo.y; ky < hi.y; ky++) {
            float wyz = (ky == 0 ? 1.0 - f.y : f.y) * wz;
            uint row = voxel_index(ivec3(i1.x, i1.y + ky, i1.z + kz));
            for (int kx = lo.x; kx < hi.x; kx++) {
                float wt = (kx == 0 ? 1.0 - f.x : f.x) * wyz;
                if (wt == 0.0)
                    continue;
                uint o = row + uint(kx);
                deposit_add(3, o, wt * qd.x);
                deposit_add(4, o, wt * qd.y);
                deposit_add(5, o, wt * qd.z);
            }
        }
    }
    // irradiance: cubic B-spline over i1 - 1 .. i1 + 2
    ivec3 i0 = i1 - 1;
    vec4 wx = bspline_weights(f.x), wy = bspline_weights(f.y), wz4 = bspline_weights(f.z);
    lo = max(-i0, ivec3(0));
    hi = min(ls.dims.xyz - i0, ivec3(4));
    for (int kz = lo.z; kz < hi.z; kz++) {
        for (int ky = lo.y; ky < hi.y; ky++) {
            float wyz = wy[ky] * wz4[kz];
            uint row = voxel_index(ivec3(i0.x, i0.y + ky, i0.z + kz));
            for (int kx = lo.x; kx < hi.x; kx++) {
                float wt = wx[kx] * wyz;
                if (wt == 0.0)
                    continue;
                uint o = row + uint(kx);
                deposit_add(0, o, wt * q.r);
                deposit_add(1, o, wt * q.g);
                deposit_add(2, o, wt * q.b);
            }
        }
    }
}

// Flux mode: deposits the pending sum, q = sum(P ds) / voxel^3, at the midpoint of the
// pending segment from .. to with direction dir, and clears it (docs/lightsim.md step 5).
void flush_pending(inout vec4 pend, vec3 from, vec3 to, vec3 dir)
{
    if (pend.w == 0.0)
        return;
    float voxel = ls.grid_min.w;
    splat(0.5 * (from + to), pend.rgb / (voxel * voxel * voxel), dir);
    pend = vec4(0.0);
}

// Max mode (thesis sect. 6.2.3): the voxel containing m keeps the largest E_p; the
// direction q_lum d is added in that voxel only.
void deposit_max(vec3 m, vec3 e_p, vec3 q, vec3 d)
{
    ivec3 c = ivec3(floor((m - ls.grid_min.xyz) / ls.grid_min.w));
    if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, ls.dims.xyz)))
        return;
    uint o = voxel_index(c);
    atomicMax(deposit_bits[0].v[o], floatBitsToUint(max(e_p.r, 0.0)));
    atomicMax(deposit_bits[1].v[o], floatBitsToUint(max(e_p.g, 0.0)));
    atomicMax(deposit_bits[2].v[o], floatBitsToUint(max(e_p.b, 0.0)));
    float q_lum = (q.r + q.g + q.b) / 3.0;
    deposit_add(3, o, q_lum * d.x);
    deposit_add(4, o, q_lum * d.y);
    deposit_add(5, o, q_lum * d.z);
}

// dx/dt = w / n^2, dw/dt = grad n / n (tevs2007 eqs. 4.12/4.13).
void ray_rate(vec3 x, vec3 w, out vec3 dx, out vec3 dw)
{
    vec4 s = ls_ior_grad_at(x);
    dx = w / (s.a * s.a);
    dw = s.rgb / s.a;
}

// Explicit midpoint rule, the same dt for every corner (equitemporal). Called once per
// corner with constant indices: a loop over p.x[k] would index the patch dynamically,
// which llvmpipe spills to scratch memory.
void propagate(inout vec4 x, inout vec4 w, float dt)
{
    vec3 k1x, k1w, k2x, k2w;
    ray_rate(x.xyz, w.xyz, k1x, k1w);
    ray_rate(x.xyz + 0.5 * dt * k1x, w.xyz + 0.5 * dt * k1w, k2x, k2w);
    x.xyz += dt * k2x;
    w.xyz += dt * k2w;
}

#if LS_SURFACES
#include "lightsim_corner.glsl"
#else
struct ls_spawn_t {
    bool spawned;
    int surface;
    int mask;
    float R_mean;
    vec3 P;
};
#endif

// Per-work-group sums (one global atomic per group and counter).
shared vec4 red[4][LS_LOCAL_X];
shared int ev[5];

// Steps 1-6 of one patch (docs/lightsim.md "A time step"); returns its output count (0, 1
// or 4). first: a surface event may begin and the patch may split (false for a twin in
// its first step).
uint step_patch(inout ls_gpu_patch p, bool first, inout ls_spawn_t sp, inout vec3 acc_out,
                inout vec3 acc_refl, inout vec3 acc_abs, inout vec3 acc_cull)
{
        uint count = 0u;
        float dt = ls.grid_max.w, voxel = ls.grid_min.w;
        vec3 c = 0.25 * (p.x[0].xyz + p.x[1].xyz + p.x[2].xyz + p.x[3].xyz);
        vec3 d = normalize(p.w[0].xyz + p.w[1].xyz + p.w[2].xyz + p.w[3].xyz);
        // The samples at the old centre: kept from the previous step when it ended
        // there (state.w = 1; children have new centres), else taken now.
        float n0;
        vec3 sigma0;
        if (p.state.w != 0) {
            n0 = p.power.w;
            sigma0 = vec3(p.x[0].w, p.x[1].w, p.x[2].w);
        } else {
            n0 = ls_ior_grad_at(c).a;
            sigma0 = ls_extinction_at(c).rgb;
        }
        // 1. propagate the four corners (among exact surfaces: lightsim_corner.glsl).
#if LS_SURFACES
        // A loop the compiler cannot unroll (ls_corner_count): one inlined copy of the
        // corner move and the surface intersections under it.
        vec3 tau[4] = vec3[4](vec3(0.0), vec3(0.0), vec3(0.0), vec3(0.0));
        for (int k = 0; k < ls_corner_count(); k++)
            ls_corner_move(p, k, dt, first, sp, tau[k], acc_refl);
#else
        propagate(p.x[0], p.w[0], dt);
        propagate(p.x[1], p.w[1], dt);
        propagate(p.x[2], p.w[2], dt);
        propagate(p.x[3], p.w[3], dt);
#endif
        vec3 c1 = 0.25 * (p.x[0].xyz + p.x[1].xyz + p.x[2].xyz + p.x[3].xyz);
        vec3 d1 = normalize(p.w[0].xyz + p.w[1].xyz + p.w[2].xyz + p.w[3].xyz);
        float ds = length(c1 - c);
        // 2. extinction (trapezoid of sigma_t along the centre's path).
        vec4 ext1 = ls_extinction_at(c1);
        vec3 T = exp(-0.5 * (sigma0 + ext1.rgb) * ds);
#if LS_SURFACES
        // Beer-Lambert along each corner's legs, averaged
        T *= 0.25 * (exp(-tau[0]) + exp(-tau[1]) + exp(-tau[2]) + exp(-tau[3]));
#endif
        vec3 P = p.power.rgb;
        acc_abs += P * (1.0 - T);
        P *= T;
        // 3. interface zone and Fresnel transmission; the three tests in order.
        vec4 s1 = ls_ior_grad_at(c1);
        float glen = length(s1.rgb);
        float g = glen * voxel;
        float thr = ls.medium.z;
        if (p.state.y == 0 && g > thr) {
            vec3 N = s1.rgb / glen;
            float k = ls.medium.y;
            p.state.y = 1;
            p.zone.x = ls_ior_grad_at(c1 - k * N).a;
            p.zone.y = ls_ior_grad_at(c1 + k * N).a;
            p.state.z = 0;
        }
        if (p.state.y != 0 && p.state.z == 0) {
            float n_mid = 0.5 * (p.zone.x + p.zone.y);
            if ((n0 >= n_mid) != (s1.a >= n_mid)) {
                vec3 w_bar = 0.25 * (p.w[0].xyz + p.w[1].xyz + p.w[2].xyz + p.w[3].xyz);
                vec3 N = glen > 0.0 ? s1.rgb / glen : normalize(w_bar);
                float n_i = s1.a > n0 ? p.zone.x : p.zone.y;
                float n_t = s1.a > n0 ? p.zone.y : p.zone.x;
                // Snell's invariant: the ray equation changes w = n d only along grad n, so
                // |w x N| is the incident side's n_i sin(theta_i) anywhere in the smoothed
                // interface. w_t >= n_t: total internal reflection (the ray equation turns
                // the wavefront round); w_t >= n_i: it turned round inside the zone and
                // comes back, no surface is crossed.
                float w_t = length(cross(w_bar, N));
                if (w_t < n_t && w_t < n_i) {
                    float sin_i = min(1.0, w_t / n_i);
                    float cos_i = sqrt(1.0 - sin_i * sin_i);
                    float R = fresnel_unpolarized(cos_i, n_i, n_t);
                    acc_refl += P * R;
                    P *= 1.0 - R;
                    p.state.z = 1;
                }
            }
        }
        if (p.state.y != 0 && g < 0.5 * thr)
            p.state.y = 0;
        p.power.rgb = P;
        // 4. opaque embeddings absorb the patch; this step deposits nothing, the pending
        // steps (they ended at c) are deposited.
        bool flux = ls.dims.w != LS_DEPOSIT_MAX;
        if (ext1.a >= 0.5) {
            if (flux)
                flush_pending(p.pend, p.pend_from.xyz, c, d);
            acc_abs += P;
        } else {
            // 5. deposit: max mode at the segment midpoint; flux mode accumulates P ds and
            // deposits every ls.limits.z steps and before the patch dies or splits.
            vec3 D1 = ls_diagonal_cross(p.x[0].xyz, p.x[1].xyz, p.x[2].xyz, p.x[3].xyz);
            if (flux) {
                if (p.pend.w == 0.0)
                    p.pend_from.xyz = c;
                p.pend += vec4(P * ds, 1.0);
            } else {
                vec3 m = 0.5 * (c + c1);
                vec3 q = P * ds / (voxel * voxel * voxel);
                deposit_max(m, P / max(0.5 * length(D1), 1e-4 * voxel * voxel), q, d1);
            }
            // 6. fate, in the order of docs/lightsim.md.
            bool inside = ls_inside_box(c1);
            float e_max = max(max(length(p.x[1].xyz - p.x[0].xyz), length(p.x[2].xyz - p.x[1].xyz)),
                              max(length(p.x[3].xyz - p.x[2].xyz), length(p.x[0].xyz - p.x[3].xyz)));
            if (!inside && !ls_ray_meets_box(c1, d1, ls.grid_min.xyz, ls.grid_max.xyz)) {
                acc_out += P;
            } else if (max(P.r, max(P.g, P.b)) < ls.cull.x) {
                acc_cull += P;
                atomicAdd(ev[1], 1);
            } else if (ls.cull.y != 0.0 && p.event.y == 0 && !(dot(D1, d1) > 0.0)) {
                acc_cull += P;
                atomicAdd(ev[3], 1);
            } else if (e_max > ls.medium.w) {
                if (!first || p.event.y != 0) {
                    count = 1u; // a pending event, or a twin's first step: no split
                } else if (p.state.x < ls.limits.x) {
                    count = 4u;
                    atomicAdd(ev[0], 1);
                } else {
                    acc_cull += P;
                    atomicAdd(ev[2], 1);
                }
            } else {
                count = 1u;
            }
            if (flux && (count != 1u || p.pend.w >= float(ls.limits.z)))
                flush_pending(p.pend, p.pend_from.xyz, c1, d1);
        }
        p.power.w = s1.a;
        p.x[0].w = ext1.r;
        p.x[1].w = ext1.g;
        p.x[2].w = ext1.b;
        p.state.w = 1;
        return count;
}

// Swaps corners 1 and 3: a mirror image's winding, so that it comes out positive.
void swap_winding(inout ls_gpu_patch t)
{
    vec4 x1 = t.x[1], w1 = t.w[1];
    t.x[1] = t.x[3];
    t.w[1] = t.w[3];
    t.x[3] = x1;
    t.w[3] = w1;
    t.inside = t.inside.xwzy;
    t.last = t.last.xwzy;
    int m = t.event.y;
    t.event.y = (m & 5) | ((m & 2) << 2) | ((m & 8) >> 2);
}

void main()
{
    uint i = gl_GlobalInvocationID.x;
    uint lid = gl_LocalInvocationID.x;
    if (lid < 5u)
        ev[lid] = 0;
    barrier();
    vec3 acc_out = vec3(0.0), acc_refl = vec3(0.0), acc_abs = vec3(0.0), acc_cull = vec3(0.0);
    if (i < uint(control.counts.x)) {
        ls_gpu_patch before = patches_in[i], p = before;
        ls_spawn_t sp;
        sp.spawned = false;
        sp.surface = -1;
        sp.mask = 0;
        sp.R_mean = 0.0;
        sp.P = vec3(0.0);
        uint count = 0u, twin = 0u;
#if LS_SURFACES
        // Pass 0 steps the patch; pass 1 the reflected twin of a surface event that began
        // in it (the patch as it was, the event's share of the power, its crossing corners
        // pending), so that the wavefront stays equitemporal. One loop body: the step is
        // inlined once.
        for (int pass = 0; pass < 2; pass++) {
            if (pass == 1) {
                if (!sp.spawned)
                    break;
                p = before;
                p.power.rgb = sp.P * sp.R_mean;
                p.pend = vec4(0.0);
                p.event = ivec4(sp.surface, sp.mask, 1, 0);
                swap_winding(p);
            }
            uint c = step_patch(p, pass == 0, sp, acc_out, acc_refl, acc_abs, acc_cull);
            if (pass == 0) {
                count = c;
                if (c != 0u || sp.spawned) {
                    p.event.w = 0;
                    patches_in[i] = p; // rewritten below when a twin lives
                }
            } else {
                twin = c;
                if (c != 0u) {
                    p.event.w = 0;
                    twins[i] = p;
                }
            }
        }
        if (twin != 0u)
            patches_in[i].event.w = 1;
#else
        count = step_patch(p, true, sp, acc_out, acc_refl, acc_abs, acc_cull);
        if (count != 0u)
            patches_in[i] = p;
#endif
        out_count[i] = count + twin;
    }
    red[0][lid] = vec4(acc_out, 0.0);
    red[1][lid] = vec4(acc_refl, 0.0);
    red[2][lid] = vec4(acc_abs, 0.0);
    red[3][lid] = vec4(acc_cull, 0.0);
    barrier();
    for (uint s = LS_LOCAL_X / 2u; s > 0u; s >>= 1u) {
        if (lid < s)
            for (int k = 0; k < 4; k++)
                red[k][lid] += red[k][lid + s];
        barrier();
    }
    if (lid == 0u) {
        const int slot[4] = int[4](LS_ACC_OUT, LS_ACC_REFLECTED, LS_ACC_ABSORBED, LS_ACC_CULLED);
        for (int k = 0; k < 4; k++)
            for (int ch = 0; ch < 3; ch++)
                if (red[k][0][ch] != 0.0)
                    accum_add(slot[k] + ch, red[k][0][ch]);
        if (ev[0] != 0)
            atomicAdd(control.events.x, ev[0]);
        if (ev[1] != 0)
            atomicAdd(control.events.y, ev[1]);
        if (ev[2] != 0)
            atomicAdd(control.events.z, ev[2]);
        if (ev[3] != 0)
            atomicAdd(control.events.w, ev[3]);
    }
}
