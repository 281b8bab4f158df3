/*
 * test_scene_pathtrace.c - a scene document as the reference path tracer sees it
 * (scene/scene_pathtrace.h): the peer scenes' examples become a spherical emitter of
 * radiance Phi / (4 pi^2 r^2) = 2533.03 that camera rays do not see, a glass sphere (filled
 * with sigma_s 0.5, sigma_a 0.05 in B) and, in A, a floor; scene A's document with the ball
 * removed reads the check value 0.264553 through the converted scene; the light's and the
 * medium's new keys are checked; what the path tracer cannot render is refused by name.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/pathtrace_image.h"
#include "scene/scene_pathtrace.h"
#include "test.h"

static struct scene *parse(const char *json, struct err *e)
{
    struct scene *s = NULL;
    err_clear(e);
    if (scene_parse(json, strlen(json), NULL, &s, e) != REFRACT_E_OK)
        return NULL;
    return s;
}

static char *read_example(const char *name)
{
    const char *src = getenv("REFRACT_SOURCE_DIR");
    if (src == NULL)
        test_skip("test_scene_pathtrace", "REFRACT_SOURCE_DIR is not set (run it with ctest)");
    char path[1024];
    snprintf(path, sizeof path, "%s/proto/examples/%s", src, name);
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    char *buf = calloc(1, 1 << 16);
    size_t n = buf ? fread(buf, 1, (1 << 16) - 1, f) : 0;
    (void)n;
    fclose(f);
    return buf;
}

static void peer_examples_convert_to_their_specification(void)
{
    const char *names[2] = {"peer_scene_a.json", "peer_scene_b.json"};
    for (int k = 0; k < 2; k++) {
        char *text = read_example(names[k]);
        CHECK_MSG(text != NULL, "cannot read %s", names[k]);
        if (text == NULL)
            continue;
        struct err e;
        struct scene *s = parse(text, &e);
        free(text);
        CHECK_MSG(s != NULL, "%s: %s", names[k], e.msg);
        if (s == NULL)
            continue;
        struct scene_pathtrace pt;
        CHECK(scene_pathtrace_init(s, NULL, NULL, &pt, &e) == REFRACT_E_OK);
        const struct pathtrace_light *l = &pt.scene.lights[0];
        CHECK_INT(pt.scene.light_count, 1);
        CHECK_INT(l->kind, PATHTRACE_LIGHT_SPHERE);
        CHECK_NEAR(l->radius, 0.1, 0.0);
        CHECK(!l->visible);
        /* SCENES.md: L_e = Phi / (4 pi^2 r^2) = 2533.03 */
        CHECK_NEAR(l->value[0], 2533.03, 0.01);
        CHECK_NEAR(l->value[0], pathtrace_sphere_radiance(1000.0, 0.1), 1e-3);
        CHECK_INT(pt.scene.surface_count, 1);
        CHECK_NEAR(pt.scene.surfaces[0].medium.ior, 1.5, 0.0);
        CHECK(pt.scene.env_radiance[1] == 0.0);
        if (k == 0) {
            CHECK(pt.scene.receiver.enabled);
            CHECK_NEAR(pt.scene.receiver.height, -1.0, 0.0);
            CHECK_NEAR(pt.scene.receiver.albedo[1], 0.8, 0.0);
        } else {
            CHECK(!pt.scene.receiver.enabled);
            CHECK_NEAR(pt.scene.surfaces[0].medium.sigma_s[1], 0.5, 0.0);
            CHECK_NEAR(pt.scene.surfaces[0].medium.sigma_a[1], 0.05, 0.0);
            CHECK_NEAR(pt.scene.surfaces[0].medium.g, 0.0, 0.0);
        }
        scene_destroy(s);
    }
}

/* Scene A's document without the ball (a surface far from the check point keeps the
 * receiver's default size rule happy) through the converted scene. */
static void scene_a_document_without_the_ball_reads_the_check_value(void)
{
    const char *json =
        "{\"camera\": {\"eye\": [0, 2.5, 7], \"look_at\": [0, -0.5, 0], \"fov_y_deg\": 35, "
        "\"width\": 320, \"height\": 240}, \"environment\": {\"intensity\": 0}, "
        "\"lights\": [{\"type\": \"point\", \"position\": [2, 6, 1], \"intensity\": 79.5775, "
        "\"radius\": 0.1, \"camera_visible\": false}], "
        "\"receiver\": {\"height\": -1, \"half_size\": 100}, "
        "\"surfaces\": [{\"shape\": \"sphere\", \"center\": [5, 0, -30], \"radius\": 0.5, "
        "\"medium\": {\"ior\": 1.5}}]}";
    struct err e;
    struct scene *s = parse(json, &e);
    CHECK_MSG(s != NULL, "%s", e.msg);
    if (s == NULL)
        return;
    struct scene_pathtrace pt;
    CHECK(scene_pathtrace_init(s, NULL, NULL, &pt, &e) == REFRACT_E_OK);
    const struct scene_camera *c = &s->camera;
    struct pathtrace_camera cam = {c->eye, c->look_at, c->up, c->fov_y_deg, c->width, c->height};
    double sum = 0.0;
    int n = 4000;
    for (int i = 0; i < n; i++) {
        struct pathtrace_rng rng;
        pathtrace_rng_init(&rng, 9, 0, (uint64_t)i);
        double L[3];
        pathtrace_camera_sample(&pt.scene, &cam, 32.6, 199.5, &rng, L);
        sum += L[0];
    }
    CHECK_NEAR(sum / n, 0.264553, 0.01 * 0.264553);
    scene_destroy(s);
}

static void new_keys_are_checked(void)
{
    struct err e;
    struct scene *s = parse("{\"lights\": [{\"type\": \"point\", \"position\": [0, 1, 0], "
                            "\"radius\": -1}], \"surfaces\": [{\"shape\": \"sphere\", "
                            "\"medium\": {\"ior\": 1.5}}]}",
                            &e);
    CHECK(s == NULL && e.code == REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "lights[0].radius");
    s = parse(
        "{\"lights\": [{\"type\": \"spot\", \"position\": [0, 1, 0], \"direction\": [0, -1, "
        "0], \"radius\": 0.1}], \"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": "
        "{\"ior\": 1.5}}]}",
        &e);
    CHECK(s == NULL && e.code == REFRACT_E_UNKNOWN_FIELD);
    CHECK_CONTAINS(e.msg, "radius");
    s = parse("{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": {\"ior\": 1.5, "
              "\"anisotropy\": 1}}]}",
              &e);
    CHECK(s == NULL && e.code == REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "surfaces[0].medium.anisotropy");
    s = parse("{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": {\"ior\": 1.5, "
              "\"scattering\": [1, -1, 0]}}]}",
              &e);
    CHECK(s == NULL && e.code == REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "surfaces[0].medium.scattering");
}

static void what_the_path_tracer_cannot_render_is_refused(void)
{
    struct err e;
    struct scene *s = parse("{\"objects\": [{\"name\": \"lens\", \"bounds\": {\"min\": [-1, -1, "
                            "-1], \"max\": [1, 1, 1]}, \"resolution\": 8, \"ior\": 1.2}]}",
                            &e);
    CHECK_MSG(s != NULL, "%s", e.msg);
    struct scene_pathtrace pt;
    if (s != NULL) {
        CHECK(scene_pathtrace_init(s, NULL, NULL, &pt, &e) == REFRACT_E_CONFLICT);
        CHECK_CONTAINS(e.msg, "objects[0] (\"lens\") is a volume object");
        scene_destroy(s);
    }
    s = parse("{\"surfaces\": [{\"name\": \"lamp\", \"shape\": \"sphere\", \"radius\": 1, "
              "\"medium\": {\"ior\": "
              "1.0, \"emission\": [1, 1, 1]}}]}",
              &e);
    CHECK_MSG(s != NULL, "%s", e.msg);
    if (s != NULL) {
        CHECK(scene_pathtrace_init(s, NULL, NULL, &pt, &e) == REFRACT_E_CONFLICT);
        CHECK_CONTAINS(e.msg, "surfaces[0] (\"lamp\") has an emitting medium");
        scene_destroy(s);
    }
}

int main(void)
{
    peer_examples_convert_to_their_specification();
    scene_a_document_without_the_ball_reads_the_check_value();
    new_keys_are_checked();
    what_the_path_tracer_cannot_render_is_refused();
    return test_summary("test_scene_pathtrace");
}
