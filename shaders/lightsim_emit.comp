#version 450
// lightsim_emit.comp - stream compaction/expansion of the patch list (docs/lightsim.md
// items 6-7, "Children of a split"; the prefix-sum form of ziegler2007's HistoPyramids):
// patch i's survivors (itself, or its four children) go to the next list from position
// out_offset[i], in order; those at positions >= max_patches are dropped (capacity).
// Twin: the split and capacity code of lightsim_ref_run.
#include "lightsim_common.glsl"
#include "lightsim_patches.glsl"

layout(local_size_x = LS_LOCAL_X) in;

shared vec4 red[2][LS_LOCAL_X];
shared int dropped;

// Mean of ray vectors, rescaled to their mean length: the new particle keeps the optical
// speed of its parents.
vec3 mean_ray2(vec3 a, vec3 b)
{
    return normalize(a + b) * (0.5 * (length(a) + length(b)));
}

void put(uint o, ls_patch q, inout vec3 live, inout vec3 capacity)
{
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
        ls_patch p = patches_in[i];
        if (n == 1u) {
            put(o, p, live, capacity);
        } else if (n == 4u) {
            vec3 x00 = p.x[0].xyz, x10 = p.x[1].xyz, x11 = p.x[2].xyz, x01 = p.x[3].xyz;
            vec3 w00 = p.w[0].xyz, w10 = p.w[1].xyz, w11 = p.w[2].xyz, w01 = p.w[3].xyz;
            vec3 xm[5], wm[5];
            xm[0] = 0.5 * (x00 + x10);
            xm[1] = 0.5 * (x10 + x11);
            xm[2] = 0.5 * (x11 + x01);
            xm[3] = 0.5 * (x01 + x00);
            xm[4] = 0.25 * (x00 + x10 + x11 + x01);
            wm[0] = mean_ray2(w00, w10);
            wm[1] = mean_ray2(w10, w11);
            wm[2] = mean_ray2(w11, w01);
            wm[3] = mean_ray2(w01, w00);
            wm[4] = normalize(w00 + w10 + w11 + w01) *
                    (0.25 * (length(w00) + length(w10) + length(w11) + length(w01)));
            // Children [p00, m0, mc, m3], [m0, p10, m1, mc], [mc, m1, p11, m2],
            // [m3, mc, m2, p01]: corner k of child j is node cx[j][k] of this table.
            vec3 nx[9] = vec3[9](x00, x10, x11, x01, xm[0], xm[1], xm[2], xm[3], xm[4]);
            vec3 nw[9] = vec3[9](w00, w10, w11, w01, wm[0], wm[1], wm[2], wm[3], wm[4]);
            const int cx[16] = int[16](0, 4, 8, 7, 4, 1, 5, 8, 8, 5, 2, 6, 7, 8, 6, 3);
            float area[4];
            float sum = 0.0;
            for (int j = 0; j < 4; j++) {
                area[j] = 0.5 * length(ls_diagonal_cross(nx[cx[4 * j]], nx[cx[4 * j + 1]],
                                                         nx[cx[4 * j + 2]], nx[cx[4 * j + 3]]));
                sum += area[j];
            }
            for (int j = 0; j < 4; j++) {
                ls_patch q = p;
                for (int k = 0; k < 4; k++) {
                    q.x[k] = vec4(nx[cx[4 * j + k]], 0.0);
                    q.w[k] = vec4(nw[cx[4 * j + k]], 0.0);
                }
                q.power.rgb = sum > 0.0 ? p.power.rgb * (area[j] / sum) : 0.25 * p.power.rgb;
                q.state.x = p.state.x + 1;
                put(o + uint(j), q, live, capacity);
            }
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
