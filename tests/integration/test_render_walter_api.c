/*
 * test_render_walter_api.c - exact single scattering (docs/walter.md) through a real
 * refractd: peer scene B (a scattering glass ball lit from behind) says
 * "single_scattering": "walter" and needs no light simulation; a render lights the medium at
 * once, only inside the ball's image (black sky, no floor); a lamp moved to the mirror
 * position gives the mirror picture (the scene is symmetric), which differs from the first
 * one; a scene with a second optical surface
 * falls back to the light simulator's volume ("volume", needed).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "irradiance_util.h"
#include "render_util.h"
#include "test.h"

#define W 80
#define H 60

static const char *const scene_doc =
    "{\"name\": \"scattering ball\", \"camera\": {\"eye\": [0, 2.5, 7], \"look_at\": [0, -0.5, "
    "0], \"fov_y_deg\": 35, \"width\": 80, \"height\": 60}, \"environment\": {\"intensity\": 0}, "
    "\"lights\": [{\"name\": \"lamp\", \"type\": \"point\", \"position\": [-4, 1, -3], "
    "\"intensity\": 79.5775}], "
    "\"surfaces\": [{\"name\": \"ball\", \"shape\": \"sphere\", \"center\": [0, 0, 0], "
    "\"radius\": 1, \"medium\": {\"ior\": 1.5, \"attenuation\": [0.05, 0.05, 0.05], "
    "\"scattering\": [0.5, 0.5, 0.5]}, \"brdf\": {\"type\": \"none\"}}]}";

/* The irradiance status names the single-scattering method and whether volumes are needed. */
static void status_says(struct test_daemon *d, const char *id, const char *method, bool needed)
{
    cJSON *st = irr_status(d, id);
    CHECK(st != NULL);
    CHECK_STR(irr_str(st, "single_scattering"), method);
    CHECK(cJSON_IsBool(cJSON_GetObjectItem(st, "needed")) &&
          cJSON_IsTrue(cJSON_GetObjectItem(st, "needed")) == needed);
    cJSON_Delete(st);
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
    status_says(&d, id, "walter", false);
    static float left[W * H * 4], right[W * H * 4];
    /* The lamp to the left (x = -4), behind: the light crosses the ball toward +x. */
    CHECK(test_render_exr(&d, id, W, H, left));
    CHECK_INT(refract_light_put(d.client, id, "lamp",
                                "{\"type\": \"point\", \"position\": [4, 1, -3], \"intensity\": "
                                "79.5775}",
                                NULL),
              REFRACT_E_OK);
    CHECK(test_render_exr(&d, id, W, H, right));
    /* The scene is symmetric under x -> -x and the camera sits on that plane: the picture
     * with the lamp on the right is the mirror image of the one with it on the left, which
     * is not symmetric itself (the light comes from one side). The lit pixels are the
     * ball's image only (black sky, no floor): a disc about 13 pixels in radius. */
    double sum = 0.0, mirror_diff = 0.0, asym = 0.0;
    int lit = 0;
    for (int j = 0; j < H; j++)
        for (int i = 0; i < W; i++) {
            float l = left[(j * W + i) * 4 + 1], r = right[(j * W + (W - 1 - i)) * 4 + 1];
            float lm = left[(j * W + (W - 1 - i)) * 4 + 1];
            sum += l;
            mirror_diff += fabs(l - r);
            asym += fabs(l - lm);
            lit += l > 1e-6f;
            if (l > 1e-6f)
                CHECK_MSG(hypot(i - 0.5 * (W - 1), j - 0.5 * (H - 1)) < 20.0,
                          "lit pixel (%d, %d) far from the ball", i, j);
        }
    printf("lamp left: %d lit pixels, mean %.4f; |left - mirror(right)| %.2e, |left - "
           "mirror(left)| %.3f of the sum\n",
           lit, sum / lit, mirror_diff / sum, asym / sum);
    CHECK(lit > 300 && lit < 1000);
    CHECK(mirror_diff < 1e-3 * sum);
    CHECK(asym > 0.02 * sum);
    /* A second optical surface: light may reach the medium through both, the exact single
     * crossing does not hold, the light simulator's volume serves. */
    const char *two =
        "{\"lights\": [{\"type\": \"point\", \"position\": [0, 3, 0]}], "
        "\"surfaces\": [{\"shape\": \"sphere\", \"radius\": 1, \"medium\": "
        "{\"ior\": 1.5, \"scattering\": [0.5, 0.5, 0.5]}}, {\"shape\": \"box\", \"center\": "
        "[0, 2, 0], \"size\": [1, 0.2, 1], \"medium\": {\"ior\": 1.5}}]}";
    char id2[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, two, id2));
    status_says(&d, id2, "volume", true);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_render_walter_api");
}
