/*
 * cmd_volume.c - `refract volume upload`: sends a raw float32 file as a named volume
 * of a scene; the older, narrower form of `refract upload ID FILE --volume NAME
 * --format raw`, and sent the same way (cli_upload.c: streamed, with progress).
 *
 * The file's size is checked against --dims and --components before anything is sent,
 * because a wrong size almost always means wrong dims, and saying so with both numbers
 * beats uploading hundreds of megabytes to be told the same. That check exits with
 * REFRACT_E_INVALID_VOLUME, the code refractd gives for the same mistake.
 */
#include <string.h>

#include "cli.h"
#include "cli_upload.h"

#define VOLUME_USAGE                                                                               \
    "usage: refract volume upload ID NAME FILE|- --dims X,Y,Z [--components C] [--quiet]\n"        \
    "\n"                                                                                           \
    "Uploads FILE as the volume NAME of scene ID. FILE holds raw little-endian float32\n"          \
    "values, x fastest, then y, then z, with C values per voxel (default 1), so it must\n"         \
    "be exactly X*Y*Z*C*4 bytes. Prints refractd's description of what it stored.\n"               \
    "The file is streamed, with its progress on stderr; 'refract upload' sends the\n"              \
    "other types and formats, meshes and environment images.\n"                                    \
    "\n"                                                                                           \
    "  --dims X,Y,Z       voxels along x, y and z (each 1..65536)\n"                               \
    "  --components C     values per voxel (default 1)\n"                                          \
    "  -q, --quiet        no progress on stderr\n"                                                 \
    "\n"                                                                                           \
    "Example:\n"                                                                                   \
    "  refract volume upload \"$ID\" ior ior_64.raw --dims 64,64,64\n"

static int run_group(struct cli *cli, int argc, char **argv);

const struct cli_command cli_cmd_volume = {
    .name = "volume",
    .synopsis = "volume upload",
    .summary = "upload a raw float32 volume into a scene",
    .usage = VOLUME_USAGE,
    .run = run_group,
};

static const struct cli_command volume_upload_cmd = {.name = "volume upload",
                                                     .usage = VOLUME_USAGE};

/* Reads --dims and --components. */
static int parse_shape(struct cli_opt *dims_opt, struct cli_opt *comp_opt, int dims[3],
                       int *components)
{
    char why[256];
    long comp = 1;

    if (!dims_opt->given)
        return cli_usage_error(&volume_upload_cmd, "volume upload: missing --dims X,Y,Z");
    if (!cli_parse_dims(dims_opt->value, dims, why, sizeof(why)))
        return cli_usage_error(&volume_upload_cmd, "volume upload: --dims: %s", why);
    if (comp_opt->given && !cli_parse_long(comp_opt->value, 1, 65536, &comp, why, sizeof(why)))
        return cli_usage_error(&volume_upload_cmd, "volume upload: --components: %s", why);
    *components = (int)comp;
    return REFRACT_E_OK;
}

static int run_upload(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene ID", "the volume NAME",
                                        "the FILE of float32 values"};
    struct cli_opt opts[] = {{.name = "--dims", .takes_value = true},
                             {.name = "--components", .takes_value = true},
                             {.name = "--quiet", .alias = "-q"}};
    struct cli_parsed p;
    int code = cli_parse_command(&volume_upload_cmd, argc, argv, opts, 3, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&volume_upload_cmd, &p, 3, 3, names);
    struct cli_upload up = {
        .cmd = &volume_upload_cmd,
        .scene = p.pos[0],
        .file = p.pos[2],
        .desc = {.kind = REFRACT_UPLOAD_VOLUME,
                 .name = p.pos[1],
                 .format = "raw",
                 .type = "float32"},
        .quiet = opts[2].given,
    };
    if (code == REFRACT_E_OK)
        code = parse_shape(&opts[0], &opts[1], up.desc.dims, &up.desc.components);
    if (code == REFRACT_E_OK)
        code = cli_upload_run(cli, &up);
    return code;
}

static int run_group(struct cli *cli, int argc, char **argv)
{
    if (argc == 0)
        return cli_usage_error(&cli_cmd_volume, "volume: missing the command (upload)");
    if (strcmp(argv[0], "-h") == 0 || strcmp(argv[0], "--help") == 0) {
        fputs(cli_cmd_volume.usage, stdout);
        return REFRACT_E_OK;
    }
    if (strcmp(argv[0], "upload") == 0)
        return run_upload(cli, argc - 1, argv + 1);
    return cli_usage_error(&cli_cmd_volume, "unknown volume command '%s'", argv[0]);
}
