/*
 * test_gpu_budget.c - GPU memory for cached scenes stays within --gpu-scene-budget:
 *   - a scene larger than the whole budget is refused with 507 gpu_out_of_memory naming
 *     the flag (and its GET shows the build failed, with the same message);
 *   - scenes that fit one at a time are evicted least-recently-used and rebuilt on
 *     demand: rendering A, B, A again all succeed and give the same picture for A;
 *   - the daemon keeps serving afterwards.
 * Sizes: the ior+gradient atlas is 16 bytes per voxel, so 64^3 is 4 MiB and 40^3 is
 * 1 MiB; the budget is 1.5 MiB.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "daemon.h"
#include "test.h"

#define SCENE_AT(res)                                                                              \
    "{\"camera\": {\"eye\": [0, 0, 4], \"width\": 24, \"height\": 16}, \"objects\": "              \
    "[{\"bounds\": "                                                                               \
    "{\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": " #res                           \
    ", \"smoothing_sigma\": 0, "                                                                   \
    "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.7, \"inside\": 1.4}}]}"

static long render(struct test_daemon *d, const char *id, char **body)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    return test_request(d, "POST", path, "{\"format\": \"png\"}", body);
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, (const char *[]){"--gpu-scene-budget", "1536K", NULL}))
        test_setup_failed("test_gpu_budget", d.why);

    char big[REFRACT_ID_SIZE], a[REFRACT_ID_SIZE], b[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, SCENE_AT(64), big));
    char *body = NULL;
    CHECK_INT(render(&d, big, &body), 507);
    CHECK(test_error_is(body, "gpu_out_of_memory", "--gpu-scene-budget"));
    CHECK_CONTAINS(body, "4.0 MiB");
    free(body);
    /* The background build saw the same refusal; GET says so (it may still be running
     * just after the create, so wait for it). */
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s", big);
    for (int i = 0; i < 100; i++) {
        CHECK_INT(test_request(&d, "GET", path, NULL, &body), 200);
        if (body && strstr(body, "\"state\":\"failed\""))
            break;
        free(body);
        body = NULL;
        usleep(50 * 1000);
    }
    CHECK_CONTAINS(body, "\"state\":\"failed\"");
    CHECK_CONTAINS(body, "--gpu-scene-budget");
    free(body);

    CHECK(test_create_scene(&d, SCENE_AT(40), a));
    CHECK(test_create_scene(&d, SCENE_AT(39), b));
    struct refract_image first_a, then_b, again_a;
    CHECK_INT(refract_render(d.client, a, "{\"format\": \"exr\"}", &first_a), REFRACT_E_OK);
    CHECK_INT(refract_render(d.client, b, "{\"format\": \"exr\"}", &then_b), REFRACT_E_OK);
    /* evicted by b: rebuilt now, and the picture is the same */
    CHECK_INT(refract_render(d.client, a, "{\"format\": \"exr\"}", &again_a), REFRACT_E_OK);
    CHECK(first_a.len > 0 && first_a.len == again_a.len &&
          memcmp(first_a.bytes, again_a.bytes, first_a.len) == 0);
    refract_image_free(&first_a);
    refract_image_free(&then_b);
    refract_image_free(&again_a);

    char *log = NULL;
    FILE *f = fopen(d.log_path, "r");
    if (f) {
        log = calloc(1, 1 << 20);
        size_t got = fread(log, 1, (1 << 20) - 1, f);
        log[got] = '\0';
        fclose(f);
    }
    CHECK_CONTAINS(log ? log : "", "evicting scene");
    free(log);

    CHECK_INT(test_request(&d, "GET", "/v1/health", NULL, &body), 200);
    free(body);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_gpu_budget");
}
