/*
 * cmd_irradiance.c - `refract irradiance status|wait|get`: the irradiance volumes refractd
 * keeps for a scene's lights.
 *
 * status prints a table for people (--json prints refractd's reply for scripts); get
 * downloads one light's volume as OpenEXR, written only after refractd answered with
 * one, so a failed download never truncates an older file.
 */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "cli_image.h"
#include "cli_irradiance.h"

#define IRRADIANCE_USAGE                                                                           \
    "usage: refract irradiance status ID [--json]\n"                                               \
    "       refract irradiance wait ID\n"                                                          \
    "       refract irradiance get ID LIGHT -o FILE.exr\n"                                         \
    "\n"                                                                                           \
    "status shows, for each light of scene ID, the state of its irradiance volume\n"               \
    "(ready, queued, computing, stale, failed, not_needed), the simulation's\n"                    \
    "progress and live wavefront patches, the GPU and host memory the volume takes,\n"             \
    "its compute time, and which volume renders use now (current, previous, none).\n"              \
    "--json prints refractd's reply instead of the table.\n"                                       \
    "\n"                                                                                           \
    "wait waits until every light's volume is ready, failed or not needed, with a\n"               \
    "progress bar on stderr (--timeout bounds it, default 120 s), then prints the\n"               \
    "table; it exits with the failed light's code when a simulation failed.\n"                     \
    "\n"                                                                                           \
    "get writes LIGHT's irradiance volume to FILE (- = stdout) as OpenEXR: the z\n"                \
    "slices stacked vertically, z = 0 at the top; channels R, G, B (irradiance) and\n"             \
    "dir.X, dir.Y, dir.Z, dir.W (light direction); see docs/api.md.\n"                             \
    "\n"                                                                                           \
    "Examples:\n"                                                                                  \
    "  refract irradiance status \"$ID\"\n"                                                        \
    "  refract irradiance status \"$ID\" --json | jq '.lights[] | {name, state}'\n"                \
    "  refract irradiance wait \"$ID\" && refract render \"$ID\" -o lit.png\n"                     \
    "  refract irradiance get \"$ID\" sun -o sun_irradiance.exr\n"

static int run_group(struct cli *cli, int argc, char **argv);

const struct cli_command cli_cmd_irradiance = {
    .name = "irradiance",
    .synopsis = "irradiance status|wait|get",
    .summary = "show the lights' irradiance volumes, or download one as EXR",
    .usage = IRRADIANCE_USAGE,
    .run = run_group,
};

static const struct cli_command irradiance_status_cmd = {.name = "irradiance status",
                                                         .usage = IRRADIANCE_USAGE};
static const struct cli_command irradiance_wait_cmd = {.name = "irradiance wait",
                                                       .usage = IRRADIANCE_USAGE};
static const struct cli_command irradiance_get_cmd = {.name = "irradiance get",
                                                      .usage = IRRADIANCE_USAGE};

static int run_status(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene ID"};
    struct cli_opt opts[] = {{.name = "--json"}};
    struct refract_irradiance status = {0};
    struct cli_parsed p;
    int code = cli_parse_command(&irradiance_status_cmd, argc, argv, opts, 1, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&irradiance_status_cmd, &p, 1, 1, names);
    if (code == REFRACT_E_OK)
        code = cli_connect(cli);
    if (code != REFRACT_E_OK)
        return code;
    code = refract_irradiance_status(cli->client, p.pos[0], &status);
    if (code != REFRACT_E_OK) {
        code = cli_call_failed(cli, code);
    } else if (opts[0].given) {
        code = cli_print_json(status.json);
    } else {
        cli_irradiance_table(stdout, &status);
        if (fflush(stdout) != 0 || ferror(stdout))
            code = cli_fail(REFRACT_E_IO, "cannot write to stdout");
    }
    refract_irradiance_free(&status);
    return code;
}

/* The first failed light's code (gpu_error when refractd named none), or OK. */
static int failed_code(const struct refract_irradiance *s)
{
    for (size_t i = 0; i < s->light_count; i++) {
        if (strcmp(s->lights[i].state, "failed") == 0)
            return cli_fail(s->lights[i].code > 0 ? s->lights[i].code : REFRACT_E_GPU_ERROR,
                            "light %s: the irradiance simulation failed: %s", s->lights[i].name,
                            s->lights[i].message[0] != '\0' ? s->lights[i].message
                                                            : "(refractd gave no message)");
    }
    return REFRACT_E_OK;
}

static int run_wait(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene ID"};
    struct refract_irradiance status = {0};
    struct cli_parsed p;
    int code = cli_parse_command(&irradiance_wait_cmd, argc, argv, NULL, 0, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&irradiance_wait_cmd, &p, 1, 1, names);
    if (code == REFRACT_E_OK)
        code = cli_connect(cli);
    if (code != REFRACT_E_OK)
        return code;
    code = refract_irradiance_status(cli->client, p.pos[0], &status);
    if (code != REFRACT_E_OK)
        return cli_call_failed(cli, code);
    code = cli_wait_irradiance(cli, p.pos[0], &status);
    if (code != REFRACT_E_OK) {
        refract_irradiance_free(&status);
        return cli_call_failed(cli, code);
    }
    cli_irradiance_table(stdout, &status);
    code = failed_code(&status);
    if (fflush(stdout) != 0 || ferror(stdout))
        code = cli_fail(REFRACT_E_IO, "cannot write to stdout");
    refract_irradiance_free(&status);
    return code;
}

/* -o FILE: required, not a terminal, and not named for another image format. */
static int check_output(const struct cli_opt *out)
{
    const char *named;

    if (!out->given)
        return cli_usage_error(&irradiance_get_cmd, "irradiance get: missing -o FILE (where to "
                                                    "write the EXR; - for stdout)");
    if (strcmp(out->value, "-") == 0 && isatty(1))
        return cli_usage_error(&irradiance_get_cmd, "irradiance get: refusing to write an EXR "
                                                    "to a terminal; give -o FILE or redirect "
                                                    "stdout");
    named = strcmp(out->value, "-") == 0 ? NULL : cli_format_from_path(out->value);
    if (named != NULL && strcmp(named, "exr") != 0)
        return cli_usage_error(&irradiance_get_cmd,
                               "irradiance get: the volume is an OpenEXR "
                               "file but '%s' is named for %s; name it .exr",
                               out->value, named);
    return REFRACT_E_OK;
}

/* "wrote FILE (WxH EXR, N bytes)" on stderr, and a note when the volume is stale. */
static void report_get(const char *path, const char *scene, const char *light,
                       const struct refract_image *img)
{
    const char *shown = strcmp(path, "-") == 0 ? "<stdout>" : path;
    long width = 0;
    long height = 0;

    if (cli_image_size(img->bytes, img->len, &width, &height))
        fprintf(stderr, "wrote %s (%ldx%ld EXR, %zu bytes)\n", shown, width, height, img->len);
    else
        fprintf(stderr, "wrote %s (EXR, %zu bytes)\n", shown, img->len);
    if (strcmp(img->irradiance, "stale") == 0)
        fprintf(stderr,
                "refract: note: light %s's volume for its current pose is not ready yet; "
                "this is the previous pose's. 'refract irradiance status %s' shows the "
                "progress\n",
                light, scene);
}

static int run_get(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene ID", "the LIGHT name"};
    struct cli_opt opts[] = {{.name = "--output", .alias = "-o", .takes_value = true}};
    struct refract_image img = {0};
    struct cli_parsed p;
    int code = cli_parse_command(&irradiance_get_cmd, argc, argv, opts, 1, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&irradiance_get_cmd, &p, 2, 2, names);
    if (code == REFRACT_E_OK)
        code = check_output(&opts[0]);
    if (code == REFRACT_E_OK)
        code = cli_connect(cli);
    if (code == REFRACT_E_OK) {
        code = refract_irradiance_get_exr(cli->client, p.pos[0], p.pos[1], &img);
        if (code != REFRACT_E_OK)
            code = cli_call_failed(cli, code);
    }
    if (code == REFRACT_E_OK)
        code = cli_write_file(opts[0].value, img.bytes, img.len);
    if (code == REFRACT_E_OK)
        report_get(opts[0].value, p.pos[0], p.pos[1], &img);
    refract_image_free(&img);
    return code;
}

static int run_group(struct cli *cli, int argc, char **argv)
{
    if (argc == 0)
        return cli_usage_error(&cli_cmd_irradiance, "irradiance: missing the command (status, "
                                                    "wait or get)");
    if (strcmp(argv[0], "-h") == 0 || strcmp(argv[0], "--help") == 0) {
        fputs(cli_cmd_irradiance.usage, stdout);
        return REFRACT_E_OK;
    }
    if (strcmp(argv[0], "status") == 0)
        return run_status(cli, argc - 1, argv + 1);
    if (strcmp(argv[0], "get") == 0)
        return run_get(cli, argc - 1, argv + 1);
    if (strcmp(argv[0], "wait") == 0)
        return run_wait(cli, argc - 1, argv + 1);
    return cli_usage_error(&cli_cmd_irradiance, "unknown irradiance command '%s'", argv[0]);
}
