/*
 * cmd_volume.c - `refract volume upload`: sends a raw float32 file as a named volume
 * of a scene.
 *
 * The file's size is checked against --dims and --components before anything is sent,
 * because a wrong size almost always means wrong dims, and saying so with both numbers
 * beats uploading hundreds of megabytes to be told the same. That check exits with
 * REFRACT_E_INVALID_VOLUME, the code refractd gives for the same mistake.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#define VOLUME_USAGE                                                                               \
    "usage: refract volume upload ID NAME FILE|- --dims X,Y,Z [--components C]\n"                  \
    "\n"                                                                                           \
    "Uploads FILE as the volume NAME of scene ID. FILE holds raw little-endian float32\n"          \
    "values, x fastest, then y, then z, with C values per voxel (default 1), so it must\n"         \
    "be exactly X*Y*Z*C*4 bytes. Prints refractd's description of what it stored.\n"               \
    "\n"                                                                                           \
    "  --dims X,Y,Z       voxels along x, y and z (each 1..65536)\n"                               \
    "  --components C     values per voxel (default 1)\n"                                          \
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

/* Turns little-endian float32 bytes into host floats in place (a no-op on little-endian
 * hosts, which is every host we ship on; the runtime test keeps big-endian correct). */
static void floats_from_le(unsigned char *bytes, size_t count)
{
    const uint32_t one = 1;
    unsigned char first;

    memcpy(&first, &one, 1);
    if (first == 1)
        return;
    for (size_t i = 0; i < count; i++) {
        unsigned char *b = bytes + 4 * i;
        uint32_t bits =
            (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;

        memcpy(b, &bits, 4);
    }
}

/* Checks FILE's size against the dims; prints the mismatch with both numbers. */
static int check_size(const char *path, const int dims[3], int components, size_t found)
{
    uint64_t expected = 0;

    if (!cli_volume_bytes(dims, components, &expected))
        return cli_usage_error(&volume_upload_cmd,
                               "volume upload: --dims %d,%d,%d with "
                               "--components %d is too large",
                               dims[0], dims[1], dims[2], components);
    if ((uint64_t)found == expected)
        return REFRACT_E_OK;
    return cli_fail(REFRACT_E_INVALID_VOLUME,
                    "volume upload: '%s' has %zu bytes, but --dims "
                    "%d,%d,%d --components %d needs %d*%d*%d*%d*4 = %llu bytes of float32; "
                    "check --dims and --components",
                    path, found, dims[0], dims[1], dims[2], components, dims[0], dims[1], dims[2],
                    components, (unsigned long long)expected);
}

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
                             {.name = "--components", .takes_value = true}};
    struct cli_parsed p;
    int dims[3] = {0, 0, 0};
    int components = 1;
    char *data = NULL;
    char *json = NULL;
    size_t len = 0;
    int code = cli_parse_command(&volume_upload_cmd, argc, argv, opts, 2, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&volume_upload_cmd, &p, 3, 3, names);
    if (code == REFRACT_E_OK)
        code = parse_shape(&opts[0], &opts[1], dims, &components);
    if (code == REFRACT_E_OK)
        code = cli_read_file(p.pos[2], &data, &len);
    if (code == REFRACT_E_OK)
        code = check_size(p.pos[2], dims, components, len);
    if (code == REFRACT_E_OK)
        code = cli_connect(cli);
    if (code == REFRACT_E_OK) {
        /* cli_read_file's buffer comes from malloc, so it is aligned for float. */
        floats_from_le((unsigned char *)data, len / 4);
        code = refract_volume_upload(cli->client, p.pos[0], p.pos[1], dims, components,
                                     (const float *)(const void *)data, &json);
        code = code == REFRACT_E_OK ? cli_print_json(json) : cli_call_failed(cli, code);
    }
    refract_free(json);
    free(data);
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
