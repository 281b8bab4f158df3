/*
 * main.c - the refract command-line tool: global options, then dispatch to a command.
 *
 *   refract [--url URL] [--timeout SECONDS] [--token-file FILE] [--cacert FILE] COMMAND ...
 *
 * The global options may also follow the command (until a "--"), so they can be added
 * to the end of any command line. -h/--help before the command is the program's help;
 * after it, the command's. The exit status is a code number of proto/refract_errors.h.
 * This file knows no command's arguments; the cmd_*.c files do.
 */
#include <curl/curl.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "cli_args.h"

#ifndef REFRACT_VERSION
#define REFRACT_VERSION "0"
#endif

/* The global options, wherever they appear; what is left goes to the command. */
struct globals {
    const char *url;
    const char *timeout;
    const char *token_file;
    const char *cacert;
    bool help;
    bool version;
    const char *command; /* NULL when none was given */
    int argc;            /* the command's arguments */
    char **argv;         /* owned array of borrowed strings */
};

/* If argv[*i] is a global option with a value (either "--x V" or "--x=V"), stores its
 * value, steps past it and returns 1; returns 0 when it is not one; -1 when its value is
 * missing. */
static int take_global(int argc, char **argv, int *i, struct globals *g)
{
    static const char *const names[4] = {"--url", "--timeout", "--token-file", "--cacert"};
    const char **slots[4] = {&g->url, &g->timeout, &g->token_file, &g->cacert};

    for (int k = 0; k < 4; k++) {
        size_t len = strlen(names[k]);

        if (strncmp(argv[*i], names[k], len) != 0)
            continue;
        if (argv[*i][len] == '=') {
            *slots[k] = argv[*i] + len + 1;
            return 1;
        }
        if (argv[*i][len] != '\0')
            continue;
        if (*i + 1 >= argc) {
            cli_fail(REFRACT_E_USAGE, "%s needs a value; see 'refract --help'", names[k]);
            return -1;
        }
        *slots[k] = argv[++*i];
        return 1;
    }
    return 0;
}

static int scan_globals(int argc, char **argv, struct globals *g)
{
    bool options_done = false;

    g->argv = calloc((size_t)argc + 1, sizeof(*g->argv));
    if (g->argv == NULL)
        return cli_fail(REFRACT_E_OUT_OF_MEMORY, "out of memory reading the command line");
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        int taken = options_done ? 0 : take_global(argc, argv, &i, g);

        if (taken < 0)
            return REFRACT_E_USAGE;
        if (taken > 0)
            continue;
        if (g->command == NULL && (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0)) {
            g->help = true;
        } else if (g->command == NULL && strcmp(arg, "--version") == 0) {
            g->version = true;
        } else if (g->command == NULL && arg[0] == '-') {
            return cli_fail(REFRACT_E_USAGE, "unknown option '%s'; see 'refract --help'", arg);
        } else if (g->command == NULL) {
            g->command = arg;
        } else {
            if (strcmp(arg, "--") == 0)
                options_done = true; /* kept: the command's parser stops there too */
            g->argv[g->argc++] = argv[i];
        }
    }
    return REFRACT_E_OK;
}

/* Fills cli->url, cli->timeout_ms, token file and CA file from the options and REFRACT_URL
 * (REFRACT_TOKEN is librefract's own). The URL is
 * checked when a command first needs it (cli_connect), so help works with any. */
static int resolve_connection(const struct globals *g, struct cli *cli)
{
    const char *env = getenv("REFRACT_URL");
    char why[256];

    cli->url = g->url;
    cli->url_source = "--url";
    if (cli->url == NULL && env != NULL && env[0] != '\0') {
        cli->url = env;
        cli->url_source = "REFRACT_URL";
    }
    if (cli->url == NULL) {
        cli->url = REFRACT_DEFAULT_URL;
        cli->url_source = "the default address";
    }
    cli->token_file = g->token_file;
    cli->cacert = g->cacert;
    cli->timeout_ms = -1;
    if (g->timeout != NULL && !cli_parse_timeout(g->timeout, &cli->timeout_ms, why, sizeof(why)))
        return cli_fail(REFRACT_E_USAGE, "--timeout: %s", why);
    return REFRACT_E_OK;
}

static int dispatch(struct cli *cli, const struct globals *g)
{
    const struct cli_command *cmd;

    if (strcmp(g->command, "help") == 0)
        return cli_help_command(g->argc, g->argv);
    cmd = cli_find_command(g->command);
    if (cmd == NULL) {
        cli_fail(REFRACT_E_USAGE, "unknown command '%s'\n", g->command);
        cli_print_help(stderr);
        return REFRACT_E_USAGE;
    }
    return cmd->run(cli, g->argc, g->argv);
}

int main(int argc, char **argv)
{
    struct globals g = {0};
    struct cli cli = {.timeout_ms = -1};
    int code = scan_globals(argc, argv, &g);

    if (code == REFRACT_E_OK && g.version) {
        printf("refract %s (librefract %s, libcurl %s)\n", REFRACT_VERSION, REFRACT_VERSION,
               curl_version_info(CURLVERSION_NOW)->version);
    } else if (code == REFRACT_E_OK && g.help) {
        cli_print_help(stdout);
    } else if (code == REFRACT_E_OK && g.command == NULL) {
        cli_fail(REFRACT_E_USAGE, "no command given\n");
        cli_print_help(stderr);
        code = REFRACT_E_USAGE;
    } else if (code == REFRACT_E_OK) {
        code = resolve_connection(&g, &cli);
        if (code == REFRACT_E_OK)
            code = dispatch(&cli, &g);
    }
    refract_client_destroy(cli.client);
    free(g.argv);
    return code;
}
