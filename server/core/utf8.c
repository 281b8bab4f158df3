/*
 * utf8.c - UTF-8 well-formedness (RFC 3629, Table 3-7 of the Unicode standard) and the
 * \xNN escaping of what is not printable. A table-free decoder: the lead byte gives the
 * length and the allowed range of the second byte, which is where overlong forms,
 * surrogates and values above U+10FFFF are excluded.
 */
#include "utf8.h"

#include <stdint.h>

/* The length of the well-formed sequence at s[0..len), or 0 when it is ill-formed;
 * *cp receives its code point. */
static size_t sequence_at(const unsigned char *s, size_t len, uint32_t *cp)
{
    unsigned char c = s[0];
    if (c < 0x80) {
        *cp = c;
        return 1;
    }
    size_t n;
    unsigned char lo = 0x80, hi = 0xbf;
    if (c >= 0xc2 && c <= 0xdf) {
        n = 2;
    } else if (c >= 0xe0 && c <= 0xef) {
        n = 3;
        if (c == 0xe0)
            lo = 0xa0; /* overlong below U+0800 */
        else if (c == 0xed)
            hi = 0x9f; /* surrogates U+D800..U+DFFF */
    } else if (c >= 0xf0 && c <= 0xf4) {
        n = 4;
        if (c == 0xf0)
            lo = 0x90; /* overlong below U+10000 */
        else if (c == 0xf4)
            hi = 0x8f; /* above U+10FFFF */
    } else {
        return 0; /* a continuation byte, an overlong lead (C0, C1) or F5..FF */
    }
    if (len < n || s[1] < lo || s[1] > hi)
        return 0;
    uint32_t v = c & (0xffu >> (n + 1));
    v = (v << 6) | (s[1] & 0x3fu);
    for (size_t i = 2; i < n; i++) {
        if ((s[i] & 0xc0) != 0x80)
            return 0;
        v = (v << 6) | (s[i] & 0x3fu);
    }
    *cp = v;
    return n;
}

size_t utf8_invalid_at(const char *s, size_t len)
{
    const unsigned char *u = (const unsigned char *)s;
    size_t i = 0;
    while (i < len) {
        uint32_t cp;
        size_t n = sequence_at(u + i, len - i, &cp);
        if (n == 0)
            return i;
        i += n;
    }
    return len;
}

bool utf8_valid(const char *s, size_t len)
{
    return utf8_invalid_at(s, len) == len;
}

static bool printable(uint32_t cp)
{
    return cp >= 0x20 && cp != 0x7f && !(cp >= 0x80 && cp <= 0x9f);
}

size_t utf8_escape(char *dst, size_t size, const char *src, size_t len, size_t *consumed)
{
    static const char hex[] = "0123456789abcdef";
    const unsigned char *u = (const unsigned char *)src;
    size_t o = 0, i = 0;
    if (consumed)
        *consumed = 0;
    if (size == 0)
        return 0;
    while (i < len) {
        uint32_t cp = 0;
        size_t n = sequence_at(u + i, len - i, &cp);
        if (n > 0 && printable(cp)) {
            if (o + n >= size)
                break;
            for (size_t k = 0; k < n; k++)
                dst[o++] = (char)u[i + k];
            i += n;
            continue;
        }
        /* A control character is escaped byte by byte (C1 controls are two bytes); an
         * ill-formed sequence one byte at a time, resynchronising on the next. */
        size_t bytes = n > 0 ? n : 1;
        if (o + 4 * bytes >= size)
            break;
        for (size_t k = 0; k < bytes; k++) {
            unsigned char b = u[i + k];
            dst[o++] = '\\';
            dst[o++] = 'x';
            dst[o++] = hex[b >> 4];
            dst[o++] = hex[b & 15];
        }
        i += bytes;
    }
    dst[o] = '\0';
    if (consumed)
        *consumed = i;
    return o;
}
