// lighting.glsl - the light-dependent terms of the image formation model (tevs2007 eqs.
// 5.4-5.8): the Henyey-Greenstein phase function, the BRDFs of boundary reflections, the
// lookup of a light's irradiance E and direction l at a world point (irradiance volumes,
// or the unshadowed direct light in scenes that need no light simulation), and the
// receiver plane (thesis fig. 7.4). The double twins are server/core/phase.c, brdf.c
// and reftrace_light.c; docs/tracing.md "Light" fixes every formula. Needs march_params
// `params`, the march_lights block `lights` and the samplers irradiance_volume[],
// light_direction_volume[] (march_bindings.glsl).

const float LIGHT_PI = 3.14159265358979;

// Henyey-Greenstein (tevs2007 eq. 5.5), normalised over the sphere: 1 / (4 pi) at g = 0.
// cos_theta is between the light's travel direction and the scattered direction.
float phase_hg(float g, float cos_theta)
{
    float d = 1.0 + g * g - 2.0 * g * cos_theta;
    return (1.0 - g * g) / (4.0 * LIGHT_PI * d * sqrt(d));
}

#include "walter.glsl"

// Smith's separable masking term G1 for GGX with a2 = alpha^2 at cosine c (brdf.c's twin).
float brdf_smith_g1(float a2, float c)
{
    return 2.0 * c / (c + sqrt(a2 + (1.0 - a2) * c * c));
}

// f_r(v, l_in) for unit v (towards the eye), l_in (towards the light) and normal n on their
// side (tevs2007 eq. 5.6/5.8). The event's Fresnel R multiplies outside; GGX has no F.
vec3 brdf_eval(int obj, vec3 v, vec3 l_in, vec3 n)
{
    vec4 b = lights.brdf[obj];
    vec3 color = lights.brdf_color[obj].rgb;
    int kind = int(b.x);
    float cos_i = dot(n, l_in), cos_o = dot(n, v);
    if (kind == BRDF_NONE || cos_i <= 0.0 || cos_o <= 0.0)
        return vec3(0.0);
    if (kind == BRDF_LAMBERT)
        return color / LIGHT_PI;
    if (kind == BRDF_PHONG) {
        // Normalised Phong: (e + 2) / (2 pi) cos^e of the angle between v and the mirror
        // direction of the light.
        float c = max(dot(reflect(-l_in, n), v), 0.0);
        return color * (b.z + 2.0) / (2.0 * LIGHT_PI) * pow(c, b.z);
    }
    // GGX (Trowbridge-Reitz) D with the separable Smith G, D G / (4 cos_i cos_o).
    float a2 = b.y * b.y;
    vec3 h = normalize(v + l_in);
    float ch = max(dot(n, h), 0.0);
    float t = ch * ch * (a2 - 1.0) + 1.0;
    float D = a2 / (LIGHT_PI * t * t);
    return color * D * brdf_smith_g1(a2, cos_i) * brdf_smith_g1(a2, cos_o) / (4.0 * cos_i * cos_o);
}

vec4 light_sample_irradiance(int j, vec3 u)
{
    if (j == 0)
        return textureLod(irradiance_volume0, u, 0.0);
    if (j == 1)
        return textureLod(irradiance_volume1, u, 0.0);
    if (j == 2)
        return textureLod(irradiance_volume2, u, 0.0);
    return textureLod(irradiance_volume3, u, 0.0);
}

vec4 light_sample_direction(int j, vec3 u)
{
    if (j == 0)
        return textureLod(light_direction_volume0, u, 0.0);
    if (j == 1)
        return textureLod(light_direction_volume1, u, 0.0);
    if (j == 2)
        return textureLod(light_direction_volume2, u, 0.0);
    return textureLod(light_direction_volume3, u, 0.0);
}

// The light's unshadowed direct E (times its scale) and travel direction l at world x,
// whatever its mode: directional E = 1 along its direction; point and spot 1 / r^2 (radiant
// intensity 1 per steradian), the spot inside its cone only. Returns false when it adds
// nothing. The twin is reftrace_light_direct.
bool light_direct(int j, vec3 x, out vec3 E, out vec3 l)
{
    E = vec3(0.0);
    l = vec3(0.0, -1.0, 0.0);
    light_params lp = lights.lights[j];
    int kind = int(lp.position.w);
    if (kind == LIGHT_KIND_DIRECTIONAL) {
        l = lp.direction.xyz;
        E = lp.scale.rgb;
        return true;
    }
    vec3 r = x - lp.position.xyz;
    float r2 = dot(r, r);
    if (r2 <= 1e-12)
        return false;
    l = r / sqrt(r2);
    if (kind == LIGHT_KIND_SPOT && dot(l, lp.direction.xyz) < lp.direction.w)
        return false;
    E = lp.scale.rgb / r2;
    return true;
}

// Irradiance E (unit light, times the light's scale) and the direction l the light travels
// at world point x, for light j. Returns false when the light adds nothing there.
// Volumes: trilinear at v = (x - bmin) / voxel - 0.5, clamped to the grid's edge; outside
// the grid (x not in [bmin, bmin + dims voxel]) E = 0. The direction's xyz is normalised
// after interpolation.
bool light_at(int j, vec3 x, out vec3 E, out vec3 l)
{
    E = vec3(0.0);
    l = vec3(0.0, -1.0, 0.0);
    light_params lp = lights.lights[j];
    int mode = int(lp.scale.w);
    if (mode == LIGHT_MODE_OFF)
        return false;
    if (mode == LIGHT_MODE_VOLUME) {
        vec3 u = (x - lp.grid_min.xyz) / lp.grid_size.xyz;
        if (any(lessThan(u, vec3(0.0))) || any(greaterThan(u, vec3(1.0))))
            return false;
        vec3 d = light_sample_direction(j, u).xyz;
        float dl = length(d);
        if (dl <= 1e-6)
            return false;
        l = d / dl;
        E = light_sample_irradiance(j, u).rgb * lp.scale.rgb;
        return true;
    }
    // Unshadowed direct light (scenes without light simulation; LIGHT_MODE_WALTER outside
    // its in-scattering).
    return light_direct(j, x, E, l);
}

// Reflected light of the lights at a Fresnel event (the delta(x) R L_r term of eq. 5.4):
// sum_j f_r(v, -l_j, N) max(0, dot(N, -l_j)) E_j(x) with N facing the viewer (v = -d),
// times R. The caller multiplies by T_f exp(-alpha) and the basic radiance factor.
vec3 light_reflected(int obj, vec3 x, vec3 d, vec3 N, float R)
{
    vec3 v = -d;
    vec3 n = dot(N, v) < 0.0 ? -N : N;
    vec3 sum = vec3(0.0);
    for (int j = 0; j < MAX_LIGHTS; j++) {
        if (j >= lights.count.x)
            break;
        vec3 E, l;
        if (!light_at(j, x, E, l))
            continue;
        float c = dot(n, -l);
        if (c <= 0.0)
            continue;
        sum += brdf_eval(obj, v, -l, n) * c * E;
    }
    return R * sum;
}

// In-scattered radiance per unit length at x for view direction d (eq. 5.5 without the
// transmittance): sigma_s sum_j p_HG(g, dot(l_j, -d)) E_j(x).
// LIGHT_MODE_WALTER (lights.count.w = 1): the light reaches x, inside the sphere
// lights.walter_sphere, by the exact refracted paths of walter2009 (walter.glsl); a light
// inside the sphere shines on x straight, attenuated over the distance.
vec3 light_inscatter(vec3 x, vec3 d, vec3 sigma_s, float g)
{
    vec3 sum = vec3(0.0);
    for (int j = 0; j < MAX_LIGHTS; j++) {
        if (j >= lights.count.x)
            break;
        light_params lp = lights.lights[j];
        if (int(lp.scale.w) == LIGHT_MODE_WALTER) {
            int kind = int(lp.position.w);
            bool at_infinity = kind == LIGHT_KIND_DIRECTIONAL;
            vec3 c = lights.walter_sphere.xyz;
            float R = lights.walter_sphere.w;
            vec3 sigma_t = lights.walter_medium.rgb;
            if (!at_infinity && length(lp.position.xyz - c) < R) {
                vec3 E, l;
                if (light_direct(j, x, E, l))
                    sum += phase_hg(g, dot(l, -d)) * E *
                           exp(-sigma_t * length(x - lp.position.xyz));
                continue;
            }
            float cos_spot = kind == LIGHT_KIND_SPOT ? lp.direction.w : -2.0;
            sum += lp.scale.rgb *
                   walter_sphere_inscatter(c, R, lights.walter_medium.w,
                                           at_infinity ? lp.direction.xyz : lp.position.xyz,
                                           at_infinity, x, d, g, sigma_t, lp.direction.xyz,
                                           cos_spot);
            continue;
        }
        vec3 E, l;
        if (light_at(j, x, E, l))
            sum += phase_hg(g, dot(l, -d)) * E;
    }
    return sigma_s * sum;
}

// The step of in-scattering along a surface medium's segment (medium_step.glsl): half the
// smallest voxel of the lights' irradiance volumes, where trilinear irradiance is sampled
// finely enough; 0 where no light has a volume (direct lights: MEDIUM_DIRECT_STEPS).
float light_inscatter_step()
{
    float voxel = 0.0;
    for (int j = 0; j < MAX_LIGHTS; j++) {
        if (j >= lights.count.x)
            break;
        float v = lights.lights[j].grid_min.w;
        if (int(lights.lights[j].scale.w) == LIGHT_MODE_VOLUME && v > 0.0)
            voxel = voxel > 0.0 ? min(voxel, v) : v;
    }
    return 0.5 * voxel;
}

#if MARCH_SURFACES && MARCH_LIGHTS
// The "photons" caustics mode (lights.count.z = 1; shaders/photons.glsl, after the surfaces).
vec3 photon_irradiance(int light, vec2 xz);
bool photon_light_visible(int j, vec3 at);
#endif

// The receiver plane y = height, |x - cx|, |z - cz| <= half_size (half_size <= 0: the
// whole plane; thesis fig. 7.4), seen by a ray that has left the scene at x going d.
// Returns true with its radiance when hit:
// (albedo / pi) sum_j E_j(hit) max(0, -l_j.y) + albedo env(0, 1, 0), the last a simple
// ambient term (the environment's zenith radiance). E is read on the plane itself, between
// the voxel layers half a voxel above and below it: the light grid reaches two voxels
// below the plane and the wavefront passes through it (docs/lightsim.md "Domain"), so the
// deposit kernel there is whole. A light's volume covers the objects' footprint on the
// plane as that light sees it: at least LIGHT_RECEIVER_INSET voxels inside its grid's x
// and z faces (the pad and a margin) the volume is read, elsewhere the light's closed
// form (light_direct), as no object can shade the plane there. In the "photons" caustics
// mode (lights.count.z = 1, docs/photons.md) each light's unshadowed direct light counts
// where no optical surface is in the way (photon_light_visible), and its photon map's
// irradiance photon_irradiance (unit light, the cosine already in it) times its scale.
bool light_receiver(vec3 x, vec3 d, out vec3 L)
{
    L = vec3(0.0);
    if (lights.count.y == 0 || d.y >= 0.0)
        return false;
    float height = lights.receiver.x, half_size = lights.receiver.y;
    vec2 center = lights.receiver.zw;
    float t = (height - x.y) / d.y;
    if (t < 0.0)
        return false;
    vec3 hit = x + t * d;
    if (half_size > 0.0 &&
        (abs(hit.x - center.x) > half_size || abs(hit.z - center.y) > half_size))
        return false;
    vec3 albedo = lights.receiver_albedo.rgb;
    vec3 sum = vec3(0.0);
    vec3 at = vec3(hit.x, height, hit.z);
    for (int j = 0; j < MAX_LIGHTS; j++) {
        if (j >= lights.count.x)
            break;
        vec3 E, l;
        bool lit;
        light_params lp = lights.lights[j];
#if MARCH_SURFACES && MARCH_LIGHTS
        if (lights.count.z == 1) {
            lit = light_direct(j, at, E, l) && photon_light_visible(j, at);
            sum += lp.scale.rgb * photon_irradiance(j, at.xz);
        } else
#endif
            if (int(lp.scale.w) == LIGHT_MODE_VOLUME) {
            vec2 u = (at.xz - lp.grid_min.xz) / lp.grid_min.w;
            vec2 dims = lp.grid_size.xz / lp.grid_min.w;
            bool in_grid = all(greaterThanEqual(u, vec2(LIGHT_RECEIVER_INSET))) &&
                           all(lessThanEqual(u, dims - LIGHT_RECEIVER_INSET));
            lit = in_grid ? light_at(j, at, E, l) : light_direct(j, at, E, l);
        } else {
            lit = light_at(j, at, E, l);
        }
        if (lit)
            sum += E * max(0.0, -l.y);
    }
    L = albedo / LIGHT_PI * sum + albedo * environment_radiance(vec3(0.0, 1.0, 0.0));
    return true;
}

// The nearest lamp a ray leaving the scene at x along unit d meets before t_max: true with
// its radiance scale / (pi r^2), the radiance of the path tracer's spherical emitter of the
// same far-field intensity (docs/pathtracer.md "Lights"). Point lights whose radius r > 0
// (grid_size.w: r, or -r when hidden from the camera) only; primary: the ray has met
// nothing yet, so hidden lamps are skipped (docs/tracing.md "Lamps"). Twin of
// reftrace_light_emitter.
bool light_emitter(vec3 x, vec3 d, float t_max, bool primary, out vec3 L)
{
    L = vec3(0.0);
    bool hit = false;
    for (int j = 0; j < MAX_LIGHTS; j++) {
        if (j >= lights.count.x)
            break;
        light_params lp = lights.lights[j];
        float rs = lp.grid_size.w, r = abs(rs);
        if (int(lp.position.w) != LIGHT_KIND_POINT || !(r > 0.0) || (primary && rs < 0.0))
            continue;
        vec3 oc = x - lp.position.xyz;
        float b = dot(oc, d), c = dot(oc, oc) - r * r, disc = b * b - c;
        if (disc < 0.0)
            continue;
        float sq = sqrt(disc), t = -b - sq;
        if (t < 0.0)
            t = -b + sq; // x inside the lamp: its far side
        if (!(t > 0.0) || t >= t_max)
            continue;
        t_max = t;
        L = lp.scale.rgb / (LIGHT_PI * r * r);
        hit = true;
    }
    return hit;
}
