/*
 * cli_help.c - the refract CLI's command table and its help: `refract --help`,
 * `refract help [COMMAND]`, and the exit code list generated from the shared error
 * table, so the help cannot disagree with what the program returns.
 *
 * Each command's own usage text lives beside its code in cmd_*.c.
 */
#include <stdio.h>
#include <string.h>

#include "cli.h"

const struct cli_command *const cli_commands[] = {
    &cli_cmd_health,
    &cli_cmd_scene,
    &cli_cmd_upload,
    &cli_cmd_volume,
    &cli_cmd_env,
    &cli_cmd_render,
    &cli_cmd_trace,
    &cli_cmd_light,
    &cli_cmd_irradiance,
    &cli_cmd_view,
    &cli_cmd_events,
    &cli_cmd_job,
    NULL,
};

const struct cli_command *cli_find_command(const char *name)
{
    for (size_t i = 0; cli_commands[i] != NULL; i++) {
        if (strcmp(cli_commands[i]->name, name) == 0)
            return cli_commands[i];
    }
    return NULL;
}

static void print_exit_codes(FILE *f)
{
    fputs("Exit status: 0 on success; otherwise the number of the error code (the same\n"
          "table as refractd's \"error.code\", proto/refract_errors.h):\n",
          f);
#define CLI_X_EXIT(name, num, http, json, text)                                                    \
    if ((num) != 0)                                                                                \
        fprintf(f, "  %2d  %-24s %s\n", (num), (json), (text));
    REFRACT_ERROR_TABLE(CLI_X_EXIT)
#undef CLI_X_EXIT
}

void cli_print_help(FILE *f)
{
    fputs("usage: refract [--url URL] [--timeout SECONDS] [--token-file FILE] [--cacert FILE]\n"
          "               COMMAND [ARGS...]\n"
          "\n"
          "refract talks to refractd, the Refract render daemon, through its HTTP API.\n"
          "\n"
          "Commands:\n",
          f);
    for (size_t i = 0; cli_commands[i] != NULL; i++)
        fprintf(f, "  %-30s %s\n", cli_commands[i]->synopsis, cli_commands[i]->summary);
    fprintf(f, "  %-30s %s\n", "help [COMMAND]", "show the help of a command");
    fputs("\n"
          "Global options (before or after the command):\n"
          "  --url URL          refractd's address (default: $REFRACT_URL, else\n"
          "                     " REFRACT_DEFAULT_URL ")\n"
          "  --timeout SECONDS  give up on a request, or on light set's wait for an\n"
          "                     irradiance volume, after this long (default 120;\n"
          "                     0 = never)\n"
          "  --token-file FILE  the bearer token of a refractd started with\n"
          "                     --token-file (default: $REFRACT_TOKEN)\n"
          "  --cacert FILE      PEM CA certificates that verify an https URL's\n"
          "                     certificate (default: the system's)\n"
          "  -h, --help         show this help; after a command, that command's help\n"
          "  --version          show the versions of refract and libcurl\n"
          "\n",
          f);
    print_exit_codes(f);
}

int cli_help_command(int argc, char **argv)
{
    const struct cli_command *cmd;

    if (argc == 0) {
        cli_print_help(stdout);
        return REFRACT_E_OK;
    }
    cmd = cli_find_command(argv[0]);
    if (cmd == NULL) {
        cli_fail(REFRACT_E_USAGE, "no help for '%s': there is no such command\n", argv[0]);
        cli_print_help(stderr);
        return REFRACT_E_USAGE;
    }
    fputs(cmd->usage, stdout);
    return REFRACT_E_OK;
}
