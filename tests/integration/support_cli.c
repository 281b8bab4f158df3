/*
 * support_cli.c - running the refract CLI for integration tests; see support_cli.h.
 */
#include "support_cli.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

char *cli_slurp(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return strdup("");
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    size_t got = fread(buf, 1, (size_t)n, f);
    buf[got] = '\0';
    fclose(f);
    return buf;
}

struct cli_run cli_run(const struct test_daemon *d, const char *url, const char *stdin_path,
                       const char *const *args)
{
    struct cli_run r = {-1, NULL, NULL};
    char out_path[400], err_path[400];
    snprintf(out_path, sizeof out_path, "%s/cli.out", d->dir);
    snprintf(err_path, sizeof err_path, "%s/cli.err", d->dir);
    const char *cli = getenv("REFRACT_CLI");
    const char *argv[32];
    int n = 0;
    argv[n++] = cli;
    argv[n++] = "--url";
    argv[n++] = url ? url : d->url;
    for (int i = 0; args[i] && n < 31; i++)
        argv[n++] = args[i];
    argv[n] = NULL;
    pid_t pid = fork();
    if (pid == 0) {
        int in = open(stdin_path ? stdin_path : "/dev/null", O_RDONLY);
        int out = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
        int er = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0600);
        if (in < 0 || out < 0 || er < 0)
            _exit(127);
        dup2(in, 0);
        dup2(out, 1);
        dup2(er, 2);
        execv(cli, (char *const *)argv);
        _exit(127);
    }
    int st = 0;
    if (pid > 0 && waitpid(pid, &st, 0) == pid && WIFEXITED(st))
        r.status = WEXITSTATUS(st);
    r.out = cli_slurp(out_path);
    r.err = cli_slurp(err_path);
    return r;
}

void cli_run_free(struct cli_run *r)
{
    free(r->out);
    free(r->err);
}
