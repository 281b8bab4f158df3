/*
 * support_cli.h - running the refract CLI ($REFRACT_CLI, the real binary) against a test
 * daemon and capturing what it printed, for the CLI's integration tests:
 *
 *     struct cli_run r = cli_run(&d, NULL, NULL, (const char *[]){"health", NULL});
 *     CHECK_INT(r.status, 0);
 *     cli_run_free(&r);
 */
#ifndef REFRACT_TEST_SUPPORT_CLI_H
#define REFRACT_TEST_SUPPORT_CLI_H

#include "daemon.h"

struct cli_run {
    int status; /* exit status, or -1 when it did not exit normally */
    char *out;  /* stdout, NUL-terminated */
    char *err;  /* stderr */
};

/* The whole file at `path`, NUL-terminated (malloc'd; "" when it cannot be opened). */
char *cli_slurp(const char *path);

/* Runs $REFRACT_CLI --url <url, or the daemon's when NULL> ARGS... (NULL-terminated) with
 * stdin from `stdin_path` (or /dev/null) and stdout and stderr in files under the daemon's
 * directory (so stderr is not a terminal: progress comes as lines). */
struct cli_run cli_run(const struct test_daemon *d, const char *url, const char *stdin_path,
                       const char *const *args);

void cli_run_free(struct cli_run *r);

#endif
