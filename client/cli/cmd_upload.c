/*
 * cmd_upload.c - `refract upload ID FILE`: sends a volume, a mesh or an environment
 * image to a scene, streamed from disk with a progress bar (cli_upload.c does the
 * sending). This file turns the command line into a struct refract_upload_desc: the
 * kind comes from --volume, --mesh, --environment or --as, else from the extension;
 * the name from --volume/--mesh, else from the file's name; the rest from the flags.
 */
#include <string.h>

#include "cli.h"
#include "cli_upload.h"

#define UPLOAD_USAGE                                                                               \
    "usage: refract upload ID FILE|- [--volume NAME | --mesh NAME | --environment |\n"             \
    "                                 --as volume|mesh|environment]\n"                             \
    "                      [--format F] [--dims X,Y,Z] [--type T] [--components C]\n"              \
    "                      [--scale S] [--offset O] [--quiet]\n"                                   \
    "\n"                                                                                           \
    "Uploads FILE into scene ID, streamed from disk (a file of any size costs no\n"                \
    "memory), with its progress on stderr: a bar on a terminal (bytes, percent, MB/s,\n"           \
    "ETA), a line per 10 % otherwise. Prints refractd's description of what it stored\n"           \
    "(dims, range, checksum and sha256) on stdout.\n"                                              \
    "\n"                                                                                           \
    "What FILE is comes from its extension, unless a flag says:\n"                                 \
    "  .nrrd .nhdr .raw     a volume (NRRD with attached raw or gzip data; raw samples)\n"         \
    "  .obj .ply            a mesh (Wavefront OBJ; PLY, ascii or binary)\n"                        \
    "  .hdr .png .jpg .jpeg the environment map (equirectangular)\n"                               \
    "  .exr                 a volume or the environment: give --volume NAME or --environment\n"    \
    "A volume or mesh is named after the file (ior.nrrd -> ior) unless NAME is given;\n"           \
    "scene layers and mesh shapes refer to it by that name.\n"                                     \
    "\n"                                                                                           \
    "  --volume NAME      upload a volume called NAME\n"                                           \
    "  --mesh NAME        upload a mesh called NAME\n"                                             \
    "  --environment      upload the scene's environment image\n"                                  \
    "  --as KIND          volume, mesh or environment, named after the file\n"                     \
    "  --format F         volume: raw, nrrd or exr; mesh: obj or ply (default: the\n"              \
    "                     extension's, else refractd recognises the file)\n"                       \
    "  --dims X,Y,Z       voxels along x, y, z: required for raw and for an EXR slice atlas\n"     \
    "  --type T           raw samples: float32 (default), float16, uint8, uint16\n"                \
    "  --components C     values per voxel: 1 (default) or 3 (RGB)\n"                              \
    "  --scale S          stored value = O + S * sample (default 1), e.g. 0.00392157\n"            \
    "  --offset O         for uint8 samples to 0..1 (default 0)\n"                                 \
    "  -q, --quiet        no progress on stderr\n"                                                 \
    "\n"                                                                                           \
    "Checked before anything is sent: FILE can be read; a raw file has exactly\n"                  \
    "X*Y*Z*C*(bytes per sample) bytes and an NRRD file its data attached (else exit 17,\n"         \
    "invalid_volume). refractd validates the rest and its errors come back with their\n"           \
    "message and code.\n"                                                                          \
    "\n"                                                                                           \
    "Examples:\n"                                                                                  \
    "  refract upload \"$ID\" ior.nrrd\n"                                                          \
    "  refract upload \"$ID\" density.raw --dims 256,256,256 --type uint8 --scale 0.00392157\n"    \
    "  refract upload \"$ID\" gem.ply --mesh gem\n"                                                \
    "  refract upload \"$ID\" sky.exr --environment\n"

static int run_upload(struct cli *cli, int argc, char **argv);

const struct cli_command cli_cmd_upload = {
    .name = "upload",
    .synopsis = "upload ID FILE",
    .summary = "upload a volume, mesh or environment image, with progress",
    .usage = UPLOAD_USAGE,
    .run = run_upload,
};

enum {
    OPT_VOLUME,
    OPT_MESH,
    OPT_ENVIRONMENT,
    OPT_AS,
    OPT_FORMAT,
    OPT_DIMS,
    OPT_TYPE,
    OPT_COMPONENTS,
    OPT_SCALE,
    OPT_OFFSET,
    OPT_QUIET,
    OPT_COUNT
};

static const char *const kind_names[] = {"", "volume", "mesh", "environment"};

/* The kind the flags name (0 = none); a usage error when they name two. */
static int kind_from_flags(const struct cli_opt *o, int *kind)
{
    int n = o[OPT_VOLUME].given + o[OPT_MESH].given + o[OPT_ENVIRONMENT].given + o[OPT_AS].given;

    *kind = 0;
    if (n > 1)
        return cli_usage_error(&cli_cmd_upload,
                               "upload: give one of --volume NAME, --mesh NAME, --environment "
                               "and --as KIND");
    if (o[OPT_VOLUME].given)
        *kind = REFRACT_UPLOAD_VOLUME;
    else if (o[OPT_MESH].given)
        *kind = REFRACT_UPLOAD_MESH;
    else if (o[OPT_ENVIRONMENT].given)
        *kind = REFRACT_UPLOAD_ENVIRONMENT;
    for (int k = 1; k <= 3 && o[OPT_AS].given; k++) {
        if (strcmp(o[OPT_AS].value, kind_names[k]) == 0)
            *kind = k;
    }
    if (o[OPT_AS].given && *kind == 0)
        return cli_usage_error(&cli_cmd_upload,
                               "upload: --as: expected volume, mesh or environment, got '%s'",
                               o[OPT_AS].value);
    return REFRACT_E_OK;
}

/* The kind, format and name of the upload of file. */
static int choose_kind(const struct cli_opt *o, const char *file, struct refract_upload_desc *d,
                       char *name, size_t name_size)
{
    const char *ext_format = NULL;
    int ext_kind = strcmp(file, "-") == 0 ? 0 : cli_upload_kind_from_path(file, &ext_format);
    int kind = 0;
    int code = kind_from_flags(o, &kind);

    if (code != REFRACT_E_OK)
        return code;
    if (kind == 0 && ext_format != NULL && strcmp(ext_format, "exr") == 0)
        return cli_usage_error(&cli_cmd_upload,
                               "upload: '%s' could be a volume or an environment map; add "
                               "--volume NAME or --environment",
                               file);
    if (kind == 0 && ext_kind == 0)
        return cli_usage_error(&cli_cmd_upload,
                               "upload: cannot tell what '%s' is from its name; add --volume "
                               "NAME, --mesh NAME or --environment",
                               file);
    d->kind = kind != 0 ? kind : ext_kind;
    /* The extension's format, when it is one of this kind's. */
    if (ext_format != NULL &&
        (ext_kind == (int)d->kind || (ext_kind == 0 && d->kind == REFRACT_UPLOAD_VOLUME)))
        d->format = ext_format;
    if (o[OPT_FORMAT].given)
        d->format = o[OPT_FORMAT].value;
    if (d->kind == REFRACT_UPLOAD_ENVIRONMENT) {
        d->format = NULL;
        if (o[OPT_FORMAT].given)
            return cli_usage_error(&cli_cmd_upload,
                                   "upload: --format applies to volumes and meshes; refractd "
                                   "recognises environment images by their content");
        return REFRACT_E_OK;
    }
    const struct cli_opt *named = d->kind == REFRACT_UPLOAD_VOLUME ? &o[OPT_VOLUME] : &o[OPT_MESH];
    if (named->given) {
        d->name = named->value;
    } else if (cli_upload_default_name(file, name, name_size)) {
        d->name = name;
    } else {
        return cli_usage_error(&cli_cmd_upload,
                               "upload: '%s' does not make a %s name (1..63 of A-Z a-z 0-9 _ "
                               "-); give it with --%s NAME",
                               file, kind_names[d->kind], kind_names[d->kind]);
    }
    return REFRACT_E_OK;
}

/* The volume-only flags into d; a usage error when they are given for another kind. */
static int volume_flags(const struct cli_opt *o, struct refract_upload_desc *d)
{
    static const int flags[] = {OPT_DIMS, OPT_TYPE, OPT_COMPONENTS, OPT_SCALE, OPT_OFFSET};
    char why[256];
    long comps = 0;

    for (size_t i = 0; i < sizeof(flags) / sizeof(flags[0]); i++) {
        if (o[flags[i]].given && d->kind != REFRACT_UPLOAD_VOLUME)
            return cli_usage_error(&cli_cmd_upload, "upload: %s applies to volumes only, not to %s",
                                   o[flags[i]].name,
                                   d->kind == REFRACT_UPLOAD_MESH ? "a mesh" : "the environment");
    }
    if (o[OPT_DIMS].given && !cli_parse_dims(o[OPT_DIMS].value, d->dims, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_upload, "upload: --dims: %s", why);
    if (o[OPT_TYPE].given && cli_upload_sample_bytes(o[OPT_TYPE].value) == 0)
        return cli_usage_error(&cli_cmd_upload,
                               "upload: --type: expected float32, float16, uint8 or uint16, got "
                               "'%s'",
                               o[OPT_TYPE].value);
    if (o[OPT_TYPE].given && d->format != NULL && strcmp(d->format, "raw") != 0)
        return cli_usage_error(&cli_cmd_upload,
                               "upload: --type applies to raw volumes; a %s file says its own "
                               "sample type",
                               d->format);
    d->type = o[OPT_TYPE].value;
    if (o[OPT_COMPONENTS].given &&
        (!cli_parse_long(o[OPT_COMPONENTS].value, 1, 3, &comps, why, sizeof(why)) || comps == 2))
        return cli_usage_error(&cli_cmd_upload,
                               "upload: --components: expected 1 (scalar) or 3 (RGB), got '%s'",
                               o[OPT_COMPONENTS].value);
    d->components = (int)comps;
    d->has_scale = o[OPT_SCALE].given;
    if (d->has_scale && !cli_parse_double(o[OPT_SCALE].value, &d->scale, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_upload, "upload: --scale: %s", why);
    d->has_offset = o[OPT_OFFSET].given;
    if (d->has_offset && !cli_parse_double(o[OPT_OFFSET].value, &d->offset, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_upload, "upload: --offset: %s", why);
    return REFRACT_E_OK;
}

static int run_upload(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene ID", "the FILE to upload"};
    struct cli_opt o[OPT_COUNT] = {
        [OPT_VOLUME] = {.name = "--volume", .takes_value = true},
        [OPT_MESH] = {.name = "--mesh", .takes_value = true},
        [OPT_ENVIRONMENT] = {.name = "--environment"},
        [OPT_AS] = {.name = "--as", .takes_value = true},
        [OPT_FORMAT] = {.name = "--format", .takes_value = true},
        [OPT_DIMS] = {.name = "--dims", .takes_value = true},
        [OPT_TYPE] = {.name = "--type", .takes_value = true},
        [OPT_COMPONENTS] = {.name = "--components", .takes_value = true},
        [OPT_SCALE] = {.name = "--scale", .takes_value = true},
        [OPT_OFFSET] = {.name = "--offset", .takes_value = true},
        [OPT_QUIET] = {.name = "--quiet", .alias = "-q"},
    };
    struct cli_parsed p;
    char name[64];
    int code = cli_parse_command(&cli_cmd_upload, argc, argv, o, OPT_COUNT, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&cli_cmd_upload, &p, 2, 2, names);
    struct cli_upload up = {
        .cmd = &cli_cmd_upload, .scene = p.pos[0], .file = p.pos[1], .quiet = o[OPT_QUIET].given};
    if (code == REFRACT_E_OK)
        code = choose_kind(o, up.file, &up.desc, name, sizeof(name));
    if (code == REFRACT_E_OK)
        code = volume_flags(o, &up.desc);
    if (code == REFRACT_E_OK)
        code = cli_upload_run(cli, &up);
    return code;
}
