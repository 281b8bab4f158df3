/*
 * env.c - the procedural environment at infinity (tevs2007 eq. 5.3's L_bg), the
 * equirectangular lookup coordinates and the pinhole camera, in double precision.
 *
 * shaders/environment.glsl and shaders/camera.glsl are written from the same text
 * (docs/tracing.md "Camera" and "Environment") and compared pixel by pixel, so every
 * formula here is written the way GLSL would write it: smoothstep, mix, floor-based
 * rounding and mod, no library function GLSL lacks. Keep the two in step.
 *
 * Not here: image environments (the bilinear equirect fetch belongs to whoever owns the
 * image) and the environment intensity (callers multiply).
 */
#include "env.h"

#include <math.h>

#define DEG_PER_RAD (180.0 / M_PI)

/* GLSL clamp, smoothstep and mix, spelled out so the twin is obvious. */
static double clampd(double x, double lo, double hi)
{
    return fmin(fmax(x, lo), hi);
}

static double smoothstep(double e0, double e1, double x)
{
    double t = clampd((x - e0) / (e1 - e0), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

static vec3 mix3(vec3 a, vec3 b, double t)
{
    return vec3_add(vec3_scale(a, 1.0 - t), vec3_scale(b, t));
}

/* Distance from x to the nearest multiple of `period` (GLSL: abs(x - p*floor(x/p+0.5))). */
static double dist_to_multiple(double x, double period)
{
    return fabs(x - period * floor(x / period + 0.5));
}

/* Sky, d.y >= 0: mix(horizon, zenith, sqrt(d.y)), darkened to 75 % on grid lines every
 * 15 degrees. Distances are angles along the sky in degrees: the elevation distance is
 * |el - nearest multiple of 15|; the azimuth distance is the azimuth difference times
 * cos(el), the length of the arc along the circle of constant elevation, so lines keep
 * their width on the sky and converge at the zenith. At d.x = d.z = 0 (where atan2 is
 * undefined in GLSL) the azimuth is taken as 0. */
static vec3 sky(vec3 d)
{
    const vec3 horizon = {0.85, 0.90, 1.00};
    const vec3 zenith = {0.20, 0.40, 0.85};
    vec3 base = mix3(horizon, zenith, sqrt(d.y));

    double el_deg = asin(clampd(d.y, -1.0, 1.0)) * DEG_PER_RAD; /* [0, 90] */
    double az_deg = 0.0;
    if (d.x != 0.0 || d.z != 0.0)
        az_deg = atan2(d.x, -d.z) * DEG_PER_RAD; /* (-180, 180], 0 towards -z */
    double dist_el = dist_to_multiple(el_deg, 15.0);
    double dist_az = dist_to_multiple(az_deg, 15.0) * cos(el_deg / DEG_PER_RAD);
    double dist_deg = fmin(dist_el, dist_az);
    double line = 1.0 - smoothstep(0.25, 0.75, dist_deg);
    return vec3_scale(base, 1.0 - 0.25 * line); /* mix(1, 0.75, line) */
}

/* Ground, d.y < 0: the direction meets the plane y = -1 at P = d / -d.y. For
 * -1e-6 < d.y < 0 the result is the haze colour itself (there the haze weight is
 * 1 - exp(-|P.xz| / 25) <= 1 - exp(-40000), i.e. 1 in any precision), which keeps P
 * finite. Unit squares in (P.x, P.z): even floor(P.x) + floor(P.z) is light, odd is
 * dark. With e the distance to the nearest square edge, the colour is
 * mix((light + dark) / 2, own, smoothstep(0, 0.04, e)): at the edge both sides show the
 * mean, so the pattern is continuous; the blend reaches 0.04 units into each square.
 * Then mix(colour, haze, 1 - exp(-|P.xz| / 25)). */
static vec3 ground(vec3 d)
{
    const vec3 light = {0.80, 0.78, 0.74};
    const vec3 dark = {0.12, 0.12, 0.15};
    const vec3 haze = {0.45, 0.45, 0.48};
    if (d.y > -1e-6)
        return haze;
    double px = d.x / -d.y;
    double pz = d.z / -d.y;

    double cells = floor(px) + floor(pz);
    double parity = cells - 2.0 * floor(cells * 0.5); /* GLSL mod(cells, 2.0): 0 or 1 */
    vec3 own = parity < 0.5 ? light : dark;
    double fx = px - floor(px); /* GLSL fract */
    double fz = pz - floor(pz);
    double e = fmin(fmin(fx, 1.0 - fx), fmin(fz, 1.0 - fz));
    vec3 edge_mix = vec3_scale(vec3_add(light, dark), 0.5);
    vec3 checker = mix3(edge_mix, own, smoothstep(0.0, 0.04, e));

    double fade = 1.0 - exp(-sqrt(px * px + pz * pz) / 25.0);
    return mix3(checker, haze, fade);
}

vec3 env_procedural(vec3 d)
{
    return d.y >= 0.0 ? sky(d) : ground(d);
}

void env_equirect_uv(vec3 d, double rotation_deg, double *u, double *v)
{
    double uu = 0.5 + atan2(d.x, -d.z) / (2.0 * M_PI) + rotation_deg / 360.0;
    *u = uu - floor(uu); /* wrap into [0, 1) */
    *v = acos(clampd(d.y, -1.0, 1.0)) / M_PI;
}

/* frisvad2010 "Ray casting": eye point, view point, up direction, vertical field of
 * view. col and row are pixel indices (fractions allowed for sub-pixel positions); the
 * ray passes through (col + 0.5, row + 0.5), row 0 at the top. */
void camera_ray(vec3 eye, vec3 look_at, vec3 up, double fov_y_deg, int width, int height,
                double col, double row, vec3 *origin, vec3 *dir)
{
    vec3 f = vec3_normalize(vec3_sub(look_at, eye));
    vec3 r = vec3_normalize(vec3_cross(f, up));
    vec3 u = vec3_cross(r, f);
    double t = tan(0.5 * fov_y_deg / DEG_PER_RAD);
    double w = (double)width, h = (double)height;
    double sx = (2.0 * (col + 0.5) / w - 1.0) * t * w / h;
    double sy = (1.0 - 2.0 * (row + 0.5) / h) * t;
    *origin = eye;
    *dir = vec3_normalize(vec3_add(f, vec3_add(vec3_scale(r, sx), vec3_scale(u, sy))));
}
