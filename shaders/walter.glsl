// walter.glsl - exact single scattering through a sphere (walter2009; docs/walter.md): the
// refracted paths light -> P -> V through the sphere's boundary, found by the same 1D
// search as server/core/walter.c (its twin: the same names, brackets and formulas, in
// float). Needs fresnel_unpolarized (fresnel.glsl).

#define WALTER_SPHERE_BRACKETS 48

struct walter_normal {
    vec3 m, dm_a, dm_b, g_a, g_b, N_g;
};

struct walter_path {
    vec3 P, N, omega_V, omega_L;
    float d_V, d_L, T, D, gain;
};

// The derivative of u / |u| along u' (walter2009 eq. 10).
vec3 walter_unit_deriv(vec3 u, vec3 du)
{
    float l2 = dot(u, u);
    return (du * l2 - u * dot(u, du)) / (l2 * sqrt(l2));
}

// The spread D of the path (eq. 19-26; walter.h walter_spread).
float walter_spread(vec3 V, vec3 L, bool at_infinity, vec3 P, float eta, walter_normal nrm)
{
    vec3 dv = V - P;
    float d_V = length(dv);
    if (!(d_V > 0.0))
        return 0.0;
    vec3 u = dv / d_V;
    vec3 wL;
    float d_L = 0.0;
    if (at_infinity) {
        wL = -L;
    } else {
        d_L = length(L - P);
        if (!(d_L > 0.0))
            return 0.0;
        wL = (L - P) / d_L;
    }
    vec3 N = normalize(nrm.m);
    float c = dot(u, N), cos_L = dot(wL, N), ug = dot(u, nrm.N_g);
    if (!(c < 0.0) || !(cos_L > 0.0) || abs(ug) < 1e-30)
        return 0.0;
    float mu = cos_L + eta * c;
    vec3 a = abs(u.x) < 0.6 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
    vec3 e0 = normalize(a - u * dot(a, u));
    vec3 e1 = cross(u, e0);
    vec3 Lp[2];
    for (int k = 0; k < 2; k++) {
        vec3 du = k == 0 ? e0 : e1;
        vec3 Pp = -d_V * (du - u * (dot(du, nrm.N_g) / ug));
        vec3 mp = nrm.dm_a * dot(nrm.g_a, Pp) + nrm.dm_b * dot(nrm.g_b, Pp);
        vec3 Np = walter_unit_deriv(nrm.m, mp);
        float cp = dot(du, N) + dot(u, Np);
        float mup = cp * (eta + eta * eta * c / cos_L);
        vec3 wLp = N * mup + Np * mu - du * eta;
        Lp[k] = at_infinity ? wLp : Pp - wL * dot(Pp, wL) + wLp * d_L;
    }
    return length(cross(Lp[0], Lp[1]));
}

// A path's T, D and gain eta^2 T / D (walter.h walter_path_finish).
bool walter_path_finish(inout walter_path p, vec3 V, vec3 L, bool at_infinity, float eta,
                        walter_normal nrm)
{
    vec3 dv = V - p.P;
    p.d_V = length(dv);
    if (!(p.d_V > 0.0))
        return false;
    p.omega_V = dv / p.d_V;
    if (at_infinity) {
        p.omega_L = -L;
        p.d_L = 1e30;
    } else {
        p.d_L = length(L - p.P);
        if (!(p.d_L > 0.0))
            return false;
        p.omega_L = (L - p.P) / p.d_L;
    }
    p.N = normalize(nrm.m);
    float cos_L = dot(p.omega_L, p.N);
    if (!(dot(p.omega_V, nrm.N_g) <= 0.0) || !(dot(p.omega_L, nrm.N_g) >= 0.0) ||
        !(cos_L > 0.0) || !(dot(p.omega_V, p.N) < 0.0))
        return false;
    p.T = 1.0 - fresnel_unpolarized(cos_L, 1.0, eta);
    p.D = walter_spread(V, L, at_infinity, p.P, eta, nrm);
    if (!(p.T > 0.0) || !(p.D > 0.0) || isinf(p.D))
        return false;
    p.gain = eta * eta * p.T / p.D;
    return true;
}

// The sphere's search plane: P(theta) = c + R (cos theta e1 + sin theta e2), e1 toward the
// light.
struct walter_sphere_plane {
    vec3 c, e1, e2, L, V;
    float R, eta;
    bool at_infinity;
};

vec3 walter_sphere_point(walter_sphere_plane s, float th, out vec3 N, out vec3 tg)
{
    float ct = cos(th), st = sin(th);
    N = s.e1 * ct + s.e2 * st;
    tg = -s.e1 * st + s.e2 * ct;
    return s.c + N * s.R;
}

// The tangential condition g(theta) and its derivative (walter.c sphere_g).
float walter_sphere_g(walter_sphere_plane s, float th, out float dg)
{
    vec3 N, tg;
    vec3 P = walter_sphere_point(s, th, N, tg);
    vec3 u = s.V - P, w = s.L - P;
    vec3 wV = normalize(u);
    vec3 wL = s.at_infinity ? -s.L : normalize(w);
    vec3 h = wL + wV * s.eta;
    vec3 Pp = tg * s.R;
    vec3 hp = walter_unit_deriv(u, -Pp) * s.eta;
    if (!s.at_infinity)
        hp += walter_unit_deriv(w, -Pp);
    dg = dot(hp, tg) - dot(h, N);
    return dot(h, tg);
}

// The root in [a, b] (g(a) = ga and g(b) of opposite signs): Newton kept in the bracket.
float walter_sphere_root(walter_sphere_plane s, float a, float b, float ga)
{
    float x = 0.5 * (a + b);
    for (int it = 0; it < 40; it++) {
        if (b - a <= 1e-6 * max(1.0, abs(x)))
            break;
        float dg;
        float g = walter_sphere_g(s, x, dg);
        if (g == 0.0)
            return x;
        if ((g < 0.0) == (ga < 0.0)) {
            a = x;
            ga = g;
        } else {
            b = x;
        }
        float xn = dg != 0.0 ? x - g / dg : 0.5 * (a + b);
        x = xn > a && xn < b ? xn : 0.5 * (a + b);
    }
    return x;
}

// The path at theta, when valid (walter.c sphere_add without the merge of a root found
// twice on a bracket's end, which float makes improbable).
bool walter_sphere_path(walter_sphere_plane s, float th, out walter_path p)
{
    vec3 N, tg;
    p.P = walter_sphere_point(s, th, N, tg);
    vec3 b2 = cross(s.e1, s.e2);
    walter_normal nrm = walter_normal(N * s.R, tg, b2, tg, b2, N);
    return walter_path_finish(p, s.V, s.L, s.at_infinity, s.eta, nrm);
}

// The light a unit light (intensity 1, or irradiance 1 for a directional one) scatters
// toward -d at V per unit sigma_s: sum over the paths of p_HG(g, omega_V . -d) gain
// exp(-sigma_t d_V) (walter2009 eq. 17 with the phase function; walter.c
// walter_sphere_paths' search, the sum of reftrace_light.c's walter case). spot_dir,
// cos_spot: a spot light's cone (cos_spot <= -1: none).
vec3 walter_sphere_inscatter(vec3 c, float R, float eta, vec3 L, bool at_infinity, vec3 V,
                             vec3 d, float g, vec3 sigma_t, vec3 spot_dir, float cos_spot)
{
    walter_sphere_plane s;
    s.c = c;
    s.R = R;
    s.eta = eta;
    s.L = L;
    s.V = V;
    s.at_infinity = at_infinity;
    vec3 toward = at_infinity ? -L : L - c;
    float dl = length(toward);
    if (!(dl > 0.0) || (!at_infinity && dl <= R) || length(V - c) >= R)
        return vec3(0.0);
    s.e1 = toward / dl;
    vec3 b = V - c;
    vec3 bp = b - s.e1 * dot(b, s.e1);
    float bl = length(bp);
    vec3 sum = vec3(0.0);
    walter_path p;
    if (bl < 1e-6 * R) {
        vec3 a = abs(s.e1.x) < 0.6 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
        s.e2 = normalize(a - s.e1 * dot(a, s.e1));
        if (walter_sphere_path(s, 0.0, p) && dot(-p.omega_L, spot_dir) >= cos_spot)
            sum += phase_hg(g, dot(p.omega_V, -d)) * p.gain * exp(-sigma_t * p.d_V);
        return sum;
    }
    s.e2 = bp / bl;
    float th_max = at_infinity ? 0.5 * LIGHT_PI : acos(R / dl);
    float h = 2.0 * th_max / float(WALTER_SPHERE_BRACKETS);
    float d0;
    float t0 = -th_max;
    float g0 = walter_sphere_g(s, t0, d0);
    for (int i = 1; i <= WALTER_SPHERE_BRACKETS; i++) {
        float t1 = -th_max + float(i) * h, d1;
        float g1 = walter_sphere_g(s, t1, d1);
        float roots[2];
        int n = 0;
        if (g0 == 0.0) {
            roots[n++] = t0;
        } else if ((g0 < 0.0) != (g1 < 0.0) && g1 != 0.0) {
            roots[n++] = walter_sphere_root(s, t0, t1, g0);
        } else if (g0 * d0 < 0.0 && g1 * d1 > 0.0) {
            // a minimum of |g| inside the bracket that may cross zero
            float a = t0, bb = t1, da = d0;
            for (int it = 0; it < 24; it++) {
                float m = 0.5 * (a + bb), dm;
                walter_sphere_g(s, m, dm);
                if ((dm < 0.0) == (da < 0.0)) {
                    a = m;
                    da = dm;
                } else {
                    bb = m;
                }
            }
            float tm = 0.5 * (a + bb), dm;
            float gm = walter_sphere_g(s, tm, dm);
            if ((gm < 0.0) != (g0 < 0.0)) {
                roots[n++] = walter_sphere_root(s, t0, tm, g0);
                roots[n++] = walter_sphere_root(s, tm, t1, gm);
            }
        }
        for (int k = 0; k < n; k++) {
            if (walter_sphere_path(s, roots[k], p) && dot(-p.omega_L, spot_dir) >= cos_spot)
                sum += phase_hg(g, dot(p.omega_V, -d)) * p.gain * exp(-sigma_t * p.d_V);
        }
        t0 = t1;
        g0 = g1;
        d0 = d1;
    }
    return sum;
}
