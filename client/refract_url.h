/*
 * refract_url.h - URL string helpers of librefract: base URL checks, joining, and
 * percent-encoding of path segments. Pure string work with no libcurl, so the CLI and
 * tests/unit/test_cli_args.c can use it without a network stack.
 *
 * Internal to the client: librefract's files and the refract CLI use it; it is not part
 * of refract.h.
 */
#ifndef REFRACT_URL_H
#define REFRACT_URL_H

#include <stdbool.h>
#include <stddef.h>

/* Writes segment percent-encoded for use as one URL path segment into dst (dst_size
 * bytes, always NUL-terminated when dst_size > 0) and returns the length of the whole
 * encoding, like snprintf: the output was cut when the result is >= dst_size.
 * RFC 3986 unreserved characters (A-Z a-z 0-9 - . _ ~) stay as they are; every other byte
 * becomes %XX. A segment of only dots ("." or "..") is encoded entirely ("%2E%2E"), so it
 * cannot be read as a relative path step. dst may be NULL when dst_size is 0. */
size_t refract_url_escape(char *dst, size_t dst_size, const char *segment);

/* Returns a new string: segment percent-encoded as above; the caller frees it with
 * free(). NULL when out of memory. */
char *refract_url_escape_dup(const char *segment);

/* Returns a new string: base without its trailing slashes followed by path, with exactly
 * one '/' between them when path is not empty ("http://h:1/" + "/v1/health" ->
 * "http://h:1/v1/health"). The caller frees it with free(). NULL when out of memory. */
char *refract_url_join(const char *base, const char *path);

/* True when url starts with "http://" or "https://" (any letter case) followed by a
 * non-empty host, and contains no whitespace or control characters. */
bool refract_url_is_http(const char *url);

#endif
