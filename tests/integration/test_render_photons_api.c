/*
 * test_render_photons_api.c - receiver.caustics "photons" through a real refractd
 * (docs/photons.md): the scene status says "photons" and a photon map per light; once the
 * map is ready a render shows the caustic where the photon tracer puts it (the brightest
 * floor pixel, far above the floor's direct light); moving the light moves the caustic (the
 * map is made for the new pose; test_photon_cache.c tests the cache itself); scenes the
 * photon tracer cannot
 * handle are refused with a message that names the field and what to do.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/env.h"
#include "daemon.h"
#include "irradiance_util.h"
#include "render_util.h"
#include "test.h"

#define W 80
#define H 60

/* A glass ball over a floor under a point light straight above: the caustic lies under
 * the ball, the floor near its paraxial focus (nR / (2 (n - 1)) = 1.5 R below the centre
 * for n = 1.5). The camera looks at the floor from the side, past the ball. */
static const char *const scene_doc =
    "{\"name\": \"photons\", \"camera\": {\"eye\": [3, 1.2, 0], \"look_at\": [0, -0.7, 0], "
    "\"fov_y_deg\": 50, \"width\": 80, \"height\": 60}, \"environment\": {\"intensity\": 0}, "
    "\"lights\": [{\"name\": \"lamp\", \"type\": \"point\", \"position\": [0, 6, 0], "
    "\"intensity\": 40}], "
    "\"receiver\": {\"height\": -0.8, \"half_size\": 4, \"caustics\": \"photons\", "
    "\"photons\": 262144}, "
    "\"surfaces\": [{\"name\": \"ball\", \"shape\": \"sphere\", \"center\": [0, 0, 0], "
    "\"radius\": 0.5, \"medium\": {\"ior\": 1.5}, \"brdf\": {\"type\": \"none\"}}]}";

/* The brightest pixel of an EXR render, and the image's median (the lit floor). */
static bool brightest(struct test_daemon *d, const char *id, int *col, int *row, double *peak,
                      double *typical)
{
    static float rgba[W * H * 4];
    if (!test_render_exr(d, id, W, H, rgba))
        return false;
    *peak = -1.0;
    int lit = 0;
    double sum = 0.0;
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            double v = rgba[(j * W + i) * 4 + 1];
            if (v > *peak) {
                *peak = v;
                *col = i;
                *row = j;
            }
            if (v > 0.0) {
                lit++;
                sum += v;
            }
        }
    *typical = lit > 0 ? sum / lit : 0.0;
    return true;
}

/* The pixel a world point lands on (the scene's camera). */
static void project(vec3 p, int *col, int *row)
{
    test_project(vec3_make(3, 1.2, 0), vec3_make(0, -0.7, 0), 50.0, W, H, p, col, row);
}

static void status_says_photons(struct test_daemon *d, const char *id)
{
    cJSON *st = irr_status(d, id);
    CHECK(st != NULL);
    CHECK_STR(irr_str(st, "caustics"), "photons");
    CHECK(cJSON_IsTrue(cJSON_GetObjectItem(st, "needed"))); /* a photon map per light */
    CHECK(cJSON_IsObject(cJSON_GetObjectItem(irr_light(st, "lamp"), "photon_map")));
    CHECK(cJSON_IsFalse(cJSON_GetObjectItem(st, "caustics_auto"))); /* the document said so */
    CHECK_STR(irr_str(st, "caustics_reason"), "given in the document");
    cJSON_Delete(st);
}

static void caustic_where_it_belongs(struct test_daemon *d, const char *id, vec3 focus)
{
    int col = -1, row = -1, want_col, want_row;
    double peak, typical;
    if (!brightest(d, id, &col, &row, &peak, &typical)) {
        CHECK(false);
        return;
    }
    project(focus, &want_col, &want_row);
    printf("caustic: brightest pixel (%d, %d) %.3f, expected near (%d, %d); mean lit %.3f\n", col,
           row, peak, want_col, want_row, typical);
    CHECK_MSG(abs(col - want_col) <= 3 && abs(row - want_row) <= 3,
              "brightest (%d, %d), expected (%d, %d)", col, row, want_col, want_row);
    CHECK_MSG(peak > 5.0 * typical, "peak %.3f vs mean %.3f", peak, typical);
}

/* Without "caustics" refractd chooses (docs/photons.md "Choosing") and says why: photons for
 * the glass ball, the light simulator once a voxel object joins, none for a clear ball. */
static void auto_choice(struct test_daemon *d)
{
    static const struct {
        const char *doc, *want, *reason;
    } cases[] = {
        {"{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": {\"ior\": "
         "1.5}}], \"lights\": [{\"type\": \"point\", \"position\": [0, 4, 0]}], "
         "\"receiver\": {\"height\": -2}}",
         "photons", "exact surfaces"},
        {"{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, "
         "\"resolution\": 8, \"ior\": 1.2}], \"lights\": [{\"type\": \"point\", \"position\": "
         "[0, 4, 0]}], \"receiver\": {\"height\": -2}}",
         "volume", "volume object"},
        {"{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": {\"ior\": "
         "1}}], \"lights\": [{\"type\": \"point\", \"position\": [0, 4, 0]}], "
         "\"receiver\": {\"height\": -2}}",
         "none", "no surface"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char id[REFRACT_ID_SIZE];
        CHECK(test_create_scene(d, cases[i].doc, id));
        cJSON *st = irr_status(d, id);
        CHECK_STR(irr_str(st, "caustics"), cases[i].want);
        CHECK(cJSON_IsTrue(cJSON_GetObjectItem(st, "caustics_auto")));
        CHECK_CONTAINS(irr_str(st, "caustics_reason"), cases[i].reason);
        CHECK(cJSON_IsTrue(cJSON_GetObjectItem(st, "needed")) == (strcmp(cases[i].want, "none") != 0));
        cJSON_Delete(st);
    }
}

static void refusals(struct test_daemon *d)
{
    static const struct {
        const char *doc, *needle;
    } bad[] = {
        {"{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": "
         "8, \"ior\": 1.2}], \"lights\": [{\"type\": \"point\", \"position\": [0, 4, 0]}], "
         "\"receiver\": {\"height\": -2, \"caustics\": \"photons\"}}",
         "volume object"},
        {"{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": {\"ior\": 1.3, "
         "\"scattering\": 0.5}}], \"receiver\": {\"height\": -2, \"caustics\": \"photons\"}}",
         "scattering"},
        {"{\"surfaces\": [{\"shape\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0], "
         "\"medium\": {\"ior\": 1.33}}], \"receiver\": {\"height\": -2, \"half_size\": 5, "
         "\"caustics\": "
         "\"photons\"}}",
         "infinite plane"},
        {"{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": {\"ior\": 1.5}}], "
         "\"receiver\": {\"height\": -2, \"caustics\": \"rays\"}}",
         "photons"},
        {"{\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": {\"ior\": 1.5}}], "
         "\"receiver\": {\"height\": -2, \"caustics\": \"photons\", \"photons\": 100}}",
         "receiver.photons"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        char *body = NULL;
        long status = test_request(d, "POST", "/v1/scenes", bad[i].doc, &body);
        CHECK_MSG(status == 400 && body && test_error_is(body, "invalid_field", bad[i].needle),
                  "case %zu: %ld %s", i, status, body ? body : "(none)");
        free(body);
    }
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL)) {
        fprintf(stderr, "daemon: %s\n", d.why);
        return 1;
    }
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, scene_doc, id));
    status_says_photons(&d, id);
    /* The light straight above: the focus under the ball's centre (renders never wait for
     * the map: wait for it here). */
    cJSON_Delete(irr_wait_ready(&d, id, 60));
    caustic_where_it_belongs(&d, id, vec3_make(0, -0.8, 0));
    /* Light moved to x = 2 (at y = 6): the caustic moves the other way, along the line
     * from the light through the ball's centre, to where that line meets the floor. */
    CHECK_INT(refract_light_put(d.client, id, "lamp",
                                "{\"type\": \"point\", \"position\": [2, 6, 0], \"intensity\": 40}",
                                NULL),
              REFRACT_E_OK);
    cJSON_Delete(irr_wait_ready(&d, id, 60));
    caustic_where_it_belongs(&d, id, vec3_make(-2.0 * 0.8 / 6.0, -0.8, 0));
    auto_choice(&d);
    refusals(&d);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_render_photons_api");
}
