/*
 * utf8.h - the one UTF-8 validator and the one escaping function of refractd.
 *
 * Bytes from clients (URLs, JSON documents, file headers) reach error messages, logs and
 * stored documents. Two rules keep them from breaking what reads those (docs/api.md,
 * "Bytes"): text refractd stores must be well-formed UTF-8 (utf8_invalid_at), and text it
 * shows (error messages, log lines) has every byte that is not printable UTF-8 written as
 * \xNN (utf8_escape), so a JSON reader never meets invalid UTF-8 and a "%0a" never starts
 * a forged log line.
 *
 * Thread: any; nothing allocates.
 */
#ifndef REFRACT_UTF8_H
#define REFRACT_UTF8_H

#include <stdbool.h>
#include <stddef.h>

/* The offset of the first byte of s[0..len) that does not begin a well-formed UTF-8
 * sequence (RFC 3629: no overlong forms, no surrogates U+D800..U+DFFF, nothing above
 * U+10FFFF, no truncated sequence), or len when the whole text is well-formed. */
size_t utf8_invalid_at(const char *s, size_t len);

/* True when s[0..len) is well-formed UTF-8. */
bool utf8_valid(const char *s, size_t len);

/* Copies src[0..len) to dst (size bytes, always NUL-terminated when size > 0), writing
 * each byte that is not printable UTF-8 as the four characters \xNN (lower-case hex):
 * control characters (U+0000..U+001F, U+007F, U+0080..U+009F) and every byte of an
 * ill-formed sequence. Printable characters, ASCII or not, are copied unchanged. Stops
 * before a character or escape that would not fit whole; *consumed (when not NULL) gets
 * the bytes of src that were written out. Returns the bytes written (without the NUL).
 * A src that is already clean comes out identical. */
size_t utf8_escape(char *dst, size_t size, const char *src, size_t len, size_t *consumed);

#endif
