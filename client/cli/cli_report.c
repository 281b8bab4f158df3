/*
 * cli_report.c - how the refract CLI reports: "refract: <message>" on stderr, the exit
 * code from proto/refract_errors.h, JSON replies on stdout, and the one librefract
 * client of a run.
 *
 * Every message the CLI prints on failure goes through this file, so its form is the
 * same everywhere and is written once.
 */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "../refract_url.h"
#include "cli.h"

int cli_fail(int code, const char *fmt, ...)
{
    va_list ap;

    fputs("refract: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    return code;
}

int cli_usage_error(const struct cli_command *cmd, const char *fmt, ...)
{
    const char *end = strstr(cmd->usage, "\n\n");
    int synopsis_len = end != NULL ? (int)(end - cmd->usage) : (int)strlen(cmd->usage);
    int group_len = (int)strcspn(cmd->name, " ");
    va_list ap;

    fputs("refract: ", stderr);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    /* The synopsis only: the whole help would bury the one line that says what is wrong. */
    fprintf(stderr, "\n%.*s\nRun 'refract help %.*s' for the details.\n", synopsis_len, cmd->usage,
            group_len, cmd->name);
    return REFRACT_E_USAGE;
}

int cli_parse_command(const struct cli_command *cmd, int argc, char **argv, struct cli_opt *opts,
                      size_t n_opts, struct cli_parsed *p)
{
    char why[256];

    if (cli_parse_args(argc, argv, opts, n_opts, p, why, sizeof(why)) != REFRACT_E_OK)
        return cli_usage_error(cmd, "%s: %s", cmd->name, why);
    if (p->help)
        fputs(cmd->usage, stdout);
    return REFRACT_E_OK;
}

int cli_expect_args(const struct cli_command *cmd, const struct cli_parsed *p, size_t min,
                    size_t max, const char *const names[])
{
    if (p->n_pos < min)
        return cli_usage_error(cmd, "%s: missing %s", cmd->name, names[p->n_pos]);
    if (p->n_pos > max)
        return cli_usage_error(cmd, "%s: unexpected argument '%s'", cmd->name, p->pos[max]);
    return REFRACT_E_OK;
}

int cli_call_failed(struct cli *cli, int code)
{
    const char *msg = refract_errmsg(cli->client);

    return cli_fail(code, "%s", msg[0] != '\0' ? msg : refract_strerror(code));
}

int cli_connect(struct cli *cli)
{
    if (cli->client != NULL)
        return REFRACT_E_OK;
    if (!refract_url_is_http(cli->url))
        return cli_fail(REFRACT_E_USAGE, "%s: expected an address such as %s, got '%s'",
                        cli->url_source, REFRACT_DEFAULT_URL, cli->url);
    cli->client = refract_client_create(cli->url);
    if (cli->client == NULL)
        return cli_fail(REFRACT_E_OUT_OF_MEMORY,
                        "cannot create a client for %s: out of "
                        "memory, or libcurl failed to initialise",
                        cli->url);
    if (cli->timeout_ms >= 0)
        refract_set_timeout_ms(cli->client, cli->timeout_ms);
    if (cli->token_file != NULL && refract_set_token_file(cli->client, cli->token_file) != 0)
        return cli_fail(REFRACT_E_USAGE, "--token-file: %s", refract_errmsg(cli->client));
    if (cli->cacert != NULL && refract_set_cacert(cli->client, cli->cacert) != 0)
        return cli_fail(REFRACT_E_USAGE, "--cacert: %s", refract_errmsg(cli->client));
    return REFRACT_E_OK;
}

int cli_print_json(const char *json)
{
    size_t len = strlen(json);

    fputs(json, stdout);
    if (len == 0 || json[len - 1] != '\n')
        fputc('\n', stdout);
    if (fflush(stdout) != 0 || ferror(stdout))
        return cli_fail(REFRACT_E_IO, "cannot write to stdout");
    return REFRACT_E_OK;
}
