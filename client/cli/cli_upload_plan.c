/*
 * cli_upload_plan.c - the pure part of `refract upload` (cli_upload.h): what a file's
 * name says about its upload, and the local checks that need only a few bytes.
 */
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "cli_upload.h"

int cli_upload_kind_from_path(const char *path, const char **format)
{
    static const struct {
        const char *ext;
        int kind;
        const char *format;
    } table[] = {
        {"nrrd", REFRACT_UPLOAD_VOLUME, "nrrd"},   {"nhdr", REFRACT_UPLOAD_VOLUME, "nrrd"},
        {"raw", REFRACT_UPLOAD_VOLUME, "raw"},     {"exr", 0, "exr"},
        {"obj", REFRACT_UPLOAD_MESH, "obj"},       {"ply", REFRACT_UPLOAD_MESH, "ply"},
        {"hdr", REFRACT_UPLOAD_ENVIRONMENT, NULL}, {"png", REFRACT_UPLOAD_ENVIRONMENT, NULL},
        {"jpg", REFRACT_UPLOAD_ENVIRONMENT, NULL}, {"jpeg", REFRACT_UPLOAD_ENVIRONMENT, NULL},
    };
    const char *base = strrchr(path, '/');
    const char *dot;

    *format = NULL;
    base = base != NULL ? base + 1 : path;
    dot = strrchr(base, '.');
    if (dot == NULL || dot == base)
        return 0;
    for (size_t i = 0; i < sizeof(table) / sizeof(table[0]); i++) {
        if (strcasecmp(dot + 1, table[i].ext) == 0) {
            *format = table[i].format;
            return table[i].kind;
        }
    }
    return 0;
}

bool cli_upload_default_name(const char *path, char *out, size_t size)
{
    const char *base = strrchr(path, '/');
    const char *dot;
    size_t len;

    base = base != NULL ? base + 1 : path;
    dot = strrchr(base, '.');
    len = dot != NULL && dot != base ? (size_t)(dot - base) : strlen(base);
    if (len == 0 || len > 63 || len >= size)
        return false;
    for (size_t i = 0; i < len; i++) {
        char ch = base[i];
        bool ok = (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') ||
                  (ch >= '0' && ch <= '9') || ch == '_' || ch == '-';

        if (!ok)
            return false;
    }
    memcpy(out, base, len);
    out[len] = '\0';
    return true;
}

int cli_upload_sample_bytes(const char *type)
{
    static const struct {
        const char *name;
        int bytes;
    } types[] = {{"float32", 4}, {"float16", 2}, {"uint8", 1}, {"uint16", 2}};

    for (size_t i = 0; type != NULL && i < sizeof(types) / sizeof(types[0]); i++) {
        if (strcmp(type, types[i].name) == 0)
            return types[i].bytes;
    }
    return 0;
}

bool cli_upload_nrrd_detached(const char *head, size_t len)
{
    size_t i = 0;

    /* Header lines up to the first empty one (the NRRD format's end of header). */
    while (i < len) {
        const char *line = head + i;
        const char *nl = memchr(line, '\n', len - i);
        size_t n = nl != NULL ? (size_t)(nl - line) : len - i;

        if (n > 0 && line[n - 1] == '\r')
            n--;
        if (n == 0)
            return false;
        if ((n >= 10 && strncasecmp(line, "data file:", 10) == 0) ||
            (n >= 9 && strncasecmp(line, "datafile:", 9) == 0))
            return true;
        if (nl == NULL)
            break;
        i += (size_t)(nl - line) + 1;
    }
    return false;
}
