/*
 * cmd_render.c - `refract render`: renders a view of a scene into an image file.
 *
 * The request is built in three layers, each overriding the one before: the scene's
 * defaults (refractd's side), the --request file, then the flags. Only syntax is checked
 * here (numbers are numbers, vectors have three); ranges and allowed values are
 * refractd's to check, so a new stepper needs no new CLI. The one exception is the
 * format, which must agree with the output file's extension: an EXR called out.png
 * helps nobody. The image is written only after refractd answered with one, so a failed
 * render never truncates an earlier file.
 */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "cli_image.h"
#include "cli_json.h"

#define RENDER_USAGE                                                                               \
    "usage: refract render ID -o FILE [options]\n"                                                 \
    "\n"                                                                                           \
    "Renders a view of scene ID and writes the image to FILE (- = stdout). Prints\n"               \
    "\"wrote FILE (WxH, FORMAT, N bytes, render R ms on RENDERER, irradiance I)\" to\n"            \
    "stderr, and a note when some light's irradiance was stale or missing (see\n"                  \
    "refract light set).\n"                                                                        \
    "\n"                                                                                           \
    "  -o, --output FILE      where to write the image (required)\n"                               \
    "  --width W, --height H  image size in pixels\n"                                              \
    "  --format png|jpeg|exr  default: from FILE's extension (.png, .jpg, .jpeg, .exr);\n"         \
    "                         png when FILE is -\n"                                                \
    "  --exposure EV          exposure in stops (0 = unchanged)\n"                                 \
    "  --stepper NAME         ray equation stepper: euler, rk2, rk4 or adaptive\n"                 \
    "  --step VOXELS          integration step, in voxels of the finest object\n"                  \
    "  --samples N            rays per pixel, a square (1, 4, 9, 16, ...): anti-aliasing\n"        \
    "  --eye X,Y,Z            camera position, world space\n"                                      \
    "  --look-at X,Y,Z        the point the camera looks at, world space\n"                        \
    "  --up X,Y,Z             the camera's up direction\n"                                         \
    "  --fov DEG              vertical field of view in degrees\n"                                 \
    "  --request FILE         a whole render request JSON (- = stdin); the flags above\n"          \
    "                         override its keys\n"                                                 \
    "\n"                                                                                           \
    "Examples:\n"                                                                                  \
    "  refract render \"$ID\" -o view.png --width 640 --height 480 --eye 0,0,4\n"                  \
    "  refract render \"$ID\" -o view.exr --request close_up.json --exposure -1\n"

static int run_render(struct cli *cli, int argc, char **argv);

const struct cli_command cli_cmd_render = {
    .name = "render",
    .synopsis = "render ID -o FILE",
    .summary = "render a view of a scene into a PNG, JPEG or EXR file",
    .usage = RENDER_USAGE,
    .run = run_render,
};

enum render_opt {
    OPT_OUTPUT,
    OPT_WIDTH,
    OPT_HEIGHT,
    OPT_FORMAT,
    OPT_EXPOSURE,
    OPT_STEPPER,
    OPT_STEP,
    OPT_SAMPLES,
    OPT_EYE,
    OPT_LOOK_AT,
    OPT_UP,
    OPT_FOV,
    OPT_REQUEST,
    OPT_COUNT
};

enum value_kind { KIND_SIZE, KIND_NUMBER, KIND_STRING, KIND_VEC3 };

/* Which request key each flag sets. The keys are the API's words (proto/openapi.yaml). */
static const struct {
    enum render_opt opt;
    const char *key;
    enum value_kind kind;
    bool in_camera; /* a member of "camera" rather than of the request */
} flag_keys[] = {
    {OPT_WIDTH, "width", KIND_SIZE, false},
    {OPT_HEIGHT, "height", KIND_SIZE, false},
    {OPT_EXPOSURE, "exposure", KIND_NUMBER, false},
    {OPT_STEPPER, "stepper", KIND_STRING, false},
    {OPT_STEP, "step", KIND_NUMBER, false},
    {OPT_SAMPLES, "samples_per_pixel", KIND_SIZE, false},
    {OPT_EYE, "eye", KIND_VEC3, true},
    {OPT_LOOK_AT, "look_at", KIND_VEC3, true},
    {OPT_UP, "up", KIND_VEC3, true},
    {OPT_FOV, "fov_y_deg", KIND_NUMBER, true},
};

/* Makes the JSON value of a flag; NULL with why filled when its syntax is wrong. */
static cJSON *flag_value(enum value_kind kind, const char *text, char *why, size_t why_size)
{
    double v[3];
    long size;

    switch (kind) {
    case KIND_SIZE:
        return cli_parse_long(text, 1, 65536, &size, why, why_size)
                   ? cJSON_CreateNumber((double)size)
                   : NULL;
    case KIND_NUMBER:
        return cli_parse_double(text, v, why, why_size) ? cJSON_CreateNumber(v[0]) : NULL;
    case KIND_VEC3:
        return cli_parse_vec3(text, v, why, why_size) ? cJSON_CreateDoubleArray(v, 3) : NULL;
    case KIND_STRING:
        return cJSON_CreateString(text);
    }
    return NULL;
}

static int apply_flags(cJSON *request, const struct cli_opt *opts)
{
    for (size_t i = 0; i < sizeof(flag_keys) / sizeof(flag_keys[0]); i++) {
        const struct cli_opt *opt = &opts[flag_keys[i].opt];
        cJSON *target = request;
        cJSON *item;
        char why[256] = "";

        if (!opt->given)
            continue;
        if (flag_keys[i].in_camera)
            target = cli_json_object_member(request, "camera");
        if (target == NULL)
            return cli_fail(REFRACT_E_INVALID_FIELD,
                            "render: --request: \"camera\" must be "
                            "an object to take %s",
                            opt->name);
        item = flag_value(flag_keys[i].kind, opt->value, why, sizeof(why));
        if (item == NULL && why[0] != '\0')
            return cli_usage_error(&cli_cmd_render, "render: %s: %s", opt->name, why);
        if (flag_keys[i].opt == OPT_STEPPER) /* the flag overrides --request's old key too */
            cJSON_DeleteItemFromObjectCaseSensitive(target, "integrator"); /* renamed: old key */
        if (!cli_json_set(target, flag_keys[i].key, item))
            return cli_fail(REFRACT_E_OUT_OF_MEMORY, "render: out of memory building the "
                                                     "request");
    }
    return REFRACT_E_OK;
}

/*
 * Decides the image format: --format, else the request file's "format", else the output
 * file's extension, else png for stdout. A format that disagrees with a recognised
 * extension is a usage error. Writes it into the request and returns it (static).
 */
static int resolve_format(cJSON *request, const struct cli_opt *opts, const char **format)
{
    const char *path = opts[OPT_OUTPUT].value;
    const char *from_ext = strcmp(path, "-") == 0 ? NULL : cli_format_from_path(path);
    const cJSON *in_request = cJSON_GetObjectItemCaseSensitive(request, "format");
    const char *chosen = NULL;

    if (opts[OPT_FORMAT].given) {
        chosen = cli_format_canonical(opts[OPT_FORMAT].value);
        if (chosen == NULL)
            return cli_usage_error(&cli_cmd_render,
                                   "render: --format: expected png, jpeg or "
                                   "exr, got '%s'",
                                   opts[OPT_FORMAT].value);
    } else if (cJSON_IsString(in_request)) {
        chosen = cli_format_canonical(in_request->valuestring);
        if (chosen == NULL)
            return cli_fail(REFRACT_E_INVALID_FIELD,
                            "render: --request: \"format\" must be "
                            "png, jpeg or exr, got \"%s\"",
                            in_request->valuestring);
    } else if (in_request != NULL) {
        return cli_fail(REFRACT_E_INVALID_FIELD, "render: --request: \"format\" must be a "
                                                 "string (png, jpeg or exr)");
    }
    if (chosen == NULL)
        chosen = from_ext != NULL ? from_ext : (strcmp(path, "-") == 0 ? "png" : NULL);
    if (chosen == NULL)
        return cli_usage_error(&cli_cmd_render,
                               "render: cannot tell the image format from "
                               "'%s'; name it .png, .jpg or .exr, or give --format",
                               path);
    if (from_ext != NULL && strcmp(from_ext, chosen) != 0)
        return cli_usage_error(&cli_cmd_render,
                               "render: the format is %s but '%s' is named "
                               "for %s; rename the file or change the format",
                               chosen, path, from_ext);
    if (!cli_json_set(request, "format", cJSON_CreateString(chosen)))
        return cli_fail(REFRACT_E_OUT_OF_MEMORY, "render: out of memory building the request");
    *format = chosen;
    return REFRACT_E_OK;
}

/* Builds the request JSON text from --request and the flags; *text is a new string the
 * caller frees with cJSON_free(). */
static int build_request(const struct cli_opt *opts, char **text)
{
    cJSON *request = NULL;
    const char *format = NULL;
    int code;

    *text = NULL;
    if (opts[OPT_REQUEST].given) {
        code = cli_json_load_object(opts[OPT_REQUEST].value, "--request", &request);
    } else {
        request = cJSON_CreateObject();
        code = request != NULL ? REFRACT_E_OK : REFRACT_E_OUT_OF_MEMORY;
    }
    if (code == REFRACT_E_OK)
        code = apply_flags(request, opts);
    if (code == REFRACT_E_OK)
        code = resolve_format(request, opts, &format);
    if (code == REFRACT_E_OK) {
        *text = cJSON_PrintUnformatted(request);
        if (*text == NULL)
            code = cli_fail(REFRACT_E_OUT_OF_MEMORY, "render: out of memory building the "
                                                     "request");
    }
    cJSON_Delete(request);
    return code;
}

/* Prints "wrote FILE (WxH, FORMAT, N bytes, render R ms on RENDERER, irradiance I)" to
 * stderr; the last part only when refractd sent X-Refract-Irradiance. */
static void report(const char *path, const struct refract_image *img)
{
    const char *format = cli_format_from_content_type(img->content_type);
    long width = 0;
    long height = 0;
    char size[48] = "unknown size";
    char time[48] = "render time unknown";

    if (cli_image_size(img->bytes, img->len, &width, &height))
        snprintf(size, sizeof(size), "%ldx%ld", width, height);
    if (img->render_ms >= 0)
        snprintf(time, sizeof(time), "render %.1f ms", img->render_ms);
    char irradiance[64] = "";

    /* Which irradiance the light-dependent terms used, when refractd says (issue 3). */
    if (img->irradiance[0] != '\0')
        snprintf(irradiance, sizeof(irradiance), ", irradiance %s", img->irradiance);
    fprintf(stderr, "wrote %s (%s, %s, %zu bytes, %s on %s%s)\n",
            strcmp(path, "-") == 0 ? "<stdout>" : path, size,
            format != NULL ? format : img->content_type, img->len, time,
            img->renderer[0] != '\0' ? img->renderer : "an unknown renderer", irradiance);
}

/* A note on stderr when the image lacks some light's current irradiance: the exit status
 * stays 0, because the image is what refractd could render now, and a script that wants
 * the final image waits with `refract light set` (which waits by default) first. */
static void note_irradiance(const char *scene, const struct refract_image *img)
{
    if (strcmp(img->irradiance, "stale") == 0)
        fprintf(stderr,
                "refract: note: a light's irradiance is being recomputed for its new pose; "
                "this image used the previous pose's volume (X-Refract-Irradiance: stale). "
                "'refract irradiance status %s' shows the progress\n",
                scene);
    else if (strcmp(img->irradiance, "missing") == 0)
        fprintf(stderr,
                "refract: note: a light has no irradiance volume yet, so this image was "
                "rendered without its light-dependent terms (X-Refract-Irradiance: missing). "
                "'refract irradiance status %s' shows the progress\n",
                scene);
}

static int run_render(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene ID"};
    struct cli_opt opts[OPT_COUNT] = {
        [OPT_OUTPUT] = {.name = "--output", .alias = "-o", .takes_value = true},
        [OPT_WIDTH] = {.name = "--width", .takes_value = true},
        [OPT_HEIGHT] = {.name = "--height", .takes_value = true},
        [OPT_FORMAT] = {.name = "--format", .takes_value = true},
        [OPT_EXPOSURE] = {.name = "--exposure", .takes_value = true},
        [OPT_STEPPER] = {.name = "--stepper",
                         .alias = "--integrator", /* renamed: the old flag keeps working */
                         .takes_value = true},
        [OPT_STEP] = {.name = "--step", .takes_value = true},
        [OPT_SAMPLES] = {.name = "--samples", .takes_value = true},
        [OPT_EYE] = {.name = "--eye", .takes_value = true},
        [OPT_LOOK_AT] = {.name = "--look-at", .takes_value = true},
        [OPT_UP] = {.name = "--up", .takes_value = true},
        [OPT_FOV] = {.name = "--fov", .takes_value = true},
        [OPT_REQUEST] = {.name = "--request", .takes_value = true},
    };
    struct refract_image img = {0};
    struct cli_parsed p;
    char *request = NULL;
    int code = cli_parse_command(&cli_cmd_render, argc, argv, opts, OPT_COUNT, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&cli_cmd_render, &p, 1, 1, names);
    if (code == REFRACT_E_OK && !opts[OPT_OUTPUT].given)
        code = cli_usage_error(&cli_cmd_render, "render: missing -o FILE (where to write the "
                                                "image; - for stdout)");
    if (code == REFRACT_E_OK && strcmp(opts[OPT_OUTPUT].value, "-") == 0 && isatty(1))
        code = cli_usage_error(&cli_cmd_render, "render: refusing to write an image to a "
                                                "terminal; give -o FILE or redirect stdout");
    if (code == REFRACT_E_OK)
        code = build_request(opts, &request);
    if (code == REFRACT_E_OK)
        code = cli_connect(cli);
    if (code == REFRACT_E_OK) {
        code = refract_render(cli->client, p.pos[0], request, &img);
        if (code != REFRACT_E_OK)
            code = cli_call_failed(cli, code);
    }
    if (code == REFRACT_E_OK)
        code = cli_write_file(opts[OPT_OUTPUT].value, img.bytes, img.len);
    if (code == REFRACT_E_OK) {
        report(opts[OPT_OUTPUT].value, &img);
        note_irradiance(p.pos[0], &img);
    }
    refract_image_free(&img);
    cJSON_free(request);
    return code;
}
