/*
 * log.h - the daemon's one logger: timestamped lines on stderr.
 *
 * Thread: any (one fprintf per line, which POSIX makes atomic per FILE).
 * Levels below the configured one are dropped.
 */
#ifndef REFRACT_LOG_H
#define REFRACT_LOG_H

enum log_level { LOG_DEBUG = 0, LOG_INFO = 1, LOG_WARN = 2, LOG_ERROR = 3 };

void log_set_level(enum log_level level);
/* Parses "debug|info|warn|error"; returns -1 when unknown. */
int log_level_parse(const char *name);
void log_msg(enum log_level level, const char *module, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

#define log_debug(module, ...) log_msg(LOG_DEBUG, module, __VA_ARGS__)
#define log_info(module, ...) log_msg(LOG_INFO, module, __VA_ARGS__)
#define log_warn(module, ...) log_msg(LOG_WARN, module, __VA_ARGS__)
#define log_error(module, ...) log_msg(LOG_ERROR, module, __VA_ARGS__)

#endif
