/*
 * cmd_trace.c - `refract trace`: traces rays through a scene and prints refractd's
 * answer (exit point and direction, transmittance, optical path length, steps).
 *
 * Two forms: a trace request file, sent byte for byte unless --step or --stepper
 * override its keys; or one ray given by --origin and --direction. Directions are passed
 * on as typed, not normalised, so what refractd checks is what the user wrote.
 */
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "cli_json.h"

#define TRACE_USAGE                                                                                \
    "usage: refract trace ID FILE|- [--step VOXELS] [--stepper NAME] [--events]\n"                 \
    "       refract trace ID --origin X,Y,Z --direction X,Y,Z [--step VOXELS]\n"                   \
    "                        [--stepper NAME] [--events]\n"                                        \
    "\n"                                                                                           \
    "Traces rays through scene ID and prints the JSON reply: for each ray its status,\n"           \
    "exit_origin, exit_direction, transmittance, optical_path_length and steps.\n"                 \
    "FILE is a trace request, {\"rays\": [{\"origin\": [x,y,z], \"direction\": [x,y,z]}]}.\n"      \
    "\n"                                                                                           \
    "  --origin X,Y,Z      one ray's start, world space (instead of FILE)\n"                       \
    "  --direction X,Y,Z   that ray's direction of propagation, world space\n"                     \
    "  --step VOXELS       integration step in voxels (overrides FILE's \"step\")\n"               \
    "  --stepper NAME      euler, rk2, rk4 or adaptive (overrides FILE's \"stepper\")\n"           \
    "  --events            list each ray's surface events (point, normal, media, n on\n"           \
    "                      both sides, refracted or totally reflected, Fresnel R)\n"               \
    "\n"                                                                                           \
    "Examples:\n"                                                                                  \
    "  refract trace \"$ID\" rays.json\n"                                                          \
    "  refract trace \"$ID\" --origin 0,0,4 --direction 0,0,-1 --step 0.25\n"                      \
    "  refract trace glass_sphere --origin 0,0.5,-3 --direction 0,0,1 --events\n"

static int run_trace(struct cli *cli, int argc, char **argv);

const struct cli_command cli_cmd_trace = {
    .name = "trace",
    .synopsis = "trace ID FILE|--origin ...",
    .summary = "trace rays through a scene and print where they leave it",
    .usage = TRACE_USAGE,
    .run = run_trace,
};

enum trace_opt { OPT_ORIGIN, OPT_DIRECTION, OPT_STEP, OPT_STEPPER, OPT_EVENTS, OPT_COUNT };

/* Builds {"rays": [{"origin": [...], "direction": [...]}]} from the flags; *out is a new
 * tree the caller deletes. */
static int one_ray_request(const struct cli_opt *opts, cJSON **out)
{
    double origin[3];
    double direction[3];
    char why[256];
    cJSON *ray;
    cJSON *rays;

    *out = NULL;
    if (!opts[OPT_ORIGIN].given || !opts[OPT_DIRECTION].given)
        return cli_usage_error(&cli_cmd_trace, "trace: %s needs %s too",
                               opts[OPT_ORIGIN].given ? "--origin" : "--direction",
                               opts[OPT_ORIGIN].given ? "--direction" : "--origin");
    if (!cli_parse_vec3(opts[OPT_ORIGIN].value, origin, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_trace, "trace: --origin: %s", why);
    if (!cli_parse_vec3(opts[OPT_DIRECTION].value, direction, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_trace, "trace: --direction: %s", why);
    *out = cJSON_CreateObject();
    rays = cJSON_AddArrayToObject(*out, "rays"); /* owned by *out from here on */
    ray = cJSON_CreateObject();
    if (rays == NULL || ray == NULL || !cJSON_AddItemToArray(rays, ray) ||
        !cli_json_set(ray, "origin", cJSON_CreateDoubleArray(origin, 3)) ||
        !cli_json_set(ray, "direction", cJSON_CreateDoubleArray(direction, 3))) {
        if (rays == NULL || cJSON_GetArraySize(rays) == 0)
            cJSON_Delete(ray); /* never attached */
        cJSON_Delete(*out);
        *out = NULL;
        return cli_fail(REFRACT_E_OUT_OF_MEMORY, "trace: out of memory building the request");
    }
    return REFRACT_E_OK;
}

static int apply_overrides(cJSON *request, const struct cli_opt *opts)
{
    char why[256];
    double step;

    if (opts[OPT_STEP].given) {
        if (!cli_parse_double(opts[OPT_STEP].value, &step, why, sizeof(why)))
            return cli_usage_error(&cli_cmd_trace, "trace: --step: %s", why);
        if (!cli_json_set(request, "step", cJSON_CreateNumber(step)))
            return cli_fail(REFRACT_E_OUT_OF_MEMORY, "trace: out of memory");
    }
    if (opts[OPT_STEPPER].given) /* the flag overrides FILE's old key too */
        cJSON_DeleteItemFromObjectCaseSensitive(request, "integrator"); /* renamed: old key */
    if (opts[OPT_STEPPER].given &&
        !cli_json_set(request, "stepper", cJSON_CreateString(opts[OPT_STEPPER].value)))
        return cli_fail(REFRACT_E_OUT_OF_MEMORY, "trace: out of memory");
    if (opts[OPT_EVENTS].given && !cli_json_set(request, "events", cJSON_CreateTrue()))
        return cli_fail(REFRACT_E_OUT_OF_MEMORY, "trace: out of memory");
    return REFRACT_E_OK;
}

/* Parses and edits the request; *text is a new string the caller frees with free(). */
static int edited_request(const struct cli_parsed *p, const struct cli_opt *opts, bool one_ray,
                          char **text)
{
    cJSON *request = NULL;
    char *printed;
    int code = one_ray ? one_ray_request(opts, &request)
                       : cli_json_load_object(p->pos[1], "trace", &request);

    if (code == REFRACT_E_OK)
        code = apply_overrides(request, opts);
    if (code == REFRACT_E_OK) {
        printed = cJSON_PrintUnformatted(request);
        *text = printed != NULL ? strdup(printed) : NULL;
        cJSON_free(printed);
        if (*text == NULL)
            code = cli_fail(REFRACT_E_OUT_OF_MEMORY, "trace: out of memory");
    }
    cJSON_Delete(request);
    return code;
}

/* The request text: FILE unchanged, FILE with overrides, or the one-ray form. *text is
 * a new string the caller frees with free(). */
static int build_request(const struct cli_parsed *p, const struct cli_opt *opts, char **text)
{
    bool one_ray = opts[OPT_ORIGIN].given || opts[OPT_DIRECTION].given;
    bool overrides = opts[OPT_STEP].given || opts[OPT_STEPPER].given || opts[OPT_EVENTS].given;
    size_t len;

    *text = NULL;
    if (one_ray && p->n_pos > 1)
        return cli_usage_error(&cli_cmd_trace, "trace: give either a request FILE or "
                                               "--origin and --direction, not both");
    if (!one_ray && p->n_pos < 2)
        return cli_usage_error(&cli_cmd_trace, "trace: missing the request FILE (or - for "
                                               "stdin), or --origin and --direction");
    /* Unchanged, the file's own bytes go out, so refractd's error positions match it. */
    if (!one_ray && !overrides)
        return cli_read_file(p->pos[1], text, &len);
    return edited_request(p, opts, one_ray, text);
}

static int run_trace(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene ID"};
    struct cli_opt opts[OPT_COUNT] = {
        [OPT_ORIGIN] = {.name = "--origin", .takes_value = true},
        [OPT_DIRECTION] = {.name = "--direction", .takes_value = true},
        [OPT_STEP] = {.name = "--step", .takes_value = true},
        [OPT_STEPPER] = {.name = "--stepper",
                         .alias = "--integrator", /* renamed: the old flag keeps working */
                         .takes_value = true},
        [OPT_EVENTS] = {.name = "--events"},
    };
    struct cli_parsed p;
    char *request = NULL;
    char *json = NULL;
    int code = cli_parse_command(&cli_cmd_trace, argc, argv, opts, OPT_COUNT, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&cli_cmd_trace, &p, 1, 2, names);
    if (code == REFRACT_E_OK)
        code = build_request(&p, opts, &request);
    if (code == REFRACT_E_OK)
        code = cli_connect(cli);
    if (code == REFRACT_E_OK) {
        code = refract_trace(cli->client, p.pos[0], request, &json);
        code = code == REFRACT_E_OK ? cli_print_json(json) : cli_call_failed(cli, code);
    }
    refract_free(json);
    free(request);
    return code;
}
