// ray_march.glsl - a ray's whole journey through a scene's volume objects: docs/tracing.md
// "The march", implemented step for step (the CPU twin is server/core/reftrace.c).
//
// Image formation follows tevs2007 eqs. 5.4-5.10: L = sum T_f exp(-alpha) (n_amb/n)^2
// (L_e + L_s) ds + reflections (environment and, eq. 5.6/5.8, the lights' L_r) +
// T_f exp(-alpha) (receiver or L_bg), with Fresnel transmission factors T_f multiplied
// along the ray (sect. 5.1.3), Beer-Lambert optical depth alpha over the extinction
// sigma_a + sigma_s (eq. 5.9), and frisvad2010's basic radiance factor (n_amb/n)^2 for
// light that starts inside a medium of index n. Define MARCH_RADIANCE to 1 before
// including this file to gather radiance (render_view, which also includes lighting.glsl);
// trace_rays leaves it 0 and only transports the ray.

#ifndef MARCH_RADIANCE
#define MARCH_RADIANCE 0
#endif
// The variant switches MARCH_STEPPER, MARCH_ATTENUATION, MARCH_EMISSION, MARCH_OPAQUE,
// MARCH_SCATTERING, MARCH_LIGHTS and MARCH_SKIP are set in march_bindings.glsl.

#if MARCH_SURFACES
#include "geom/kinds.glsl"
#include "interface.glsl"
#include "medium_step.glsl"
#if MARCH_RADIANCE && MARCH_LIGHTS
#include "photons.glsl"
#endif
#endif

const float MARCH_INDEX_EPS = 1e-6;       // |n_field - n_ambient| below this: no interface
// The absorbed cut-off (throughput below it ends the ray) is params.settings_f3.x,
// render.min_throughput (default 1e-6; 0: never).
const float MARCH_EXIT_EPS = 1e-3;        // voxels: a bounds this close behind is already left
const float MARCH_RAMP_SLOPE_RATIO = 0.5; // zone sides keep this much of the slope: a ramp
const float MARCH_SKIP_EXIT_PAD = 1e-3;   // voxels: a skip to the bounds ends this far past them

struct march_state {
    vec3 x;          // world position
    vec3 d;          // unit world direction
    float t_f;       // product of Fresnel transmission factors
    vec3 alpha;      // optical depth per channel (tevs2007 eq. 5.9)
    vec3 L;          // gathered radiance (MARCH_RADIANCE)
    float opl;       // optical path length, world units
    int steps;       // integration steps taken
    int status;      // RAY_STATUS_*
    bool crossed;    // entered at least one object
    int events;      // surface events (MARCH_SURFACES)
};

float march_object_scale(int obj)
{
    return params.objects[obj].bounds_min.w;
}

vec3 march_point_to_object(int obj, vec3 x)
{
    return (params.objects[obj].object_from_world * vec4(x, 1.0)).xyz;
}

vec3 march_point_to_world(int obj, vec3 p)
{
    return (params.objects[obj].world_from_object * vec4(p, 1.0)).xyz;
}

// Rotation only: world_from_object's 3x3 part is scale * R.
vec3 march_dir_to_world(int obj, vec3 q)
{
    return normalize(mat3(params.objects[obj].world_from_object) * q);
}

vec3 march_dir_to_object(int obj, vec3 d)
{
    return normalize(mat3(params.objects[obj].object_from_world) * d);
}

float march_throughput(march_state s)
{
    vec3 t = exp(-s.alpha);
    return s.t_f * max(t.r, max(t.g, t.b));
}

// frisvad2010's basic radiance: radiance that starts in a medium of index n reaches the
// viewer in the ambient medium times (n_amb / n)^2 (docs/tracing.md "Basic radiance").
float march_basic_radiance(float n)
{
    float r = params.settings_f.z / n;
    return r * r;
}

#if MARCH_RADIANCE
// What a ray leaving the scene at world point x along world direction d sees: a lamp (a
// point light with a radius) where it meets one first, else the receiver plane where it
// hits it (both MARCH_LIGHTS), else the environment; primary: the ray has met nothing (the
// camera does not see hidden lamps). Reflected rays look it up
// directly (tevs2007 sect. 6.3: they are not cast back through the volume), so the floor
// shows in a glass's reflection as the sky does (issue 14 item 4; the twin is
// reftrace.c's seen_from).
vec3 march_seen(vec3 x, vec3 d, bool primary)
{
    vec3 seen = environment_radiance(d);
#if MARCH_LIGHTS
    vec3 plane, lamp;
    float t_max = 3.0e38;
    if (light_receiver(x, d, plane)) {
        seen = plane;
        t_max = (lights.receiver.x - x.y) / d.y;
    }
    if (light_emitter(x, d, t_max, primary, lamp))
        seen = lamp;
#endif
    return seen;
}
#endif

// Adds a reflection seen from world point x_world in world direction d_world with weight R
// (MARCH_RADIANCE only).
void march_add_reflection(inout march_state s, float R, vec3 x_world, vec3 d_world)
{
#if MARCH_RADIANCE
    s.L += s.t_f * exp(-s.alpha) * R * march_seen(x_world, d_world, false);
#endif
}

// The lights' reflected radiance at a Fresnel event with reflectance R (the delta(x) R L_r
// term of tevs2007 eq. 5.4): world point, the view ray's world direction before the event,
// the surface normal (object space, either orientation) and the index on the viewer's side.
void march_add_light_reflection(inout march_state s, int obj, vec3 p, vec3 q, vec3 N, float R,
                                float n_view)
{
#if MARCH_RADIANCE && MARCH_LIGHTS
    vec3 Lr = light_reflected(obj, march_point_to_world(obj, p), march_dir_to_world(obj, q),
                              march_dir_to_world(obj, N), R);
    s.L += s.t_f * exp(-s.alpha) * march_basic_radiance(n_view) * Lr;
#endif
}

// Slab test of an object-space ray against the bounds. Returns true when the ray's line
// meets the box with t1 > MARCH_EXIT_EPS voxels; t0 may be negative (origin inside). axis0 and
// sign0 name the entry face (outward normal = sign0 along axis0).
bool march_bounds_hit(int obj, vec3 o, vec3 q, out float t0, out float t1, out int axis0,
                      out float sign0)
{
    vec3 bmin = params.objects[obj].bounds_min.xyz;
    vec3 bmax = params.objects[obj].bounds_max.xyz;
    t0 = -1e30;
    t1 = 1e30;
    axis0 = 0;
    sign0 = -1.0;
    for (int a = 0; a < 3; a++) {
        if (abs(q[a]) < 1e-12) {
            if (o[a] < bmin[a] || o[a] > bmax[a])
                return false;
            continue;
        }
        float inv = 1.0 / q[a];
        float ta = (bmin[a] - o[a]) * inv;
        float tb = (bmax[a] - o[a]) * inv;
        float tn = min(ta, tb);
        float tf = max(ta, tb);
        if (tn > t0) {
            t0 = tn;
            axis0 = a;
            sign0 = q[a] > 0.0 ? -1.0 : 1.0;
        }
        t1 = min(t1, tf);
    }
    return t0 <= t1 && t1 > MARCH_EXIT_EPS * params.objects[obj].bounds_max.w;
}

// Fraction f in [0, 1] of the segment p0 -> p1 inside the bounds, and the face it leaves
// through (outward normal = sign along axis). Called when p1 is outside.
float march_exit_fraction(int obj, vec3 p0, vec3 p1, out int axis, out float sign)
{
    vec3 bmin = params.objects[obj].bounds_min.xyz;
    vec3 bmax = params.objects[obj].bounds_max.xyz;
    float f = 1.0;
    axis = 0;
    sign = 1.0;
    vec3 dp = p1 - p0;
    for (int a = 0; a < 3; a++) {
        float fa = 2.0;
        if (p1[a] > bmax[a] && dp[a] > 0.0)
            fa = (bmax[a] - p0[a]) / dp[a];
        else if (p1[a] < bmin[a] && dp[a] < 0.0)
            fa = (bmin[a] - p0[a]) / dp[a];
        if (fa < f) {
            f = fa;
            axis = a;
            sign = dp[a] > 0.0 ? 1.0 : -1.0;
        }
    }
    return clamp(f, 0.0, 1.0);
}

bool march_outside(int obj, vec3 p)
{
    vec3 bmin = params.objects[obj].bounds_min.xyz;
    vec3 bmax = params.objects[obj].bounds_max.xyz;
    return any(lessThan(p, bmin)) || any(greaterThan(p, bmax));
}

vec3 march_axis_normal(int axis, float sign)
{
    vec3 n = vec3(0.0);
    n[axis] = sign;
    return n;
}

// Finds the object the world ray enters first. Returns -1 when none.
int march_next_object(march_state s, out float t_world, out bool inside, out int face_axis,
                      out float face_sign)
{
    int best = -1;
    t_world = 1e30;
    inside = false;
    face_axis = 0;
    face_sign = 1.0;
    for (int i = 0; i < params.settings_i.z; i++) {
        if ((params.objects[i].resolution.w & OBJECT_BOUND) != 0)
            continue; // fills a surface: seen only inside it (march_bound.glsl)
        vec3 o = march_point_to_object(i, s.x);
        vec3 q = march_dir_to_object(i, s.d);
        float t0, t1, sgn;
        int ax;
        if (!march_bounds_hit(i, o, q, t0, t1, ax, sgn))
            continue;
        float tw = max(t0, 0.0) * march_object_scale(i);
        if (tw < t_world) {
            t_world = tw;
            best = i;
            inside = t0 <= 0.0;
            face_axis = ax;
            face_sign = sgn;
        }
    }
    return best;
}

// Sharp boundaries inside the field (docs/tracing.md "Sharp boundaries"). Entering a
// boundary zone probes the index on both sides along grad n; the Fresnel event happens
// where the ray crosses the zone's middle index, so a ray that only grazes the smoothed
// halo of an interface (tevs2007 sect. 3.1) is not reflected.
struct march_zone {
    bool inside; // in a zone (|grad n| h_min above the threshold, with hysteresis)
    bool armed;  // its middle index has not been crossed yet
    float n_lo, n_hi, n_mid;
    float slope_sides; // the smaller slope along N at the two probes (smooth-ramp test)
};

void march_zone_enter(inout march_zone z, int obj, vec3 p, vec4 sample_at_p)
{
    vec3 N = normalize(sample_at_p.rgb);
    float h_min = params.objects[obj].bounds_max.w;
    float k = (3.0 * params.objects[obj].inv_voxel_size.w + 2.0) * h_min;
    vec4 lo = volume_sample_ior_grad(obj, p - k * N);
    vec4 hi = volume_sample_ior_grad(obj, p + k * N);
    z.n_lo = lo.a;
    z.n_hi = hi.a;
    z.n_mid = 0.5 * (z.n_lo + z.n_hi);
    z.slope_sides = min(dot(lo.rgb, N), dot(hi.rgb, N));
    z.inside = true;
    z.armed = true;
}

bool march_zone_crossed(march_zone z, float n_before, float n_after)
{
    return z.armed && n_before != n_after && (n_before - z.n_mid) * (n_after - z.n_mid) <= 0.0;
}

// The crossing: unpolarised Fresnel from the side the ray comes from to the other.
void march_zone_event(inout march_state s, inout march_zone z, int obj, vec3 p, vec4 sample_at_p,
                      float n_before, vec3 q)
{
    z.armed = false;
    if (dot(sample_at_p.rgb, sample_at_p.rgb) <= 0.0)
        return;
    // A smooth ramp, not an interface: the slope continues on both sides of the zone at
    // more than half its value here. The ray equation bends the ray; there is no surface
    // to reflect from (a steep GRIN field must not lose light to grazing "Fresnel").
    if (z.slope_sides > MARCH_RAMP_SLOPE_RATIO * length(sample_at_p.rgb))
        return;
    vec3 N = normalize(sample_at_p.rgb);
    bool rising = sample_at_p.a > n_before;
    float n_i = rising ? z.n_lo : z.n_hi;
    float n_t = rising ? z.n_hi : z.n_lo;
    float R = fresnel_unpolarized(abs(dot(q, N)), n_i, n_t);
    if (R >= 1.0)
        return; // total internal reflection emerges from the ray equation itself
    march_add_reflection(s, R, march_point_to_world(obj, p), march_dir_to_world(obj, reflect(q, N)));
    march_add_light_reflection(s, obj, p, q, N, R, n_i);
    s.t_f *= 1.0 - R;
}

// The ray stopped on an opaque embedding (tevs2007 sect. 6.1, T6).
void march_opaque_hit(inout march_state s, int obj, vec3 p, vec4 opaque, float n_here, vec3 q)
{
#if MARCH_RADIANCE
    vec3 h = 1.0 / params.objects[obj].inv_voxel_size.xyz; // one voxel along each axis
    vec3 g;
    g.x = volume_sample_opaque(obj, p + vec3(h.x, 0, 0)).a - volume_sample_opaque(obj, p - vec3(h.x, 0, 0)).a;
    g.y = volume_sample_opaque(obj, p + vec3(0, h.y, 0)).a - volume_sample_opaque(obj, p - vec3(0, h.y, 0)).a;
    g.z = volume_sample_opaque(obj, p + vec3(0, 0, h.z)).a - volume_sample_opaque(obj, p - vec3(0, 0, h.z)).a;
    g /= h;
    vec3 N = length(g) > 1e-12 ? -normalize(g) : -q; // outward from the embedding
    float R = fresnel_unpolarized(abs(dot(q, N)), n_here, params.objects[obj].atlas_offset.w);
    s.L += s.t_f * exp(-s.alpha) *
           (R * march_seen(march_point_to_world(obj, p), march_dir_to_world(obj, reflect(q, N)), false) +
            (1.0 - R) * opaque.rgb);
    march_add_light_reflection(s, obj, p, q, N, R, n_here);
#endif
    s.status = RAY_STATUS_ABSORBED;
}

// Crossing a bounds face from n_from to n_to with outward normal N (object space).
// Returns false on total internal reflection (q is then mirrored); otherwise q refracts
// and the reflected part is gathered.
bool march_face(inout march_state s, int obj, vec3 p, inout vec3 q, vec3 N, float n_from,
                float n_to)
{
    if (abs(n_from - n_to) <= MARCH_INDEX_EPS)
        return true;
    float R = fresnel_unpolarized(abs(dot(q, N)), n_from, n_to);
    vec3 r = reflect(q, N);
    if (R >= 1.0) {
        q = r;
        return false;
    }
    march_add_reflection(s, R, march_point_to_world(obj, p), march_dir_to_world(obj, r));
    march_add_light_reflection(s, obj, p, q, N, R, n_from);
    s.t_f *= 1.0 - R;
    vec3 t;
    snell_refract(q, N, n_from, n_to, t);
    q = t;
    return true;
}

#if MARCH_SKIP
// Empty-space skipping (docs/tracing.md "Empty space"): the distance (object units) along
// the unit direction q from p over consecutive empty macro cells, a 3D DDA (Amanatides and
// Woo) over params.skip_cells; t_bounds when they reach the bounds (to_bounds), 0 when p's
// own cell is not empty. In an empty cell grad n = 0 and n is constant, so the ray equation
// (tevs2007 eqs. 4.8/4.9) gives a straight line: one jump replaces the steps. CPU twin:
// macrocell_skip_distance (server/core/macrocell.c).
float march_skip_distance(int obj, vec3 p, vec3 q, out bool to_bounds)
{
    ivec4 sc = params.skip_cells[obj];
    float cell = params.settings_f3.y;
    vec3 bmin = params.objects[obj].bounds_min.xyz;
    vec3 bmax = params.objects[obj].bounds_max.xyz;
    vec3 inv_vs = params.objects[obj].inv_voxel_size.xyz;
    vec3 c0 = (p - bmin) * inv_vs / cell;
    ivec3 ci = clamp(ivec3(floor(c0)), ivec3(0), sc.xyz - 1);
    to_bounds = false;
    // The common case first: p's own cell is not empty (one read, no DDA set-up).
    if (skip_empty[sc.w + (ci.z * sc.y + ci.y) * sc.x + ci.x] == 0u)
        return 0.0;
    vec3 dc = q * inv_vs / cell;
    float t_bounds = 1e30;
    ivec3 stp;
    vec3 tmax, tdelta;
    for (int a = 0; a < 3; a++) {
        if (q[a] > 0.0)
            t_bounds = min(t_bounds, (bmax[a] - p[a]) / q[a]);
        else if (q[a] < 0.0)
            t_bounds = min(t_bounds, (bmin[a] - p[a]) / q[a]);
        if (dc[a] > 0.0) {
            stp[a] = 1;
            tmax[a] = (float(ci[a] + 1) - c0[a]) / dc[a];
            tdelta[a] = 1.0 / dc[a];
        } else if (dc[a] < 0.0) {
            stp[a] = -1;
            tmax[a] = (float(ci[a]) - c0[a]) / dc[a];
            tdelta[a] = -1.0 / dc[a];
        } else {
            stp[a] = 0;
            tmax[a] = 1e30;
            tdelta[a] = 1e30;
        }
    }
    t_bounds = max(t_bounds, 0.0);
    float t = 0.0;
    int guard = sc.x + sc.y + sc.z + 3;
    for (int k = 0; k < guard; k++) {
        if (skip_empty[sc.w + (ci.z * sc.y + ci.y) * sc.x + ci.x] == 0u)
            break;
        int a = tmax.x <= tmax.y && tmax.x <= tmax.z ? 0 : (tmax.y <= tmax.z ? 1 : 2);
        t = max(t, tmax[a]);
        if (t >= t_bounds) {
            t = t_bounds;
            to_bounds = true;
            break;
        }
        ci[a] += stp[a];
        tmax[a] += tdelta[a];
        if (ci[a] < 0 || ci[a] >= sc[a]) {
            t = t_bounds; // the cells end at the bounds (or beyond, in a partial cell)
            to_bounds = true;
            break;
        }
    }
    return t;
}
#endif

// Integrates through object obj from object-space point p with unit direction q until the
// ray leaves the bounds or stops. Updates s.x and s.d on exit.
//
// The inner loop only steps and accumulates; anything rare and expensive (a Fresnel event,
// an opaque hit, leaving the bounds) breaks out of it and is handled once in the outer
// loop. On SIMD hardware and llvmpipe, code inside a branch of the inner loop costs every
// lane every step even when no lane takes it, so keeping the inner loop lean is what makes
// the march fast.
void march_through_object(inout march_state s, int obj, vec3 p, vec3 q)
{
    float scale = march_object_scale(obj);
    float h_min = params.objects[obj].bounds_max.w;
    float h_max = params.settings_f.x * h_min;
    float h = h_max; // the adaptive stepper changes it step by step
#if MARCH_STEPPER == STEPPER_ADAPTIVE
    float tol = params.settings_f2.x * h_min;
    vec3 extent3 = params.objects[obj].bounds_max.xyz - params.objects[obj].bounds_min.xyz;
    float extent = max(extent3.x, max(extent3.y, extent3.z));
#endif
    float ambient = params.settings_f.z;
    float threshold = params.settings_f.y;
    int max_steps = params.settings_i.y;
    vec4 s0 = volume_sample_ior_grad(obj, p);
    vec3 sig0 = volume_sample_extinction(obj, p);
    vec3 w = s0.a * q;
    march_zone zone;
    zone.inside = false;
    zone.armed = false;
    zone.n_lo = zone.n_hi = zone.n_mid = s0.a;
    float n_before = s0.a;
    float min_throughput = params.settings_f3.x;
#if MARCH_SKIP
    bool skipped = false; // the last step was a skip
#endif
    while (s.status == RAY_STATUS_RUNNING) {
        bool leaving = false, entering = false, crossed = false, opaque = false, absorbed = false;
        int exit_axis = 0;
        float exit_sign = 1.0;
        vec4 op = vec4(0.0);
        for (;;) {
            if (s.steps >= max_steps) {
                s.status = RAY_STATUS_MAX_STEPS;
                break;
            }
            vec3 p1 = p;
            vec3 w1 = w;
#if MARCH_SKIP
            // An empty run of two steps or more: jump over it (w unchanged), then integrate
            // at least once before the next jump. A skip counts as one step.
            bool skip = false;
            if (!skipped) {
                vec3 qs = normalize(w);
                bool to_bounds;
                float t_skip = march_skip_distance(obj, p, qs, to_bounds);
                // Whole steps: in empty space a step moves p by h_max w / n, whose length
                // h_max |w| / n is h_max only as far as the integration kept |w| = n, so the
                // jump is k such moves and the steps after it sample where they would have.
                // To the bounds: a little past them, and the cut lands it on the face as the
                // last step would.
                vec3 move = (h_max / s0.a) * w;
                float whole = floor(t_skip / length(move));
                if (to_bounds ? t_skip >= 2.0 * length(move) : whole >= 2.0) {
                    skip = true;
                    p1 = to_bounds ? p + (t_skip + MARCH_SKIP_EXIT_PAD * h_min) * qs
                                   : p + whole * move;
                }
            }
            skipped = skip;
            if (skip) {
                h = h_max; // the adaptive stepper restarts as in empty space
            } else
#endif
            {
#if MARCH_STEPPER == STEPPER_EULER
                ray_equation_step_euler(obj, s0, h, p1, w1);
#elif MARCH_STEPPER == STEPPER_RK2
                ray_equation_step_rk2(obj, s0, h, p1, w1);
#elif MARCH_STEPPER == STEPPER_ADAPTIVE
                float err = ray_equation_step_bs23(obj, s0, h, extent, p1, w1);
                float h_next = ray_equation_next_step(h, err, tol, h_max);
                if (err > tol && h > RAY_BS23_FLOOR * h_max * 1.0001) {
                    h = h_next; // rejected: retry from p with the smaller step
                    s.steps++;  // a rejected attempt counts against the budget too
                    continue;
                }
                h = h_next; // accepted: p1, w1 stand; the next step tries h_next
#else
                ray_equation_step_rk4(obj, s0, h, p1, w1);
#endif
            }
            s.steps++;
            leaving = march_outside(obj, p1);
            if (leaving) {
                float f = march_exit_fraction(obj, p, p1, exit_axis, exit_sign);
                p1 = p + f * (p1 - p);
                w1 = w + f * (w1 - w);
            }
            vec4 s1 = volume_sample_ior_grad(obj, p1);
            vec4 sc1 = volume_sample_scattering(obj, p1);
            vec3 sig1 = volume_sample_attenuation(obj, p1) + sc1.rgb; // extinction
            float ds = length(p1 - p) * scale;
            s.opl += 0.5 * (s0.a + s1.a) * ds;
            s.alpha += 0.5 * (sig0 + sig1) * ds;
#if MARCH_RADIANCE && MARCH_EMISSION
            s.L += s.t_f * exp(-s.alpha) * march_basic_radiance(s1.a) *
                   volume_sample_emission(obj, p1) * ds;
#endif
#if MARCH_RADIANCE && MARCH_SCATTERING
            // In-scattering L_s (tevs2007 eqs. 5.4/5.5) at the step's end, towards the eye.
            if (any(greaterThan(sc1.rgb, vec3(0.0))))
                s.L += s.t_f * exp(-s.alpha) * march_basic_radiance(s1.a) * ds *
                       light_inscatter(march_point_to_world(obj, p1),
                                       march_dir_to_world(obj, normalize(w1)), sc1.rgb, sc1.a);
#endif
            float g = length(s1.rgb) * h_min;
            entering = !zone.inside && g > threshold;
            crossed = march_zone_crossed(zone, s0.a, s1.a);
            n_before = s0.a;
            if (zone.inside && g < 0.5 * threshold) {
                zone.inside = false;
                zone.armed = false;
            }
#if MARCH_OPAQUE
            op = volume_sample_opaque(obj, p1);
            opaque = op.a >= 0.5;
#endif
            absorbed = march_throughput(s) < min_throughput;
            p = p1;
            w = w1;
            s0 = s1;
            sig0 = sig1;
            if (leaving || entering || crossed || opaque || absorbed)
                break;
        }
        q = normalize(w);
        if (s.status != RAY_STATUS_RUNNING)
            break;
        if (entering) {
            march_zone_enter(zone, obj, p, s0);
            crossed = march_zone_crossed(zone, n_before, s0.a); // a thin zone, one step
        }
        if (crossed)
            march_zone_event(s, zone, obj, p, s0, n_before, q);
        if (opaque) {
            march_opaque_hit(s, obj, p, op, s0.a, q);
            break;
        }
        if (absorbed || march_throughput(s) < min_throughput) {
            s.status = RAY_STATUS_ABSORBED;
            break;
        }
        if (leaving) {
            // From the index the ray carries, |w| (= n along an exact ray, tevs2007 eq. 4.8),
            // not the sampled n(p'), which is clamped in the half voxel before the face while
            // grad n still changes w (docs/tracing.md "The rim"). Twin: march_object in
            // server/core/reftrace.c.
            vec3 N = march_axis_normal(exit_axis, exit_sign);
            float n_w = length(w);
            if (march_face(s, obj, p, q, N, n_w, ambient)) {
                s.x = march_point_to_world(obj, p);
                s.d = march_dir_to_world(obj, q);
                return;
            }
            w = s0.a * q; // totally reflected at the face: keep marching inside (as before)
        }
    }
    s.x = march_point_to_world(obj, p);
    s.d = march_dir_to_world(obj, q);
}

#if MARCH_SURFACES
// ---- exact surfaces (docs/tracing.md "Surfaces"); twin: server/core/reftrace.c ----

// The view ray's first internal reflection in a walter scene's scattering medium
// (docs/walter.md "The view ray's reflection"; reftrace.c struct march_deferred): recorded
// by march_surface_event when march_defer_ok, traced by the caller as a second ray from
// march_start_surface's primitive march_start_prim, its radiance times march_defer_w.
bool march_defer_ok = false;
bool march_deferred = false;
vec3 march_defer_x, march_defer_d, march_defer_w;
uint march_defer_inside;
int march_defer_surface, march_defer_prim;
int march_start_surface = -1, march_start_prim = -1;
// True while the deferred ray runs: its legs take a quarter of the in-scattering steps
// (its weight is a Fresnel reflectance, a few percent; reftrace.c surface_leg).
bool march_second_ray = false;
// Where in each inner in-scattering step the source is sampled (0.5: the midpoint; a leg's
// first and last steps always use it). In walter scenes render_view shifts it per pixel
// sample (docs/walter.md "Steps").
float march_step_offset = 0.5;

// A hit this close (relative to a surface's size) on a surface other than the one just
// left is a real crossing; the one just left is searched from surfaces[k].medium.z on.
const float MARCH_SURFACE_EPS_OTHER = 1e-7;

// The nearest surface crossing before t_max; -1 when none.
int march_next_surface(vec3 x, vec3 d, int last, int last_prim, float t_max, out geom_hit hit)
{
    int best = -1;
    float t_best = t_max;
    hit.t = 0.0;
    hit.normal = vec3(0.0);
    hit.shading = vec3(0.0);
    hit.prim = -1;
    for (int k = 0; k < params.surfaces.x; k++) {
        float tmin = k == last ? surfaces[k].medium.z : 0.0;
        geom_hit h;
        if (geom_surface_intersect(k, x, d, tmin, t_best, k == last ? last_prim : -1, h)) {
            t_best = h.t;
            hit = h;
            best = k;
        }
    }
    return best;
}

// n of the medium of surface `medium` at world point x: the constant, or the sample of the
// object that fills it (surfaces[k].attenuation.w >= 0, march_bound.glsl); -1: ambient.
float march_medium_ior(int medium, vec3 x)
{
    if (medium < 0)
        return params.settings_f.z;
    if (surfaces[medium].attenuation.w < 0.0)
        return surfaces[medium].medium.x;
    int obj = int(surfaces[medium].attenuation.w);
    return volume_sample_ior_grad(obj, march_point_to_object(obj, x)).a;
}

// A straight leg of length t through the medium of surface `medium` (-1: ambient): optical
// path n t, optical depth sigma_t t with sigma_t = sigma_a + sigma_s (tevs2007 eq. 5.9), and
// eq. 5.4's source terms with the basic radiance factor: the emission and (MARCH_SCATTERING,
// with lights) the single in-scattering of eq. 5.5 with the medium's g, over the steps of
// medium_step.glsl: per step exp(-alpha_i) (1 - exp(-sigma_t h)) / sigma_t times the source
// at the step's midpoint. Twin of surface_leg in server/core/reftrace.c.
void march_surface_leg(inout march_state s, int medium, float t)
{
    s.opl += march_medium_ior(medium, s.x) * t;
    if (medium >= 0) {
        vec3 sigma_t = surface_extinction(medium);
#if MARCH_RADIANCE
        vec3 le = surfaces[medium].emission.rgb;
        float w = s.t_f * march_basic_radiance(surfaces[medium].medium.x);
        int steps = 1;
#if MARCH_SCATTERING && MARCH_LIGHTS
        vec4 sc = surfaces[medium].scattering;
        bool scatters = lights.count.x > 0 && any(greaterThan(sc.rgb, vec3(0.0)));
        if (scatters)
            steps = medium_step_count(t, light_inscatter_step());
        if (march_second_ray)
            steps = max(1, steps / 4);
#endif
        float h = t / float(steps);
        vec3 weight = medium_step_weight(sigma_t, h);
        for (int i = 0; i < steps; i++) {
            vec3 source = le;
#if MARCH_SCATTERING && MARCH_LIGHTS
            if (scatters) {
                float o = i == 0 || i == steps - 1 ? 0.5 : march_step_offset;
                source += light_inscatter(s.x + s.d * ((float(i) + o) * h), s.d, sc.rgb, sc.a);
            }
#endif
            s.L += w * exp(-s.alpha) * weight * source;
            s.alpha += sigma_t * h;
        }
#else
        s.alpha += sigma_t * t;
#endif
    }
    s.x += s.d * t;
}

// Crossing surface k (core/interface.h): toggles k in the inside set; where the medium
// changes, the Fresnel event with the environment's reflection gathered, or total
// internal reflection. n_leaving: leaving a field-filled surface, the index on the inside
// as march_through_bound found it; < 0: the medium's index at s.x.
void march_surface_event(inout march_state s, inout uint inside, int k, geom_hit h,
                         float n_leaving)
{
    uint next = inside ^ (1u << uint(k));
    int from = interface_medium(inside), to = interface_medium(next);
    s.steps++;
    s.crossed = true;
    if (from == to) {
        inside = next;
        return;
    }
    float n_from = n_leaving >= 0.0 ? n_leaving : march_medium_ior(from, s.x);
    float n_to = march_medium_ior(to, s.x);
    if (abs(n_from - n_to) <= MARCH_INDEX_EPS) {
        inside = next;
        return;
    }
    interface_event ev = interface_cross(s.d, h.shading, n_from, n_to);
#ifdef MARCH_TRACE_EVENTS
    march_trace_event(s.events, s.x, s.d, h.shading, ev.tir, ev.R, k, from, ev.tir ? from : to,
                      n_from, n_to);
#endif
    s.events++;
    if (ev.tir) {
        s.d = ev.reflected;
        return;
    }
#if MARCH_RADIANCE && MARCH_LIGHTS && MARCH_SCATTERING
    if (march_defer_ok && !march_deferred && lights.count.w == 1 && from >= 0 && ev.R > 0.0 &&
        any(greaterThan(surfaces[from].scattering.rgb, vec3(0.0)))) {
        // Leaving a walter scene's scattering medium: the reflected ray runs back through
        // it, gathering in-scattered light.
        march_deferred = true;
        march_defer_x = s.x;
        march_defer_d = ev.reflected;
        march_defer_w = s.t_f * exp(-s.alpha) * ev.R;
        march_defer_inside = inside;
        march_defer_surface = k;
        march_defer_prim = h.prim;
    } else
#endif
        march_add_reflection(s, ev.R, s.x, ev.reflected);
#if MARCH_RADIANCE && MARCH_LIGHTS
    // The lights' reflected radiance (eq. 5.6/5.8) with the surface's BRDF, in its slot
    // after the objects' (render.c fill_lights).
    s.L += s.t_f * exp(-s.alpha) * march_basic_radiance(n_from) *
           light_reflected(MAX_OBJECTS + k, s.x, s.d, h.shading, ev.R);
#endif
    s.t_f *= 1.0 - ev.R;
    s.d = ev.refracted;
    inside = next;
}

#include "march_bound.glsl"
#endif

// Traces a world ray through the scene. Statuses, exit point and direction, transmittance
// and optical path length follow docs/tracing.md; s.L holds the gathered radiance.
// inside: the set of surfaces whose solids contain the origin (MARCH_SURFACES).
march_state march_ray(vec3 origin, vec3 dir, uint inside)
{
    march_state s;
    s.x = origin;
    s.d = normalize(dir);
    s.t_f = 1.0;
    s.alpha = vec3(0.0);
    s.L = vec3(0.0);
    s.opl = 0.0;
    s.steps = 0;
    s.status = RAY_STATUS_RUNNING;
    s.crossed = false;
    s.events = 0;
    float ambient = params.settings_f.z;
    bool left_scene = false;
    // Each pass enters one object (or reflects off one face); the step budget bounds
    // the loop, the pass cap guards against a ray that reflects off faces forever.
    int max_passes = 4 * MAX_OBJECTS + 64;
#if MARCH_SURFACES
    max_passes += params.settings_i.y; // a surface event counts as a step
    int last_surface = march_start_surface, last_prim = march_start_prim;
    float min_throughput = params.settings_f3.x;
#endif
    for (int pass = 0; pass < max_passes && s.status == RAY_STATUS_RUNNING; pass++) {
        float t_world = 1e30;
        bool in_bounds = false;
        int axis = 0;
        float sgn = 1.0;
        int obj = -1;
#if MARCH_SURFACES
        int med = interface_medium(inside);
        if (med >= 0 && surfaces[med].attenuation.w >= 0.0) {
            // A field fills this medium: the ray equation up to the next surface.
            geom_hit hb;
            float n_in;
            int kb = march_through_bound(s, med, last_surface, last_prim, hb, n_in);
            if (kb < 0)
                break;
            march_surface_event(s, inside, kb, hb, n_in);
            last_surface = kb;
            last_prim = hb.prim;
            if (march_throughput(s) < min_throughput)
                s.status = RAY_STATUS_ABSORBED;
            continue;
        }
        // Voxel objects lie in the ambient medium, outside every surface.
        if (inside == 0u)
#endif
            obj = march_next_object(s, t_world, in_bounds, axis, sgn);
#if MARCH_SURFACES
        geom_hit h;
        int k = march_next_surface(s.x, s.d, last_surface, last_prim, obj >= 0 ? t_world : 1e30, h);
        if (k >= 0) {
            if (s.steps >= params.settings_i.y) {
                s.status = RAY_STATUS_MAX_STEPS;
                break;
            }
            march_surface_leg(s, interface_medium(inside), h.t);
            march_surface_event(s, inside, k, h, -1.0);
            last_surface = k;
            last_prim = h.prim;
            if (march_throughput(s) < min_throughput)
                s.status = RAY_STATUS_ABSORBED;
            continue;
        }
        last_surface = -1;
        if (obj < 0 && inside != 0u && surfaces[interface_medium(inside)].medium.w > 0.5) {
            // A solid that never ends (a half-space) whose extinction is positive in every
            // channel.
            s.alpha = vec3(1e30);
            s.status = RAY_STATUS_ABSORBED;
            break;
        }
#endif
        if (obj < 0) {
            left_scene = true;
            break;
        }
        s.x += s.d * t_world;
        s.opl += ambient * t_world;
        s.crossed = true;
        vec3 p = march_point_to_object(obj, s.x);
        vec3 q = march_dir_to_object(obj, s.d);
        if (!in_bounds) {
            float n_in = volume_sample_ior_grad(obj, p).a;
            if (!march_face(s, obj, p, q, march_axis_normal(axis, sgn), ambient, n_in)) {
                s.d = march_dir_to_world(obj, q); // reflected off the face, never entered
                continue;
            }
        }
        march_through_object(s, obj, p, q);
    }
    if (s.status == RAY_STATUS_RUNNING && !left_scene) {
        s.status = RAY_STATUS_MAX_STEPS; // the pass cap: a ray that keeps reflecting off faces
    } else if (s.status == RAY_STATUS_RUNNING) {
        s.status = s.crossed ? RAY_STATUS_EXITED : RAY_STATUS_MISSED;
#if MARCH_RADIANCE
        // The receiver plane where the ray hits it (MARCH_LIGHTS), else the background.
        s.L += s.t_f * exp(-s.alpha) * march_seen(s.x, s.d, !s.crossed && s.events == 0);
#endif
    }
    return s;
}
