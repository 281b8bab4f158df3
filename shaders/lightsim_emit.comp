#version 450
// lightsim_emit.comp - stream compaction/expansion of the patch list (docs/lightsim.md
// items 6-7, "Children of a split"; the prefix-sum form of ziegler2007's HistoPyramids):
// patch i's survivors (itself, or its four children, then the reflected twin of a surface
// event, docs/lightsim.md "Surfaces") go to the next list from position out_offset[i], in
// order; those at positions >= max_patches are dropped (capacity). A child's new corners
// take the parent's inside set where its four corners agree, else the set where they are.
// Twin: the split and capacity code of lightsim_ref_run.
#include "lightsim_common.glsl"
#include "lightsim_patches.glsl"
// LS_SURFACES (the "(surfaces)" program): twins and the new corners' inside sets.
#if LS_SURFACES
#include "fresnel.glsl"

layout(std430, binding = BIND_SSBO_LS_TWINS) readonly buffer ls_twins_block
{
    ls_gpu_patch twins[];
};

// lightsim_corner.glsl's surface code calls propagate(); emit never moves a corner.
void propagate(inout vec4 x, inout vec4 w, float dt)
{
}
#include "lightsim_corner.glsl"
#endif

layout(local_size_x = LS_LOCAL_X) in;

shared vec4 red[2][LS_LOCAL_X];
shared int dropped;

// Mean of ray vectors, rescaled to their mean length: the new particle keeps the optical
// speed of its parents.
vec3 mean_ray2(vec3 a, vec3 b)
{
    return normalize(a + b) * (0.5 * (length(a) + length(b)));
}

// One child of p: corners a, b, c, d (p00, p10, p11, p01 order), ray vectors, and its
// share of the power; level + 1, the parent's zone state, no cached centre samples.
ls_gpu_patch child(ls_gpu_patch p, vec3 a, vec3 b, vec3 c, vec3 d, vec3 wa, vec3 wb, vec3 wc,
                   vec3 wd, ivec4 inside, ivec4 last, float share)
{
    ls_gpu_patch q = p;
    q.inside = inside;
    q.last = last;
    q.x[0] = vec4(a, 0.0);
    q.x[1] = vec4(b, 0.0);
    q.x[2] = vec4(c, 0.0);
    q.x[3] = vec4(d, 0.0);
    q.w[0] = vec4(wa, 0.0);
    q.w[1] = vec4(wb, 0.0);
    q.w[2] = vec4(wc, 0.0);
    q.w[3] = vec4(wd, 0.0);
    q.power = vec4(p.power.rgb * share, 0.0);
    q.state.x = p.state.x + 1;
    q.state.w = 0;
    q.pend = vec4(0.0); // the parent flushed its pending deposit before splitting
    q.pend_from = vec4(0.0);
    return q;
}

void put(uint o, ls_gpu_patch q, inout vec3 live, inout vec3 capacity)
{
    q.event.w = 0;
    if (o < uint(ls.limits.y)) {
        patches_out[o] = q;
        live += q.power.rgb;
    } else {
        capacity += q.power.rgb;
        atomicAdd(dropped, 1);
    }
}

void main()
{
    uint i = gl_GlobalInvocationID.x;
    uint lid = gl_LocalInvocationID.x;
    if (lid == 0u)
        dropped = 0;
    barrier();
    vec3 live = vec3(0.0), capacity = vec3(0.0);
    if (i < uint(control.counts.x)) {
        uint n = out_count[i], o = out_offset[i];
        ls_gpu_patch p = patches_in[i];
#if LS_SURFACES
        if (n != 0u && p.event.w != 0) { // the last output is the twin
            n -= 1u;
            put(o + n, twins[i], live, capacity);
        }
#endif
        if (n == 1u) {
            put(o, p, live, capacity);
        } else if (n == 4u) {
            // Children [p00, m0, mc, m3], [m0, p10, m1, mc], [mc, m1, p11, m2],
            // [m3, mc, m2, p01], written out corner by corner (no dynamic indexing).
            vec3 x00 = p.x[0].xyz, x10 = p.x[1].xyz, x11 = p.x[2].xyz, x01 = p.x[3].xyz;
            vec3 w00 = p.w[0].xyz, w10 = p.w[1].xyz, w11 = p.w[2].xyz, w01 = p.w[3].xyz;
            vec3 m0 = 0.5 * (x00 + x10), m1 = 0.5 * (x10 + x11);
            vec3 m2 = 0.5 * (x11 + x01), m3 = 0.5 * (x01 + x00);
            vec3 mc = 0.25 * (x00 + x10 + x11 + x01);
            vec3 v0 = mean_ray2(w00, w10), v1 = mean_ray2(w10, w11);
            vec3 v2 = mean_ray2(w11, w01), v3 = mean_ray2(w01, w00);
            vec3 vc = normalize(w00 + w10 + w11 + w01) *
                      (0.25 * (length(w00) + length(w10) + length(w11) + length(w01)));
            vec4 area = 0.5 * vec4(length(ls_diagonal_cross(x00, m0, mc, m3)),
                                   length(ls_diagonal_cross(m0, x10, m1, mc)),
                                   length(ls_diagonal_cross(mc, m1, x11, m2)),
                                   length(ls_diagonal_cross(m3, mc, m2, x01)));
            float sum = area.x + area.y + area.z + area.w;
            vec4 share = sum > 0.0 ? area / sum : vec4(0.25);
            // inside sets (docs/lightsim.md "Surfaces"): parent corner k keeps its own
            ivec4 s = p.inside;
            int ins[5] = int[5](s.x, s.y, s.z, s.w, s.x);
#if LS_SURFACES
            // Corners in different media: each new corner takes the set where it lies (a
            // loop the compiler cannot unroll: one inlined copy of every surface kind's
            // inside test, see ls_corner_count).
            if (!all(equal(s, s.xxxx))) {
                vec3 mid[5] = vec3[5](m0, m1, m2, m3, mc);
                for (int j = 0; j < ls_corner_count() + 1; j++)
                    ins[j] = int(ls_surfaces_inside(mid[j]));
            }
#endif
            int i0 = ins[0], i1 = ins[1], i2 = ins[2], i3 = ins[3], ic = ins[4];
            ivec4 l = p.last;
            put(o + 0u, child(p, x00, m0, mc, m3, w00, v0, vc, v3, ivec4(s.x, i0, ic, i3),
                              ivec4(l.x, -1, -1, -1), share.x), live, capacity);
            put(o + 1u, child(p, m0, x10, m1, mc, v0, w10, v1, vc, ivec4(i0, s.y, i1, ic),
                              ivec4(-1, l.y, -1, -1), share.y), live, capacity);
            put(o + 2u, child(p, mc, m1, x11, m2, vc, v1, w11, v2, ivec4(ic, i1, s.z, i2),
                              ivec4(-1, -1, l.z, -1), share.z), live, capacity);
            put(o + 3u, child(p, m3, mc, m2, x01, v3, vc, v2, w01, ivec4(i3, ic, i2, s.w),
                              ivec4(-1, -1, -1, l.w), share.w), live, capacity);
        }
    }
    red[0][lid] = vec4(live, 0.0);
    red[1][lid] = vec4(capacity, 0.0);
    barrier();
    for (uint s = LS_LOCAL_X / 2u; s > 0u; s >>= 1u) {
        if (lid < s) {
            red[0][lid] += red[0][lid + s];
            red[1][lid] += red[1][lid + s];
        }
        barrier();
    }
    if (lid == 0u) {
        for (int ch = 0; ch < 3; ch++) {
            if (red[0][0][ch] != 0.0)
                accum_add(LS_ACC_LIVE + ch, red[0][0][ch]);
            if (red[1][0][ch] != 0.0)
                accum_add(LS_ACC_CULLED + ch, red[1][0][ch]);
        }
        if (dropped != 0)
            atomicAdd(control.events2.x, dropped);
    }
}
