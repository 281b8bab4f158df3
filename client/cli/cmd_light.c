/*
 * cmd_light.c - `refract light set|list`: a scene's lights.
 *
 * set changes the flags it is given and keeps the rest of the light (cli_light.c), sends
 * the light with PUT /v1/scenes/{id}/lights/{name}, and by default waits until refractd
 * has the light's irradiance volume, showing progress on stderr. The final irradiance
 * status goes to stdout as JSON, so a script can read it with jq. The read-modify-write
 * is not atomic: two `light set` of the same light at the same moment may each keep the
 * other's old values.
 */
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "cli_irradiance.h"
#include "cli_light.h"

/* How long --wait waits when --timeout is not given: the request timeout's default. */

#define LIGHT_USAGE                                                                                \
    "usage: refract light set ID NAME [--type directional|point|spot]\n"                           \
    "           [--direction X,Y,Z] [--position X,Y,Z] [--angle DEG]\n"                            \
    "           [--color R,G,B] [--intensity I] [--wait|--no-wait]\n"                              \
    "       refract light list ID\n"                                                               \
    "\n"                                                                                           \
    "set adds the light NAME to scene ID, or changes the light of that name: the\n"                \
    "flags given replace those values and the others are kept. refractd then looks\n"              \
    "up the light's irradiance volume in its cache, or computes it. By default set\n"              \
    "waits until the volume is ready, with a progress bar on stderr (plain progress\n"             \
    "lines when stderr is not a terminal), for at most --timeout seconds (default\n"               \
    "120); --no-wait returns as soon as refractd has the light. Either way it prints\n"            \
    "the irradiance status as JSON on stdout. list prints the scene's lights as JSON.\n"           \
    "\n"                                                                                           \
    "  --type T           directional (a plane wavefront), point, or spot (a cone)\n"              \
    "  --direction X,Y,Z  directional, spot: the way the light travels (world space)\n"            \
    "  --position X,Y,Z   point, spot: where the light is (world space)\n"                         \
    "  --angle DEG        spot: half angle of the cone in degrees\n"                               \
    "  --color R,G,B      linear RGB colour (default 1,1,1)\n"                                     \
    "  --intensity I      directional: irradiance across the beam; point, spot:\n"                 \
    "                     radiant intensity per steradian (default 1)\n"                           \
    "  --wait             wait for the irradiance volume (the default)\n"                          \
    "  --no-wait          return once refractd has the light (HTTP 200 or 202)\n"                  \
    "\n"                                                                                           \
    "Examples:\n"                                                                                  \
    "  refract light set \"$ID\" sun --type directional --direction 0,-1,0.3\n"                    \
    "  refract light set \"$ID\" bulb --type point --position 0,2,0 --intensity 5\n"               \
    "  refract light set \"$ID\" bulb --position 1,2,0 --no-wait\n"                                \
    "  refract light list \"$ID\" | jq '.lights[].name'\n"

static int run_group(struct cli *cli, int argc, char **argv);

const struct cli_command cli_cmd_light = {
    .name = "light",
    .synopsis = "light set|list",
    .summary = "add, change or list a scene's lights",
    .usage = LIGHT_USAGE,
    .run = run_group,
};

static const struct cli_command light_set_cmd = {.name = "light set", .usage = LIGHT_USAGE};
static const struct cli_command light_list_cmd = {.name = "light list", .usage = LIGHT_USAGE};

enum set_opt {
    OPT_TYPE,
    OPT_DIRECTION,
    OPT_POSITION,
    OPT_ANGLE,
    OPT_COLOR,
    OPT_INTENSITY,
    OPT_WAIT,
    OPT_NO_WAIT,
    OPT_COUNT
};

/* The light that was set, in a status; NULL when refractd did not list it. */
static const struct refract_light_status *find_status(const struct refract_irradiance *s,
                                                      const char *name)
{
    for (size_t i = 0; i < s->light_count; i++) {
        if (strcmp(s->lights[i].name, name) == 0)
            return &s->lights[i];
    }
    return NULL;
}

/*
 * Says on stderr how the light's volume stands and returns the exit code: 0, or when
 * the light's simulation failed the code refractd named for it (gpu_error when none).
 * Other lights that failed get a note but do not fail this command: they were not set.
 */
static int report_outcome(const char *scene, const char *name, const struct refract_irradiance *s)
{
    const struct refract_light_status *l = find_status(s, name);
    char ms[32];

    for (size_t i = 0; i < s->light_count; i++) {
        const struct refract_light_status *o = &s->lights[i];

        if (o != l && strcmp(o->state, "failed") == 0)
            fprintf(stderr, "refract: note: the irradiance of light %s failed too: %s\n", o->name,
                    o->message[0] != '\0' ? o->message : "(no message)");
    }
    if (!s->needed) {
        fprintf(stderr,
                "light %s set; scene %s needs no light simulation (no scattering "
                "medium and no receiver), so there is no irradiance to compute\n",
                name, scene);
        return REFRACT_E_OK;
    }
    if (l == NULL) {
        fprintf(stderr, "light %s set; refractd's irradiance status does not list it\n", name);
        return REFRACT_E_OK;
    }
    if (strcmp(l->state, "failed") == 0)
        return cli_fail(l->code > 0 ? l->code : REFRACT_E_GPU_ERROR,
                        "light %s: the irradiance simulation failed: %s", name,
                        l->message[0] != '\0' ? l->message : "(refractd gave no message)");
    cli_format_ms(ms, sizeof(ms), l->compute_ms);
    if (strcmp(l->state, "ready") == 0 && s->http_status == 200)
        fprintf(stderr, "light %s set; irradiance ready (from the cache)\n", name);
    else if (strcmp(l->state, "ready") == 0)
        fprintf(stderr, "light %s set; irradiance ready (computed in %s)\n", name, ms);
    else
        fprintf(stderr,
                "light %s set; irradiance %s, renders use %s volume until it is ready; "
                "'refract irradiance status %s' shows its progress\n",
                name, l->state,
                strcmp(l->using_volume, "previous") == 0 ? "the previous pose's" : "no", scene);
    return REFRACT_E_OK;
}

/* Reads the scene's light NAME (NULL when new) and builds the light to send; *text is a
 * new string the caller frees with cJSON_free(). */
static int build_light(struct cli *cli, const char *scene, const char *name,
                       const struct cli_light_spec *spec, char **text)
{
    char *lights_json = NULL;
    cJSON *doc = NULL;
    cJSON *light = NULL;
    char why[256] = "";
    int code = refract_lights_get(cli->client, scene, &lights_json);

    *text = NULL;
    if (code != REFRACT_E_OK)
        return cli_call_failed(cli, code);
    doc = cJSON_Parse(lights_json);
    light = cli_light_build(cli_light_find(doc, name), name, spec, why, sizeof(why));
    if (light == NULL && why[0] != '\0')
        code = cli_usage_error(&light_set_cmd, "light set: %s %s: %s", scene, name, why);
    else if (light == NULL || (*text = cJSON_PrintUnformatted(light)) == NULL)
        code = cli_fail(REFRACT_E_OUT_OF_MEMORY, "light set: out of memory building the light");
    cJSON_Delete(light);
    cJSON_Delete(doc);
    refract_free(lights_json);
    return code;
}

/* Waits for the scene's irradiance (unless it is settled already); *status is replaced
 * by the final one. */
static int wait_for_volumes(struct cli *cli, const char *scene, const char *name,
                            struct refract_irradiance *status)
{
    int code = cli_wait_irradiance(cli, scene, status);

    if (code != REFRACT_E_OK)
        /* The light is stored either way; say so, or a script would set it again. */
        return cli_fail(code, "light %s is set, but waiting for its irradiance failed: %s", name,
                        refract_errmsg(cli->client));
    return REFRACT_E_OK;
}

static int run_set(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene ID", "the light NAME"};
    struct cli_opt opts[OPT_COUNT] = {
        [OPT_TYPE] = {.name = "--type", .takes_value = true},
        [OPT_DIRECTION] = {.name = "--direction", .takes_value = true},
        [OPT_POSITION] = {.name = "--position", .takes_value = true},
        [OPT_ANGLE] = {.name = "--angle", .takes_value = true},
        [OPT_COLOR] = {.name = "--color", .takes_value = true},
        [OPT_INTENSITY] = {.name = "--intensity", .takes_value = true},
        [OPT_WAIT] = {.name = "--wait"},
        [OPT_NO_WAIT] = {.name = "--no-wait"},
    };
    struct refract_irradiance status = {0};
    struct cli_light_spec spec;
    struct cli_parsed p;
    char why[256];
    char *light = NULL;
    int code = cli_parse_command(&light_set_cmd, argc, argv, opts, OPT_COUNT, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&light_set_cmd, &p, 2, 2, names);
    if (code != REFRACT_E_OK)
        return code;
    if (opts[OPT_WAIT].given && opts[OPT_NO_WAIT].given)
        return cli_usage_error(&light_set_cmd, "light set: --wait and --no-wait contradict "
                                               "each other; give one");
    if (!cli_light_spec_parse(&(struct cli_light_flags){.type = opts[OPT_TYPE].value,
                                                        .direction = opts[OPT_DIRECTION].value,
                                                        .position = opts[OPT_POSITION].value,
                                                        .angle = opts[OPT_ANGLE].value,
                                                        .color = opts[OPT_COLOR].value,
                                                        .intensity = opts[OPT_INTENSITY].value},
                              &spec, why, sizeof(why)))
        return cli_usage_error(&light_set_cmd, "light set: %s", why);
    if (!cli_light_spec_fits(&spec, spec.type, why, sizeof(why)))
        return cli_usage_error(&light_set_cmd, "light set: %s", why);
    code = cli_connect(cli);
    if (code == REFRACT_E_OK)
        code = build_light(cli, p.pos[0], p.pos[1], &spec, &light);
    if (code == REFRACT_E_OK) {
        code = refract_light_put(cli->client, p.pos[0], p.pos[1], light, &status);
        if (code != REFRACT_E_OK)
            code = cli_call_failed(cli, code);
    }
    if (code == REFRACT_E_OK && !opts[OPT_NO_WAIT].given)
        code = wait_for_volumes(cli, p.pos[0], p.pos[1], &status);
    if (code == REFRACT_E_OK)
        code = cli_print_json(status.json);
    if (code == REFRACT_E_OK)
        code = report_outcome(p.pos[0], p.pos[1], &status);
    refract_irradiance_free(&status);
    cJSON_free(light);
    return code;
}

static int run_list(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene ID"};
    struct cli_parsed p;
    char *json = NULL;
    int code = cli_parse_command(&light_list_cmd, argc, argv, NULL, 0, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&light_list_cmd, &p, 1, 1, names);
    if (code == REFRACT_E_OK)
        code = cli_connect(cli);
    if (code != REFRACT_E_OK)
        return code;
    code = refract_lights_get(cli->client, p.pos[0], &json);
    code = code == REFRACT_E_OK ? cli_print_json(json) : cli_call_failed(cli, code);
    refract_free(json);
    return code;
}

static int run_group(struct cli *cli, int argc, char **argv)
{
    if (argc == 0)
        return cli_usage_error(&cli_cmd_light, "light: missing the command (set or list)");
    if (strcmp(argv[0], "-h") == 0 || strcmp(argv[0], "--help") == 0) {
        fputs(cli_cmd_light.usage, stdout);
        return REFRACT_E_OK;
    }
    if (strcmp(argv[0], "set") == 0)
        return run_set(cli, argc - 1, argv + 1);
    if (strcmp(argv[0], "list") == 0)
        return run_list(cli, argc - 1, argv + 1);
    return cli_usage_error(&cli_cmd_light, "unknown light command '%s'", argv[0]);
}
