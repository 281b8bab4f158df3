/*
 * test_cli_lights.c - the refract CLI's light and irradiance commands ($REFRACT_CLI, the
 * real binary) against a real refractd computing real irradiance volumes (small grids,
 * so llvmpipe takes well under a second per light):
 *   - light list; light set of a new pose waits (progress lines on a non-terminal
 *     stderr) until the volume is ready; a colour/intensity change is a cache hit that
 *     keeps the pose (the merge of the flags into the stored light);
 *   - irradiance status as a table and as JSON; irradiance get writes an OpenEXR file,
 *     and a light the scene lacks is an error that writes nothing;
 *   - a render right after `light set --no-wait` says which irradiance it used, with a
 *     note when it was stale or missing;
 *   - the exit codes of refractd's refusals (2, 6), of a scene that needs no light
 *     simulation (0), and of a wait that runs out of time (14);
 *   - the librefract calls underneath, called directly where the CLI does not reach:
 *     refract_lights_put (no command replaces all lights), refract_irradiance_wait's
 *     callback and interval, refract_irradiance_get_exr's image, argument errors.
 */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cjson/cJSON.h>

#include "daemon.h"
#include "support_cli.h"
#include "test.h"

/* A glass ball over a receiver: light simulation needed; a 16^3 light grid. */
static const char lit_scene[] =
    "{\"name\": \"lit ball\", \"camera\": {\"eye\": [0, 0.5, 4], \"look_at\": [0, -0.5, 0]},"
    " \"objects\": [{\"bounds\": {\"min\": [-0.5, -0.5, -0.5], \"max\": [0.5, 0.5, 0.5]},"
    "   \"resolution\": 16, \"ior\": {\"shape\": \"sphere\", \"radius\": 0.45, \"inside\": 1.5}}],"
    " \"receiver\": {\"height\": -1, \"half_size\": 1.5},"
    " \"lights\": [{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0, -1, 0]}],"
    " \"lightsim\": {\"resolution\": 16, \"initial_patches\": 16, \"max_level\": 3}}";

/* The same ball with no receiver and no scattering: no light simulation at all. */
static const char unlit_scene[] =
    "{\"name\": \"unlit ball\", \"objects\": [{\"bounds\": {\"min\": [-0.5, -0.5, -0.5],"
    " \"max\": [0.5, 0.5, 0.5]}, \"resolution\": 16, \"ior\": {\"shape\": \"sphere\","
    " \"radius\": 0.45, \"inside\": 1.5}}]}";

/* A light grid large enough that llvmpipe needs seconds: for the wait's timeout. */
static const char slow_scene[] =
    "{\"name\": \"slow ball\", \"objects\": [{\"bounds\": {\"min\": [-0.5, -0.5, -0.5],"
    " \"max\": [0.5, 0.5, 0.5]}, \"resolution\": 32, \"ior\": {\"shape\": \"sphere\","
    " \"radius\": 0.45, \"inside\": 1.5}}], \"receiver\": {\"height\": -1, \"half_size\": 1.5},"
    " \"lightsim\": {\"resolution\": 128, \"initial_patches\": 256, \"max_level\": 6}}";

/* $REFRACT_CLI --url <daemon> ARGS... with stdin from /dev/null (support_cli.h). */
static struct cli_run run_cli(const struct test_daemon *d, const char *const *args)
{
    return cli_run(d, NULL, NULL, args);
}

/* The state of light `name` in an irradiance status JSON (a static buffer; "" if none). */
static const char *state_of(const char *status_json, const char *name)
{
    static char state[32];
    cJSON *root = cJSON_Parse(status_json);
    const cJSON *light = NULL;

    state[0] = '\0';
    cJSON_ArrayForEach(light, cJSON_GetObjectItemCaseSensitive(root, "lights"))
    {
        const cJSON *n = cJSON_GetObjectItemCaseSensitive(light, "name");
        const cJSON *s = cJSON_GetObjectItemCaseSensitive(light, "state");
        if (cJSON_IsString(n) && strcmp(n->valuestring, name) == 0 && cJSON_IsString(s))
            snprintf(state, sizeof state, "%s", s->valuestring);
    }
    cJSON_Delete(root);
    return state;
}

/* Member `key` of light `name` in a {"lights": [...]} JSON, duplicated (or NULL). */
static cJSON *light_member(const char *lights_json, const char *name, const char *key)
{
    cJSON *root = cJSON_Parse(lights_json);
    const cJSON *light = NULL;
    cJSON *found = NULL;

    cJSON_ArrayForEach(light, cJSON_GetObjectItemCaseSensitive(root, "lights"))
    {
        const cJSON *n = cJSON_GetObjectItemCaseSensitive(light, "name");
        if (cJSON_IsString(n) && strcmp(n->valuestring, name) == 0)
            found = cJSON_Duplicate(cJSON_GetObjectItemCaseSensitive(light, key), 1);
    }
    cJSON_Delete(root);
    return found;
}

static bool file_is_exr(const char *path)
{
    unsigned char magic[4] = {0};
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return false;
    size_t got = fread(magic, 1, 4, f);
    fclose(f);
    return got == 4 && memcmp(magic, "\x76\x2f\x31\x01", 4) == 0; /* OpenEXR 20000630 */
}

/* light list, then light set of a new pose: waits, prints progress lines, ends ready;
 * then a change of intensity alone is a cache hit that keeps the new direction. */
static void light_set_waits_and_merges(struct test_daemon *d, const char *id)
{
    struct cli_run r = run_cli(d, (const char *[]){"light", "list", id, NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, "\"name\":\"sun\"");
    CHECK_CONTAINS(r.out, "\"type\":\"directional\"");
    cli_run_free(&r);

    r = run_cli(d, (const char *[]){"light", "set", id, "sun", "--direction", "0.4,-1,0", NULL});
    CHECK_INT(r.status, 0);
    CHECK_STR(state_of(r.out, "sun"), "ready");
    /* A new pose is a miss (202), so the command waited, logging each change. */
    CHECK_CONTAINS(r.err, "irradiance: sun ");
    CHECK_CONTAINS(r.err, "irradiance: sun ready\n");
    CHECK_CONTAINS(r.err, "light sun set; irradiance ready (computed in ");
    cli_run_free(&r);

    r = run_cli(d, (const char *[]){"light", "set", id, "sun", "--intensity", "3", "--color",
                                    "1,0.8,0.6", "--no-wait", NULL});
    CHECK_INT(r.status, 0);
    CHECK_STR(state_of(r.out, "sun"), "ready");
    CHECK_CONTAINS(r.err, "light sun set; irradiance ready (from the cache)");
    cli_run_free(&r);

    r = run_cli(d, (const char *[]){"light", "list", id, NULL});
    CHECK_INT(r.status, 0);
    cJSON *intensity = light_member(r.out, "sun", "intensity");
    cJSON *direction = light_member(r.out, "sun", "direction");
    CHECK(cJSON_IsNumber(intensity) && intensity->valuedouble == 3.0);
    /* The direction of the earlier set survived the intensity change (stored normalised). */
    CHECK(cJSON_GetArraySize(direction) == 3 &&
          cJSON_GetArrayItem(direction, 0)->valuedouble > 0.3);
    cJSON_Delete(intensity);
    cJSON_Delete(direction);
    cli_run_free(&r);
}

static void irradiance_status_and_get(struct test_daemon *d, const char *id)
{
    struct cli_run r = run_cli(d, (const char *[]){"irradiance", "status", id, NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, "needs light simulation");
    CHECK_CONTAINS(r.out, "LIGHT");
    CHECK_CONTAINS(r.out, "USING");
    CHECK_CONTAINS(r.out, "sun ");
    CHECK_CONTAINS(r.out, " ready ");
    CHECK_CONTAINS(r.out, "current");
    cli_run_free(&r);

    r = run_cli(d, (const char *[]){"irradiance", "status", id, "--json", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.out, "\"transport_hash\"");
    CHECK_STR(state_of(r.out, "sun"), "ready");
    cli_run_free(&r);

    char exr[400];
    snprintf(exr, sizeof exr, "%s/sun.exr", d->dir);
    r = run_cli(d, (const char *[]){"irradiance", "get", id, "sun", "-o", exr, NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.err, " EXR, ");
    CHECK(file_is_exr(exr));
    cli_run_free(&r);

    /* A light the scene does not have: refractd's 404 not_found; nothing is written. */
    char none[400];
    snprintf(none, sizeof none, "%s/moon.exr", d->dir);
    r = run_cli(d, (const char *[]){"irradiance", "get", id, "moon", "-o", none, NULL});
    CHECK_INT(r.status, REFRACT_E_NOT_FOUND);
    CHECK_CONTAINS(r.err, "refract: ");
    CHECK(access(none, F_OK) != 0);
    cli_run_free(&r);
}

/* A new light with --no-wait, and a render at once: the render says which irradiance it
 * used, and notes a stale or missing one. Which it is depends on how far the simulation
 * got, so each outcome is checked for what it must print. */
static void render_after_no_wait_says_what_it_used(struct test_daemon *d, const char *id)
{
    struct cli_run r = run_cli(d, (const char *[]){"light", "set", id, "bulb", "--type", "point",
                                                   "--position", "0,1.5,0", "--no-wait", NULL});
    CHECK_INT(r.status, 0);
    CHECK(state_of(r.out, "bulb")[0] != '\0');
    CHECK_CONTAINS(r.err, "light bulb set; irradiance ");
    cli_run_free(&r);

    char png[400];
    snprintf(png, sizeof png, "%s/view.png", d->dir);
    r = run_cli(d,
                (const char *[]){"render", id, "-o", png, "--width", "32", "--height", "24", NULL});
    CHECK_INT(r.status, 0);
    bool ready = strstr(r.err, ", irradiance ready)") != NULL;
    bool stale = strstr(r.err, ", irradiance stale)") != NULL;
    bool missing = strstr(r.err, ", irradiance missing)") != NULL;
    CHECK_MSG(ready + stale + missing == 1, "render said: %s", r.err);
    if (ready)
        CHECK(strstr(r.err, "note:") == NULL);
    if (stale)
        CHECK_CONTAINS(r.err, "refract: note: a light's irradiance is being recomputed");
    if (missing)
        CHECK_CONTAINS(r.err, "refract: note: a light has no irradiance volume yet");
    cli_run_free(&r);

    /* `irradiance wait` returns when the --no-wait light is settled, with the table. */
    r = run_cli(d, (const char *[]){"irradiance", "wait", id, NULL});
    CHECK_MSG(r.status == 0, "irradiance wait: %s", r.err);
    CHECK_CONTAINS(r.out, "LIGHT");
    CHECK_CONTAINS(r.out, "bulb");
    CHECK(strstr(r.out, "computing") == NULL && strstr(r.out, "queued") == NULL);
    cli_run_free(&r);
    r = run_cli(d, (const char *[]){"irradiance", "status", id, "--json", NULL});
    CHECK_STR(state_of(r.out, "bulb"), "ready");
    cli_run_free(&r);
    r = run_cli(d, (const char *[]){"irradiance", "wait", "no_such_scene", NULL});
    CHECK_INT(r.status, REFRACT_E_SCENE_NOT_FOUND);
    cli_run_free(&r);

    /* Moving it and waiting ends with both lights ready. */
    r = run_cli(d, (const char *[]){"light", "set", id, "bulb", "--position", "0.3,1.5,0", NULL});
    CHECK_INT(r.status, 0);
    CHECK_STR(state_of(r.out, "bulb"), "ready");
    CHECK_STR(state_of(r.out, "sun"), "ready");
    cli_run_free(&r);

    r = run_cli(d,
                (const char *[]){"render", id, "-o", png, "--width", "32", "--height", "24", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.err, ", irradiance ready)");
    CHECK(strstr(r.err, "note:") == NULL);
    cli_run_free(&r);
}

static void refusals_and_unneeded_simulation(struct test_daemon *d, const char *id)
{
    /* refractd validates the merged light and names the field (invalid_field, 2). */
    struct cli_run r = run_cli(d, (const char *[]){"light", "set", id, "sun", "--type", "spot",
                                                   "--position", "0,2,0", "--angle", "200", NULL});
    CHECK_INT(r.status, REFRACT_E_INVALID_FIELD);
    CHECK_CONTAINS(r.err, "angle_deg");
    cli_run_free(&r);

    r = run_cli(d,
                (const char *[]){"light", "set", "no_such_scene", "sun", "--type", "point", NULL});
    CHECK_INT(r.status, REFRACT_E_SCENE_NOT_FOUND);
    cli_run_free(&r);

    r = run_cli(d, (const char *[]){"irradiance", "status", "no_such_scene", NULL});
    CHECK_INT(r.status, REFRACT_E_SCENE_NOT_FOUND);
    cli_run_free(&r);

    char unlit[REFRACT_ID_SIZE];
    CHECK(test_create_scene(d, unlit_scene, unlit));
    r = run_cli(d, (const char *[]){"light", "set", unlit, "sun", "--type", "directional",
                                    "--direction", "0,-1,0", NULL});
    CHECK_INT(r.status, 0);
    CHECK_CONTAINS(r.err, "needs no light simulation");
    cli_run_free(&r);
}

/* A wait that runs out of time exits 14 and names the light still to come. On a machine
 * fast enough to finish a 128^3 simulation within the second, the wait ends ready. */
static void a_wait_gives_up_after_the_timeout(struct test_daemon *d)
{
    char slow[REFRACT_ID_SIZE];
    CHECK(test_create_scene(d, slow_scene, slow));
    struct cli_run r =
        run_cli(d, (const char *[]){"light", "set", slow, "sun", "--type", "directional",
                                    "--direction", "0,-1,0.2", "--timeout", "1", NULL});
    if (r.status == REFRACT_E_TIMEOUT) {
        CHECK_CONTAINS(r.err, "refract: light sun is set, but waiting for its irradiance "
                              "failed: ");
        CHECK_CONTAINS(r.err, "irradiance not ready after 1.0 s (sun ");
        CHECK_STR(r.out, "");
    } else {
        CHECK_INT(r.status, 0);
        CHECK_STR(state_of(r.out, "sun"), "ready");
    }
    cli_run_free(&r);
}

struct wait_count {
    int calls;
    bool last_settled;
};

static void count_progress(const struct refract_irradiance *status, void *user)
{
    struct wait_count *w = user;
    w->calls++;
    w->last_settled = refract_irradiance_settled(status);
}

static void librefract_calls(struct test_daemon *d, const char *id)
{
    refract_client *c = d->client;
    struct refract_irradiance status;

    /* Replace all lights by one new pose: a miss (202) that the wait sees through. */
    CHECK_INT(refract_lights_put(c, id,
                                 "{\"lights\": [{\"name\": \"sun\", \"type\": \"directional\","
                                 " \"direction\": [-0.3, -1, 0]}]}",
                                 &status),
              REFRACT_E_OK);
    CHECK_INT(status.http_status, 202);
    CHECK_INT(status.light_count, 1);
    CHECK(status.json != NULL && strstr(status.json, "\"transport_hash\"") != NULL);
    refract_irradiance_free(&status);

    struct wait_count w = {0};
    struct refract_wait_options opts = {
        .timeout_ms = 120000, .interval_ms = 1, .progress = count_progress, .user = &w};
    CHECK_INT(refract_irradiance_wait(c, id, &opts, &status), REFRACT_E_OK);
    CHECK(refract_irradiance_settled(&status));
    CHECK_STR(status.light_count == 1 ? status.lights[0].state : "", "ready");
    CHECK(w.calls >= 1 && w.last_settled);
    refract_irradiance_free(&status);

    /* The same pose again: a hit, 200, every light ready at once. */
    CHECK_INT(refract_lights_put(c, id,
                                 "{\"lights\": [{\"name\": \"sun\", \"type\": \"directional\","
                                 " \"direction\": [-0.3, -1, 0], \"intensity\": 2}]}",
                                 &status),
              REFRACT_E_OK);
    CHECK_INT(status.http_status, 200);
    CHECK(refract_irradiance_settled(&status));
    refract_irradiance_free(&status);

    struct refract_image img;
    CHECK_INT(refract_irradiance_get_exr(c, id, "sun", &img), REFRACT_E_OK);
    CHECK_STR(img.content_type, "image/x-exr");
    CHECK_STR(img.irradiance, "ready");
    CHECK(img.len > 4 && memcmp(img.bytes, "\x76\x2f\x31\x01", 4) == 0);
    refract_image_free(&img);

    /* refractd's refusal arrives as its code and message. */
    CHECK_INT(refract_light_put(c, id, "sun", "{\"type\": \"laser\"}", &status),
              REFRACT_E_INVALID_FIELD);
    CHECK(strstr(refract_errmsg(c), "type") != NULL);
    CHECK(status.json == NULL && status.lights == NULL);

    /* Wrong arguments are the caller's mistake, found before anything is sent. */
    CHECK_INT(refract_light_put(c, id, "", "{}", NULL), REFRACT_E_USAGE);
    CHECK(strstr(refract_errmsg(c), "light name is empty") != NULL);
    CHECK_INT(refract_lights_put(c, id, NULL, NULL), REFRACT_E_USAGE);
    CHECK_INT(refract_irradiance_status(c, id, NULL), REFRACT_E_USAGE);
    CHECK_INT(refract_irradiance_get_exr(c, NULL, "sun", &img), REFRACT_E_USAGE);
    CHECK_INT(
        refract_irradiance_wait(c, id, &(struct refract_wait_options){.timeout_ms = -1}, NULL),
        REFRACT_E_USAGE);
    CHECK_INT(refract_irradiance_parse(c, "{\"lights\": 3}", &status), REFRACT_E_PROTOCOL);
    CHECK(strstr(refract_errmsg(c), "lights: expected an array") != NULL);
}

int main(void)
{
    if (getenv("REFRACT_CLI") == NULL || access(getenv("REFRACT_CLI"), X_OK) != 0)
        test_skip("test_cli_lights",
                  "REFRACT_CLI is not set to the refract binary (ctest sets it)");
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL)) {
        fprintf(stderr, "cannot start refractd: %s\n", d.why);
        return 1;
    }
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&d, lit_scene, id));

    light_set_waits_and_merges(&d, id);
    irradiance_status_and_get(&d, id);
    render_after_no_wait_says_what_it_used(&d, id);
    refusals_and_unneeded_simulation(&d, id);
    librefract_calls(&d, id);
    a_wait_gives_up_after_the_timeout(&d);

    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_cli_lights");
}
