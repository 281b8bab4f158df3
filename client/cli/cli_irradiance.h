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
#include "cli_progress.h"

/* The fraction of the scene's irradiance work that is done, 0..1: the mean over the
 * lights that need a volume of their progress, a settled light counting as 1 and a
 * queued one as 0. 1 when no light needs a volume. */
double cli_irradiance_fraction(const struct refract_irradiance *s);

/* One line for a status: "sun computing 45% (12034 patches), bulb queued, spot ready"
 * (a queued light shows no percentage: it has not started). With step
 * > 0 the percentages are rounded down to multiples of step percent, so that a log
 * gets a new line every step percent and not on every read. */
void cli_irradiance_summary(char *buf, size_t size, const struct refract_irradiance *s, int step);

/* Prints the status as a table (LIGHT STATE PROGRESS PATCHES GPU-MEM HOST-MEM COMPUTE
 * USING), a line about the scene above it, and each failed light's message below it. */
void cli_irradiance_table(FILE *f, const struct refract_irradiance *s);

/* Shows s on p (cli_progress.h): on a terminal the bar of cli_irradiance_fraction() and
 * the summary, redrawn; otherwise "irradiance: <summary>" (in 10 % steps) when it
 * changed. */
void cli_progress_update(struct cli_progress *p, const struct refract_irradiance *s);

#endif
