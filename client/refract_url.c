/*
 * refract_url.c - percent-encoding of path segments and joining of the base URL with a
 * request path.
 *
 * Scene ids and volume names travel as path segments, so an id such as "a/b" or "x y"
 * must reach refractd as one segment ("a%2Fb", "x%20y"), never as two. This file is
 * deliberately free of libcurl (curl_easy_escape needs a handle) so the unit tests can
 * compile it on its own; it is not a general URL parser.
 */
#include "refract_url.h"

#include <stdlib.h>
#include <string.h>

static bool is_unreserved(unsigned char ch)
{
    if ((ch >= 'A' && ch <= 'Z') || (ch >= 'a' && ch <= 'z') || (ch >= '0' && ch <= '9'))
        return true;
    return ch == '-' || ch == '.' || ch == '_' || ch == '~';
}

static bool is_all_dots(const char *s)
{
    if (*s == '\0')
        return false;
    while (*s == '.')
        s++;
    return *s == '\0';
}

size_t refract_url_escape(char *dst, size_t dst_size, const char *segment)
{
    static const char hex[] = "0123456789ABCDEF";
    bool dots = is_all_dots(segment);
    size_t n = 0;

    for (const unsigned char *p = (const unsigned char *)segment; *p != '\0'; p++) {
        char enc[3];
        size_t len = 1;

        if (is_unreserved(*p) && !dots) {
            enc[0] = (char)*p;
        } else {
            enc[0] = '%';
            enc[1] = hex[*p >> 4];
            enc[2] = hex[*p & 0x0F];
            len = 3;
        }
        for (size_t i = 0; i < len; i++) {
            if (n + 1 < dst_size)
                dst[n] = enc[i];
            n++;
        }
    }
    if (dst_size > 0)
        dst[n < dst_size ? n : dst_size - 1] = '\0';
    return n;
}

char *refract_url_escape_dup(const char *segment)
{
    size_t len = refract_url_escape(NULL, 0, segment);
    char *out = malloc(len + 1);

    if (out == NULL)
        return NULL;
    refract_url_escape(out, len + 1, segment);
    return out;
}

char *refract_url_join(const char *base, const char *path)
{
    size_t base_len = strlen(base);
    size_t path_len = strlen(path);
    bool need_slash = path_len > 0 && path[0] != '/';
    char *out;

    while (base_len > 0 && base[base_len - 1] == '/')
        base_len--;
    out = malloc(base_len + (need_slash ? 1 : 0) + path_len + 1);
    if (out == NULL)
        return NULL;
    memcpy(out, base, base_len);
    if (need_slash)
        out[base_len++] = '/';
    memcpy(out + base_len, path, path_len + 1);
    return out;
}

static bool has_prefix_nocase(const char *s, const char *prefix)
{
    for (; *prefix != '\0'; s++, prefix++) {
        char ch = *s;

        if (ch >= 'A' && ch <= 'Z')
            ch = (char)(ch - 'A' + 'a');
        if (ch != *prefix)
            return false;
    }
    return true;
}

bool refract_url_is_http(const char *url)
{
    const char *host;

    if (has_prefix_nocase(url, "http://"))
        host = url + strlen("http://");
    else if (has_prefix_nocase(url, "https://"))
        host = url + strlen("https://");
    else
        return false;
    if (*host == '\0' || *host == '/' || *host == ':')
        return false;
    for (const unsigned char *p = (const unsigned char *)url; *p != '\0'; p++) {
        if (*p <= ' ' || *p == 0x7F)
            return false;
    }
    return true;
}
