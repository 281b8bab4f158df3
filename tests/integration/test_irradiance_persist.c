/*
 * test_irradiance_persist.c - irradiance volumes leave memory and come back from the data
 * directory instead of being recomputed:
 *   - under a 1-byte GPU and host budget, a second pose evicts the first from both
 *     memories (the counters say so); asking for the first pose again is a hit (200),
 *     read back from <data>/irradiance (loaded_from_disk, the "loaded" counter, the
 *     original compute_ms), with nothing recomputed; a render then uses it ("ready") and
 *     gives the same image as before the eviction;
 *   - after a restart on the same data directory the scene's volume is ready without a
 *     recompute (computed 0, loaded_from_disk) and renders the same image.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/io_image.h"
#include "irradiance_util.h"

static const char sun_down[] =
    "[{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0, -1, 0]}]";

static long put_lights(const struct test_daemon *d, const char *id, const char *body)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/lights", id);
    struct irr_answer a = irr_http(d, "PUT", path, body);
    CHECK_MSG(a.status == 200 || a.status == 202, "PUT %s: %ld %s", path, a.status,
              a.body ? a.body : "");
    free(a.body);
    return a.status;
}

/* The sum of the default view's linear RGB radiance (EXR), and its X-Refract-Irradiance. */
static double render_sum(const struct test_daemon *d, const char *id, char *irradiance)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    struct irr_answer a = irr_http(d, "POST", path, "{\"format\": \"exr\"}");
    CHECK_INT(a.status, 200);
    snprintf(irradiance, 32, "%s", a.irradiance);
    double sum = 0;
    struct io_image img = {0};
    struct err e = {0};
    if (a.status == 200 && io_image_decode(a.body, a.len, 1 << 20, &img, &e) == REFRACT_E_OK) {
        for (int i = 0; i < img.width * img.height; i++)
            sum += img.rgba[i * 4] + img.rgba[i * 4 + 1] + img.rgba[i * 4 + 2];
    }
    io_image_free(&img);
    free(a.body);
    return sum;
}

int main(void)
{
    struct test_daemon d;
    const char *tiny[] = {"--irradiance-gpu-budget", "1", "--irradiance-host-budget", "1", NULL};
    if (!test_daemon_start(&d, tiny))
        test_setup_failed("test_irradiance_persist", d.why);
    char *scene = beam_scene(sun_down);
    char id[REFRACT_ID_SIZE] = "";
    CHECK(test_create_scene(&d, scene, id));
    free(scene);
    cJSON *st = irr_wait_ready(&d, id, 30);
    double first_ms = irr_num(irr_light(st, "sun"), "compute_ms");
    cJSON_Delete(st);
    char irr[32];
    double before = render_sum(&d, id, irr);
    CHECK_STR(irr, "ready");
    CHECK(before > 0);

    /* A second pose: the first leaves both memories once it is on disk. */
    CHECK_INT(put_lights(&d, id,
                         "{\"lights\": [{\"name\": \"sun\", \"type\": \"directional\", "
                         "\"direction\": [0.3, -1, 0]}]}"),
              202);
    cJSON_Delete(irr_wait_ready(&d, id, 30));
    CHECK(render_sum(&d, id, irr) > 0);
    CHECK_STR(irr, "ready");
    st = irr_status(&d, id);
    CHECK(irr_counter(st, "evicted_gpu") >= 1);
    CHECK(irr_counter(st, "evicted_host") >= 1);
    CHECK_NEAR(irr_counter(st, "computed"), 2, 0);
    cJSON_Delete(st);

    /* The first pose again: read back, not recomputed. */
    CHECK_INT(put_lights(&d, id,
                         "{\"lights\": [{\"name\": \"sun\", \"type\": \"directional\", "
                         "\"direction\": [0, -1, 0]}]}"),
              200);
    st = irr_status(&d, id);
    const cJSON *sun = irr_light(st, "sun");
    CHECK_STR(irr_str(sun, "state"), "ready");
    CHECK(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(sun, "loaded_from_disk")));
    CHECK_NEAR(irr_num(sun, "compute_ms"), first_ms, 1e-6 * first_ms);
    CHECK(irr_counter(st, "loaded") >= 1);
    CHECK_NEAR(irr_counter(st, "computed"), 2, 0);
    cJSON_Delete(st);
    double reloaded = render_sum(&d, id, irr);
    CHECK_STR(irr, "ready");
    CHECK_NEAR(reloaded, before, 1e-6 * before);
    CHECK_INT(test_daemon_stop(&d), 0);

    /* A restart: the volume comes from the disk index. */
    struct test_daemon d2;
    test_daemon_restart(&d, &d2, "test_irradiance_persist (restart)");
    st = irr_wait_loaded(&d2, id, "sun", 30);
    sun = irr_light(st, "sun");
    CHECK(cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(sun, "loaded_from_disk")));
    CHECK_NEAR(irr_num(sun, "compute_ms"), first_ms, 1e-6 * first_ms);
    CHECK_NEAR(irr_counter(st, "computed"), 0, 0);
    cJSON_Delete(st);
    double restarted = render_sum(&d2, id, irr);
    CHECK_STR(irr, "ready");
    CHECK_NEAR(restarted, before, 1e-6 * before);
    printf("first compute %.1f ms; evicted, read back and restarted: render sums %.6f %.6f %.6f\n",
           first_ms, before, reloaded, restarted);
    CHECK_INT(test_daemon_stop(&d2), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_irradiance_persist");
}
