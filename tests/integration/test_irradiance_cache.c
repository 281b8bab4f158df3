/*
 * test_irradiance_cache.c - the irradiance cache through a real refractd (issue 3,
 * "Irradiance cache and asynchronous recompute"), on a scene that needs light simulation
 * (an index-matched box over a receiver, lit straight down, 16-voxel light grid), with
 * --lightsim-chunk-steps 1 so a recompute spans tens of GPU work items:
 *   - creating the scene starts the recompute at once: queued/computing, then ready;
 *   - a PUT of the same pose (other intensity) is a hit: 200, nothing computed;
 *   - quantisation: a turn well below --light-direction-tolerance keeps the key (200), a
 *     turn well above it makes a new one (202, then ready); likewise a point light's
 *     moves against --light-position-tolerance (0.01 here), and a second light's
 *     changes leave the first one's volume alone;
 *   - progress is observable during a recompute (0 < progress < 1 with live patches,
 *     never decreasing);
 *   - colour and intensity are not in the key and scale the render linearly;
 *   - a render issued during a recompute answers promptly, flagged stale, and the status
 *     says "using": "previous"; after the recompute it is flagged ready;
 *   - supersession: two quick pose changes compute only the newest (the first is
 *     counted superseded and never reaches the disk);
 *   - the EXR download decodes with io's EXR reader: its grid is the status's, the
 *     irradiance is E = 1 (unit light, normal incidence, index-matched medium) inside the
 *     beam and the direction (0, -1, 0);
 *   - a scene that needs no light simulation reports not_needed and renders say so;
 *   - the simulator's input fields were built once for all those poses (the log).
 */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "io/io_exr.h"
#include "io/io_image.h"
#include "irradiance_util.h"

static const char sun_down[] =
    "[{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0, -1, 0]}]";

/* PUT /v1/scenes/{id}/lights/sun with `light`; returns the answer's status and, in
 * key_out (17 bytes), the light's key. */
static long put_sun(const struct test_daemon *d, const char *id, const char *light, char *key_out)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/lights/sun", id);
    struct irr_answer a = irr_http(d, "PUT", path, light);
    cJSON *root = cJSON_Parse(a.body ? a.body : "");
    snprintf(key_out, 17, "%s", irr_str(irr_light(root, "sun"), "key"));
    CHECK_MSG(a.status == 200 || a.status == 202, "PUT %s: %ld %s", path, a.status,
              a.body ? a.body : "");
    cJSON_Delete(root);
    free(a.body);
    return a.status;
}

/* Renders the scene's default view as EXR; returns the sum of each channel over the image
 * and the X-Refract-Irradiance header. */
static void render_sum(const struct test_daemon *d, const char *id, double sum[3], char *irradiance,
                       size_t size, double *seconds)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    struct irr_answer a = irr_http(d, "POST", path, "{\"format\": \"exr\"}");
    CHECK_MSG(a.status == 200, "render: %ld %s", a.status, a.status != 200 && a.body ? a.body : "");
    snprintf(irradiance, size, "%s", a.irradiance);
    if (seconds)
        *seconds = a.seconds;
    sum[0] = sum[1] = sum[2] = 0;
    struct io_image img = {0};
    struct err e = {0};
    if (a.status == 200 &&
        IRR_CHECK(io_image_decode(a.body, a.len, 1 << 20, &img, &e) == REFRACT_E_OK, e.msg)) {
        for (int i = 0; i < img.width * img.height; i++) {
            for (int c = 0; c < 3; c++)
                sum[c] += img.rgba[i * 4 + c];
        }
    }
    io_image_free(&img);
    free(a.body);
}

static void first_compute_and_hit(struct test_daemon *d, const char *id)
{
    cJSON *st = irr_status(d, id);
    const char *state = irr_str(irr_light(st, "sun"), "state");
    CHECK_MSG(strcmp(state, "queued") == 0 || strcmp(state, "computing") == 0 ||
                  strcmp(state, "ready") == 0,
              "right after the create: state %s", state);
    CHECK(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(st, "needed")));
    cJSON_Delete(st);
    st = irr_wait_ready(d, id, 30);
    const cJSON *sun = irr_light(st, "sun");
    CHECK_STR(irr_str(sun, "using"), "current");
    CHECK(irr_num(sun, "compute_ms") > 0);
    CHECK(irr_num(sun, "gpu_bytes") > 0);
    CHECK_NEAR(irr_num(sun, "progress"), 1.0, 1e-12);
    const cJSON *stats = cJSON_GetObjectItemCaseSensitive(sun, "stats");
    CHECK(irr_num(stats, "steps") > 0);
    CHECK_NEAR(irr_counter(st, "computed"), 1, 0);
    char key[17];
    snprintf(key, sizeof key, "%s", irr_str(sun, "key"));
    cJSON_Delete(st);

    /* The same pose, three times brighter: a hit. */
    char again[17];
    CHECK_INT(put_sun(d, id,
                      "{\"type\": \"directional\", \"direction\": [0, -1, 0], \"intensity\": 3}",
                      again),
              200);
    CHECK_STR(again, key);
    st = irr_status(d, id);
    CHECK_STR(irr_str(irr_light(st, "sun"), "state"), "ready");
    CHECK_NEAR(irr_counter(st, "computed"), 1, 0);
    cJSON_Delete(st);
}

static void quantisation(struct test_daemon *d, const char *id)
{
    char k0[17], k1[17], k2[17];
    CHECK_INT(put_sun(d, id, "{\"type\": \"directional\", \"direction\": [0, -1, 0]}", k0), 200);
    /* 1e-4 rad: a tenth of the default tolerance. */
    CHECK_INT(put_sun(d, id, "{\"type\": \"directional\", \"direction\": [0.0001, -1, 0]}", k1),
              200);
    CHECK_STR(k1, k0);
    /* 0.02 rad: twenty tolerances. */
    CHECK_INT(put_sun(d, id, "{\"type\": \"directional\", \"direction\": [0.02, -1, 0]}", k2), 202);
    CHECK(strcmp(k2, k0) != 0);
    cJSON *st = irr_wait_ready(d, id, 30);
    CHECK_STR(irr_str(irr_light(st, "sun"), "key"), k2);
    CHECK_NEAR(irr_counter(st, "computed"), 2, 0);
    cJSON_Delete(st);
    /* Back to the first pose: still cached. */
    CHECK_INT(put_sun(d, id, "{\"type\": \"directional\", \"direction\": [0, -1, 0]}", k1), 200);
    CHECK_STR(k1, k0);
}

static void colour_scales_linearly(struct test_daemon *d, const char *id)
{
    char key[17], irr[32];
    double s1[3], s2[3], sc[3];
    CHECK_INT(put_sun(d, id, "{\"type\": \"directional\", \"direction\": [0, -1, 0]}", key), 200);
    render_sum(d, id, s1, irr, sizeof irr, NULL);
    CHECK_STR(irr, "ready");
    CHECK_MSG(s1[0] > 0 && s1[1] > 0 && s1[2] > 0, "the lit receiver is black: %g %g %g", s1[0],
              s1[1], s1[2]);
    CHECK_INT(put_sun(d, id,
                      "{\"type\": \"directional\", \"direction\": [0, -1, 0], \"intensity\": 2.5}",
                      key),
              200);
    render_sum(d, id, s2, irr, sizeof irr, NULL);
    CHECK_STR(irr, "ready");
    CHECK_INT(put_sun(d, id,
                      "{\"type\": \"directional\", \"direction\": [0, -1, 0], \"color\": [1, 0.5, "
                      "0.25]}",
                      key),
              200);
    render_sum(d, id, sc, irr, sizeof irr, NULL);
    static const double tint[3] = {1, 0.5, 0.25};
    for (int c = 0; c < 3; c++) {
        CHECK_NEAR(s2[c] / s1[c], 2.5, 1e-4);
        CHECK_NEAR(sc[c] / s1[c], tint[c], 1e-4);
    }
    printf("render sum (unit sun): %.4f %.4f %.4f; x2.5: ratio %.6f\n", s1[0], s1[1], s1[2],
           s2[0] / s1[0]);
    cJSON *st = irr_status(d, id);
    CHECK_NEAR(irr_counter(st, "computed"), 2, 0);
    cJSON_Delete(st);
}

static void stale_render_during_recompute(struct test_daemon *d, const char *id)
{
    char key[17], irr[32];
    double sum[3], seconds = 0;
    CHECK_INT(put_sun(d, id, "{\"type\": \"directional\", \"direction\": [0, -1, 0.05]}", key),
              202);
    render_sum(d, id, sum, irr, sizeof irr, &seconds);
    CHECK_STR(irr, "stale");
    CHECK_MSG(seconds < 10, "the render took %.2f s", seconds);
    CHECK_MSG(sum[0] > 0, "a stale render still shows the previous pose's light");
    cJSON *st = irr_status(d, id);
    const cJSON *sun = irr_light(st, "sun");
    char *text = cJSON_PrintUnformatted(sun);
    CHECK_MSG(strcmp(irr_str(sun, "state"), "ready") == 0 ||
                  strcmp(irr_str(sun, "using"), "previous") == 0,
              "during the recompute: %s", text);
    free(text);
    cJSON_Delete(st);
    /* Progress is observable while it computes: poll as fast as the API answers. */
    bool seen_progress = false;
    double last_progress = 0;
    struct timespec watch_start, watch_end;
    clock_gettime(CLOCK_MONOTONIC, &watch_start);
    for (int i = 0; i < 100000; i++) {
        st = irr_status(d, id);
        sun = irr_light(st, "sun");
        double progress = irr_num(sun, "progress");
        bool ready = strcmp(irr_str(sun, "state"), "ready") == 0;
        if (!ready && progress > 0 && progress < 1 && irr_num(sun, "patches_live") > 0) {
            seen_progress = true;
            CHECK(progress >= last_progress); /* the swept fraction never shrinks */
            last_progress = progress;
        }
        double ms = irr_num(sun, "compute_ms");
        cJSON_Delete(st);
        if (ready) {
            /* How long the polls watched it compute: the stale render above takes part of
             * the recompute (most of it on a loaded machine), and on a GPU fast enough to
             * finish between two polls nothing can be seen. Progress moves once per chunk
             * of wavefront steps, so a third of a second of watching must see it. */
            clock_gettime(CLOCK_MONOTONIC, &watch_end);
            double watched_ms = 1e3 * (double)(watch_end.tv_sec - watch_start.tv_sec) +
                                1e-6 * (double)(watch_end.tv_nsec - watch_start.tv_nsec);
            if (ms > 150 && watched_ms > 300)
                CHECK_MSG(seen_progress,
                          "a %.0f ms recompute watched for %.0f ms showed no "
                          "progress",
                          ms, watched_ms);
            printf("recompute %.1f ms, watched %.0f ms; progress seen: %s (last %.3f)\n", ms,
                   watched_ms, seen_progress ? "yes" : "no", last_progress);
            break;
        }
    }
    cJSON_Delete(irr_wait_ready(d, id, 30));
    render_sum(d, id, sum, irr, sizeof irr, NULL);
    CHECK_STR(irr, "ready");
    printf("render during a recompute: %.3f s, flagged stale\n", seconds);
}

static void supersession(struct test_daemon *d, const char *id)
{
    cJSON *st = irr_status(d, id);
    double computed = irr_counter(st, "computed"), superseded = irr_counter(st, "superseded");
    cJSON_Delete(st);
    char first[17], second[17];
    CHECK_INT(put_sun(d, id, "{\"type\": \"directional\", \"direction\": [0.1, -1, 0]}", first),
              202);
    CHECK_INT(put_sun(d, id, "{\"type\": \"directional\", \"direction\": [0.2, -1, 0]}", second),
              202);
    st = irr_wait_ready(d, id, 30);
    CHECK_STR(irr_str(irr_light(st, "sun"), "key"), second);
    CHECK_NEAR(irr_counter(st, "computed"), computed + 1, 0);
    CHECK_NEAR(irr_counter(st, "superseded"), superseded + 1, 0);
    cJSON_Delete(st);
    char path[512];
    struct stat sb;
    snprintf(path, sizeof path, "%s/irradiance/%s.exr", d->data_dir, first);
    CHECK_MSG(stat(path, &sb) != 0, "the superseded pose was computed: %s exists", path);
    /* The worker writes a finished volume to disk just after it is ready. */
    snprintf(path, sizeof path, "%s/irradiance/%s.json", d->data_dir, second);
    for (int i = 0; i < 250 && stat(path, &sb) != 0; i++)
        nanosleep(&(struct timespec){0, 20 * 1000 * 1000}, NULL);
    CHECK_MSG(stat(path, &sb) == 0, "the newest pose is not on disk: %s", path);
}

static void exr_download(struct test_daemon *d, const char *id)
{
    char key[17];
    put_sun(d, id, "{\"type\": \"directional\", \"direction\": [0, -1, 0]}", key);
    cJSON_Delete(irr_wait_ready(d, id, 30));
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/irradiance/sun.exr", id);
    struct irr_answer a = irr_http(d, "GET", path, NULL);
    CHECK_INT(a.status, 200);
    CHECK_STR(a.irradiance, "ready");
    static const char *const names[] = {"R", "G", "B", "dir.X", "dir.Y", "dir.Z", "dir.W"};
    float *px = NULL;
    int w = 0, h = 0;
    char grid_text[512];
    struct err e = {0};
    if (a.status != 200 || !IRR_CHECK(io_decode_exr_channels(a.body, a.len, 7, names, 1 << 24, &px,
                                                             &w, &h, "refract.grid", grid_text,
                                                             sizeof grid_text, &e) == REFRACT_E_OK,
                                      e.msg)) {
        free(a.body);
        return;
    }
    cJSON *grid = cJSON_Parse(grid_text);
    const cJSON *dims = cJSON_GetObjectItemCaseSensitive(grid, "dims");
    int nx = (int)cJSON_GetArrayItem(dims, 0)->valuedouble;
    int ny = (int)cJSON_GetArrayItem(dims, 1)->valuedouble;
    int nz = (int)cJSON_GetArrayItem(dims, 2)->valuedouble;
    CHECK_INT(w, nx);
    CHECK_INT(h, ny * nz);
    /* resolution 16 along the longest axis (y: from the receiver at -1 to the box's top at
     * 0.5, 12 voxels of 0.125 and the pad); x: the box's footprint under the light
     * straight down (8 voxels), the pad and the receiver margin (docs/lightsim.md "Domain") */
    CHECK_INT(nx, 16);
    CHECK_INT(ny, 16);
    double voxel = irr_num(grid, "voxel");
    const cJSON *bmin = cJSON_GetObjectItemCaseSensitive(grid, "bmin");
    double y0 = cJSON_GetArrayItem(bmin, 1)->valuedouble;
    /* Interior voxels above the receiver, away from the domain's padded edges (the beam
     * covers the whole domain's cross-section): E = 1, direction (0, -1, 0). */
    double sum = 0, dir_err = 0;
    int count = 0;
    for (int k = 3; k < nz - 3; k++) {
        for (int j = 0; j < ny; j++) {
            double yc = y0 + (j + 0.5) * voxel;
            if (yc < -0.8 || yc > 0.4)
                continue;
            for (int i = 3; i < nx - 3; i++) {
                const float *p = px + ((size_t)(k * ny + j) * nx + i) * 7;
                sum += p[0];
                dir_err = fmax(dir_err, fabs(p[4] + 1.0));
                CHECK_NEAR(p[6], 1.0, 1e-6);
                CHECK_NEAR(p[0], p[1], 1e-6);
                count++;
            }
        }
    }
    CHECK(count > 100);
    double mean = sum / count;
    CHECK_NEAR(mean, 1.0, 0.05);
    CHECK(dir_err < 1e-3);
    printf("EXR %dx%d (%dx%dx%d voxels of %.4f): mean E %.4f over %d beam voxels, |dir.y + 1| "
           "<= %.2e\n",
           w, h, nx, ny, nz, voxel, mean, count, dir_err);
    cJSON_Delete(grid);
    free(px);
    free(a.body);
}

/* A point light: positions are rounded to --light-position-tolerance (here 0.01). */
static void point_light_positions(struct test_daemon *d, const char *id)
{
    char path[128], k0[17], k1[17], k2[17];
    snprintf(path, sizeof path, "/v1/scenes/%s/lights/bulb", id);
    static const char *const poses[] = {
        "{\"type\": \"point\", \"position\": [0, 2, 0]}",
        "{\"type\": \"point\", \"position\": [0.002, 2, -0.001], \"intensity\": 7}",
        "{\"type\": \"point\", \"position\": [0.05, 2, 0]}"};
    char *keys[] = {k0, k1, k2};
    long want[] = {202, 200, 202};
    for (int i = 0; i < 3; i++) {
        struct irr_answer a = irr_http(d, "PUT", path, poses[i]);
        CHECK_INT(a.status, want[i]);
        cJSON *root = cJSON_Parse(a.body ? a.body : "");
        snprintf(keys[i], 17, "%s", irr_str(irr_light(root, "bulb"), "key"));
        CHECK_STR(irr_str(irr_light(root, "sun"), "state"), "ready"); /* the sun is untouched */
        cJSON_Delete(root);
        free(a.body);
        cJSON_Delete(irr_wait_ready(d, id, 30));
    }
    CHECK_STR(k1, k0);
    CHECK(strcmp(k2, k0) != 0);
}

static void not_needed(struct test_daemon *d)
{
    static const char scene[] =
        "{\"name\": \"glass\", \"camera\": {\"width\": 16, \"height\": 12},"
        " \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": "
        "8,"
        " \"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}}],"
        " \"lights\": [{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0, -1, 0]}]}";
    char id[REFRACT_ID_SIZE];
    if (!IRR_CHECK(test_create_scene(d, scene, id), "create the glass scene"))
        return;
    cJSON *st = irr_status(d, id);
    CHECK(cJSON_IsFalse(cJSON_GetObjectItemCaseSensitive(st, "needed")));
    CHECK_STR(irr_str(irr_light(st, "sun"), "state"), "not_needed");
    cJSON_Delete(st);
    char key[17], irr[32];
    double sum[3];
    CHECK_INT(put_sun(d, id, "{\"type\": \"directional\", \"direction\": [0.5, -1, 0]}", key), 200);
    render_sum(d, id, sum, irr, sizeof irr, NULL);
    CHECK_STR(irr, "not-needed");
}

int main(void)
{
    struct test_daemon d;
    const char *args[] = {"--lightsim-chunk-steps", "1", "--light-position-tolerance", "0.01",
                          NULL};
    if (!test_daemon_start(&d, args))
        test_setup_failed("test_irradiance_cache", d.why);
    char *scene = beam_scene(sun_down);
    char id[REFRACT_ID_SIZE] = "";
    CHECK(test_create_scene(&d, scene, id));
    free(scene);
    if (id[0]) {
        first_compute_and_hit(&d, id);
        quantisation(&d, id);
        colour_scales_linearly(&d, id);
        stale_render_during_recompute(&d, id);
        supersession(&d, id);
        exr_download(&d, id);
        point_light_positions(&d, id);
    }
    /* Every pose above shares one transport, but with a receiver each light pose has its
     * own light grid (the objects' footprint as that light sees it, docs/lightsim.md
     * "Domain"), so the input fields are built once per grid: at most once per computed
     * volume, and a pose whose grid is kept builds nothing. */
    double computed = 0;
    if (id[0]) {
        cJSON *st = irr_status(&d, id);
        computed = st ? irr_counter(st, "computed") : 0;
        cJSON_Delete(st);
    }
    not_needed(&d);
    FILE *log = fopen(d.log_path, "r");
    int builds = 0;
    char line[2048];
    while (log && fgets(line, sizeof line, log))
        builds += strstr(line, "light fields") != NULL;
    if (log)
        fclose(log);
    printf("light fields built %d times for %.0f computed volumes\n", builds, computed);
    CHECK(builds >= 1 && builds <= computed);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_irradiance_cache");
}
