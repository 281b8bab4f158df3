/*
 * test_scene_examples.c - every scene in proto/examples parses, each channel of each
 * object evaluates to finite values in its channel's range, the camera looks at the
 * object, and the scenes hold what their names promise (including the lights, receivers
 * and light-simulation needs of the caustic and smoke scenes).
 *
 * The examples directory comes from REFRACT_SOURCE_DIR, which ctest sets.
 */
#include <dirent.h>
#include <math.h>
#include <stdbool.h>
#include <string.h>
#include <time.h>

#include "scene/scene.h"
#include "test.h"

static const double channel_lo[SCENE_CH_COUNT] = {0.1, 0.0, 0.0, 0.0, 0.0, -0.99};
static const double channel_hi[SCENE_CH_COUNT] = {5.0, 1e5, 1e6, 1.0, 1e5, 0.99};

static char *read_all(const char *path, size_t *len)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    size_t cap = 1 << 16, n = 0;
    char *buf = malloc(cap);
    size_t got;
    while (buf != NULL && (got = fread(buf + n, 1, cap - n, f)) > 0) {
        n += got;
        if (n == cap) {
            char *grown = realloc(buf, cap * 2);
            if (grown == NULL) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = grown;
            cap *= 2;
        }
    }
    fclose(f);
    *len = n;
    return buf;
}

static double seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* Evaluates every channel of obj (at its own resolution) and checks each value. */
static void check_channels(const char *file, const struct scene *s, const struct scene_object *obj)
{
    size_t nv = (size_t)obj->resolution[0] * obj->resolution[1] * obj->resolution[2];
    for (int ch = 0; ch < SCENE_CH_COUNT; ch++) {
        int comps = scene_channel_components((enum scene_channel)ch);
        float *out = malloc(nv * (size_t)comps * sizeof *out);
        struct err e;
        err_clear(&e);
        enum refract_code rc =
            scene_field_eval(s, obj, (enum scene_channel)ch, NULL, NULL, out, &e);
        CHECK_MSG(rc == REFRACT_E_OK, "%s %s: %s", file, obj->name, e.msg);
        size_t bad = 0;
        for (size_t i = 0; i < nv * (size_t)comps; i++) {
            double v = out[i];
            bool is_alpha = comps == 4 && i % 4 == 3;
            double hi = is_alpha ? (ch == SCENE_CH_OPAQUE ? 1.0 : 0.0) : channel_hi[ch];
            double lo = is_alpha ? 0.0 : channel_lo[ch];
            if (!isfinite(v) || v < lo || v > hi)
                bad++;
        }
        CHECK_MSG(bad == 0, "%s %s %s: %zu values out of range", file, obj->name,
                  scene_channel_name((enum scene_channel)ch), bad);
        free(out);
    }
}

/* Times the channels the first object uses, at full resolution (the numbers to watch
 * when changing scene_field.c). */
static void print_full_resolution_time(const char *file, const struct scene *s)
{
    if (s->object_count == 0)
        return; /* surfaces only: nothing to evaluate into voxels */
    const struct scene_object *o = &s->objects[0];
    size_t nv = (size_t)o->resolution[0] * o->resolution[1] * o->resolution[2];
    float *out = malloc(nv * 4 * sizeof *out);
    double t0 = seconds();
    for (int ch = 0; ch < SCENE_CH_COUNT; ch++) {
        struct err e;
        if (scene_channel_used(o, (enum scene_channel)ch))
            scene_field_eval(s, o, (enum scene_channel)ch, NULL, NULL, out, &e);
    }
    printf("%-32s %d x %d x %d voxels: used channels evaluated in %.3f s\n", file, o->resolution[0],
           o->resolution[1], o->resolution[2], seconds() - t0);
    free(out);
}

/* The camera must see the object: the centre of its world bounds lies near the view
 * axis, the camera stands outside the bounds' bounding sphere, and that sphere spans
 * more than a quarter of the frame height. (How much of the frame the visible object
 * fills depends on what the fields hold, so the upper end is left to the eye.) */
static void check_framing(const char *file, const struct scene *s)
{
    vec3 c;
    double radius;
    if (s->object_count > 0) {
        const struct scene_object *o = &s->objects[0];
        vec3 mid = vec3_scale(vec3_add(o->bounds_min, o->bounds_max), 0.5);
        c = xform_point_to_world(&o->world_from_object, mid);
        radius =
            0.5 * vec3_length(vec3_sub(o->bounds_max, o->bounds_min)) * o->world_from_object.scale;
    } else {
        /* A scene of surfaces: the union of the bounded surfaces' world boxes (the first
         * alone may be a small solid nested in a larger one: surfaces are stored by
         * priority). */
        vec3 lo = {INFINITY, INFINITY, INFINITY}, hi = {-INFINITY, -INFINITY, -INFINITY};
        bool found = false;
        for (size_t k = 0; k < s->surface_count; k++) {
            vec3 a, b;
            if (scene_surface_world_bounds(&s->surfaces[k], &a, &b) && isfinite(a.x) &&
                isfinite(b.x) && isfinite(a.y) && isfinite(b.y) && isfinite(a.z) && isfinite(b.z)) {
                lo = vec3_make(fmin(lo.x, a.x), fmin(lo.y, a.y), fmin(lo.z, a.z));
                hi = vec3_make(fmax(hi.x, b.x), fmax(hi.y, b.y), fmax(hi.z, b.z));
                found = true;
            }
        }
        CHECK_MSG(found, "%s: no object and no bounded surface to frame", file);
        c = vec3_scale(vec3_add(lo, hi), 0.5);
        radius = 0.5 * vec3_length(vec3_sub(hi, lo));
    }
    vec3 view = vec3_sub(c, s->camera.eye);
    vec3 f = vec3_normalize(vec3_sub(s->camera.look_at, s->camera.eye));
    double off_axis_deg = acos(fmin(1.0, vec3_dot(f, vec3_normalize(view)))) * 180 / M_PI;
    double span_deg = 2 * asin(fmin(1.0, radius / vec3_length(view))) * 180 / M_PI;
    double frac = span_deg / s->camera.fov_y_deg;
    CHECK_MSG(off_axis_deg < 5.0, "%s: the object is %.1f degrees off the view axis", file,
              off_axis_deg);
    CHECK_MSG(vec3_length(view) > radius, "%s: the camera is inside the object's bounds", file);
    CHECK_MSG(frac > 0.25, "%s: the bounds span only %.0f%% of the frame height", file, 100 * frac);
}

static struct scene *parse_file(const char *dir, const char *name)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    size_t len = 0;
    char *text = read_all(path, &len);
    CHECK_MSG(text != NULL, "cannot read %s", path);
    if (text == NULL)
        return NULL;
    struct scene *s = NULL;
    struct err e;
    err_clear(&e);
    enum refract_code rc = scene_parse(text, len, NULL, &s, &e);
    CHECK_MSG(rc == REFRACT_E_OK, "%s: %s", name, e.msg);
    free(text);
    return s;
}

static void every_example_parses_and_evaluates_in_range(const char *dir)
{
    DIR *d = opendir(dir);
    CHECK_MSG(d != NULL, "cannot open %s", dir);
    if (d == NULL)
        return;
    int count = 0;
    const struct dirent *ent;
    while ((ent = readdir(d)) != NULL) {
        size_t n = strlen(ent->d_name);
        if (n < 6 || strcmp(ent->d_name + n - 5, ".json") != 0)
            continue;
        struct scene *s = parse_file(dir, ent->d_name);
        if (s == NULL)
            continue;
        count++;
        for (size_t i = 0; i < s->object_count; i++) {
            /* A coarse copy of the object: at most 24 voxels per axis. */
            struct scene_object coarse = s->objects[i];
            for (int a = 0; a < 3; a++)
                coarse.resolution[a] = coarse.resolution[a] < 24 ? coarse.resolution[a] : 24;
            check_channels(ent->d_name, s, &coarse);
        }
        print_full_resolution_time(ent->d_name, s);
        check_framing(ent->d_name, s);
        scene_destroy(s);
    }
    closedir(d);
    CHECK_MSG(count >= 10, "found %d examples in %s", count, dir);
}

/* n at the object-space point p, from the evaluated ior field (nearest voxel). */
static double ior_at(const struct scene *s, vec3 p)
{
    const struct scene_object *o = &s->objects[0];
    size_t nv = (size_t)o->resolution[0] * o->resolution[1] * o->resolution[2];
    float *n = malloc(nv * sizeof *n);
    struct err e;
    scene_field_eval(s, o, SCENE_CH_IOR, NULL, NULL, n, &e);
    vec3 vs = scene_object_voxel_size(o);
    int i = (int)floor((p.x - o->bounds_min.x) / vs.x);
    int j = (int)floor((p.y - o->bounds_min.y) / vs.y);
    int k = (int)floor((p.z - o->bounds_min.z) / vs.z);
    double v = n[((size_t)k * o->resolution[1] + (size_t)j) * o->resolution[0] + (size_t)i];
    free(n);
    return v;
}

static void examples_hold_what_their_names_promise(const char *dir)
{
    struct scene *s = parse_file(dir, "glass_sphere_voxels.json");
    if (s != NULL) {
        CHECK_NEAR(ior_at(s, vec3_make(0.01, 0.01, 0.01)), 1.5, 1e-6);
        CHECK_NEAR(ior_at(s, vec3_make(0.95, 0.95, 0.95)), 1.0, 1e-6);
        scene_destroy(s);
    }
    /* The same sphere as an exact surface. */
    s = parse_file(dir, "glass_sphere.json");
    if (s != NULL) {
        CHECK_INT((int)s->object_count, 0);
        CHECK_INT((int)s->surface_count, 1);
        CHECK_INT(s->surfaces[0].shape.kind, SCENE_SHAPE_SPHERE);
        CHECK_NEAR(s->surfaces[0].shape.radius, 0.8, 0);
        CHECK_NEAR(s->surfaces[0].medium.ior, 1.5, 0);
        scene_destroy(s);
    }
    s = parse_file(dir, "luneburg_lens.json");
    if (s != NULL) {
        CHECK_INT(s->objects[0].fields[SCENE_CH_IOR].layers[0].profile.kind, GRIN_LUNEBURG);
        CHECK_NEAR(s->objects[0].smoothing_sigma_voxels, 0.0, 0);
        CHECK_NEAR(ior_at(s, vec3_make(0.001, 0.001, 0.001)), sqrt(2.0), 1e-3);
        scene_destroy(s);
    }
    s = parse_file(dir, "wine_glass.json");
    if (s != NULL) {
        /* Exact lathes: the glass (priority 2) first, the wine (1) overlapping its wall; in
         * the stem, glass; in the bowl, wine; above the wine, air (the inside sets). */
        CHECK_INT((int)s->surface_count, 2);
        CHECK(strcmp(s->surfaces[0].name, "glass") == 0 && s->surfaces[0].medium.ior == 1.5);
        CHECK(strcmp(s->surfaces[1].name, "wine") == 0 && s->surfaces[1].medium.ior == 1.34);
        CHECK_INT((int)scene_surfaces_inside(s, NULL, NULL, vec3_make(0.0, -0.7, 0.0)), 1);
        CHECK_INT((int)scene_surfaces_inside(s, NULL, NULL, vec3_make(0.0, 0.1, 0.0)), 2);
        CHECK_INT((int)scene_surfaces_inside(s, NULL, NULL, vec3_make(0.0, 0.8, 0.0)), 0);
        CHECK_INT((int)scene_surfaces_inside(s, NULL, NULL, vec3_make(0.525, 0.3, 0.0)), 3);
        scene_destroy(s);
    }
    s = parse_file(dir, "wine_glass_voxels.json");
    if (s != NULL) {
        /* Glass in the stem, wine in the bowl, air above the wine inside the bowl. */
        CHECK_NEAR(ior_at(s, vec3_make(0.0, -0.7, 0.0)), 1.5, 1e-6);
        CHECK_NEAR(ior_at(s, vec3_make(0.0, 0.1, 0.0)), 1.34, 1e-6);
        CHECK_NEAR(ior_at(s, vec3_make(0.0, 0.8, 0.0)), 1.0, 1e-6);
        scene_destroy(s);
    }
    s = parse_file(dir, "glass_block_lettering.json");
    if (s != NULL) {
        /* An exact rounded box filled by the voxel object "block": n 1.5 constant, the
         * letters in its attenuation field. */
        CHECK_INT((int)s->surface_count, 1);
        CHECK_INT(s->surfaces[0].shape.kind, SCENE_SHAPE_ROUNDED_BOX);
        CHECK(s->surfaces[0].medium.has_object && s->surfaces[0].medium.object == 0);
        const struct scene_field *a = &s->objects[0].fields[SCENE_CH_ATTENUATION];
        CHECK_INT(a->count, 2);
        CHECK_INT(a->layers[1].shape.kind, SCENE_SHAPE_TEXT);
        scene_destroy(s);
    }
    s = parse_file(dir, "glass_block_lettering_voxels.json");
    if (s != NULL) {
        const struct scene_field *a = &s->objects[0].fields[SCENE_CH_ATTENUATION];
        CHECK_INT(a->count, 2);
        CHECK_INT(a->layers[1].shape.kind, SCENE_SHAPE_TEXT);
        CHECK_STR(a->layers[1].shape.text, "REFRACT");
        scene_destroy(s);
    }
    s = parse_file(dir, "rounded_cube_three_layers.json");
    if (s != NULL) {
        /* Exact rounded boxes, stored highest priority first: inner (bit 0), middle, outer.
         * Rotated 30 degrees about y: (0.7, 0, 0) is at x' = 0.61 in the cube, outside the
         * middle shell (half size 0.575). */
        CHECK_INT((int)s->surface_count, 3);
        CHECK(strcmp(s->surfaces[0].name, "inner") == 0 && s->surfaces[0].medium.ior == 1.7);
        CHECK_INT(s->surfaces[2].shape.kind, SCENE_SHAPE_ROUNDED_BOX);
        CHECK_INT((int)scene_surfaces_inside(s, NULL, NULL, vec3_make(0.01, 0.01, 0.01)), 7);
        CHECK_INT((int)scene_surfaces_inside(s, NULL, NULL, vec3_make(0.5, 0.01, 0.01)), 6);
        CHECK_INT((int)scene_surfaces_inside(s, NULL, NULL, vec3_make(0.7, 0.01, 0.01)), 4);
        /* The outer cube's box holds (0.88, 0.75, 0) (x' = 0.76, z' = 0.44 in the cube), its
         * rounded edge (radius 0.2 about x' = y = 0.6) does not. */
        CHECK_INT((int)scene_surfaces_inside(s, NULL, NULL, vec3_make(0.0, 0.78, 0.0)), 4);
        CHECK_INT((int)scene_surfaces_inside(s, NULL, NULL, vec3_make(0.88, 0.75, 0.0)), 0);
        scene_destroy(s);
    }
    s = parse_file(dir, "rounded_cube_three_layers_voxels.json");
    if (s != NULL) {
        CHECK_NEAR(ior_at(s, vec3_make(0.01, 0.01, 0.01)), 1.7, 1e-6);
        CHECK_NEAR(ior_at(s, vec3_make(0.5, 0.01, 0.01)), 1.5, 1e-6);
        CHECK_NEAR(ior_at(s, vec3_make(0.7, 0.01, 0.01)), 1.35, 1e-6);
        scene_destroy(s);
    }
}

/* Channel component c at p (nearest voxel) for the 4-component channels. */
static double rgb_at(const struct scene *s, enum scene_channel ch, vec3 p, int c)
{
    const struct scene_object *o = &s->objects[0];
    size_t nv = (size_t)o->resolution[0] * o->resolution[1] * o->resolution[2];
    float *v = malloc(nv * 4 * sizeof *v);
    struct err e;
    scene_field_eval(s, o, ch, NULL, NULL, v, &e);
    vec3 vs = scene_object_voxel_size(o);
    int i = (int)floor((p.x - o->bounds_min.x) / vs.x);
    int j = (int)floor((p.y - o->bounds_min.y) / vs.y);
    int k = (int)floor((p.z - o->bounds_min.z) / vs.z);
    double r = v[4 * (((size_t)k * o->resolution[1] + (size_t)j) * o->resolution[0] + (size_t)i) +
                 (size_t)c];
    free(v);
    return r;
}

static void light_examples_hold_what_their_names_promise(const char *dir)
{
    struct scene *s = parse_file(dir, "ball_lens_caustic.json");
    if (s != NULL) {
        CHECK_INT((int)s->surface_count, 1);
        CHECK_INT(s->surfaces[0].shape.kind, SCENE_SHAPE_SPHERE);
        CHECK_NEAR(s->surfaces[0].medium.ior, 1.5, 0);
        CHECK(s->receiver.enabled);
        CHECK_NEAR(-s->receiver.height, 1.5 * 0.5 / (2 * 0.5), 1e-12);
        /* The daemon's choice ("auto", docs/photons.md "Choosing"): photons through the
         * exact sphere, no light simulation. */
        CHECK(s->receiver.caustics_auto);
        CHECK_INT((int)s->receiver.caustics, SCENE_CAUSTICS_PHOTONS);
        CHECK(!scene_needs_light_simulation(s) && scene_needs_photon_maps(s));
        scene_destroy(s);
    }
    s = parse_file(dir, "ball_lens_caustic_voxels.json");
    if (s != NULL) {
        CHECK_INT(s->light_count, 1);
        CHECK_INT(s->lights[0].kind, SCENE_LIGHT_DIRECTIONAL);
        CHECK_NEAR(s->lights[0].direction.y, -1.0, 0);
        CHECK(s->receiver.enabled);
        /* The receiver lies at the ball lens's back focal distance n R / (2 (n - 1)). */
        CHECK_NEAR(-s->receiver.height, 1.5 * 0.5 / (2 * 0.5), 1e-12);
        CHECK_INT(s->lightsim.resolution, 64);
        CHECK_INT((int)s->receiver.caustics, SCENE_CAUSTICS_VOLUME); /* auto: a voxel object */
        CHECK(scene_needs_light_simulation(s));
        CHECK_NEAR(ior_at(s, vec3_make(0.01, 0.01, 0.01)), 1.5, 1e-6);
        scene_destroy(s);
    }
    s = parse_file(dir, "bumpy_sphere.json");
    if (s != NULL) {
        const struct scene_shape *sh = &s->objects[0].fields[SCENE_CH_IOR].layers[0].shape;
        CHECK_INT(sh->kind, SCENE_SHAPE_BUMPY_SPHERE);
        CHECK(sh->bump_amplitude > 0.0);
        CHECK_INT(s->light_count, 1);
        CHECK(s->receiver.enabled);
        /* The bumps stay inside the object's bounds. */
        vec3 lo, hi;
        CHECK(scene_shape_bounds(sh, &lo, &hi));
        CHECK(lo.x > s->objects[0].bounds_min.x && hi.y < s->objects[0].bounds_max.y);
        scene_destroy(s);
    }
    s = parse_file(dir, "smoke_spot.json");
    if (s != NULL) {
        CHECK_INT(s->light_count, 1);
        CHECK_INT(s->lights[0].kind, SCENE_LIGHT_SPOT);
        CHECK(!s->receiver.enabled);
        CHECK(scene_needs_light_simulation(s)); /* by the smoke alone */
        /* Smoke at a corner of the box, glass and no smoke at the sphere's centre. */
        CHECK_NEAR(rgb_at(s, SCENE_CH_SCATTERING, vec3_make(-0.95, -0.95, -0.95), 1), 0.3, 1e-6);
        CHECK_NEAR(rgb_at(s, SCENE_CH_SCATTERING, vec3_make(0.01, 0.41, 0.01), 1), 0.0, 1e-6);
        CHECK_NEAR(ior_at(s, vec3_make(0.01, 0.41, 0.01)), 1.5, 1e-6);
        CHECK_NEAR(s->objects[0].fields[SCENE_CH_ANISOTROPY].layers[0].inside[0], 0.3, 0);
        /* The spot's cone covers the sphere: tan(angle) * distance > radius. */
        double dist = s->lights[0].position.y - 0.4;
        CHECK(tan(s->lights[0].spot_angle_deg * M_PI / 180) * dist > 0.4);
        scene_destroy(s);
    }
    s = parse_file(dir, "milk_glass.json");
    if (s != NULL) {
        /* The particle medium (docs/media.md) fills the water and only the water: milky
         * water scatters blue more than red and forward (fat globules), the glass wall and
         * the air above do not scatter. */
        vec3 water = vec3_make(0.01, -0.2, 0.01);
        CHECK(scene_needs_light_simulation(s));
        CHECK(rgb_at(s, SCENE_CH_SCATTERING, water, 2) > rgb_at(s, SCENE_CH_SCATTERING, water, 0));
        CHECK(rgb_at(s, SCENE_CH_SCATTERING, water, 0) > 1.0);
        CHECK(s->objects[0].fields[SCENE_CH_ANISOTROPY].layers[0].inside[0] > 0.8);
        CHECK_NEAR(rgb_at(s, SCENE_CH_SCATTERING, vec3_make(0.48, -0.2, 0.0), 1), 0.0, 0.0);
        CHECK_NEAR(rgb_at(s, SCENE_CH_SCATTERING, vec3_make(0.0, 0.55, 0.0), 1), 0.0, 0.0);
        CHECK_NEAR(ior_at(s, vec3_make(0.48, -0.2, 0.0)), 1.5, 1e-3);
        scene_destroy(s);
    }
    s = parse_file(dir, "wine_glass.json");
    if (s != NULL) {
        CHECK_INT(s->light_count, 1);
        CHECK(s->receiver.enabled);
        /* The table is at the glass's foot. */
        CHECK_NEAR(s->receiver.height, -1.25, 0);
        CHECK_INT((int)s->receiver.caustics, SCENE_CAUSTICS_PHOTONS); /* docs/photons.md */
        CHECK(!scene_needs_light_simulation(s));
        scene_destroy(s);
    }
    /* The scenes from before lights existed need no light simulation. */
    s = parse_file(dir, "glass_sphere.json");
    if (s != NULL) {
        CHECK(!scene_needs_light_simulation(s));
        scene_destroy(s);
    }
}

int main(void)
{
    const char *src = getenv("REFRACT_SOURCE_DIR");
    if (src == NULL)
        test_skip("test_scene_examples", "REFRACT_SOURCE_DIR is not set (run it with ctest)");
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/proto/examples", src);
    every_example_parses_and_evaluates_in_range(dir);
    examples_hold_what_their_names_promise(dir);
    light_examples_hold_what_their_names_promise(dir);
    return test_summary("test_scene_examples");
}
