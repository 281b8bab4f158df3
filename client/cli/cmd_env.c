/*
 * cmd_env.c - `refract env upload`: sends an image file as a scene's environment map
 * (the same as `refract upload ID FILE --environment`: cli_upload.c, streamed, with
 * progress). The bytes go as they are; refractd decodes them (EXR, Radiance HDR, PNG or
 * JPEG) and answers invalid_image when it cannot, so this file does not sniff formats.
 */
#include <string.h>

#include "cli.h"
#include "cli_upload.h"

#define ENV_USAGE                                                                                  \
    "usage: refract env upload ID FILE|- [--quiet]\n"                                              \
    "\n"                                                                                           \
    "Uploads FILE (an equirectangular EXR, Radiance HDR, PNG or JPEG image) as the\n"              \
    "environment map of scene ID. Prints refractd's description of what it stored.\n"              \
    "\n"                                                                                           \
    "Example:\n"                                                                                   \
    "  refract env upload \"$ID\" studio.exr\n"

static int run_group(struct cli *cli, int argc, char **argv);

const struct cli_command cli_cmd_env = {
    .name = "env",
    .synopsis = "env upload",
    .summary = "upload an environment map image into a scene",
    .usage = ENV_USAGE,
    .run = run_group,
};

static const struct cli_command env_upload_cmd = {.name = "env upload", .usage = ENV_USAGE};

static int run_upload(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene ID", "the image FILE"};
    struct cli_opt opts[] = {{.name = "--quiet", .alias = "-q"}};
    struct cli_parsed p;
    int code = cli_parse_command(&env_upload_cmd, argc, argv, opts, 1, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&env_upload_cmd, &p, 2, 2, names);
    struct cli_upload up = {.cmd = &env_upload_cmd,
                            .scene = p.pos[0],
                            .file = p.pos[1],
                            .desc = {.kind = REFRACT_UPLOAD_ENVIRONMENT},
                            .quiet = opts[0].given};
    if (code == REFRACT_E_OK)
        code = cli_upload_run(cli, &up);
    return code;
}

static int run_group(struct cli *cli, int argc, char **argv)
{
    if (argc == 0)
        return cli_usage_error(&cli_cmd_env, "env: missing the command (upload)");
    if (strcmp(argv[0], "-h") == 0 || strcmp(argv[0], "--help") == 0) {
        fputs(cli_cmd_env.usage, stdout);
        return REFRACT_E_OK;
    }
    if (strcmp(argv[0], "upload") == 0)
        return run_upload(cli, argc - 1, argv + 1);
    return cli_usage_error(&cli_cmd_env, "unknown env command '%s'", argv[0]);
}
