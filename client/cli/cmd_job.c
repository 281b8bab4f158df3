/*
 * cmd_job.c - `refract job submit|status|wait|get|cancel|list`: batch jobs
 * (docs/api.md "Batch jobs"). submit prints only the new job's id, so scripts can write
 * J=$(refract job submit turntable.json). wait polls the job's status and draws its
 * progress and ETA on stderr until it finishes; its exit status says how it ended.
 */
#include <cjson/cJSON.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "cli.h"
#include "cli_progress.h"

#define JOB_USAGE                                                                                  \
    "usage: refract job submit FILE|- [--scene-file SCENE.json]\n"                                 \
    "                                          submit a job (JSON; - = stdin); prints its id;\n"   \
    "                                          --scene-file sends SCENE.json as its inline\n"      \
    "                                          \"scene\" (no POST /v1/scenes needed)\n"            \
    "       refract job status ID              print the job's status as JSON\n"                   \
    "       refract job wait ID                wait until it ends, drawing progress and ETA\n"     \
    "       refract job get ID --out DIR       save its finished frames as DIR/frame_NNNNN.EXT\n"  \
    "       refract job cancel ID              cancel it (or delete it once it has ended)\n"       \
    "       refract job list [--state S] [--scene ID]   print jobs as JSON\n"                      \
    "\n"                                                                                           \
    "wait exits 0 when the job is done, 16 (internal) when it failed, 11 (conflict) when\n"        \
    "it was cancelled; --timeout bounds the wait (default: none).\n"                               \
    "\n"                                                                                           \
    "Example:\n"                                                                                   \
    "  echo '{\"scene\": \"glass\", \"width\": 320, \"height\": 240,\n"                            \
    "         \"turntable\": {\"frames\": 36}}' > turntable.json\n"                                \
    "  J=$(refract job submit turntable.json) && refract job wait \"$J\" &&\n"                     \
    "    refract job get \"$J\" --out frames/\n"                                                   \
    "  echo '{\"turntable\": {\"frames\": 36}}' |\n"                                               \
    "    refract job submit - --scene-file glass.json\n"

static int run_group(struct cli *cli, int argc, char **argv);

const struct cli_command cli_cmd_job = {
    .name = "job",
    .synopsis = "job submit|status|wait|get|cancel|list",
    .summary = "submit batch jobs (turntables, frame lists), follow them, collect frames",
    .usage = JOB_USAGE,
    .run = run_group,
};

static const struct cli_command job_cmd = {.name = "job", .usage = JOB_USAGE};

static int parse_sub(struct cli *cli, int argc, char **argv, size_t n_args,
                     const char *const names[], struct cli_opt *opts, size_t n_opts,
                     struct cli_parsed *p)
{
    int code = cli_parse_command(&job_cmd, argc, argv, opts, n_opts, p);

    if (code != REFRACT_E_OK || p->help)
        return code;
    code = cli_expect_args(&job_cmd, p, n_args, n_args, names);
    return code == REFRACT_E_OK ? cli_connect(cli) : code;
}

static const char *const id_name[] = {"the job ID"};

/* Parses the JSON text (len bytes) of file `path` (what = "job" or "scene"): a new tree, or
 * NULL after printing why. */
static cJSON *parse_json_file(const char *path, const char *what, const char *text, size_t len)
{
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, len, &end, false);
    if (root == NULL)
        cli_fail(REFRACT_E_INVALID_JSON,
                 "job submit: the %s file %s is not valid JSON (at byte %ld)", what, path,
                 (long)(end ? end - text : 0));
    else if (!cJSON_IsObject(root))
        cli_fail(REFRACT_E_INVALID_JSON, "job submit: the %s file %s is not a JSON object", what,
                 path);
    if (root != NULL && !cJSON_IsObject(root)) {
        cJSON_Delete(root);
        root = NULL;
    }
    return root;
}

/* Replaces the "scene" of the job spec *doc (*len bytes) by the document in scene_path:
 * *doc becomes a new string (the old one is freed). */
static int inline_scene(const char *spec_path, const char *scene_path, char **doc, size_t *len)
{
    char *scene_text = NULL;
    size_t scene_len = 0;
    int code = cli_read_file(scene_path, &scene_text, &scene_len);
    if (code != REFRACT_E_OK)
        return code;
    cJSON *spec = parse_json_file(spec_path, "job", *doc, *len);
    cJSON *scene = spec ? parse_json_file(scene_path, "scene", scene_text, scene_len) : NULL;
    free(scene_text);
    if (scene == NULL) {
        cJSON_Delete(spec);
        return REFRACT_E_INVALID_JSON;
    }
    cJSON_DeleteItemFromObjectCaseSensitive(spec, "scene");
    cJSON_AddItemToObject(spec, "scene", scene); /* spec owns it now */
    char *printed = cJSON_PrintUnformatted(spec);
    cJSON_Delete(spec);
    char *text = printed ? strdup(printed) : NULL; /* *doc is freed with free() */
    cJSON_free(printed);
    if (text == NULL)
        return cli_fail(REFRACT_E_OUT_OF_MEMORY, "job submit: out of memory");
    free(*doc);
    *doc = text;
    *len = strlen(text);
    return REFRACT_E_OK;
}

static int run_submit(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the job FILE (or - for stdin)"};
    struct cli_opt opts[] = {{.name = "--scene-file", .takes_value = true}};
    struct cli_parsed p;
    char *doc = NULL, *reply = NULL;
    size_t len = 0;
    int code = parse_sub(cli, argc, argv, 1, names, opts, 1, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_read_file(p.pos[0], &doc, &len);
    if (code != REFRACT_E_OK)
        return code;
    if (opts[0].given) {
        code = inline_scene(p.pos[0], opts[0].value, &doc, &len);
        if (code != REFRACT_E_OK) {
            free(doc);
            return code;
        }
    }
    code = refract_job_submit(cli->client, doc, len, &reply);
    free(doc);
    if (code != REFRACT_E_OK)
        return cli_call_failed(cli, code);
    cJSON *root = cJSON_Parse(reply);
    const cJSON *id = cJSON_GetObjectItemCaseSensitive(root, "id");
    code = cJSON_IsString(id) ? cli_print_json(id->valuestring)
                              : cli_fail(REFRACT_E_PROTOCOL, "job submit: no id in %s", reply);
    cJSON_Delete(root);
    refract_free(reply);
    return code;
}

static int run_status(struct cli *cli, int argc, char **argv)
{
    struct cli_parsed p;
    char *json = NULL;
    int code = parse_sub(cli, argc, argv, 1, id_name, NULL, 0, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = refract_job_get(cli->client, p.pos[0], &json);
    code = code == REFRACT_E_OK ? cli_print_json(json) : cli_call_failed(cli, code);
    refract_free(json);
    return code;
}

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec / 1e9;
}

/* One progress report on p (cli_progress.h): a redrawn bar on a terminal, a line
 * otherwise (the caller draws a line only when a frame was done). */
static void draw(struct cli_progress *p, const char *id, int done, int total, const cJSON *eta)
{
    char eta_text[32] = "ETA unknown";
    char text[200];

    if (cJSON_IsNumber(eta))
        snprintf(eta_text, sizeof(eta_text), "ETA %.0f s", eta->valuedouble);
    if (p->tty) {
        snprintf(text, sizeof(text), "job %s %d/%d frames, %s", id, done, total, eta_text);
        cli_progress_show(p, total > 0 ? (double)done / (double)total : 0.0, text);
    } else {
        snprintf(text, sizeof(text), "job %s: %d/%d frames, %s", id, done, total, eta_text);
        cli_progress_show(p, -1.0, text);
    }
}

static int run_wait(struct cli *cli, int argc, char **argv)
{
    struct cli_parsed p;
    int code = parse_sub(cli, argc, argv, 1, id_name, NULL, 0, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    bool tty = isatty(2);
    struct cli_progress bar;
    double start = now_s();
    cli_progress_init(&bar, stderr, tty, cli_terminal_columns(2));
    int last_done = -1;
    for (;;) {
        char *json = NULL;
        code = refract_job_get(cli->client, p.pos[0], &json);
        if (code != REFRACT_E_OK) {
            cli_progress_finish(&bar);
            return cli_call_failed(cli, code);
        }
        cJSON *root = cJSON_Parse(json);
        const cJSON *state = cJSON_GetObjectItemCaseSensitive(root, "state");
        const cJSON *done = cJSON_GetObjectItemCaseSensitive(root, "frames_done");
        const cJSON *total = cJSON_GetObjectItemCaseSensitive(root, "frames_total");
        const cJSON *msg = cJSON_GetObjectItemCaseSensitive(root, "message");
        const char *st = cJSON_IsString(state) ? state->valuestring : "";
        int d = cJSON_IsNumber(done) ? done->valueint : 0;
        int t = cJSON_IsNumber(total) ? total->valueint : 0;
        if (d != last_done || tty)
            draw(&bar, p.pos[0], d, t, cJSON_GetObjectItemCaseSensitive(root, "eta_s"));
        last_done = d;
        bool finished = !strcmp(st, "done") || !strcmp(st, "failed") || !strcmp(st, "cancelled");
        if (finished) {
            cli_progress_finish(&bar);
            code = !strcmp(st, "done")
                       ? REFRACT_E_OK
                       : cli_fail(!strcmp(st, "failed") ? REFRACT_E_INTERNAL : REFRACT_E_CONFLICT,
                                  "job %s %s%s%s", p.pos[0], st, cJSON_IsString(msg) ? ": " : "",
                                  cJSON_IsString(msg) ? msg->valuestring : "");
        }
        cJSON_Delete(root);
        refract_free(json);
        if (finished)
            return code;
        if (cli->timeout_ms > 0 && (now_s() - start) * 1000 > cli->timeout_ms) {
            cli_progress_finish(&bar);
            return cli_fail(REFRACT_E_TIMEOUT, "job %s: still %s after --timeout; it goes on",
                            p.pos[0], st);
        }
        struct timespec ts = {0, 250000000L};
        nanosleep(&ts, NULL);
    }
}

static const char *extension(const char *content_type)
{
    if (strcmp(content_type, "image/jpeg") == 0)
        return "jpg";
    if (strcmp(content_type, "image/x-exr") == 0)
        return "exr";
    return "png";
}

static int run_get(struct cli *cli, int argc, char **argv)
{
    struct cli_opt opts[] = {{.name = "--out", .alias = "-o", .takes_value = true}};
    struct cli_parsed p;
    char *json = NULL;
    int code = parse_sub(cli, argc, argv, 1, id_name, opts, 1, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    if (!opts[0].given)
        return cli_usage_error(&job_cmd, "job get: --out DIR is required");
    const char *dir = opts[0].value;
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return cli_fail(REFRACT_E_IO, "job get: cannot create %s: %s", dir, strerror(errno));
    code = refract_job_get(cli->client, p.pos[0], &json);
    if (code != REFRACT_E_OK)
        return cli_call_failed(cli, code);
    cJSON *root = cJSON_Parse(json);
    const cJSON *done = cJSON_GetObjectItemCaseSensitive(root, "frames_done");
    int n_done = cJSON_IsNumber(done) ? done->valueint : 0;
    cJSON_Delete(root);
    refract_free(json);
    for (int n = 0; n < n_done && code == REFRACT_E_OK; n++) {
        struct refract_image img;
        code = refract_job_frame(cli->client, p.pos[0], n, &img);
        if (code != REFRACT_E_OK)
            return cli_call_failed(cli, code);
        char path[4096];
        snprintf(path, sizeof(path), "%s/frame_%05d.%s", dir, n, extension(img.content_type));
        code = cli_write_file(path, img.bytes, img.len);
        refract_image_free(&img);
    }
    if (code == REFRACT_E_OK)
        fprintf(stderr, "saved %d frames of job %s in %s\n", n_done, p.pos[0], dir);
    return code;
}

static int run_cancel(struct cli *cli, int argc, char **argv)
{
    struct cli_parsed p;
    char *json = NULL;
    int code = parse_sub(cli, argc, argv, 1, id_name, NULL, 0, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = refract_job_cancel(cli->client, p.pos[0], &json);
    if (code != REFRACT_E_OK)
        return cli_call_failed(cli, code);
    if (json)
        code = cli_print_json(json);
    else
        fprintf(stderr, "deleted job %s\n", p.pos[0]);
    refract_free(json);
    return code;
}

static int run_list(struct cli *cli, int argc, char **argv)
{
    struct cli_opt opts[] = {{.name = "--state", .takes_value = true},
                             {.name = "--scene", .takes_value = true}};
    struct cli_parsed p;
    char *json = NULL;
    int code = parse_sub(cli, argc, argv, 0, NULL, opts, 2, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = refract_job_list(cli->client, opts[0].value, opts[1].value, &json);
    code = code == REFRACT_E_OK ? cli_print_json(json) : cli_call_failed(cli, code);
    refract_free(json);
    return code;
}

static int run_group(struct cli *cli, int argc, char **argv)
{
    static const struct {
        const char *name;
        int (*run)(struct cli *cli, int argc, char **argv);
    } subs[] = {{"submit", run_submit}, {"status", run_status}, {"wait", run_wait},
                {"get", run_get},       {"cancel", run_cancel}, {"list", run_list}};

    if (argc == 0)
        return cli_usage_error(&cli_cmd_job, "job: missing the command (submit, status, wait, "
                                             "get, cancel or list)");
    if (strcmp(argv[0], "-h") == 0 || strcmp(argv[0], "--help") == 0) {
        fputs(cli_cmd_job.usage, stdout);
        return REFRACT_E_OK;
    }
    for (size_t i = 0; i < sizeof(subs) / sizeof(subs[0]); i++) {
        if (strcmp(argv[0], subs[i].name) == 0)
            return subs[i].run(cli, argc - 1, argv + 1);
    }
    return cli_usage_error(&cli_cmd_job, "unknown job command '%s'", argv[0]);
}
