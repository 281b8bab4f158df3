#version 450
// photon_trace.comp - caustic photons traced on the GPU: the twin of
// server/core/photon_trace.c (docs/photons.md "Emission", "Tracing") in float, one
// invocation per photon. The scene is the GPU path tracer's (pt_params, the surfaces'
// records); pt_params' camera fields are not used and carry the photons' own numbers:
// eye.xyz the optical surfaces' bounding sphere's centre and eye.w its radius (the emission
// target), image.x photons per light, image.w the first photon of this dispatch. Photon g
// (light g / image.x, its number g mod image.x in that light) writes two vec4 at slot
// g - image.w: (x, z, 1 when it landed after an optical surface, 2 when PHOTON_MAX_EVENTS
// ended it, else 0; 0) and (power rgb, 0). Its random numbers are the GPU path tracer's hash
// chain, not the CPU's PCG32 streams: the two agree in distribution
// (tests/gpu/test_photon_trace_gpu.c). Not here: meshes (the host traces those scenes on
// the CPU); a light's photons start in the inside set of its centre (kind.z, computed by
// the host), where the CPU tracer tests each photon's start.
#include "bindings.h"
#include "shared_types.h"
#include "pathtrace_types.h"
#define MARCH_MESHES 0
#include "fresnel.glsl"
#include "geom/kinds.glsl"
#include "interface.glsl"
#include "pathtrace_common.glsl"

layout(local_size_x = PT_LOCAL_X) in;

layout(std430, binding = BIND_SSBO_PT_PARAMS) readonly buffer pt_params_block
{
    pt_params P;
};
layout(std430, binding = BIND_SSBO_PT_ACCUM) writeonly buffer photon_out_block
{
    vec4 photon_out[];
};

#define PHOTON_MAX_EVENTS 128 // = photon.h's
const int LIGHT_POINT = 0, LIGHT_SPOT = 1, LIGHT_DIRECTIONAL = 2, LIGHT_SPHERE = 3;

pt_medium medium_of(uint inside)
{
    int k = interface_medium(inside);
    return P.media[k < 0 ? P.counts.x : k];
}

// Surface k changes light: its medium differs from the ambient one (photon.h's
// photon_surface_optical, here on the path tracer's records).
bool photon_surface_optical(int k)
{
    pt_medium m = P.media[k], a = P.media[P.counts.x];
    return m.sigma_a.w != a.sigma_a.w || any(notEqual(m.sigma_a.rgb, a.sigma_a.rgb)) ||
           any(notEqual(m.sigma_s.rgb, a.sigma_s.rgb));
}

// The cone from p that holds the target sphere (c, r): its axis and cos of its half angle.
void target_cone(vec3 p, vec3 c, float r, out vec3 axis, out float cos_max)
{
    vec3 v = c - p;
    float dist = length(v);
    if (dist <= r) {
        axis = vec3(0.0, -1.0, 0.0);
        cos_max = -1.0;
        return;
    }
    axis = v / dist;
    float s = r / dist;
    cos_max = sqrt(max(0.0, 1.0 - s * s));
}

// emit() of photon_trace.c: the photon's ray and the power it stands for.
void emit(pt_light l, float n_l, out vec3 o, out vec3 d, out vec3 power)
{
    vec3 c = P.eye.xyz, axis;
    float r = P.eye.w, cos_max, w = 0.0;
    int kind = l.kind.x;
    if (kind == LIGHT_POINT || kind == LIGHT_SPOT) {
        target_cone(l.position.xyz, c, r, axis, cos_max);
        o = l.position.xyz;
        d = sample_cone(axis, cos_max);
        bool in_cone = kind == LIGHT_POINT || dot(d, l.direction.xyz) >= l.direction.w;
        w = in_cone ? 2.0 * PT_PI * (1.0 - cos_max) : 0.0;
    } else if (kind == LIGHT_SPHERE) {
        float z = 1.0 - 2.0 * rng_uniform(), phi = 2.0 * PT_PI * rng_uniform();
        float sz = sqrt(max(0.0, 1.0 - z * z));
        vec3 n = vec3(sz * cos(phi), sz * sin(phi), z);
        float radius = l.position.w;
        vec3 y = l.position.xyz + n * radius;
        target_cone(y, c, r, axis, cos_max);
        o = y + n * (1e-6 * (1.0 + radius));
        d = sample_cone(axis, cos_max);
        w = max(0.0, dot(n, d)) * 4.0 * PT_PI * radius * radius * 2.0 * PT_PI * (1.0 - cos_max);
    } else { // directional: a disk of radius r across the beam, 2 r before the centre
        d = l.direction.xyz;
        vec3 up = abs(d.y) < 0.9 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
        vec3 t = normalize(cross(up, d)), b = cross(d, t);
        float u = sqrt(rng_uniform()) * r, phi = 2.0 * PT_PI * rng_uniform();
        o = c - d * (2.0 * r) + t * (u * cos(phi)) + b * (u * sin(phi));
        w = PT_PI * r * r;
    }
    power = l.value.rgb * (w / n_l);
}

bool receiver_hit(vec3 o, vec3 d, float tmin, float tmax, out float t)
{
    t = 0.0;
    if (P.receiver.x == 0.0 || d.y == 0.0)
        return false;
    float tt = (P.receiver.y - o.y) / d.y;
    if (!(tt > tmin && tt < tmax))
        return false;
    vec3 p = o + d * tt;
    float hs = P.receiver.z;
    if (hs >= 0.0 && (abs(p.x - P.receiver.w) > hs || abs(p.z - P.albedo.w) > hs))
        return false;
    t = tt;
    return true;
}

void main()
{
    uint slot = gl_GlobalInvocationID.x;
    uint per_light = uint(P.image.x), g = slot + uint(P.image.w);
    uint lights = uint(P.counts.y);
    if (g >= per_light * lights || 2u * slot + 1u >= uint(photon_out.length()))
        return;
    uint j = g / per_light, k = g % per_light;
    rng_state = pixel_hash(k ^ pixel_hash(j ^ pixel_hash(uint(P.counts.z))));
    vec3 o, d, power;
    emit(P.lights[j], float(per_light), o, d, power);
    vec4 head = vec4(0.0);
    if (any(greaterThan(power, vec3(0.0)))) {
        uint inside = uint(P.lights[j].kind.z); // the set at the light (the host's)
        bool caustic = false;
        int last_surface = -1;
        int events = 0;
        for (; events < PHOTON_MAX_EVENTS; events++) {
            float tmin = 1e-5 * (1.0 + max(abs(o.x), max(abs(o.y), abs(o.z))));
            float t_best = 3.0e38;
            int hit = -1;
            geom_hit best;
            for (int s = 0; s < P.counts.x; s++) {
                geom_hit h;
                float t0 = s == last_surface ? max(tmin, surfaces[s].medium.z) : tmin;
                if (geom_surface_intersect(s, o, d, t0, t_best, -1, h)) {
                    t_best = h.t;
                    hit = s;
                    best = h;
                }
            }
            float t_recv;
            bool lands = receiver_hit(o, d, tmin, t_best, t_recv);
            float seg = lands ? t_recv : t_best;
            pt_medium m = medium_of(inside);
            if (seg < 3.0e38)
                power *= exp(-(m.sigma_a.rgb + m.sigma_s.rgb) * seg);
            if (lands) {
                vec3 p = o + d * t_recv;
                head = vec4(p.x, p.z, caustic ? 1.0 : 0.0, 0.0);
                break;
            }
            if (hit < 0)
                break;
            o += d * best.t;
            uint next = inside ^ (1u << uint(hit));
            float n_i = medium_of(inside).sigma_a.w, n_t = medium_of(next).sigma_a.w;
            if (photon_surface_optical(hit))
                caustic = true;
            last_surface = hit;
            if (n_i == n_t) {
                inside = next;
                continue;
            }
            interface_event ev = interface_cross(d, best.shading, n_i, n_t);
            if (ev.tir || rng_uniform() < ev.R) {
                d = ev.reflected;
            } else {
                d = ev.refracted;
                inside = next;
            }
        }
        if (events >= PHOTON_MAX_EVENTS)
            head = vec4(0.0, 0.0, 2.0, 0.0);
    }
    photon_out[2u * slot] = head;
    photon_out[2u * slot + 1u] = vec4(power, 0.0);
}
