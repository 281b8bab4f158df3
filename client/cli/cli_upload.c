/*
 * cli_upload.c - sending one file (cli_upload.h): the local checks, the progress
 * display, and the call to librefract, which streams the file (refract_upload.c).
 *
 * The local checks exist because a wrong --dims or a detached NRRD header is found in
 * microseconds here and only after the whole file crossed the network there. They use
 * the error codes refractd gives for the same mistakes, so a script sees one code for
 * one mistake wherever it was caught.
 */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "cli_progress.h"
#include "cli.h"
#include "cli_upload.h"

/* Redraws of the bar at most this often (a fast upload reports thousands of times). */
#define REDRAW_MS 100.0
/* A line per this many bytes when the total is unknown and stderr is not a terminal. */
#define UNKNOWN_STEP_BYTES (16LL << 20)

/* The progress display of one upload. */
struct view {
    struct cli_progress p;
    double start_ms;
    double last_draw_ms;
    long long last_step; /* the last 10 % step printed as a line (not a terminal) */
    long long sent;      /* the last count reported */
    long long total;
};

static double now_ms(void)
{
    struct timespec ts;

    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1000.0 + (double)ts.tv_nsec / 1e6;
}

static void on_progress(long long sent, long long total, void *user)
{
    struct view *v = user;
    double now = now_ms();
    double elapsed_s = (now - v->start_ms) / 1000.0;
    bool done = total >= 0 && sent >= total;
    char text[256];
    char line[300];

    v->sent = sent;
    v->total = total;
    if (v->p.tty) {
        if (!done && sent > 0 && now - v->last_draw_ms < REDRAW_MS)
            return;
        v->last_draw_ms = now;
        cli_transfer_text(text, sizeof(text), sent, total, elapsed_s, false);
        cli_progress_show(&v->p, total > 0 ? (double)sent / (double)total : (done ? 1.0 : -1.0),
                          text);
        return;
    }
    long long step = total > 0 ? sent * 10 / total : (total == 0 ? 10 : sent / UNKNOWN_STEP_BYTES);
    if (step <= v->last_step)
        return;
    v->last_step = step;
    cli_transfer_text(text, sizeof(text), sent, total, elapsed_s, true);
    snprintf(line, sizeof(line), "upload: %s", text);
    cli_progress_show(&v->p, -1.0, line);
}

/* A stream of unknown size has no 100 %: its last line says how much went. */
static void show_end(struct view *v)
{
    char text[256];
    char line[300];

    if (v->total >= 0)
        return;
    cli_transfer_text(text, sizeof(text), v->sent, -1, (now_ms() - v->start_ms) / 1000.0, false);
    snprintf(line, sizeof(line), "upload: %s, done", text);
    cli_progress_show(&v->p, -1.0, line);
}

/* The size of the file (or of stdin when it is a regular file); -1 when unknown. */
static int file_size(const struct cli_upload *up, long long *size)
{
    struct stat st;
    bool is_stdin = strcmp(up->file, "-") == 0;
    int rc = is_stdin ? fstat(0, &st) : stat(up->file, &st);

    *size = -1;
    if (rc != 0)
        return cli_fail(REFRACT_E_IO, "%s: cannot open '%s': %s", up->cmd->name,
                        is_stdin ? "<stdin>" : up->file, strerror(errno));
    if (S_ISDIR(st.st_mode))
        return cli_fail(REFRACT_E_IO, "%s: '%s' is a directory, not a file to upload",
                        up->cmd->name, up->file);
    if (!is_stdin && access(up->file, R_OK) != 0)
        return cli_fail(REFRACT_E_IO, "%s: cannot open '%s': %s", up->cmd->name, up->file,
                        strerror(errno));
    if (S_ISREG(st.st_mode))
        *size = (long long)st.st_size;
    return REFRACT_E_OK;
}

/* A raw volume: --dims is required and the size must be X*Y*Z*C*sample bytes. */
static int check_raw(const struct cli_upload *up, long long size)
{
    const struct refract_upload_desc *d = &up->desc;
    const char *type = d->type != NULL ? d->type : "float32";
    int sample = cli_upload_sample_bytes(type);
    int comps = d->components > 0 ? d->components : 1;
    uint64_t want = 0;

    if (d->dims[0] == 0)
        return cli_usage_error(up->cmd,
                               "%s: a raw volume needs --dims X,Y,Z (its file has no header "
                               "that says them)",
                               up->cmd->name);
    if (sample == 0)
        return cli_usage_error(up->cmd,
                               "%s: --type: expected float32, float16, uint8 or uint16, got '%s'",
                               up->cmd->name, type);
    if (!cli_raw_volume_bytes(d->dims, comps, sample, &want))
        return cli_usage_error(up->cmd, "%s: --dims %d,%d,%d with %d components is too large",
                               up->cmd->name, d->dims[0], d->dims[1], d->dims[2], comps);
    if (size < 0 || (uint64_t)size == want)
        return REFRACT_E_OK; /* a pipe's size is refractd's to check */
    return cli_fail(REFRACT_E_INVALID_VOLUME,
                    "%s: '%s' has %lld bytes, but --dims %d,%d,%d --components %d needs "
                    "%d*%d*%d*%d*%d = %llu bytes of %s; check --dims, --components and --type "
                    "(nothing was sent)",
                    up->cmd->name, up->file, size, d->dims[0], d->dims[1], d->dims[2], comps,
                    d->dims[0], d->dims[1], d->dims[2], comps, sample, (unsigned long long)want,
                    type);
}

/* An NRRD file must carry its data (refractd reads no second file). */
static int check_nrrd(const struct cli_upload *up)
{
    char head[65536];
    FILE *f = strcmp(up->file, "-") == 0 ? NULL : fopen(up->file, "rb");
    size_t n;

    if (f == NULL)
        return REFRACT_E_OK; /* stdin cannot be peeked at; refractd checks */
    n = fread(head, 1, sizeof(head), f);
    fclose(f);
    if (!cli_upload_nrrd_detached(head, n))
        return REFRACT_E_OK;
    return cli_fail(REFRACT_E_INVALID_VOLUME,
                    "%s: '%s' is a detached NRRD header (its \"data file:\" names another "
                    "file), and refractd takes attached data only; attach it, e.g. 'unu save "
                    "-f nrrd -e gzip -i %s -o volume.nrrd' (nothing was sent)",
                    up->cmd->name, up->file, up->file);
}

static int send_file(struct cli *cli, struct cli_upload *up, long long size, char **json)
{
    struct view v = {.start_ms = now_ms(), .last_step = -1, .total = size};

    if (!up->quiet) {
        cli_progress_init(&v.p, stderr, isatty(2), cli_terminal_columns(2));
        up->desc.progress = on_progress;
        up->desc.user = &v;
    }
    int code = strcmp(up->file, "-") == 0
                   ? refract_upload_stream(cli->client, up->scene, stdin, size, &up->desc, json)
                   : refract_upload_file(cli->client, up->scene, up->file, &up->desc, json);
    if (!up->quiet) {
        if (code == REFRACT_E_OK)
            show_end(&v);
        cli_progress_finish(&v.p);
    }
    return code;
}

int cli_upload_run(struct cli *cli, struct cli_upload *up)
{
    const struct refract_upload_desc *d = &up->desc;
    bool raw = d->kind == REFRACT_UPLOAD_VOLUME && d->format != NULL && !strcmp(d->format, "raw");
    bool nrrd = d->kind == REFRACT_UPLOAD_VOLUME && d->format != NULL && !strcmp(d->format, "nrrd");
    long long size = -1;
    char *json = NULL;
    int code = file_size(up, &size);

    if (code == REFRACT_E_OK && raw)
        code = check_raw(up, size);
    if (code == REFRACT_E_OK && nrrd)
        code = check_nrrd(up);
    if (code == REFRACT_E_OK)
        code = cli_connect(cli);
    if (code != REFRACT_E_OK)
        return code;
    code = send_file(cli, up, size, &json);
    code = code == REFRACT_E_OK ? cli_print_json(json) : cli_call_failed(cli, code);
    refract_free(json);
    return code;
}
