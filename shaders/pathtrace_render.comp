#version 450
// pathtrace_render.comp - the GPU twin of the reference path tracer (server/core/pathtrace.c,
// docs/pathtracer.md), in float: one invocation adds image.z samples to one pixel's sums.
// It shares the exact surfaces (geom/kinds.glsl), the interface event and medium rule
// (interface.glsl) and Fresnel (fresnel.glsl) with the view renderer; the estimators are
// pathtrace.c's, step for step: Fresnel-weighted reflection/refraction, homogeneous media
// with one-sample MIS over channels, Henyey-Greenstein scattering, the Lambertian
// receiver, NEE to point/spot/directional/spherical lights with MIS for spheres, Russian
// roulette, no clamping. Its random numbers are a 32-bit hash chain (not the CPU's PCG64
// streams), so GPU and CPU agree in distribution, not sample for sample: the test compares
// them with a z-test on the difference of the means (tests/gpu/test_pathtrace_gpu.c).
// Not here yet: meshes, the procedural environment (uniform only), lathes' profiles are
// bound but untested.
#include "bindings.h"
#include "shared_types.h"
#include "pathtrace_types.h"
#define MARCH_MESHES 0
#include "fresnel.glsl"
#include "geom/kinds.glsl"
#include "interface.glsl"

layout(local_size_x = PT_LOCAL_X) in;

layout(std430, binding = BIND_SSBO_PT_PARAMS) readonly buffer pt_params_block
{
    pt_params P;
};
layout(std430, binding = BIND_SSBO_PT_ACCUM) buffer pt_accum_block
{
    vec4 accum[]; // 2 per pixel: sum, sum of squares
};

#define PT_RR_DEPTH 4
#define PT_MAX_DEPTH 1024
#include "pathtrace_common.glsl"

vec3 sample_cosine(vec3 n)
{
    float u1 = rng_uniform(), u2 = rng_uniform();
    return around(n, sqrt(1.0 - u1), 2.0 * PT_PI * u2);
}
float phase_hg(float g, float c)
{
    float d = 1.0 + g * g - 2.0 * g * c;
    return (1.0 - g * g) / (4.0 * PT_PI * d * sqrt(d));
}
vec3 sample_hg(vec3 d, float g)
{
    float u1 = rng_uniform(), u2 = rng_uniform();
    float c;
    if (abs(g) < 1e-3) {
        c = 1.0 - 2.0 * u1;
    } else {
        float sq = (1.0 - g * g) / (1.0 + g - 2.0 * g * u1);
        c = (1.0 + g * g - sq * sq) / (2.0 * g);
    }
    return around(d, clamp(c, -1.0, 1.0), 2.0 * PT_PI * u2);
}

// ---- media (pathtrace_medium.c) ----
pt_medium medium_of(uint inside)
{
    int k = interface_medium(inside);
    return P.media[k < 0 ? P.counts.x : k];
}
vec3 transmittance(pt_medium m, float d)
{
    vec3 st = m.sigma_a.rgb + m.sigma_s.rgb;
    if (isinf(d))
        return vec3(st.r > 0.0 ? 0.0 : 1.0, st.g > 0.0 ? 0.0 : 1.0, st.b > 0.0 ? 0.0 : 1.0);
    return exp(-st * d);
}
bool medium_sample(pt_medium m, float t_max, inout vec3 beta, out float t)
{
    t = t_max;
    if (all(equal(m.sigma_s.rgb, vec3(0.0)))) {
        beta *= transmittance(m, t_max);
        return false;
    }
    vec3 st = m.sigma_a.rgb + m.sigma_s.rgb;
    int ch = min(int(rng_uniform() * 3.0), 2);
    float tt = st[ch] > 0.0 ? -log(1.0 - rng_uniform()) / st[ch] : 1.0 / 0.0;
    bool collide = tt < t_max;
    float d = collide ? tt : t_max;
    vec3 tr = transmittance(m, d);
    float pdf = dot(collide ? st * tr : tr, vec3(1.0 / 3.0));
    beta *= pdf > 0.0 ? (collide ? tr * m.sigma_s.rgb : tr) / pdf : vec3(0.0);
    t = d;
    return collide;
}

// ---- geometry ----
const int HIT_NONE = 0, HIT_SURFACE = 1, HIT_RECEIVER = 2, HIT_LIGHT = 3;

float sphere_light_t(pt_light l, vec3 o, vec3 d, float tmin, float tmax)
{
    geom_hit h;
    return sphere_intersect(l.position.xyz, l.position.w, o, d, tmin, tmax, h) ? h.t : -1.0;
}

// The nearest surface, receiver or (lights) spherical light; t_min of the surface the ray
// leaves is its packed offset (float hit points), of the rest a relative epsilon.
int nearest(vec3 o, vec3 d, float tmax, int last, bool lights, bool camera, out float t,
            out int index, out vec3 shading)
{
    int kind = HIT_NONE;
    t = tmax;
    index = -1;
    shading = vec3(0.0, 1.0, 0.0);
    float eps = 1e-5 * (1.0 + max(abs(o.x), max(abs(o.y), abs(o.z))));
    for (int k = 0; k < P.counts.x; k++) {
        geom_hit h;
        float tmin = k == last ? max(eps, surfaces[k].medium.z) : eps;
        if (geom_surface_intersect(k, o, d, tmin, t, -1, h)) {
            kind = HIT_SURFACE;
            t = h.t;
            index = k;
            shading = h.shading;
        }
    }
    if (P.receiver.x > 0.5 && d.y != 0.0) {
        float tt = (P.receiver.y - o.y) / d.y;
        vec3 p = o + d * tt;
        bool inside = P.receiver.z < 0.0 || (abs(p.x - P.receiver.w) <= P.receiver.z &&
                                             abs(p.z - P.albedo.w) <= P.receiver.z);
        if (tt > eps && tt < t && inside) {
            kind = HIT_RECEIVER;
            t = tt;
        }
    }
    for (int k = 0; lights && k < P.counts.y; k++) {
        pt_light l = P.lights[k];
        if (l.kind.x != 3 || (camera && l.kind.y == 0))
            continue;
        float tt = sphere_light_t(l, o, d, eps, t);
        if (tt > 0.0) {
            kind = HIT_LIGHT;
            t = tt;
            index = k;
        }
    }
    return kind;
}

vec3 shadow(vec3 p, vec3 wi, float dist, uint inside, int last)
{
    vec3 tr = vec3(1.0);
    vec3 o = p;
    for (int n = 0; n < 2 * MAX_SURFACES + 2; n++) {
        float t;
        int idx;
        vec3 sh;
        int kind = nearest(o, wi, dist, last, false, false, t, idx, sh);
        tr *= transmittance(medium_of(inside), t);
        if (kind == HIT_NONE)
            return tr;
        if (kind == HIT_RECEIVER)
            return vec3(0.0);
        uint next = inside ^ (1u << uint(idx));
        if (medium_of(next).sigma_a.w != medium_of(inside).sigma_a.w)
            return vec3(0.0);
        o += wi * t;
        dist -= t;
        inside = next;
        last = idx;
    }
    return vec3(0.0);
}

// ---- lights (pathtrace_light.c) ----
float light_pdf(pt_light l, vec3 p)
{
    if (l.kind.x != 3)
        return 0.0;
    float dc = length(l.position.xyz - p);
    if (dc <= l.position.w)
        return 0.0;
    float s = l.position.w / dc;
    return 1.0 / (2.0 * PT_PI * (1.0 - sqrt(max(0.0, 1.0 - s * s))));
}

// Writes the direction, the distance and the radiance over pdf; returns the pdf in solid
// angle (0: a delta light).
float light_sample(pt_light l, vec3 p, out vec3 wi, out float dist, out vec3 li)
{
    if (l.kind.x == 2) { // directional
        wi = -l.direction.xyz;
        dist = 1.0 / 0.0;
        li = l.value.rgb;
        return 0.0;
    }
    vec3 v = l.position.xyz - p;
    float dc = length(v);
    if (l.kind.x != 3) { // point, spot
        wi = v / dc;
        dist = dc;
        bool cone = l.kind.x != 1 || dot(-wi, l.direction.xyz) >= l.direction.w;
        li = cone ? l.value.rgb / (dc * dc) : vec3(0.0);
        return 0.0;
    }
    if (dc <= l.position.w) {
        wi = vec3(0.0, 1.0, 0.0);
        dist = 0.0;
        li = vec3(0.0);
        return 0.0;
    }
    float s = l.position.w / dc;
    float cos_max = sqrt(max(0.0, 1.0 - s * s));
    vec3 axis = v / dc;
    float u1 = rng_uniform(), u2 = rng_uniform();
    wi = around(axis, 1.0 - u1 * (1.0 - cos_max), 2.0 * PT_PI * u2);
    float ct = dot(wi, axis);
    float disc = l.position.w * l.position.w - dc * dc * (1.0 - ct * ct);
    dist = dc * ct - sqrt(max(0.0, disc));
    float pdf = 1.0 / (2.0 * PT_PI * (1.0 - cos_max));
    li = l.value.rgb / pdf;
    return pdf;
}

// NEE from p; phase_g: NaN-free flag via receiver (true: Lambertian with normal n).
vec3 next_event(vec3 p, vec3 n, vec3 d, bool on_receiver, float g, uint inside, vec3 beta_f)
{
    vec3 L = vec3(0.0);
    for (int k = 0; k < P.counts.y; k++) {
        vec3 wi, li;
        float dist;
        float pdf_l = light_sample(P.lights[k], p, wi, dist, li);
        if (all(lessThanEqual(li, vec3(0.0))))
            continue;
        float f;
        if (on_receiver) {
            float c = dot(n, wi);
            if (c <= 0.0)
                continue;
            f = c / PT_PI;
        } else {
            f = phase_hg(g, dot(d, wi));
        }
        vec3 tr = shadow(p, wi, dist, inside, -1);
        float w = pdf_l > 0.0 ? pdf_l / (pdf_l + f) : 1.0;
        L += beta_f * f * li * tr * w;
    }
    return L;
}

vec3 radiance(vec3 o, vec3 d, uint inside)
{
    vec3 L = vec3(0.0), beta = vec3(1.0);
    bool specular = true, camera = true;
    float last_pdf = 0.0;
    vec3 last_p = o;
    int last = -1;
    for (int depth = 0; depth < PT_MAX_DEPTH; depth++) {
        float t;
        int idx;
        vec3 shading;
        int kind = nearest(o, d, 1.0 / 0.0, last, true, camera, t, idx, shading);
        float ts;
        pt_medium m = medium_of(inside);
        if (medium_sample(m, t, beta, ts)) {
            vec3 p = o + d * ts;
            camera = false;
            L += next_event(p, vec3(0.0), d, false, m.sigma_s.w, inside, beta);
            vec3 nd = sample_hg(d, m.sigma_s.w);
            last_pdf = phase_hg(m.sigma_s.w, dot(d, nd));
            last_p = p;
            specular = false;
            o = p;
            d = nd;
            last = -1;
        } else if (kind == HIT_NONE) {
            return L + beta * P.env.rgb;
        } else if (kind == HIT_LIGHT) {
            pt_light l = P.lights[idx];
            float w = specular ? 1.0 : last_pdf / (last_pdf + light_pdf(l, last_p));
            return L + beta * l.value.rgb * w;
        } else if (kind == HIT_RECEIVER) {
            vec3 p = o + d * t;
            vec3 n = vec3(0.0, d.y < 0.0 ? 1.0 : -1.0, 0.0);
            camera = false;
            L += next_event(p, n, d, true, 0.0, inside, beta * P.albedo.rgb);
            vec3 nd = sample_cosine(n);
            beta *= P.albedo.rgb;
            last_pdf = dot(n, nd) / PT_PI;
            last_p = p;
            specular = false;
            o = p;
            d = nd;
            last = -1;
        } else {
            uint next = inside ^ (1u << uint(idx));
            float n_i = m.sigma_a.w, n_t = medium_of(next).sigma_a.w;
            o = o + d * t;
            last = idx;
            if (n_i == n_t) {
                inside = next;
            } else {
                interface_event ev = interface_cross(d, shading, n_i, n_t);
                if (ev.tir || rng_uniform() < ev.R) {
                    d = ev.reflected;
                } else {
                    d = ev.refracted;
                    inside = next;
                }
                specular = true;
                camera = false;
            }
        }
        if (depth >= PT_RR_DEPTH) {
            float q = max(beta.r, max(beta.g, beta.b));
            if (q < 1.0) {
                if (q <= 0.0 || rng_uniform() >= q)
                    return L;
                beta /= q;
            }
        }
    }
    return L;
}

void main()
{
    int i = int(gl_GlobalInvocationID.x);
    int w = P.image.x, h = P.image.y;
    if (i >= w * h)
        return;
    int col = i % w, row = i / w;
    vec4 sum = vec4(0.0), sq = vec4(0.0);
    for (int s = 0; s < P.image.z; s++) {
        uint sample_index = uint(P.image.w + s);
        rng_state = pixel_hash(uint(i) ^ pixel_hash(sample_index ^ pixel_hash(uint(P.counts.z))));
        float x = float(col) + rng_uniform(), y = float(row) + rng_uniform();
        float sx = (2.0 * x / float(w) - 1.0) * P.eye.w * P.forward.w;
        float sy = (1.0 - 2.0 * y / float(h)) * P.eye.w;
        vec3 d = normalize(P.forward.xyz + P.right.xyz * sx + P.up.xyz * sy);
        vec3 L = radiance(P.eye.xyz, d, uint(P.counts.w));
        sum.rgb += L;
        sq.rgb += L * L;
    }
    accum[2 * i] += sum;
    accum[2 * i + 1] += sq;
}
