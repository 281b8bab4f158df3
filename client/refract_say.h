/*
 * refract_say.h - the one way librefract and the refract CLI write a "why" message: into
 * a caller's buffer, returning false, so a check that fails ends with
 * `return refract_say(why, why_size, "...", ...)`.
 *
 * Internal to the client: librefract's files and the refract CLI use it (and
 * tests/unit/test_cli_args.c, which compiles refract_say.c directly); it is not part of
 * refract.h.
 */
#ifndef REFRACT_SAY_H
#define REFRACT_SAY_H

#include <stdbool.h>
#include <stddef.h>

/* Writes the printf-formatted message into why (why_size bytes, always NUL-terminated;
 * nothing when why is NULL or why_size is 0) and returns false. */
bool refract_say(char *why, size_t why_size, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

#endif
