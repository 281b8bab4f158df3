/*
 * cli_irradiance.h - how the refract CLI shows irradiance volumes: the status table of
 * `refract irradiance status`, and the progress of `refract light set --wait` (a bar
 * redrawn in place on a terminal, plain lines otherwise).
 *
 * Formatting is pure (buffers and a FILE *), so tests/unit/test_cli_args.c compiles
 * this file directly; it calls no librefract function but reads its structs.
 */
#ifndef CLI_IRRADIANCE_H
#define CLI_IRRADIANCE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

#include "../refract.h"

/* "-" for a negative count (absent), else "0 B", "512 B", "2.0 KiB", "12.3 MiB",
 * "1.50 GiB". */
void cli_format_bytes(char *buf, size_t size, long long bytes);

/* "-" for a negative time (absent), else "850 ms", "12.4 s", "3 min 05 s". */
void cli_format_ms(char *buf, size_t size, double ms);

/* The fraction of the scene's irradiance work that is done, 0..1: the mean over the
 * lights that need a volume of their progress, a settled light counting as 1 and a
 * queued one as 0. 1 when no light needs a volume. */
double cli_irradiance_fraction(const struct refract_irradiance *s);

/* "[##########----------]  50%" with bar_width characters between the brackets. */
void cli_progress_bar(char *buf, size_t size, double fraction, int bar_width);

/* One line for a status: "sun computing 45% (12034 patches), bulb queued, spot ready"
 * (a queued light shows no percentage: it has not started). With step
 * > 0 the percentages are rounded down to multiples of step percent, so that a log
 * gets a new line every step percent and not on every read. */
void cli_irradiance_summary(char *buf, size_t size, const struct refract_irradiance *s, int step);

/* Prints the status as a table (LIGHT STATE PROGRESS PATCHES GPU-MEM HOST-MEM COMPUTE
 * USING), a line about the scene above it, and each failed light's message below it. */
void cli_irradiance_table(FILE *f, const struct refract_irradiance *s);

/* The progress of a wait, drawn on f. */
struct cli_progress {
    FILE *f;
    bool tty;       /* redraw one line in place; otherwise print a line per change */
    int width;      /* the terminal's columns (tty only) */
    bool drawn;     /* a bar is on the current line (tty) */
    char last[512]; /* the last line shown, so repeats are left out */
};

/* Starts a progress display on f; tty and width as the caller found them. */
void cli_progress_init(struct cli_progress *p, FILE *f, bool tty, int width);
/* Shows s: redraws the bar, or prints "irradiance: <summary>" when it changed. */
void cli_progress_update(struct cli_progress *p, const struct refract_irradiance *s);
/* Ends the bar's line (tty), so later messages start on a line of their own. */
void cli_progress_finish(struct cli_progress *p);

#endif
