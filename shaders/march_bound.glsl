// march_bound.glsl - the march through a field that fills an exact surface (docs/tracing.md
// "Fields inside surfaces"; the medium "object" form of docs/scenes.md): a GRIN lens bounded
// by its exact sphere. Included by ray_march.glsl in the MARCH_SURFACES variant, after the
// surface functions. Twin: server/core/reftrace_bound.c, step for step.
//
// Inside the surface the ray follows the ray equation through the bound object's field with
// the variant's stepper; each step's chord is tested against every surface and a step whose
// chord crosses one is cut there (secant on where the chord meets the surface, bisection
// when the secant leaves the bracket) until the chord's hit lies within 1e-6 of the step
// from the step's end, or float resolution where that is coarser. The event point is that
// hit, on the surface. Where n is constant (OBJECT_IOR_CONSTANT) steps are straight and the
// first cut is exact: only the integrals are stepped.

const float MARCH_CUT_REL = 1e-6; // the cut's residual relative to the step
const int MARCH_CUT_MAX_ITER = 40;

// One step of length h from (p, w), s0 = the sample at p. Returns the adaptive stepper's
// error estimate (object units), 0 otherwise.
float march_bound_step(int obj, vec4 s0, float h, float extent, vec3 p, vec3 w, out vec3 p1,
                       out vec3 w1)
{
    p1 = p;
    w1 = w;
    if ((params.objects[obj].resolution.w & OBJECT_IOR_CONSTANT) != 0) {
        p1 = p + h * normalize(w);
        return 0.0;
    }
#if MARCH_STEPPER == STEPPER_EULER
    ray_equation_step_euler(obj, s0, h, p1, w1);
#elif MARCH_STEPPER == STEPPER_RK2
    ray_equation_step_rk2(obj, s0, h, p1, w1);
#elif MARCH_STEPPER == STEPPER_ADAPTIVE
    return ray_equation_step_bs23(obj, s0, h, extent, p1, w1);
#else
    ray_equation_step_rk4(obj, s0, h, p1, w1);
#endif
    return 0.0;
}

// The first surface the world chord x0 -> x1 crosses (-1: none), the hit point and the
// chord's length.
int march_bound_chord(vec3 x0, vec3 x1, int last, int last_prim, out geom_hit hit,
                      out vec3 x_hit, out float len)
{
    vec3 c = x1 - x0;
    len = length(c);
    x_hit = x1;
    hit.t = 0.0;
    hit.normal = vec3(0.0);
    hit.shading = vec3(0.0);
    hit.prim = -1;
    if (!(len > 0.0))
        return -1;
    vec3 d = c / len;
    int k = march_next_surface(x0, d, last, last_prim, len, hit);
    if (k >= 0)
        x_hit = x0 + d * hit.t;
    return k;
}

// Trapezoid accumulation over p -> p1 (object space), as march_through_object.
void march_bound_accumulate(inout march_state s, int obj, float scale, vec3 p, vec4 s0,
                            vec3 sig0, vec3 p1, vec4 s1, vec3 sig1)
{
    float ds = length(p1 - p) * scale;
    s.opl += 0.5 * (s0.a + s1.a) * ds;
    s.alpha += 0.5 * (sig0 + sig1) * ds;
#if MARCH_RADIANCE && MARCH_EMISSION
    s.L += s.t_f * exp(-s.alpha) * march_basic_radiance(s1.a) * volume_sample_emission(obj, p1) *
           ds;
#endif
}

// n on the inside at the exit point p: the sample, except within half a voxel of the
// bounds, where the sample is clamped and |w| is the index the ray carries
// (docs/tracing.md "The rim").
float march_bound_exit_index(int obj, vec3 p, vec4 s_at_p, vec3 w)
{
    vec3 half_voxel = 0.5 / params.objects[obj].inv_voxel_size.xyz;
    vec3 bmin = params.objects[obj].bounds_min.xyz + half_voxel;
    vec3 bmax = params.objects[obj].bounds_max.xyz - half_voxel;
    if (any(lessThan(p, bmin)) || any(greaterThan(p, bmax)))
        return length(w);
    return s_at_p.a;
}

// A lower bound of the world distance from x to surface k (0 where the kind has none that
// is cheap: lathes and meshes). Exact for spheres, boxes, rounded boxes, cylinders and planes (the
// magnitudes of their signed distances in object space, times the scale).
float march_surface_distance(int k, vec3 x)
{
    int kind = surfaces[k].kind.x;
    vec3 p = (surfaces[k].object_from_world * vec4(x, 1.0)).xyz;
    vec4 a = surfaces[k].shape0, b = surfaces[k].shape1;
    float d = 0.0;
    if (kind == GEOM_SPHERE) {
        d = abs(length(p - a.xyz) - a.w);
    } else if (kind == GEOM_BOX) {
        vec3 q = abs(p - a.xyz) - 0.5 * b.xyz;
        d = abs(min(max(q.x, max(q.y, q.z)), 0.0) + length(max(q, vec3(0.0))));
    } else if (kind == GEOM_ROUNDED_BOX) { // the box's distance, less the rounding radius
        vec3 q = abs(p - a.xyz) - (0.5 * b.xyz - vec3(a.w));
        d = abs(min(max(q.x, max(q.y, q.z)), 0.0) + length(max(q, vec3(0.0))) - a.w);
    } else if (kind == GEOM_CYLINDER) {
        vec3 rel = p - a.xyz;
        int axis = surfaces[k].kind.y;
        float along = rel[axis];
        rel[axis] = 0.0;
        vec2 q = vec2(length(rel) - a.w, abs(along) - 0.5 * b.x);
        d = abs(min(max(q.x, q.y), 0.0) + length(max(q, vec2(0.0))));
    } else if (kind == GEOM_PLANE) {
        d = abs(dot(p - a.xyz, b.xyz));
    }
    return d * surfaces[k].medium.y;
}

// The radius of a ball about x that no surface enters: the smallest distance, less a
// float margin (a few ulps of the coordinates).
float march_safe_radius(vec3 x)
{
    float r = 1e30;
    for (int k = 0; k < params.surfaces.x; k++)
        r = min(r, march_surface_distance(k, x));
    vec3 ax = abs(x);
    return max(r - 1e-5 * (1.0 + max(ax.x, max(ax.y, ax.z))), 0.0);
}

// Marches through the field filling surface `med` from s.x along s.d. Returns the surface
// crossed (hit, s.x on it, s.d the direction there, n_in the index on the inside), or -1
// when the ray stopped (s.status set).
int march_through_bound(inout march_state s, int med, int last, int last_prim, out geom_hit hit,
                        out float n_in)
{
    int obj = int(surfaces[med].attenuation.w);
    float scale = march_object_scale(obj);
    float h_min = params.objects[obj].bounds_max.w;
    float h_max = params.settings_f.x * h_min;
    float h = h_max;
    float extent = 0.0;
#if MARCH_STEPPER == STEPPER_ADAPTIVE
    bool adaptive = (params.objects[obj].resolution.w & OBJECT_IOR_CONSTANT) == 0;
    float tol = params.settings_f2.x * h_min;
    vec3 extent3 = params.objects[obj].bounds_max.xyz - params.objects[obj].bounds_min.xyz;
    extent = max(extent3.x, max(extent3.y, extent3.z));
#endif
    float min_throughput = params.settings_f3.x;
    int max_steps = params.settings_i.y;
    vec3 p = march_point_to_object(obj, s.x);
    vec4 s0 = volume_sample_ior_grad(obj, p);
    vec3 sig0 = volume_sample_extinction(obj, p);
    vec3 w = s0.a * march_dir_to_object(obj, s.d);
    s.crossed = true;
    n_in = s0.a;
    hit.t = 0.0;
    hit.normal = vec3(0.0);
    hit.shading = vec3(0.0);
    hit.prim = -1;
    // The safe ball (march_safe_radius): while a step ends inside it, its chord, which the
    // ball contains, crosses no surface, and the inner loop only steps and accumulates. A
    // step that ends outside it breaks out for the chord test against every surface, which
    // costs several times a step on llvmpipe (code in a branch of the inner loop costs every
    // lane every step even when no lane takes it, as march_through_object notes). The chord
    // test's answer is the same either way, so this is the GPU's alone; the CPU twin tests
    // every chord.
    vec3 ball_c = s.x;
    float ball_r = 0.0; // on the surface entered by: the first step is tested
    int k = -1;
    float hs = h, len = 0.0;
    vec3 w1 = w, x_hit = s.x;
    while (s.status == RAY_STATUS_RUNNING) {
        bool test = false;
        vec3 p1 = p, x1 = s.x;
        for (;;) {
            if (s.steps >= max_steps) {
                s.status = RAY_STATUS_MAX_STEPS;
                break;
            }
            hs = h;
            float err = march_bound_step(obj, s0, hs, extent, p, w, p1, w1);
            s.steps++; // a rejected attempt counts against the budget too
#if MARCH_STEPPER == STEPPER_ADAPTIVE
            if (adaptive) {
                h = ray_equation_next_step(hs, err, tol, h_max);
                if (err > tol && hs > RAY_BS23_FLOOR * h_max * 1.0001)
                    continue;
            }
#endif
            x1 = march_point_to_world(obj, p1);
            if (distance(x1, ball_c) >= ball_r) {
                test = true;
                break;
            }
            vec4 s1 = volume_sample_ior_grad(obj, p1);
            vec3 sig1 = volume_sample_extinction(obj, p1);
            march_bound_accumulate(s, obj, scale, p, s0, sig0, p1, s1, sig1);
            p = p1;
            w = w1;
            s0 = s1;
            sig0 = sig1;
            s.x = x1;
            if (march_throughput(s) < min_throughput) {
                s.status = RAY_STATUS_ABSORBED;
                break;
            }
        }
        if (!test)
            break;
        k = march_bound_chord(s.x, x1, last, last_prim, hit, x_hit, len);
        if (k >= 0)
            break;
        vec4 s1 = volume_sample_ior_grad(obj, p1);
        vec3 sig1 = volume_sample_extinction(obj, p1);
        march_bound_accumulate(s, obj, scale, p, s0, sig0, p1, s1, sig1);
        p = p1;
        w = w1;
        s0 = s1;
        sig0 = sig1;
        s.x = x1;
        last = -1; // away from the surface entered by: any crossing now is a real one
        ball_c = x1;
        ball_r = march_safe_radius(x1);
        if (march_throughput(s) < min_throughput)
            s.status = RAY_STATUS_ABSORBED;
    }
    if (k < 0) {
        s.d = march_dir_to_world(obj, normalize(w));
        return -1;
    }
    // The cut: shorten the step until its chord's hit is at the step's end.
    float lo = 0.0, hi = hs;
    float c_hi = hit.t / len, gap = len - hit.t;
    vec3 w_end = w1;
    vec3 ax = abs(s.x);
    float tol_cut =
        max(MARCH_CUT_REL * hs * scale, 4.0 * 1.2e-7 * (1.0 + max(ax.x, max(ax.y, ax.z))));
    bool bisect = false;
    for (int it = 0; it < MARCH_CUT_MAX_ITER && gap > tol_cut && hi - lo > 1e-7 * hs; it++) {
        float sm = bisect ? 0.5 * (lo + hi) : hi * c_hi;
        if (!(sm > lo && sm < hi))
            sm = 0.5 * (lo + hi);
        vec3 pm, wm;
        march_bound_step(obj, s0, sm, extent, p, w, pm, wm);
        geom_hit hm;
        vec3 xm;
        float lm;
        int km = march_bound_chord(s.x, march_point_to_world(obj, pm), last, last_prim, hm, xm, lm);
        float before = hi - lo;
        if (km >= 0) {
            hi = sm;
            k = km;
            hit = hm;
            x_hit = xm;
            c_hi = hm.t / lm;
            gap = lm - hm.t;
            w_end = wm;
        } else {
            lo = sm;
        }
        bisect = hi - lo > 0.5 * before;
    }
    vec3 p_end = march_point_to_object(obj, x_hit);
    vec4 s1 = volume_sample_ior_grad(obj, p_end);
    march_bound_accumulate(s, obj, scale, p, s0, sig0, p_end, s1,
                           volume_sample_extinction(obj, p_end));
    n_in = march_bound_exit_index(obj, p_end, s1, w_end);
    s.x = x_hit;
    s.d = march_dir_to_world(obj, normalize(w_end));
    return k;
}
