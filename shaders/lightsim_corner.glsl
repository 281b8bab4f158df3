// lightsim_corner.glsl - a patch corner's move among exact surfaces (docs/lightsim.md
// "Surfaces"; issue 12 item 4), the twin of server/lightsim/lightsim_corner.c and
// lightsim_surfaces.c with the same rules: straight legs at speed 1/n in the surfaces'
// constant media, the ray equation (tevs2007 eqs. 4.12/4.13) in the voxel field outside
// them cut where its chord meets a surface, and at each crossing interface_cross
// (frisvad2010). A Fresnel event is decided once per patch and surface when its first
// corner crosses: R from every corner's crossing point (straight lines up to the surface),
// the power split, the reflected twin made by lightsim_step.comp. Needs
// lightsim_common.glsl, fresnel.glsl and propagate() (lightsim_step.comp) before it.
#include "geom_hit.glsl"
#include "surface.glsl"
#include "sphere.glsl"
#include "box.glsl"
#include "rounded_box.glsl"
#include "cylinder.glsl"
#include "plane.glsl"
#include "lathe.glsl"
// LS_MESHES (a preamble #define, the "(meshes)" programs): mesh surfaces, traced by the
// view renderer's BVH code from one packed buffer (the step kernel has no storage block
// to spare for three).
#if LS_MESHES
#define MESH_RT_PACKED 1
#include "mesh.glsl"
#define MARCH_MESHES 1
#else
#define MARCH_MESHES 0
#endif
#include "surface_dispatch.glsl"
#include "interface.glsl"

// Legs of one corner in one step, at most; |n_i - n_t| at or below LS_INDEX_EPS passes.
const int LS_MAX_LEGS = 8;
const float LS_INDEX_EPS = 1e-6;

// Is the world point p inside surface k's solid. Kinds with a closed-form test use it;
// a lathe or a mesh counts its crossings along a fixed ray (the solid is closed: odd =
// inside; the CPU reference asks a mesh's winding number, which agrees off the surface).
bool geom_surface_inside(int k, vec3 p_world)
{
    surface_params sp = surfaces[k];
    vec3 p = (sp.object_from_world * vec4(p_world, 1.0)).xyz;
    int kind = sp.kind.x;
    if (kind == GEOM_SPHERE)
        return sphere_inside(sp.shape0.xyz, sp.shape0.w, p);
    if (kind == GEOM_BOX)
        return box_inside(sp.shape0.xyz, sp.shape1.xyz, p);
    if (kind == GEOM_ROUNDED_BOX)
        return rounded_box_inside(sp.shape0.xyz, sp.shape1.xyz, sp.shape0.w, p);
    if (kind == GEOM_CYLINDER)
        return cylinder_inside(sp.shape0.xyz, sp.shape0.w, sp.shape1.x, sp.kind.y, p);
    if (kind == GEOM_PLANE)
        return plane_inside(sp.shape0.xyz, sp.shape1.xyz, p);
    vec3 d = normalize(vec3(0.5772, 0.5774, 0.5776));
    float t = 0.0;
    int crossings = 0;
    for (int i = 0; i < 64; i++) {
        geom_hit h;
        if (!geom_surface_intersect(k, p_world, d, t, 1e30, -1, h))
            break;
        crossings++;
        t = h.t + sp.medium.z;
    }
    return (crossings & 1) == 1;
}

uint ls_surfaces_inside(vec3 p)
{
    uint set = 0u;
    for (int k = 0; k < ls.limits.w; k++)
        if (geom_surface_inside(k, p))
            set |= 1u << uint(k);
    return set;
}

// n of a medium: the surface's constant index, or the field's at x for -1.
float ls_medium_ior(int m, vec3 x)
{
    return m >= 0 ? surfaces[m].medium.x : ls_ior_grad_at(x).a;
}

bool ls_surface_hit(int k, vec3 o, vec3 d, int last, float tmax, out geom_hit h)
{
    float tmin = k == last ? surfaces[k].medium.z : 0.0;
    return geom_surface_intersect(k, o, d, tmin, tmax, -1, h);
}

int ls_next_surface(vec3 o, vec3 d, int last, float tmax, out geom_hit hit)
{
    int best = -1;
    hit.t = 0.0;
    hit.normal = vec3(0.0);
    hit.shading = vec3(0.0);
    hit.prim = -1;
    for (int k = 0; k < ls.limits.w; k++) {
        geom_hit h;
        if (ls_surface_hit(k, o, d, last, tmax, h)) {
            tmax = h.t;
            hit = h;
            best = k;
        }
    }
    return best;
}

// The transmitted limit of total internal reflection: a corner of the transmitted patch
// whose own ray is totally reflected grazes the surface.
vec3 ls_grazing(vec3 d, vec3 N)
{
    vec3 t = d - N * dot(d, N);
    float len = length(t);
    return len > 1e-6 ? t / len : d;
}

// Corner (x, w)'s reflectance where its straight line meets surface s; hits false when it
// does not (within the domain's diagonal) or meets it where the index does not change.
float ls_predict(vec3 x, vec3 w, uint inside, int last, int s, out bool hits)
{
    vec3 d = normalize(w);
    geom_hit h;
    hits = false;
    if (!ls_surface_hit(s, x, d, last, ls.cull.z, h))
        return 0.0;
    uint next = inside ^ (1u << uint(s));
    int from = interface_medium(inside), to = interface_medium(next);
    vec3 xh = x + d * h.t;
    float n_i = ls_medium_ior(from, xh), n_t = ls_medium_ior(to, xh);
    if (from == to || abs(n_i - n_t) <= LS_INDEX_EPS)
        return 0.0;
    hits = true;
    return interface_cross(d, h.shading, n_i, n_t).R;
}

// 4, the corners of a patch, read so that the compiler cannot prove it: loops over the
// corners then stay loops. Their bodies inline the surface intersections of every kind
// (a mesh's BVH walk included); unrolled four times (and again per call site) they made
// a shader that llvmpipe took minutes to compile. ls.limits.w (the surface count) >= 0.
int ls_corner_count()
{
    return 4 + min(ls.limits.w, 0);
}

struct ls_spawn_t {
    bool spawned;  // a Fresnel event began: lightsim_step.comp makes the reflected twin
    int surface;
    int mask;      // corners that cross it
    float R_mean;  // the twin's share of the power
    vec3 P;        // the patch's power when the event began
};

// Corner k of p crosses surface s at x (hit h) going along d (docs/lightsim.md "Surfaces").
void ls_cross(inout ls_gpu_patch p, int k, int s, geom_hit h, vec3 x, inout vec3 d,
              inout uint inside, bool may_spawn, inout ls_spawn_t sp, inout vec3 acc_refl)
{
    uint next = inside ^ (1u << uint(s));
    int from = interface_medium(inside), to = interface_medium(next);
    p.last[k] = s;
    float n_i = ls_medium_ior(from, x), n_t = ls_medium_ior(to, x);
    if (from == to || abs(n_i - n_t) <= LS_INDEX_EPS) {
        inside = next;
        return;
    }
    interface_event ev = interface_cross(d, h.shading, n_i, n_t);
    int bit = 1 << k;
    bool pending = p.event.x == s && (p.event.y & bit) != 0;
    if (!pending && p.event.y == 0 && may_spawn && !sp.spawned) {
        float sum = ev.R, R;
        int mask = bit;
        bool hits;
        // One call site for the four corners (a loop the compiler cannot unroll):
        // ls_predict inlines every surface kind's intersection, a mesh's BVH walk
        // included, and four inlined copies made llvmpipe's compile take minutes.
        for (int j = 0; j < ls_corner_count(); j++) {
            if (j == k)
                continue;
            R = ls_predict(p.x[j].xyz, p.w[j].xyz, uint(p.inside[j]), p.last[j], s, hits);
            if (hits) {
                sum += R;
                mask |= 1 << j;
            }
        }
        sp.spawned = true;
        sp.surface = s;
        sp.mask = mask;
        sp.R_mean = 0.25 * sum;
        sp.P = p.power.rgb;
        p.event = ivec4(s, mask, 0, 0);
        p.power.rgb *= 1.0 - sp.R_mean;
        pending = true;
    }
    if (pending) {
        p.event.y &= ~bit;
        if (p.event.z != 0) {
            d = ev.reflected; // the twin: stays in its medium
            return;
        }
        d = ev.tir ? ls_grazing(d, h.shading) : ev.refracted;
        inside = next;
        return;
    }
    // Outside an event: refracts on its own, a quarter's reflected power not followed.
    p.event.y &= ~bit;
    if (ev.tir) {
        d = ev.reflected;
        return;
    }
    vec3 loss = 0.25 * ev.R * p.power.rgb;
    acc_refl += loss;
    p.power.rgb -= loss;
    d = ev.refracted;
    inside = next;
}

// Moves corner k of p by the time dt; tau gains its optical depth through the surfaces'
// media. Without surfaces exactly propagate(). p.x[k].w (a cached sample) is kept.
void ls_corner_move(inout ls_gpu_patch p, int k, float dt, bool may_spawn, inout ls_spawn_t sp,
                    inout vec3 tau, inout vec3 acc_refl)
{
    if (ls.limits.w == 0) {
        propagate(p.x[k], p.w[k], dt);
        return;
    }
    float left = dt;
    vec3 x = p.x[k].xyz, w = p.w[k].xyz;
    uint inside = uint(p.inside[k]);
    for (int leg = 0; leg < LS_MAX_LEGS && left > 0.0; leg++) {
        int m = interface_medium(inside);
        geom_hit h;
        // The leg's straight line: in a surface's constant medium the ray itself (length
        // left / n), in the field the chord of propagate()'s curved step. One
        // ls_next_surface call site for both (see ls_corner_count).
        vec3 d = w;
        float reach;
        vec4 x1 = vec4(x, 0.0), w1 = vec4(w, 0.0);
        if (m >= 0) {
            d = normalize(w);
            reach = left / surfaces[m].medium.x;
        } else {
            propagate(x1, w1, left);
            vec3 chord = x1.xyz - x;
            reach = length(chord);
            if (reach > 0.0)
                d = chord / reach;
        }
        int s = reach > 0.0 ? ls_next_surface(x, d, p.last[k], reach, h) : -1;
        if (m >= 0) {
            float n = surfaces[m].medium.x;
            float t = s >= 0 ? h.t : reach;
            x += d * t;
            tau += surface_extinction(m) * t; // sigma_a + sigma_s: scattered light leaves the beam
            if (s < 0) {
                w = d * n;
                break;
            }
            left = max(0.0, left - t * n);
        } else {
            if (s < 0) {
                x = x1.xyz;
                w = w1.xyz;
                break;
            }
            x += d * h.t;
            left -= left * (h.t / reach);
        }
        ls_cross(p, k, s, h, x, d, inside, may_spawn, sp, acc_refl);
        w = d * ls_medium_ior(interface_medium(inside), x);
    }
    p.x[k].xyz = x;
    p.w[k].xyz = w;
    p.inside[k] = int(inside);
}
