/*
 * cli_progress.h - the one progress display of the refract CLI, on stderr: a bar redrawn
 * in place on a terminal, plain lines otherwise (a log, a pipe, a test), for anything
 * that takes a while: irradiance volumes (cli_irradiance.c), uploads (cli_upload.c),
 * batch jobs (cmd_job.c).
 * Also how sizes, times and transfers read.
 *
 * Formatting is pure (buffers and a FILE *), so tests/unit/test_cli_args.c compiles
 * this file directly.
 */
#ifndef CLI_PROGRESS_H
#define CLI_PROGRESS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

/* "-" for a negative count (absent), else "0 B", "512 B", "2.0 KiB", "12.3 MiB",
 * "1.50 GiB". */
void cli_format_bytes(char *buf, size_t size, long long bytes);

/* "-" for a negative time (absent), else "850 ms", "12.4 s", "3 min 05 s". */
void cli_format_ms(char *buf, size_t size, double ms);

/* "[##########----------]  50%" with bar_width characters between the brackets. */
void cli_progress_bar(char *buf, size_t size, double fraction, int bar_width);

/* A transfer of sent of total bytes (total < 0: unknown) that has run elapsed_s:
 * "45%  12.3 MiB of 27.0 MiB  85.2 MB/s  ETA 0.2 s" (the percentage only with
 * with_percent), "100%  27.0 MiB of 27.0 MiB  85.2 MB/s  in 0.3 s" once sent == total,
 * and "12.3 MiB  85.2 MB/s" for an unknown total. MB/s are 10^6 bytes per second (as
 * network speeds are given); the speed and ETA are left out until elapsed_s > 0. */
void cli_transfer_text(char *buf, size_t size, long long sent, long long total, double elapsed_s,
                       bool with_percent);

/* A progress display on f. */
struct cli_progress {
    FILE *f;
    bool tty;       /* redraw one line in place; otherwise print a line per change */
    int width;      /* the terminal's columns (tty only) */
    bool drawn;     /* a bar is on the current line (tty) */
    char last[512]; /* the last line shown, so repeats are left out */
};

/* Starts a progress display on f; tty and width as the caller found them. */
void cli_progress_init(struct cli_progress *p, FILE *f, bool tty, int width);
/* Shows one state. On a terminal "<bar of fraction>  <text>" (no bar when fraction < 0),
 * cut to the width (a wrapped line cannot be redrawn with \r) and redrawn in place when
 * it changed. Otherwise text on a line of its own when it differs from the last line;
 * callers round what they show (10 % steps), so a log gets a line per step. */
void cli_progress_show(struct cli_progress *p, double fraction, const char *text);
/* Ends the bar's line (tty), so later messages start on a line of their own. */
void cli_progress_finish(struct cli_progress *p);

/* The columns of the terminal on fd, else $COLUMNS, else 80. */
int cli_terminal_columns(int fd);

#endif
