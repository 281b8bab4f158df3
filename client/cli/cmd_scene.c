/*
 * cmd_scene.c - `refract scene create|list|show|delete`: the scene resources.
 *
 * create reads a scene JSON document from a file or stdin and prints only the new id
 * on stdout, so scripts can write ID=$(refract scene create glass.json). The document
 * is not validated here: refractd validates it completely and names the JSON path of
 * anything wrong, and one validator is better than two that disagree.
 */
#include <stdlib.h>
#include <string.h>

#include "cli.h"

#define SCENE_USAGE                                                                                \
    "usage: refract scene create FILE|-   create a scene from a JSON file (- = stdin);\n"          \
    "                                     prints the new scene's id\n"                             \
    "       refract scene list            print all scenes as JSON\n"                              \
    "       refract scene show ID         print one scene as JSON\n"                               \
    "       refract scene delete ID       delete a scene and everything uploaded into it\n"        \
    "\n"                                                                                           \
    "Examples:\n"                                                                                  \
    "  ID=$(refract scene create scene.json)\n"                                                    \
    "  refract scene list\n"                                                                       \
    "  refract scene show \"$ID\"\n"                                                               \
    "  refract scene delete \"$ID\"\n"

static int run_group(struct cli *cli, int argc, char **argv);

const struct cli_command cli_cmd_scene = {
    .name = "scene",
    .synopsis = "scene create|list|show|delete",
    .summary = "create, list, show or delete scenes",
    .usage = SCENE_USAGE,
    .run = run_group,
};

/* The subcommands share the group's usage; their names make messages precise. */
static const struct cli_command scene_create_cmd = {.name = "scene create", .usage = SCENE_USAGE};
static const struct cli_command scene_list_cmd = {.name = "scene list", .usage = SCENE_USAGE};
static const struct cli_command scene_show_cmd = {.name = "scene show", .usage = SCENE_USAGE};
static const struct cli_command scene_delete_cmd = {.name = "scene delete", .usage = SCENE_USAGE};

/* Parses a subcommand that takes exactly n_args positionals named by names. */
static int parse_sub(struct cli *cli, const struct cli_command *cmd, int argc, char **argv,
                     size_t n_args, const char *const names[], struct cli_parsed *p)
{
    int code = cli_parse_command(cmd, argc, argv, NULL, 0, p);

    if (code != REFRACT_E_OK || p->help)
        return code;
    code = cli_expect_args(cmd, p, n_args, n_args, names);
    return code == REFRACT_E_OK ? cli_connect(cli) : code;
}

static int run_create(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene FILE (or - for stdin)"};
    char id[REFRACT_ID_SIZE];
    struct cli_parsed p;
    char *doc = NULL;
    size_t len = 0;
    int code = parse_sub(cli, &scene_create_cmd, argc, argv, 1, names, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_read_file(p.pos[0], &doc, &len);
    if (code != REFRACT_E_OK)
        return code;
    code = refract_scene_create(cli->client, doc, len, id, sizeof(id));
    free(doc);
    if (code != REFRACT_E_OK)
        return cli_call_failed(cli, code);
    return cli_print_json(id); /* an id is a bare word; printed the same way, one line */
}

static int run_list(struct cli *cli, int argc, char **argv)
{
    struct cli_parsed p;
    char *json = NULL;
    int code = parse_sub(cli, &scene_list_cmd, argc, argv, 0, NULL, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = refract_scene_list(cli->client, &json);
    code = code == REFRACT_E_OK ? cli_print_json(json) : cli_call_failed(cli, code);
    refract_free(json);
    return code;
}

static int run_show(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene ID"};
    struct cli_parsed p;
    char *json = NULL;
    int code = parse_sub(cli, &scene_show_cmd, argc, argv, 1, names, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = refract_scene_get(cli->client, p.pos[0], &json);
    code = code == REFRACT_E_OK ? cli_print_json(json) : cli_call_failed(cli, code);
    refract_free(json);
    return code;
}

static int run_delete(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the scene ID"};
    struct cli_parsed p;
    int code = parse_sub(cli, &scene_delete_cmd, argc, argv, 1, names, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = refract_scene_delete(cli->client, p.pos[0]);
    if (code != REFRACT_E_OK)
        return cli_call_failed(cli, code);
    fprintf(stderr, "deleted scene %s\n", p.pos[0]);
    return REFRACT_E_OK;
}

static int run_group(struct cli *cli, int argc, char **argv)
{
    static const struct {
        const char *name;
        int (*run)(struct cli *cli, int argc, char **argv);
    } subs[] = {
        {"create", run_create}, {"list", run_list}, {"show", run_show}, {"delete", run_delete}};

    if (argc == 0)
        return cli_usage_error(&cli_cmd_scene, "scene: missing the command (create, list, "
                                               "show or delete)");
    if (strcmp(argv[0], "-h") == 0 || strcmp(argv[0], "--help") == 0) {
        fputs(cli_cmd_scene.usage, stdout);
        return REFRACT_E_OK;
    }
    for (size_t i = 0; i < sizeof(subs) / sizeof(subs[0]); i++) {
        if (strcmp(argv[0], subs[i].name) == 0)
            return subs[i].run(cli, argc - 1, argv + 1);
    }
    return cli_usage_error(&cli_cmd_scene, "unknown scene command '%s'", argv[0]);
}
