/*
 * test_env.c - the procedural environment, the equirectangular coordinates and the
 * pinhole camera of docs/tracing.md "Environment" and "Camera" (frisvad2010, "Ray
 * casting").
 *
 * Tolerances: 1e-12 where the expected value is the page's formula evaluated directly
 * (double rounding only).
 */
#include <math.h>
#include <stdint.h>

#include "core/env.h"
#include "test.h"

static const vec3 horizon = {0.85, 0.90, 1.00};
static const vec3 zenith = {0.20, 0.40, 0.85};
static const vec3 light = {0.80, 0.78, 0.74};
static const vec3 dark = {0.12, 0.12, 0.15};
static const vec3 haze = {0.45, 0.45, 0.48};

static double rad(double deg)
{
    return deg * M_PI / 180.0;
}

/* Direction with azimuth az (degrees, from -z towards +x) and elevation el. */
static vec3 sky_dir(double az, double el)
{
    return (vec3){cos(rad(el)) * sin(rad(az)), sin(rad(el)), -cos(rad(el)) * cos(rad(az))};
}

static vec3 mix3(vec3 a, vec3 b, double t)
{
    return vec3_add(vec3_scale(a, 1.0 - t), vec3_scale(b, t));
}

static void check_vec(vec3 a, vec3 b, double tol)
{
    CHECK_NEAR(a.x, b.x, tol);
    CHECK_NEAR(a.y, b.y, tol);
    CHECK_NEAR(a.z, b.z, tol);
}

static double luminance(vec3 c)
{
    return 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
}

/* xorshift64*: deterministic directions without libc rand. */
static double uniform01(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return (double)((*s * 2685821657736338717ull) >> 11) / 9007199254740992.0;
}

static void environment_is_finite_and_positive_in_every_direction(void)
{
    uint64_t seed = 0x9e3779b97f4a7c15ull;
    int bad = 0;
    for (int i = 0; i < 100000; i++) {
        double z = 2.0 * uniform01(&seed) - 1.0, phi = 2.0 * M_PI * uniform01(&seed);
        double r = sqrt(fmax(0.0, 1.0 - z * z));
        vec3 c = env_procedural((vec3){r * cos(phi), z, r * sin(phi)});
        if (!vec3_is_finite(c) || !(c.x > 0.0 && c.y > 0.0 && c.z > 0.0))
            bad++;
    }
    CHECK_INT(bad, 0);
    /* The special directions: zenith, nadir, exactly on the horizon, just below it. */
    const vec3 special[5] = {{0, 1, 0}, {0, -1, 0}, {1, 0, 0}, {0, -1e-300, 1}, {0, -1e-7, 1}};
    for (int i = 0; i < 5; i++) {
        vec3 c = env_procedural(special[i]);
        CHECK(vec3_is_finite(c) && c.x > 0.0 && c.y > 0.0 && c.z > 0.0);
    }
}

/* Off the grid (azimuth and elevation 7.5 deg from every line), the sky is exactly
 * mix(horizon, zenith, sqrt(d.y)); it is brighter towards the horizon. */
static void sky_follows_the_gradient_and_brightens_towards_the_horizon(void)
{
    vec3 lo = sky_dir(7.5, 7.5), hi = sky_dir(37.5, 67.5);
    check_vec(env_procedural(lo), mix3(horizon, zenith, sqrt(lo.y)), 1e-12);
    check_vec(env_procedural(hi), mix3(horizon, zenith, sqrt(hi.y)), 1e-12);
    CHECK(luminance(env_procedural(lo)) > luminance(env_procedural(hi)));
    CHECK(luminance(horizon) > luminance(zenith));
}

/* On a line (elevation 30 deg, azimuth 45 deg) the sky is darkened to 75 %; 0.25 deg
 * of arc away the mask is still 1, 0.75 deg away it is 0. */
static void sky_grid_lines_darken_to_three_quarters(void)
{
    vec3 on_el = sky_dir(7.5, 30.0);
    check_vec(env_procedural(on_el), vec3_scale(mix3(horizon, zenith, sqrt(on_el.y)), 0.75), 1e-12);
    vec3 on_az = sky_dir(45.0, 37.5);
    check_vec(env_procedural(on_az), vec3_scale(mix3(horizon, zenith, sqrt(on_az.y)), 0.75), 1e-12);
    vec3 near = sky_dir(7.5, 30.2);
    check_vec(env_procedural(near), vec3_scale(mix3(horizon, zenith, sqrt(near.y)), 0.75), 1e-12);
    vec3 clear = sky_dir(7.5, 30.8);
    check_vec(env_procedural(clear), mix3(horizon, zenith, sqrt(clear.y)), 1e-12);
    /* Halfway through the ramp, dist = 0.5 deg: mask 0.5, factor 0.875. */
    vec3 half = sky_dir(7.5, 30.5);
    check_vec(env_procedural(half), vec3_scale(mix3(horizon, zenith, sqrt(half.y)), 0.875), 1e-12);
}

/* Azimuth distance is an arc on the sky: at elevation 60 deg, 0.8 deg of azimuth off a
 * meridian is 0.4 deg of arc, so the line is still fully dark there, while at
 * elevation 7.5 (cos = 0.991) it is clear. */
static void azimuth_lines_are_measured_as_arcs_along_the_sky(void)
{
    vec3 high = sky_dir(45.8, 52.5);
    double dist = 0.8 * cos(rad(52.5)); /* 0.487 deg: mask 1 - smoothstep(.25,.75,.487) */
    double t = (dist - 0.25) / 0.5;
    double mask = 1.0 - t * t * (3.0 - 2.0 * t);
    check_vec(env_procedural(high),
              vec3_scale(mix3(horizon, zenith, sqrt(high.y)), 1.0 - 0.25 * mask), 1e-12);
    CHECK(mask > 0.4 && mask < 0.6);
    vec3 low = sky_dir(45.8, 7.5);
    check_vec(env_procedural(low), mix3(horizon, zenith, sqrt(low.y)), 1e-12);
}

/* Directions to the centres of adjacent squares on y = -1 alternate between light and
 * dark, each faded into the haze by 1 - exp(-|P.xz| / 25). */
static void ground_checker_alternates_between_adjacent_squares(void)
{
    const double centres[4][2] = {{0.5, -2.5}, {1.5, -2.5}, {1.5, -3.5}, {-0.5, -2.5}};
    /* floor sums: 0 + -3 = -3 (odd: dark), -2 (light), -3 (dark), -4 (light). */
    const int dark_square[4] = {1, 0, 1, 0};
    for (int i = 0; i < 4; i++) {
        vec3 P = {centres[i][0], -1.0, centres[i][1]};
        vec3 d = vec3_normalize(P);
        double fade = 1.0 - exp(-sqrt(P.x * P.x + P.z * P.z) / 25.0);
        vec3 expect = mix3(dark_square[i] ? dark : light, haze, fade);
        check_vec(env_procedural(d), expect, 1e-12);
    }
    CHECK(luminance(env_procedural(vec3_normalize((vec3){1.5, -1, -2.5}))) >
          luminance(env_procedural(vec3_normalize((vec3){0.5, -1, -2.5}))) + 0.3);
    /* On an edge both sides blend to the mean colour. */
    vec3 P = {1.0, -1.0, -2.5};
    double fade = 1.0 - exp(-sqrt(1.0 + 6.25) / 25.0);
    check_vec(env_procedural(vec3_normalize(P)),
              mix3(vec3_scale(vec3_add(light, dark), 0.5), haze, fade), 1e-12);
    /* Far away the ground is haze. */
    check_vec(env_procedural(vec3_normalize((vec3){0, -1e-3, 1})), haze, 1e-12);
}

static void equirect_coordinates_put_minus_z_in_the_middle_and_zenith_on_top(void)
{
    double u, v;
    env_equirect_uv((vec3){0, 0, -1}, 0.0, &u, &v);
    CHECK_NEAR(u, 0.5, 1e-15);
    CHECK_NEAR(v, 0.5, 1e-15);
    env_equirect_uv((vec3){1, 0, 0}, 0.0, &u, &v);
    CHECK_NEAR(u, 0.75, 1e-15);
    env_equirect_uv((vec3){0, 1, 0}, 0.0, &u, &v);
    CHECK_NEAR(v, 0.0, 1e-15);
    env_equirect_uv((vec3){0, -1, 0}, 0.0, &u, &v);
    CHECK_NEAR(v, 1.0, 1e-15);
    /* Rotation adds rotation / 360 and wraps into [0, 1). */
    env_equirect_uv((vec3){1, 0, 0}, 90.0, &u, &v);
    CHECK_NEAR(u, 0.0, 1e-15);
    CHECK(u >= 0.0 && u < 1.0);
    env_equirect_uv((vec3){0, 0, -1}, -270.0, &u, &v);
    CHECK_NEAR(u, 0.75, 1e-15);
}

static const vec3 eye = {1.0, 2.0, 5.0};
static const vec3 look = {0.5, 1.5, -1.0};
static const vec3 up = {0.0, 1.0, 0.0};

static void centre_pixel_of_odd_image_looks_at_the_target(void)
{
    vec3 o, d;
    camera_ray(eye, look, up, 40.0, 5, 3, 2.0, 1.0, &o, &d);
    vec3 f = vec3_normalize(vec3_sub(look, eye));
    check_vec(o, eye, 0.0);
    check_vec(d, f, 1e-15);
}

/* The top edge at the middle column is fov/2 from the axis; the top-left corner is
 * atan(t sqrt(1 + aspect^2)) from it, t = tan(fov / 2). Pixel (-0.5, -0.5) has its
 * "centre" at the image corner. */
static void edge_rays_make_half_the_field_of_view_with_the_axis(void)
{
    const double fov = 50.0;
    const int W = 9, H = 5;
    vec3 f = vec3_normalize(vec3_sub(look, eye)), o, d;
    camera_ray(eye, look, up, fov, W, H, 4.0, -0.5, &o, &d);
    CHECK_NEAR(acos(vec3_dot(d, f)), rad(fov / 2.0), 1e-12);
    camera_ray(eye, look, up, fov, W, H, -0.5, -0.5, &o, &d);
    double t = tan(rad(fov / 2.0)), aspect = (double)W / H;
    CHECK_NEAR(acos(vec3_dot(d, f)), atan(t * sqrt(1.0 + aspect * aspect)), 1e-12);
    CHECK_NEAR(vec3_length(d), 1.0, 1e-15);
}

static void rows_go_top_to_bottom_and_columns_left_to_right(void)
{
    vec3 f = vec3_normalize(vec3_sub(look, eye));
    vec3 r = vec3_normalize(vec3_cross(f, up));
    vec3 u = vec3_cross(r, f);
    vec3 o, top, bottom, left, right;
    camera_ray(eye, look, up, 60.0, 8, 6, 3.5, 0.0, &o, &top);
    camera_ray(eye, look, up, 60.0, 8, 6, 3.5, 5.0, &o, &bottom);
    camera_ray(eye, look, up, 60.0, 8, 6, 0.0, 2.5, &o, &left);
    camera_ray(eye, look, up, 60.0, 8, 6, 7.0, 2.5, &o, &right);
    CHECK(vec3_dot(top, u) > 0.0);
    CHECK(vec3_dot(bottom, u) < 0.0);
    CHECK(vec3_dot(left, r) < 0.0);
    CHECK(vec3_dot(right, r) > 0.0);
    /* World up is up in the image: the top row points higher. */
    CHECK(top.y > bottom.y);
}

int main(void)
{
    environment_is_finite_and_positive_in_every_direction();
    sky_follows_the_gradient_and_brightens_towards_the_horizon();
    sky_grid_lines_darken_to_three_quarters();
    azimuth_lines_are_measured_as_arcs_along_the_sky();
    ground_checker_alternates_between_adjacent_squares();
    equirect_coordinates_put_minus_z_in_the_middle_and_zenith_on_top();
    centre_pixel_of_odd_image_looks_at_the_target();
    edge_rays_make_half_the_field_of_view_with_the_axis();
    rows_go_top_to_bottom_and_columns_left_to_right();
    return test_summary("test_env");
}
