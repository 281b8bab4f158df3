/*
 * log.c - timestamped log lines on stderr. Deliberately not a logging framework:
 * systemd's journal or a redirect does the rest.
 *
 * One event is one line: the message is escaped (utf8_escape: control characters and
 * invalid UTF-8 become \xNN) after formatting, so a scene id sent as "x%0a2026-... info"
 * cannot forge a second line, whichever format argument carried it.
 */
#include "log.h"

#include "utf8.h"

#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static atomic_int current_level = LOG_INFO;

void log_set_level(enum log_level level)
{
    atomic_store(&current_level, (int)level);
}

int log_level_parse(const char *name)
{
    static const char *names[] = {"debug", "info", "warn", "error"};
    for (int i = 0; i < 4; i++) {
        if (strcmp(name, names[i]) == 0)
            return i;
    }
    return -1;
}

void log_msg(enum log_level level, const char *module, const char *fmt, ...)
{
    if ((int)level < atomic_load(&current_level))
        return;
    static const char *tags[] = {"debug", "info", "warn", "error"};
    char line[2048];
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    struct tm tm;
    gmtime_r(&ts.tv_sec, &tm);
    int n = snprintf(line, sizeof line, "%04d-%02d-%02dT%02d:%02d:%02d.%03ldZ %-5s %-6s ",
                     tm.tm_year + 1900, tm.tm_mon + 1, tm.tm_mday, tm.tm_hour, tm.tm_min,
                     tm.tm_sec, ts.tv_nsec / 1000000, tags[level], module);
    char message[2048];
    va_list ap;
    va_start(ap, fmt);
    int m = vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
    if (n > 0 && (size_t)n < sizeof line && m >= 0) {
        size_t mlen = (size_t)m < sizeof message ? (size_t)m : sizeof message - 1;
        utf8_escape(line + n, sizeof line - (size_t)n, message, mlen, NULL);
    }
    fprintf(stderr, "%s\n", line);
}
