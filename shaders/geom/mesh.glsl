// geom/mesh.glsl - ray tracing triangle meshes on the GPU: the float twin of
// server/mesh/mesh_rt_trace.c (same name, same arrays, same steps; change both together).
// server/mesh/mesh_rt.h documents the three records; docs/tracing.md "Triangle meshes"
// the choices.
//
// Buffers (std430, several meshes concatenated; a mesh is addressed by ivec4 mesh with
// .x its first node, .y its first triangle, .z its first vertex in these arrays, and every
// index stored inside a record is relative to those):
//   mesh_nodes[2 i]     = vec4(lo.xyz, uint bits: inner: left child; leaf: first triangle)
//   mesh_nodes[2 i + 1] = vec4(hi.xyz, uint bits: 0 = inner (children left, left + 1),
//                                      else the leaf's triangle count, 1..4)
//   mesh_tris[i]        = uvec4(v0, v1, v2, original triangle index)
//   mesh_verts[i]       = vec4(position.xyz, uint bits: packSnorm2x16 of the octahedral
//                                            shading normal)
//
// Watertightness (Woop, Benthin, Wald 2013): as in C, each edge function depends only on
// its edge's two sheared vertices, and the neighbour across an edge computes exactly its
// negation, which holds only if the compiler neither fuses a*b - c*d into an fma nor
// reorders it: hence `precise` on the shear and the edge functions. An exact zero is
// recomputed in double (GL 4.0+ core); the float products are exact in double, so the
// recomputed sign is the exact one (better than the C version's long double). Doubles are
// only touched on exact zeros, which are rare, so a GPU with slow fp64 pays nothing.
//
// mesh_rt_intersect: the nearest hit with t in (tmin, tmax) (t in units of |d|; d need not
// be unit; both faces count), ignoring the triangle whose original index is skip_tri (-1:
// none). Out: t, the unit geometric normal (v1 - v0) x (v2 - v0), the unit interpolated
// shading normal, tri = the original index of the triangle within its mesh. On a miss it
// returns false with t = tmax, normals 0 and tri = -1. Direction components below 1e-30
// in magnitude are taken as +-1e-30 for the box slopes only (no 0 * inf).
//
// The stack holds MESH_RT_MAX_DEPTH entries (bindings.h); the builder guarantees no path
// is longer (mesh_rt_build.c), so it cannot overflow.
//
// MESH_RT_PACKED (defined by the includer): the three arrays lie in one buffer,
// vec4 mesh_packed[] at BIND_SSBO_MESH_NODES, nodes first (so mesh.x still counts nodes),
// and mesh.y, mesh.z are the 16-byte record index of the mesh's first triangle and first
// vertex in it. The light simulator's step kernel uses it: it has no storage block to
// spare for two more (GL guarantees a compute shader 16, and it uses them all).
#include "bindings.h"

#ifdef MESH_RT_PACKED
layout(std430, binding = BIND_SSBO_MESH_NODES) readonly buffer mesh_packed_block
{
    vec4 mesh_packed[];
};
#define MESH_RT_NODE(i) mesh_packed[i]
#define MESH_RT_TRI(i) floatBitsToUint(mesh_packed[i])
#define MESH_RT_VERT(i) mesh_packed[i]
#else
layout(std430, binding = BIND_SSBO_MESH_NODES) readonly buffer mesh_nodes_block
{
    vec4 mesh_nodes[];
};
layout(std430, binding = BIND_SSBO_MESH_TRIS) readonly buffer mesh_tris_block
{
    uvec4 mesh_tris[];
};
layout(std430, binding = BIND_SSBO_MESH_VERTS) readonly buffer mesh_verts_block
{
    vec4 mesh_verts[];
};
#define MESH_RT_NODE(i) mesh_nodes[i]
#define MESH_RT_TRI(i) mesh_tris[i]
#define MESH_RT_VERT(i) mesh_verts[i]
#endif

// Ize 2013's 2 gamma(3) for float is 3.6e-7; a GPU's reciprocal may be off by 2.5 ulp
// more than correctly rounded division, so the far slab is pushed out by 1e-6 of itself.
#define MESH_RT_BOX_GROW 1e-6

vec3 mesh_rt_oct_decode(uint bits)
{
    vec2 e = unpackSnorm2x16(bits);
    vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (v.z < 0.0) {
        vec2 s = vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
        v.xy = (1.0 - abs(v.yx)) * s;
    }
    return normalize(v);
}

// The ray's entry into a node's box (absolute node index) within [tmin, tmax], or false.
bool mesh_rt_box(int node, vec3 o, vec3 inv, float tmin, float tmax, out float t_near)
{
    vec3 a = (MESH_RT_NODE(2 * node).xyz - o) * inv;
    vec3 b = (MESH_RT_NODE(2 * node + 1).xyz - o) * inv;
    vec3 tn = min(a, b), tf = max(a, b);
    tf += abs(tf) * MESH_RT_BOX_GROW;
    t_near = max(max(tmin, tn.x), max(tn.y, tn.z));
    float t_far = min(min(tmax, tf.x), min(tf.y, tf.z));
    return t_near <= t_far;
}

float mesh_rt_nonzero(float x)
{
    return abs(x) < 1e-30 ? (x < 0.0 ? -1e-30 : 1e-30) : x;
}

bool mesh_rt_intersect(ivec4 mesh, vec3 o, vec3 d, float tmin, float tmax, int skip_tri,
                       out float t, out vec3 n_geom, out vec3 n_shade, out int tri)
{
    t = tmax;
    n_geom = vec3(0.0);
    n_shade = vec3(0.0);
    tri = -1;
    // ray space (paper sect. 3): kz the largest |d|, kx/ky swapped to keep the winding
    vec3 ad = abs(d);
    int kz = ad.x >= ad.y ? (ad.x >= ad.z ? 0 : 2) : (ad.y >= ad.z ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (d[kz] < 0.0) {
        int s = kx;
        kx = ky;
        ky = s;
    }
    float sx = d[kx] / d[kz], sy = d[ky] / d[kz], sz = 1.0 / d[kz];
    vec3 inv = 1.0 / vec3(mesh_rt_nonzero(d.x), mesh_rt_nonzero(d.y), mesh_rt_nonzero(d.z));

    int stack_node[MESH_RT_MAX_DEPTH];
    float stack_t[MESH_RT_MAX_DEPTH];
    int sp = 0;
    float t_best = tmax, t_near;
    vec4 best = vec4(0.0); // u, v, w, det of the nearest hit
    int best_slot = -1;
    if (!mesh_rt_box(mesh.x, o, inv, tmin, t_best, t_near))
        return false;
    int node = 0;
    for (;;) {
        vec4 lo = MESH_RT_NODE(2 * (mesh.x + node)), hi = MESH_RT_NODE(2 * (mesh.x + node) + 1);
        int first = int(floatBitsToUint(lo.w)), count = int(floatBitsToUint(hi.w));
        if (count > 0) {
            for (int i = first; i < first + count; i++) {
                uvec4 tr = MESH_RT_TRI(mesh.y + i);
                if (int(tr.w) == skip_tri)
                    continue;
                vec3 A = MESH_RT_VERT(mesh.z + int(tr.x)).xyz - o;
                vec3 B = MESH_RT_VERT(mesh.z + int(tr.y)).xyz - o;
                vec3 C = MESH_RT_VERT(mesh.z + int(tr.z)).xyz - o;
                precise float ax = A[kx] - sx * A[kz], ay = A[ky] - sy * A[kz];
                precise float bx = B[kx] - sx * B[kz], by = B[ky] - sy * B[kz];
                precise float cx = C[kx] - sx * C[kz], cy = C[ky] - sy * C[kz];
                precise float u = cx * by - cy * bx;
                precise float v = ax * cy - ay * cx;
                precise float w = bx * ay - by * ax;
                if (u == 0.0 || v == 0.0 || w == 0.0) {
                    u = float(double(cx) * double(by) - double(cy) * double(bx));
                    v = float(double(ax) * double(cy) - double(ay) * double(cx));
                    w = float(double(bx) * double(ay) - double(by) * double(ax));
                }
                if ((u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0))
                    continue;
                float det = u + v + w;
                if (det == 0.0)
                    continue;
                float th = (u * (sz * A[kz]) + v * (sz * B[kz]) + w * (sz * C[kz])) / det;
                if (!(th > tmin && th < t_best))
                    continue;
                t_best = th;
                best = vec4(u, v, w, det);
                best_slot = mesh.y + i;
            }
        } else {
            int l = first;
            float tl, tr;
            bool hl = mesh_rt_box(mesh.x + l, o, inv, tmin, t_best, tl);
            bool hr = mesh_rt_box(mesh.x + l + 1, o, inv, tmin, t_best, tr);
            if (hl && hr) {
                bool left_first = tl <= tr;
                stack_node[sp] = left_first ? l + 1 : l;
                stack_t[sp] = left_first ? tr : tl;
                sp++;
                node = left_first ? l : l + 1;
                continue;
            }
            if (hl || hr) {
                node = hl ? l : l + 1;
                continue;
            }
        }
        // pop the next node the ray can still reach before the best hit
        while (sp > 0 && stack_t[sp - 1] > t_best)
            sp--;
        if (sp == 0)
            break;
        sp--;
        node = stack_node[sp];
    }
    if (best_slot < 0)
        return false;
    uvec4 tr = MESH_RT_TRI(best_slot);
    vec4 p0 = MESH_RT_VERT(mesh.z + int(tr.x)), p1 = MESH_RT_VERT(mesh.z + int(tr.y)),
         p2 = MESH_RT_VERT(mesh.z + int(tr.z));
    vec3 bary = best.xyz / best.w;
    n_geom = normalize(cross(p1.xyz - p0.xyz, p2.xyz - p0.xyz));
    uint b0 = floatBitsToUint(p0.w), b1 = floatBitsToUint(p1.w), b2 = floatBitsToUint(p2.w);
    vec3 ns = bary.x * mesh_rt_oct_decode(b0) + bary.y * mesh_rt_oct_decode(b1) +
              bary.z * mesh_rt_oct_decode(b2);
    // A corner on a crease has no smooth normal (MESH_RT_NO_NORMAL): the flat normal.
    bool crease = b0 == MESH_RT_NO_NORMAL || b1 == MESH_RT_NO_NORMAL || b2 == MESH_RT_NO_NORMAL;
    n_shade = !crease && length(ns) > 1e-6 ? normalize(ns) : n_geom;
    t = t_best;
    tri = int(tr.w);
    return true;
}
