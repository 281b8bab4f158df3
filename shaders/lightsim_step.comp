#version 450
// lightsim_step.comp - one wavefront time step of every live patch (docs/lightsim.md "A
// time step", items 1-6; tevs2007 eqs. 4.12/4.13, 6.1/6.2): propagate the four corners,
// extinction, interface (Fresnel) test, opaque test, deposit into the light grid, fate.
// Writes the patch back in place and its output count (0, 1 or 4) for the prefix sum.
// Twin: the step of lightsim_ref_run (server/lightsim/lightsim_ref.c).
#include "lightsim_common.glsl"
#include "lightsim_patches.glsl"
#include "fresnel.glsl"

layout(local_size_x = LS_LOCAL_X) in;

// Deposits: LS_DEPOSIT_STRIDE floats per voxel, added atomically (native float add or a
// compare-and-swap loop); max mode keeps the largest irradiance with atomicMax on the bits
// (positive floats order as their bits do).
layout(std430, binding = BIND_SSBO_LS_DEPOSIT) buffer ls_deposit_bits_block
{
    uint deposit_bits[];
};
#ifdef GL_NV_shader_atomic_float
layout(std430, binding = BIND_SSBO_LS_DEPOSIT) buffer ls_deposit_block
{
    float deposit[];
};
void deposit_add(uint i, float v)
{
    atomicAdd(deposit[i], v);
}
#else
void deposit_add(uint i, float v)
{
    uint seen = deposit_bits[i];
    for (;;) {
        uint expected = seen;
        seen = atomicCompSwap(deposit_bits[i], expected, floatBitsToUint(uintBitsToFloat(expected) + v));
        if (seen == expected)
            break;
    }
}
#endif

uint voxel_index(ivec3 v)
{
    return uint((v.z * ls.dims.y + v.y) * ls.dims.x + v.x);
}

// Trilinear splat of q (rgb) and q_lum * d into the 8 voxels around m; voxels outside the
// grid are skipped (docs/lightsim.md step 5, "flux").
void splat(vec3 m, vec3 q, vec3 d)
{
    vec3 v = (m - ls.grid_min.xyz) / ls.grid_min.w - 0.5;
    ivec3 i0 = ivec3(floor(v));
    vec3 f = v - vec3(i0);
    float q_lum = (q.r + q.g + q.b) / 3.0;
    for (int k = 0; k < 8; k++) {
        ivec3 o = ivec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
        ivec3 c = i0 + o;
        if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, ls.dims.xyz)))
            continue;
        vec3 wv = mix(1.0 - f, f, vec3(o));
        float wt = wv.x * wv.y * wv.z;
        if (wt == 0.0)
            continue;
        uint base = voxel_index(c) * LS_DEPOSIT_STRIDE;
        deposit_add(base + 0u, wt * q.r);
        deposit_add(base + 1u, wt * q.g);
        deposit_add(base + 2u, wt * q.b);
        deposit_add(base + 3u, wt * q_lum * d.x);
        deposit_add(base + 4u, wt * q_lum * d.y);
        deposit_add(base + 5u, wt * q_lum * d.z);
    }
}

// Max mode (thesis sect. 6.2.3): the voxel containing m keeps the largest E_p; the
// direction q_lum d is added in that voxel only.
void deposit_max(vec3 m, vec3 e_p, vec3 q, vec3 d)
{
    ivec3 c = ivec3(floor((m - ls.grid_min.xyz) / ls.grid_min.w));
    if (any(lessThan(c, ivec3(0))) || any(greaterThanEqual(c, ls.dims.xyz)))
        return;
    uint base = voxel_index(c) * LS_DEPOSIT_STRIDE;
    for (int ch = 0; ch < 3; ch++)
        atomicMax(deposit_bits[base + uint(ch)], floatBitsToUint(max(e_p[ch], 0.0)));
    float q_lum = (q.r + q.g + q.b) / 3.0;
    deposit_add(base + 3u, q_lum * d.x);
    deposit_add(base + 4u, q_lum * d.y);
    deposit_add(base + 5u, q_lum * d.z);
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

// Per-work-group sums (one global atomic per group and counter).
shared vec4 red[4][LS_LOCAL_X];
shared int ev[5];

void main()
{
    uint i = gl_GlobalInvocationID.x;
    uint lid = gl_LocalInvocationID.x;
    if (lid < 5u)
        ev[lid] = 0;
    barrier();
    vec3 acc_out = vec3(0.0), acc_refl = vec3(0.0), acc_abs = vec3(0.0), acc_cull = vec3(0.0);
    uint count = 0u;
    if (i < uint(control.counts.x)) {
        ls_gpu_patch p = patches_in[i];
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
        // 1. propagate the four corners.
        propagate(p.x[0], p.w[0], dt);
        propagate(p.x[1], p.w[1], dt);
        propagate(p.x[2], p.w[2], dt);
        propagate(p.x[3], p.w[3], dt);
        vec3 c1 = 0.25 * (p.x[0].xyz + p.x[1].xyz + p.x[2].xyz + p.x[3].xyz);
        vec3 d1 = normalize(p.w[0].xyz + p.w[1].xyz + p.w[2].xyz + p.w[3].xyz);
        float ds = length(c1 - c);
        // 2. extinction (trapezoid of sigma_t along the centre's path).
        vec4 ext1 = ls_extinction_at(c1);
        vec3 T = exp(-0.5 * (sigma0 + ext1.rgb) * ds);
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
                vec3 N = glen > 0.0 ? s1.rgb / glen : d;
                float cos_i = min(1.0, abs(dot(d, N)));
                float n_i = s1.a > n0 ? p.zone.x : p.zone.y;
                float n_t = s1.a > n0 ? p.zone.y : p.zone.x;
                if (n_i * n_i * (1.0 - cos_i * cos_i) < n_t * n_t) {
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
        // 4. opaque embeddings absorb the patch (it deposits nothing).
        if (ext1.a >= 0.5) {
            acc_abs += P;
        } else {
            // 5. deposit at the segment midpoint.
            vec3 m = 0.5 * (c + c1);
            vec3 q = P * ds / (voxel * voxel * voxel);
            vec3 D1 = ls_diagonal_cross(p.x[0].xyz, p.x[1].xyz, p.x[2].xyz, p.x[3].xyz);
            if (ls.dims.w == LS_DEPOSIT_MAX)
                deposit_max(m, P / max(0.5 * length(D1), 1e-4 * voxel * voxel), q, d1);
            else
                splat(m, q, d1);
            // 6. fate, in the order of docs/lightsim.md.
            bool inside = ls_inside_box(c1);
            float e_max = max(max(length(p.x[1].xyz - p.x[0].xyz), length(p.x[2].xyz - p.x[1].xyz)),
                              max(length(p.x[3].xyz - p.x[2].xyz), length(p.x[0].xyz - p.x[3].xyz)));
            if (!inside && !ls_ray_meets_box(c1, d1, ls.grid_min.xyz, ls.grid_max.xyz)) {
                acc_out += P;
            } else if (max(P.r, max(P.g, P.b)) < ls.cull.x) {
                acc_cull += P;
                atomicAdd(ev[1], 1);
            } else if (ls.cull.y != 0.0 && !(dot(D1, d1) > 0.0)) {
                acc_cull += P;
                atomicAdd(ev[3], 1);
            } else if (e_max > ls.medium.w) {
                if (p.state.x < ls.limits.x) {
                    count = 4u;
                    atomicAdd(ev[0], 1);
                } else {
                    acc_cull += P;
                    atomicAdd(ev[2], 1);
                }
            } else {
                count = 1u;
            }
        }
        p.power.w = s1.a;
        p.x[0].w = ext1.r;
        p.x[1].w = ext1.g;
        p.x[2].w = ext1.b;
        p.state.w = 1;
        if (count != 0u)
            patches_in[i] = p;
        out_count[i] = count;
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
