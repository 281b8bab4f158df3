/*
 * test_lights_api.c - the lights resource through a real refractd:
 *   - GET /v1/scenes/{id}/lights lists the lights with every default written out;
 *   - PUT .../lights/{name} adds a light (the name comes from the path), replaces one of
 *     that name, and PUT .../lights replaces them all (an empty list too);
 *   - each change makes a new scene version (X-Scene-Generation grows) but does not
 *     rebuild the scene's GPU data (the log has one build of the scene), and persists:
 *     after a restart the lights are the last ones set;
 *   - unknown scenes and lights, and bad bodies, get precise 4xx errors (the cases of
 *     every lights and irradiance route; test_bad_input_requests.c has the table of
 *     malformed bodies).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "expect.h"
#include "irradiance_util.h"

static const char glass[] =
    "{\"name\": \"glass\", \"camera\": {\"width\": 16, \"height\": 12},"
    " \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8,"
    " \"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}}]}";

/* GET lights, parsed (caller deletes). */
static cJSON *lights_of(struct test_daemon *d, const char *id)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s/lights", id);
    char *body = EXPECT_STATUS(d, "GET", path, NULL, 200);
    cJSON *root = cJSON_Parse(body ? body : "");
    free(body);
    return cJSON_GetObjectItemCaseSensitive(root, "lights") ? root : (cJSON_Delete(root), NULL);
}

static int count_of(const cJSON *root)
{
    return cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(root, "lights"));
}

static const cJSON *nth(const cJSON *root, int i)
{
    return cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(root, "lights"), i);
}

/* Occurrences of needle in the daemon's log. */
static int log_count(const struct test_daemon *d, const char *needle)
{
    FILE *f = fopen(d->log_path, "r");
    if (f == NULL)
        return -1;
    char line[2048];
    int n = 0;
    while (fgets(line, sizeof line, f))
        n += strstr(line, needle) != NULL;
    fclose(f);
    return n;
}

static long generation_of(struct test_daemon *d, const char *id)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/scenes/%s", id);
    char *body = EXPECT_STATUS(d, "GET", path, NULL, 200);
    cJSON *root = cJSON_Parse(body ? body : "");
    long g = (long)irr_num(root, "generation");
    cJSON_Delete(root);
    free(body);
    return g;
}

static void add_replace_and_list(struct test_daemon *d, const char *id)
{
    char path[160];
    cJSON *root = lights_of(d, id);
    CHECK_INT(count_of(root), 0);
    cJSON_Delete(root);
    long g0 = generation_of(d, id);

    snprintf(path, sizeof path, "/v1/scenes/%s/lights/bulb", id);
    free(EXPECT_STATUS(d, "PUT", path, "{\"type\": \"point\", \"position\": [0, 2, 0]}", 200));
    snprintf(path, sizeof path, "/v1/scenes/%s/lights/cone", id);
    free(EXPECT_STATUS(d, "PUT", path,
                       "{\"name\": \"cone\", \"type\": \"spot\", \"position\": [0, 3, 0], "
                       "\"direction\": [0, -2, 0], \"angle_deg\": 30, \"color\": [1, 0.5, 0.25], "
                       "\"intensity\": 4}",
                       200));
    root = lights_of(d, id);
    CHECK_INT(count_of(root), 2);
    const cJSON *bulb = nth(root, 0), *cone = nth(root, 1);
    CHECK_STR(irr_str(bulb, "name"), "bulb");
    CHECK_STR(irr_str(bulb, "type"), "point");
    CHECK_NEAR(irr_num(bulb, "intensity"), 1.0, 0);
    CHECK_NEAR(cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(bulb, "color"), 1)->valuedouble,
               1.0, 0);
    CHECK_STR(irr_str(cone, "type"), "spot");
    CHECK_NEAR(irr_num(cone, "angle_deg"), 30, 0);
    CHECK_NEAR(irr_num(cone, "intensity"), 4, 0);
    /* The direction is normalised by the parser. */
    CHECK_NEAR(
        cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(cone, "direction"), 1)->valuedouble,
        -1.0, 1e-12);
    cJSON_Delete(root);

    /* Replace the bulb: still two lights, the bulb moved. */
    snprintf(path, sizeof path, "/v1/scenes/%s/lights/bulb", id);
    free(EXPECT_STATUS(d, "PUT", path, "{\"type\": \"point\", \"position\": [1, 2, 3]}", 200));
    root = lights_of(d, id);
    CHECK_INT(count_of(root), 2);
    CHECK_NEAR(cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(nth(root, 0), "position"), 2)
                   ->valuedouble,
               3.0, 0);
    cJSON_Delete(root);
    CHECK_INT((int)(generation_of(d, id) - g0), 3);

    /* Replace all; the status answers for the new set. */
    snprintf(path, sizeof path, "/v1/scenes/%s/lights", id);
    char *body = EXPECT_STATUS(d, "PUT", path,
                               "{\"lights\": [{\"name\": \"sun\", \"type\": \"directional\", "
                               "\"direction\": [0, -1, 0]}]}",
                               200);
    cJSON *st = cJSON_Parse(body ? body : "");
    CHECK_INT(cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(st, "lights")), 1);
    CHECK_STR(irr_str(irr_light(st, "sun"), "state"), "not_needed");
    cJSON_Delete(st);
    free(body);
    /* The GPU data was built once, whatever the lights did. */
    char built[128];
    snprintf(built, sizeof built, "built scene %s", id);
    char rpath[128];
    snprintf(rpath, sizeof rpath, "/v1/scenes/%s/render", id);
    free(EXPECT_STATUS(d, "POST", rpath, "{}", 200));
    CHECK_INT(log_count(d, built), 1);
}

static void errors(struct test_daemon *d, const char *id)
{
    char p[200];
    section("lights and irradiance routes");
    EXPECT_ERROR(d, "GET", "/v1/scenes/nope/lights", NULL, 404, "scene_not_found", "nope");
    EXPECT_ERROR(d, "PUT", "/v1/scenes/nope/lights", "{\"lights\": []}", 404, "scene_not_found",
                 "nope");
    EXPECT_ERROR(d, "PUT", "/v1/scenes/nope/lights/sun", "{\"type\": \"point\"}", 404,
                 "scene_not_found", "nope");
    EXPECT_ERROR(d, "GET", "/v1/scenes/nope/irradiance", NULL, 404, "scene_not_found", "nope");
    EXPECT_ERROR(d, "GET", "/v1/scenes/nope/irradiance/sun.exr", NULL, 404, "scene_not_found",
                 "nope");
    snprintf(p, sizeof p, "/v1/scenes/%s/irradiance/moon.exr", id);
    EXPECT_ERROR(d, "GET", p, NULL, 404, "not_found", "no light named \"moon\"");
    snprintf(p, sizeof p, "/v1/scenes/%s/irradiance/sun.exr", id);
    EXPECT_ERROR(d, "GET", p, NULL, 409, "conflict", "needs no light simulation");
    snprintf(p, sizeof p, "/v1/scenes/%s/irradiance/sun", id);
    EXPECT_ERROR(d, "GET", p, NULL, 404, "not_found", "no route");
    snprintf(p, sizeof p, "/v1/scenes/%s/lights", id);
    EXPECT_ERROR(d, "DELETE", p, NULL, 405, "method_not_allowed", "GET, PUT");
    snprintf(p, sizeof p, "/v1/scenes/%s/lights/sun", id);
    EXPECT_ERROR(d, "PUT", p, "{\"name\": \"moon\", \"type\": \"point\", \"position\": [0, 1, 0]}",
                 400, "invalid_field", "name", "\"sun\"");
    EXPECT_ERROR(d, "PUT", p, "{\"type\": \"point\", \"position\": [0, 1e999, 0]}", 400,
                 "invalid_field", "position[1]", "finite");
    snprintf(p, sizeof p, "/v1/scenes/%s/lights/Sun", id);
    EXPECT_ERROR(d, "PUT", p, "{\"type\": \"point\", \"position\": [0, 1, 0]}", 400,
                 "invalid_field", "name", "\"Sun\"");
    /* A failed change leaves the lights as they were. */
    cJSON *root = lights_of(d, id);
    CHECK_INT(count_of(root), 1);
    CHECK_STR(irr_str(nth(root, 0), "name"), "sun");
    cJSON_Delete(root);
    section("");
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_lights_api", d.why);
    char id[REFRACT_ID_SIZE] = "";
    CHECK(test_create_scene(&d, glass, id));
    if (id[0]) {
        add_replace_and_list(&d, id);
        errors(&d, id);
    }
    CHECK_INT(test_daemon_stop(&d), 0);
    struct test_daemon d2;
    test_daemon_restart(&d, &d2, "test_lights_api (restart)");
    cJSON *root = lights_of(&d2, id);
    CHECK_INT(count_of(root), 1);
    CHECK_STR(irr_str(nth(root, 0), "name"), "sun");
    CHECK_STR(irr_str(nth(root, 0), "type"), "directional");
    cJSON_Delete(root);
    CHECK_INT(test_daemon_stop(&d2), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_lights_api");
}
