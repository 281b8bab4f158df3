// environment.glsl - the background at infinity, L_bg of tevs2007 eq. 5.3. The procedural
// sky/ground is the twin of env_procedural in server/core/env.c; docs/tracing.md
// "Environment" fixes every constant. Needs march_params `params` and the sampler
// `environment_map` declared by the including kernel.

const vec3 ENV_HORIZON = vec3(0.85, 0.90, 1.00);
const vec3 ENV_ZENITH = vec3(0.20, 0.40, 0.85);
const vec3 ENV_CHECK_LIGHT = vec3(0.80, 0.78, 0.74);
const vec3 ENV_CHECK_DARK = vec3(0.12, 0.12, 0.15);
const vec3 ENV_HAZE = vec3(0.45, 0.45, 0.48);

float environment_smoothstep(float e0, float e1, float x)
{
    float t = clamp((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

vec3 environment_procedural(vec3 d)
{
    if (d.y >= 0.0) {
        vec3 sky = mix(ENV_HORIZON, ENV_ZENITH, sqrt(d.y));
        float elev = degrees(asin(clamp(d.y, -1.0, 1.0)));
        // atan(0, 0) is undefined in GLSL: the zenith gets azimuth 0, as in env.c.
        float azim = (d.x == 0.0 && d.z == 0.0) ? 0.0 : degrees(atan(d.x, -d.z));
        float de = abs(elev - 15.0 * floor(elev / 15.0 + 0.5));
        float da = abs(azim - 15.0 * floor(azim / 15.0 + 0.5)) * cos(radians(elev));
        float line = 1.0 - environment_smoothstep(0.25, 0.75, min(de, da));
        return sky * (1.0 - 0.25 * line);
    }
    if (d.y > -1e-6)
        return ENV_HAZE;
    vec2 P = d.xz / -d.y;
    vec2 f = P - floor(P);
    float edge = min(min(f.x, 1.0 - f.x), min(f.y, 1.0 - f.y));
    float parity = mod(floor(P.x) + floor(P.y), 2.0);
    vec3 c = parity < 0.5 ? ENV_CHECK_LIGHT : ENV_CHECK_DARK;
    c = mix(0.5 * (ENV_CHECK_LIGHT + ENV_CHECK_DARK), c, environment_smoothstep(0.0, 0.04, edge));
    float haze = 1.0 - exp(-length(P) / 25.0);
    return mix(c, ENV_HAZE, haze);
}

vec3 environment_radiance(vec3 d)
{
    vec3 L;
    if (params.settings_i.w == 1) {
        const float PI = 3.14159265358979;
        float u = 0.5 + atan(d.x, -d.z) / (2.0 * PI) + params.env.x / 360.0;
        float v = acos(clamp(d.y, -1.0, 1.0)) / PI;
        L = textureLod(environment_map, vec2(u, v), 0.0).rgb;
    } else {
        L = environment_procedural(d);
    }
    return L * params.settings_f.w;
}
