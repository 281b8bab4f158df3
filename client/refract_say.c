/*
 * refract_say.c - writing a "why" message and returning false; see refract_say.h.
 */
#include "refract_say.h"

#include <stdarg.h>
#include <stdio.h>

bool refract_say(char *why, size_t why_size, const char *fmt, ...)
{
    va_list ap;

    if (why == NULL || why_size == 0)
        return false;
    va_start(ap, fmt);
    vsnprintf(why, why_size, fmt, ap);
    va_end(ap);
    return false;
}
