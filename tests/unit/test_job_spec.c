/*
 * test_job_spec.c - batch job specifications expanded into frames (server/jobs/job_spec.c),
 * against closed forms: the turntable's rotation (Rodrigues) keeps the distance to the
 * axis and the height along it, turns a quarter turn onto the expected point, and starts at
 * the scene camera; slerp stays on the unit sphere, at t = 1/2 equals normalize(a + b), and
 * moves at constant angular speed; a light path's frames lie on the keyframes at the ends
 * and lerp positions linearly; defaults and overrides reach every frame.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "jobs/jobs.h"
#include "scene/scene.h"
#include "test.h"

static const char *const scene_doc =
    "{\"camera\": {\"eye\": [0, 1, 4], \"look_at\": [0, 0, 0], \"width\": 64, \"height\": 48},"
    " \"lights\": [{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0, -1, 0]},"
    " {\"name\": \"bulb\", \"type\": \"point\", \"position\": [0, 2, 0]}],"
    " \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8,"
    " \"ior\": {\"shape\": \"sphere\", \"radius\": 0.5, \"inside\": 1.5}}]}";

static const struct job_limits limits = {
    .max_frames = 100, .max_image_dim = 4096, .max_image_pixels = 1 << 24};

static int expand(const struct scene *s, const char *json, struct job_frame **frames, struct err *e)
{
    cJSON *root = cJSON_Parse(json);
    int count = 0;
    *frames = NULL;
    enum refract_code rc = job_spec_expand(root, s, &limits, frames, &count, e);
    cJSON_Delete(root);
    return rc == REFRACT_E_OK ? count : -(int)rc;
}

static void rotation(void)
{
    vec3 axis = vec3_normalize(vec3_make(1, 2, 3)), c = vec3_make(0.5, -1, 2);
    vec3 p = vec3_make(3, 1, -2);
    for (int i = 0; i < 16; i++) {
        double a = i * 0.7;
        vec3 q = job_rotate_about(p, c, axis, a);
        vec3 dp = vec3_sub(p, c), dq = vec3_sub(q, c);
        CHECK_NEAR(vec3_dot(dq, axis), vec3_dot(dp, axis), 1e-12);
        CHECK_NEAR(vec3_length(dq), vec3_length(dp), 1e-12);
    }
    /* A quarter turn about +y takes +x to -z (right-handed). */
    vec3 q = job_rotate_about(vec3_make(1, 0, 0), vec3_make(0, 0, 0), vec3_make(0, 1, 0), M_PI / 2);
    CHECK_NEAR(q.x, 0, 1e-15);
    CHECK_NEAR(q.z, -1, 1e-15);
}

static void slerp(void)
{
    vec3 a = vec3_normalize(vec3_make(0, -1, 0)), b = vec3_normalize(vec3_make(0.3, -1, 0.2));
    vec3 mid = job_slerp(a, b, 0.5), ref = vec3_normalize(vec3_add(a, b));
    CHECK_NEAR(mid.x, ref.x, 1e-14);
    CHECK_NEAR(mid.y, ref.y, 1e-14);
    CHECK_NEAR(mid.z, ref.z, 1e-14);
    double w = acos(vec3_dot(a, b));
    for (int i = 0; i <= 10; i++) {
        vec3 v = job_slerp(a, b, i / 10.0);
        CHECK_NEAR(vec3_length(v), 1, 1e-14);
        CHECK_NEAR(acos(fmin(1, vec3_dot(a, v))), w * i / 10.0, 1e-7);
    }
    vec3 opp = job_slerp(vec3_make(0, 1, 0), vec3_make(0, -1, 0), 0.5);
    CHECK_NEAR(vec3_length(opp), 1, 1e-14);
    CHECK_NEAR(opp.y, 0, 1e-12); /* halfway between opposites: perpendicular to both */
}

static void turntable(const struct scene *s)
{
    struct job_frame *f = NULL;
    struct err e = {0};
    int n = expand(s,
                   "{\"scene\": \"x\", \"width\": 32, \"height\": 24, \"format\": \"jpeg\","
                   " \"turntable\": {\"frames\": 4}}",
                   &f, &e);
    CHECK_INT(n, 4);
    for (int i = 0; f && i < n; i++) {
        CHECK_INT(f[i].camera.width, 32);
        CHECK_INT(f[i].format, JOB_FORMAT_JPEG);
        CHECK_NEAR(f[i].camera.eye.y, 1, 1e-12); /* the height along the axis is kept */
        CHECK_NEAR(hypot(f[i].camera.eye.x, f[i].camera.eye.z), 4, 1e-12);
    }
    if (f) {
        CHECK_NEAR(f[0].camera.eye.z, 4, 0);     /* frame 0 is the scene camera */
        CHECK_NEAR(f[1].camera.eye.x, 4, 1e-12); /* a quarter turn about +y: +z -> +x */
        CHECK_NEAR(f[2].camera.eye.z, -4, 1e-12);
    }
    free(f);
}

static void light_path(const struct scene *s)
{
    struct job_frame *f = NULL;
    struct err e = {0};
    int n = expand(s,
                   "{\"scene\": \"x\", \"light_path\": {\"light\": \"bulb\", \"frames\": 5,"
                   " \"keyframes\": [{\"position\": [0, 2, 0]}, {\"position\": [2, 2, 0]},"
                   " {\"position\": [2, 2, 4]}]}}",
                   &f, &e);
    CHECK_INT(n, 5);
    /* t = i / 4 * 2 segments: 0, 0.5, 1, 1.5, 2. */
    const double want[5][3] = {{0, 2, 0}, {1, 2, 0}, {2, 2, 0}, {2, 2, 2}, {2, 2, 4}};
    for (int i = 0; f && i < n; i++) {
        CHECK_INT(f[i].light_count, 1);
        CHECK_INT(f[i].lights[0].field, JOB_LIGHT_POSITION);
        CHECK_STR(f[i].lights[0].light, "bulb");
        CHECK_NEAR(f[i].lights[0].value.x, want[i][0], 1e-12);
        CHECK_NEAR(f[i].lights[0].value.y, want[i][1], 1e-12);
        CHECK_NEAR(f[i].lights[0].value.z, want[i][2], 1e-12);
        CHECK_INT(f[i].camera.width, 64); /* the scene camera's size */
    }
    free(f);
    n = expand(s,
               "{\"scene\": \"x\", \"light_path\": {\"light\": \"bulb\", \"frames\": 2,"
               " \"keyframes\": [{\"direction\": [0, -1, 0]}, {\"direction\": [1, 0, 0]}]}}",
               &f, &e);
    CHECK_INT(n, -(int)REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(e.msg, "point light");
    free(f);
}

int main(void)
{
    struct scene *s = NULL;
    struct scene_limits lim = scene_limits_default();
    struct err e = {0};
    if (scene_parse(scene_doc, strlen(scene_doc), &lim, &s, &e) != REFRACT_E_OK)
        test_setup_failed("test_job_spec", e.msg);
    rotation();
    slerp();
    turntable(s);
    light_path(s);
    scene_destroy(s);
    return test_summary("test_job_spec");
}
