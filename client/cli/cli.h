/*
 * cli.h - what the refract CLI's files share: the run context, the command table entry,
 * and the helpers every command uses to report an outcome.
 *
 * The CLI is a separate program on top of librefract (as curl's tool is on libcurl).
 * main.c reads the global options and dispatches; each cmd_*.c file is one command or
 * command group; cli_args.c parses values; cli_io.c reads and writes local files;
 * cli_report.c prints "refract: <message>" and turns outcomes into exit codes, which
 * are the numbers of proto/refract_errors.h.
 */
#ifndef CLI_H
#define CLI_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "cli_args.h"
#include "refract.h"

/* One run of the program. */
struct cli {
    const char *url;        /* borrowed from argv or the environment */
    const char *url_source; /* where url came from, for messages: "--url", "REFRACT_URL" */
    long timeout_ms;        /* -1 = librefract's default */
    const char *token_file; /* --token-file (borrowed; NULL: REFRACT_TOKEN, if set) */
    const char *cacert;     /* --cacert (borrowed; NULL: the system's CA store) */
    refract_client *client; /* owned; made by cli_client() on first use */
};

/* A command or command group. */
struct cli_command {
    const char *name;     /* "scene" */
    const char *synopsis; /* its forms, for `refract --help`: "scene create|list|..." */
    const char *summary;  /* one line for `refract --help` */
    const char *usage;    /* full help, printed by `refract help NAME` and on usage errors */
    /* Runs the command; argv[0] is the first argument after the command's name.
     * Returns the exit code. */
    int (*run)(struct cli *cli, int argc, char **argv);
};

extern const struct cli_command cli_cmd_health;
extern const struct cli_command cli_cmd_scene;
extern const struct cli_command cli_cmd_upload;
extern const struct cli_command cli_cmd_volume;
extern const struct cli_command cli_cmd_env;
extern const struct cli_command cli_cmd_render;
extern const struct cli_command cli_cmd_trace;
extern const struct cli_command cli_cmd_light;
extern const struct cli_command cli_cmd_irradiance;
extern const struct cli_command cli_cmd_view;
extern const struct cli_command cli_cmd_events;
extern const struct cli_command cli_cmd_job;

/* cli_help.c */

/* Every command, in the order `refract --help` lists them; NULL-terminated. */
extern const struct cli_command *const cli_commands[];
/* The command called name, or NULL. */
const struct cli_command *cli_find_command(const char *name);
/* Prints the program's help (usage, commands, options, exit codes) to f. */
void cli_print_help(FILE *f);
/* `refract help [COMMAND]`: prints that help to stdout; returns the exit code. */
int cli_help_command(int argc, char **argv);

/* cli_report.c */

/* Prints "refract: <message>" to stderr and returns code. */
int cli_fail(int code, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Prints "refract: <message>", the synopsis of cmd's usage (up to its first blank line)
 * and where to read more, to stderr; returns REFRACT_E_USAGE. */
int cli_usage_error(const struct cli_command *cmd, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* Parses a command's arguments (cli_parse_args) and handles the outcomes every command
 * shares: a usage error is printed with cmd's usage and returns REFRACT_E_USAGE; -h or
 * --help prints the usage on stdout, sets p->help and returns REFRACT_E_OK. So a command
 * goes on only when the result is REFRACT_E_OK and p->help is false. */
int cli_parse_command(const struct cli_command *cmd, int argc, char **argv, struct cli_opt *opts,
                      size_t n_opts, struct cli_parsed *p);
/* Checks that p holds between min and max positionals; names[i] names the i-th ("the
 * scene ID") in the message for a missing one. Prints a usage error and returns
 * REFRACT_E_USAGE otherwise. */
int cli_expect_args(const struct cli_command *cmd, const struct cli_parsed *p, size_t min,
                    size_t max, const char *const names[]);
/* Prints "refract: <librefract's message>" for a failed call; returns code. */
int cli_call_failed(struct cli *cli, int code);
/* Makes cli->client on first use from --url and --timeout. Returns REFRACT_E_OK, or
 * prints why and returns REFRACT_E_USAGE (a URL that is not http:// or https://) or
 * REFRACT_E_OUT_OF_MEMORY. main() destroys the client. */
int cli_connect(struct cli *cli);
/* Prints a JSON reply on stdout, ending with a newline; returns REFRACT_E_OK, or
 * REFRACT_E_IO when stdout cannot be written. */
int cli_print_json(const char *json);

/* cli_io.c */

/* Reads all of path ("-" = stdin) into a new buffer with a NUL after its last byte.
 * On success *data owns the buffer (free() it) and *len is its length without the NUL.
 * On failure prints why and returns REFRACT_E_IO (or REFRACT_E_OUT_OF_MEMORY). */
int cli_read_file(const char *path, char **data, size_t *len);
/* Writes len bytes to path ("-" = stdout), replacing the file. A failed write removes
 * the partial file. Prints why and returns REFRACT_E_IO on failure. Borrows data. */
int cli_write_file(const char *path, const void *data, size_t len);

/* cli_wait.c */

/* Waits until every light of the scene's irradiance status is ready, failed or
 * not_needed (unless *status is settled already), drawing progress on stderr: a bar on
 * a terminal, a line per change otherwise. The wait is bounded by --timeout (default
 * 120 s; 0 = no bound). On success *status is replaced by the final status (the HTTP
 * status of the original is kept); on failure it is left alone and the librefract code
 * is returned (refract_errmsg says why). */
int cli_wait_irradiance(struct cli *cli, const char *scene, struct refract_irradiance *status);

#endif
