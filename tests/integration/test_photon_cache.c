/*
 * test_photon_cache.c - lights' photon maps in the irradiance cache through a real refractd
 * (docs/photons.md "The cache"; issue 15 item 3):
 *
 *   - a new scene's map is made ahead, without a render asking, in passes whose
 *     irradiance.ready events (one per pass, "refining" until the last) carry growing photon
 *     counts; the status then says ready, 3 of 3 passes, not refining;
 *   - a light moved: the render right after it is flagged stale and shows the old caustic,
 *     the new pose's passes follow, and then the caustic is where the new pose puts it;
 *   - a live view follows: it renders again as the new pose's map arrives, its newest frame
 *     "ready";
 *   - a pose seen before is a hit: the light put back answers 200 (not 202), nothing is
 *     computed, the render is "ready" at once with the first caustic;
 *   - after a restart the maps come from the data directory (loaded_from_disk), and the
 *     render is the same picture; maps on disk cut short are refused and made again.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/env.h"
#include "daemon.h"
#include "io/io_image.h"
#include "irradiance_util.h"
#include "sse_util.h"
#include "render_util.h"
#include "test.h"
#include "view_util.h"

#define W 80
#define H 60
#define PHOTONS 4194304 /* the first pass (2^18) takes longer than a render */

/* The ball over a floor of test_render_photons_api.c: the caustic lies where the line from
 * the lamp through the ball's centre meets the floor. */
static const char *const scene_doc =
    "{\"name\": \"photon cache\", \"camera\": {\"eye\": [3, 1.2, 0], \"look_at\": [0, -0.7, 0], "
    "\"fov_y_deg\": 50, \"width\": 80, \"height\": 60}, \"environment\": {\"intensity\": 0}, "
    "\"lights\": [{\"name\": \"lamp\", \"type\": \"point\", \"position\": [0, 6, 0], "
    "\"intensity\": 40}], "
    "\"receiver\": {\"height\": -0.8, \"half_size\": 4, \"caustics\": \"photons\", "
    "\"photons\": 4194304}, "
    "\"surfaces\": [{\"name\": \"ball\", \"shape\": \"sphere\", \"center\": [0, 0, 0], "
    "\"radius\": 0.5, \"medium\": {\"ior\": 1.5}, \"brdf\": {\"type\": \"none\"}}]}";

static const char *const lamp_above = "{\"type\": \"point\", \"position\": [0, 6, 0], "
                                      "\"intensity\": 40}";
static const char *const lamp_moved = "{\"type\": \"point\", \"position\": [2, 6, 0], "
                                      "\"intensity\": 40}";

/* The pixel a world point lands on (the scene's camera). */
static void project(vec3 p, int *col, int *row)
{
    test_project(vec3_make(3, 1.2, 0), vec3_make(0, -0.7, 0), 50.0, W, H, p, col, row);
}

/* The caustic's focus on the floor for a lamp at (lx, 6, 0). */
static void focus_pixel(double lx, int *col, int *row)
{
    project(vec3_make(-lx * 0.8 / 6.0, -0.8, 0), col, row);
}

struct picture {
    char irradiance[32]; /* X-Refract-Irradiance */
    int col, row;        /* the brightest pixel */
    double peak, mean;
    double sum; /* of the green channel */
};

/* POST .../render as EXR; false when it did not answer 200 with a W x H image. */
static bool render(struct test_daemon *d, const char *id, struct picture *p)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    struct irr_answer a = irr_http(d, "POST", path, "{\"format\": \"exr\"}");
    memset(p, 0, sizeof *p);
    snprintf(p->irradiance, sizeof p->irradiance, "%s", a.irradiance);
    struct io_image px = {0};
    struct err e = {0};
    bool ok = a.status == 200 &&
              io_image_decode(a.body, a.len, 1 << 24, &px, &e) == REFRACT_E_OK &&
              px.width == W && px.height == H;
    if (!ok)
        fprintf(stderr, "render: %ld %s %s\n", a.status, e.msg, a.status != 200 ? a.body : "");
    free(a.body);
    p->peak = -1.0;
    int lit = 0;
    for (int i = 0; ok && i < W * H; i++) {
        double v = px.rgba[i * 4 + 1];
        p->sum += v;
        if (v > p->peak) {
            p->peak = v;
            p->col = i % W;
            p->row = i / W;
        }
        lit += v > 0.0;
    }
    p->mean = lit > 0 ? p->sum / lit : 0.0;
    io_image_free(&px);
    return ok;
}

static void check_caustic(const struct picture *p, double lx, const char *what)
{
    int want_col, want_row;
    focus_pixel(lx, &want_col, &want_row);
    printf("%s: %s, brightest pixel (%d, %d) %.3f, expected near (%d, %d); mean lit %.3f\n", what,
           p->irradiance, p->col, p->row, p->peak, want_col, want_row, p->mean);
    CHECK_MSG(abs(p->col - want_col) <= 3 && abs(p->row - want_row) <= 3,
              "%s: brightest (%d, %d), expected (%d, %d)", what, p->col, p->row, want_col,
              want_row);
    CHECK_MSG(p->peak > 5.0 * p->mean, "%s: peak %.3f vs mean %.3f", what, p->peak, p->mean);
}

/* Reads irradiance.ready events of the lamp until one that is not refining: each pass's,
 * with growing photon counts, the last with `final_photons`. Returns the passes seen. */
static int passes_until(struct sse_client *c, const char *scene, const char *key,
                        double final_photons, double timeout_s)
{
    int passes = 0;
    double last_photons = 0.0;
    struct sse_event ev;
    while (sse_until(c, "irradiance.ready", timeout_s, &ev, NULL, NULL, 0)) {
        cJSON *o = cJSON_Parse(ev.data);
        if ((key && strcmp(sse_str(o, "key"), key) != 0) ||
            (scene && strcmp(sse_str(o, "scene"), scene) != 0)) {
            cJSON_Delete(o); /* another pose's or scene's */
            continue;
        }
        double photons = sse_num(o, "photons");
        bool refining = cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(o, "refining"));
        printf("  irradiance.ready: key %s, %.0f photons%s\n", sse_str(o, "key"), photons,
               refining ? ", refining" : "");
        CHECK_MSG(photons > last_photons, "pass %d: %.0f photons after %.0f", passes + 1, photons,
                  last_photons);
        last_photons = photons;
        passes++;
        cJSON_Delete(o);
        if (!refining) {
            CHECK_NEAR(photons, final_photons, 0);
            return passes;
        }
    }
    CHECK_MSG(false, "no final irradiance.ready in %.0f s after %d passes", timeout_s, passes);
    return passes;
}

static int passes_until_final(struct sse_client *c, const char *key, double timeout_s)
{
    return passes_until(c, NULL, key, PHOTONS, timeout_s);
}

/* PUT the lamp; returns the HTTP status and the lamp's key after it. */
static long put_lamp(struct test_daemon *d, const char *id, const char *light, char *key,
                     char *state, char *using_)
{
    char path[160];
    snprintf(path, sizeof path, "/v1/scenes/%s/lights/lamp", id);
    struct irr_answer a = irr_http(d, "PUT", path, light);
    cJSON *st = a.body ? cJSON_Parse(a.body) : NULL;
    const cJSON *lamp = irr_light(st, "lamp");
    snprintf(key, 17, "%s", irr_str(lamp, "key"));
    snprintf(state, 16, "%s", irr_str(lamp, "state"));
    snprintf(using_, 16, "%s", irr_str(lamp, "using"));
    cJSON_Delete(st);
    free(a.body);
    return a.status;
}

/* receiver.photons_max: past its pass of `photons` the map goes on refining, each pass
 * adding `photons` more to all before it (docs/photons.md "The cache"), until photons_max;
 * then it is persisted like any map. */
static void refines_up_to_photons_max(struct test_daemon *d)
{
    static const char doc[] =
        "{\"name\": \"photons_max\", \"camera\": {\"eye\": [3, 1.2, 0], \"look_at\": [0, -0.7, "
        "0], \"fov_y_deg\": 50, \"width\": 80, \"height\": 60}, \"environment\": "
        "{\"intensity\": 0}, \"lights\": [{\"name\": \"lamp\", \"type\": \"point\", "
        "\"position\": [0, 6, 0], \"intensity\": 40}], \"receiver\": {\"height\": -0.8, "
        "\"half_size\": 4, \"photons\": 65536, \"photons_max\": 400000}, \"surfaces\": "
        "[{\"name\": \"ball\", \"shape\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 0.5, "
        "\"medium\": {\"ior\": 1.5}, \"brdf\": {\"type\": \"none\"}}]}";
    char id[REFRACT_ID_SIZE];
    struct sse_client sse;
    /* Opened before the scene exists, so the daemon-wide stream. */
    CHECK(sse_open(&sse, d, "/v1/events", NULL));
    CHECK(test_create_scene(d, doc, id));
    /* 4096, 16384, 65536 photons, then 131072, 262144 and 400000 accumulated */
    CHECK_INT(passes_until(&sse, id, NULL, 400000, 120), 6);
    sse_close(&sse);
    cJSON *st = irr_wait_ready(d, id, 60);
    const cJSON *map = cJSON_GetObjectItemCaseSensitive(irr_light(st, "lamp"), "photon_map");
    CHECK_NEAR(irr_num(map, "passes"), 6, 0);
    CHECK_NEAR(irr_num(map, "passes_total"), 6, 0);
    CHECK_NEAR(irr_num(map, "photons"), 400000, 0);
    CHECK_STR(irr_str(st, "caustics"), "photons"); /* chosen: no "caustics" in the document */
    cJSON_Delete(st);
    struct picture p;
    CHECK(render(d, id, &p));
    CHECK_STR(p.irradiance, "ready");
    check_caustic(&p, 0.0, "photons_max");

    /* Left while accumulating, the pose stops after its pass (its photon list is dropped);
     * back again, it traces that list anew and goes on to photons_max. */
    static const char doc2[] =
        "{\"name\": \"resume\", \"environment\": {\"intensity\": 0}, \"lights\": "
        "[{\"name\": \"lamp\", \"type\": \"point\", \"position\": [0, 6, 0], \"intensity\": "
        "40}], \"receiver\": {\"height\": -0.8, \"half_size\": 4, \"photons\": 65536, "
        "\"photons_max\": 4194304}, \"surfaces\": [{\"shape\": \"sphere\", \"radius\": 0.5, "
        "\"medium\": {\"ior\": 1.5}}]}";
    CHECK(sse_open(&sse, d, "/v1/events", NULL));
    CHECK(test_create_scene(d, doc2, id));
    struct sse_event ev;
    bool accumulating = false;
    while (!accumulating && sse_until(&sse, "irradiance.ready", 60, &ev, NULL, NULL, 0)) {
        cJSON *o = cJSON_Parse(ev.data);
        accumulating = strcmp(sse_str(o, "scene"), id) == 0 && sse_num(o, "photons") > 65536;
        cJSON_Delete(o);
    }
    CHECK(accumulating);
    sse_close(&sse);
    char key[17], state[16], using_[16];
    CHECK_INT(put_lamp(d, id, lamp_moved, key, state, using_), 202);
    cJSON_Delete(irr_wait_ready(d, id, 120)); /* the moved pose, to its photons_max */
    CHECK_INT(put_lamp(d, id, lamp_above, key, state, using_), 202); /* usable, not done */
    CHECK_STR(state, "ready");
    st = irr_wait_ready(d, id, 120);
    map = cJSON_GetObjectItemCaseSensitive(irr_light(st, "lamp"), "photon_map");
    CHECK_NEAR(irr_num(map, "photons"), 4194304, 0);
    CHECK_NEAR(irr_num(map, "passes"), irr_num(map, "passes_total"), 0);
    CHECK_NEAR(irr_num(map, "passes_total"), 3 + 6, 0);
    cJSON_Delete(st);
}

static const cJSON *map_of(const cJSON *status)
{
    return cJSON_GetObjectItemCaseSensitive(irr_light(status, "lamp"), "photon_map");
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_photon_cache", d.why);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, scene_doc, id));
    char events[160];
    snprintf(events, sizeof events, "/v1/scenes/%s/events", id);
    struct sse_client sse;
    CHECK(sse_open(&sse, &d, events, NULL));

    /* Made ahead: no render asked for it. */
    CHECK_INT(passes_until_final(&sse, NULL, 120), 3);
    cJSON *st = irr_wait_ready(&d, id, 60);
    const cJSON *map = map_of(st);
    CHECK_NEAR(irr_num(map, "passes"), 3, 0);
    CHECK_NEAR(irr_num(map, "photons"), PHOTONS, 0);
    CHECK(irr_num(map, "landed") > 1000);
    CHECK(irr_num(irr_light(st, "lamp"), "host_bytes") > 0);
    CHECK_NEAR(irr_counter(st, "computed"), 1, 0);
    char first_key[17];
    snprintf(first_key, sizeof first_key, "%s", irr_str(irr_light(st, "lamp"), "key"));
    cJSON_Delete(st);
    struct picture above;
    CHECK(render(&d, id, &above));
    CHECK_STR(above.irradiance, "ready");
    check_caustic(&above, 0.0, "lamp above");

    /* A live view of the scene, idle at its first frame. */
    char vid[32];
    CHECK_INT(view_open(&d, id, "{}", vid, NULL), 201);
    double seq0 = view_wait_seq(&d, vid, 1, 60000);
    CHECK(seq0 >= 1);

    /* The lamp moved: the old caustic until the new map's first pass, then the new one. */
    char key[17], state[16], using_[16];
    CHECK_INT(put_lamp(&d, id, lamp_moved, key, state, using_), 202);
    CHECK(strcmp(key, first_key) != 0);
    struct picture stale;
    CHECK(render(&d, id, &stale));
    CHECK_STR(stale.irradiance, "stale");
    check_caustic(&stale, 0.0, "just moved (the previous pose's map)");
    int passes = passes_until_final(&sse, key, 120);
    CHECK_INT(passes, 3);
    st = irr_wait_ready(&d, id, 60);
    CHECK_STR(irr_str(irr_light(st, "lamp"), "using"), "current");
    CHECK_NEAR(irr_counter(st, "computed"), 2, 0);
    cJSON_Delete(st);
    struct picture moved;
    CHECK(render(&d, id, &moved));
    CHECK_STR(moved.irradiance, "ready");
    check_caustic(&moved, 2.0, "moved, refined");
    /* The view rendered the move and again as the new map came: at least two frames, the
     * newest lit by the finished map. */
    double seq1 = view_wait_seq(&d, vid, seq0 + 2, 60000);
    CHECK_MSG(seq1 >= seq0 + 2, "the view's frames went from %.0f to %.0f", seq0, seq1);
    cJSON *vs = view_status(&d, vid);
    const cJSON *frame = cJSON_GetObjectItemCaseSensitive(vs, "frame");
    CHECK_STR(irr_str(frame, "irradiance"), "ready");
    printf("view: frames %.0f to %.0f across the move\n", seq0, seq1);
    cJSON_Delete(vs);

    /* Back to a pose seen before: a hit, nothing computed, the first picture at once. */
    CHECK_INT(put_lamp(&d, id, lamp_above, key, state, using_), 200);
    CHECK_STR(key, first_key);
    CHECK_STR(state, "ready");
    CHECK_STR(using_, "current");
    struct picture again;
    CHECK(render(&d, id, &again));
    CHECK_STR(again.irradiance, "ready");
    CHECK_NEAR(again.sum, above.sum, 1e-6 * above.sum);
    st = irr_status(&d, id);
    CHECK_NEAR(irr_counter(st, "computed"), 2, 0);
    CHECK(!cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(map_of(st), "refining")));
    cJSON_Delete(st);
    sse_close(&sse);
    refines_up_to_photons_max(&d);
    CHECK_INT(test_daemon_stop(&d), 0);

    /* A restart: the map comes from the data directory, the same picture. */
    struct test_daemon d2;
    test_daemon_restart(&d, &d2, "test_photon_cache (restart)");
    st = irr_wait_loaded(&d2, id, "lamp", 30);
    CHECK_NEAR(irr_counter(st, "computed"), 0, 0);
    CHECK_NEAR(irr_num(map_of(st), "photons"), PHOTONS, 0);
    cJSON_Delete(st);
    struct picture restarted;
    CHECK(render(&d2, id, &restarted));
    CHECK_STR(restarted.irradiance, "ready");
    /* The map on disk holds E in double, as made: the same picture to float precision. */
    CHECK_NEAR(restarted.sum, above.sum, 1e-5 * above.sum);
    printf("render sums: first %.6f, again %.6f, after a restart %.6f\n", above.sum, again.sum,
           restarted.sum);
    CHECK_INT(test_daemon_stop(&d2), 0);

    /* Maps on disk that are not what refractd wrote (cut short): refused when read back,
     * made again, the same picture. */
    char cmd[700];
    snprintf(cmd, sizeof cmd, "for f in '%s'/irradiance/*.pmap; do head -c 30 \"$f\" > \"$f.cut\" "
             "&& mv \"$f.cut\" \"$f\"; done", d.data_dir);
    CHECK_INT(system(cmd), 0);
    struct test_daemon d3;
    test_daemon_restart(&d, &d3, "test_photon_cache (cut files)");
    struct picture cut;
    CHECK(render(&d3, id, &cut)); /* reads the file back: refused, the entry dropped */
    CHECK(render(&d3, id, &cut)); /* asks for the map again */
    cJSON_Delete(irr_wait_ready(&d3, id, 60));
    st = irr_status(&d3, id);
    CHECK_NEAR(irr_counter(st, "computed"), 1, 0);
    cJSON_Delete(st);
    CHECK(render(&d3, id, &cut));
    CHECK_STR(cut.irradiance, "ready");
    CHECK_NEAR(cut.sum, above.sum, 1e-5 * above.sum);
    CHECK_INT(test_daemon_stop(&d3), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_photon_cache");
}
