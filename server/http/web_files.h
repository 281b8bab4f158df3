/*
 * web_files.h - the web viewer's files (server/web/), compiled into refractd at build time
 * by tools/embed_files.c. Served by h_web.c: GET / and GET /viewer/{id} answer the two
 * pages, GET /assets/{file} the scripts, styles and images (docs/views.md, "The web
 * viewer"). Internal to server/http/.
 */
#ifndef REFRACT_HTTP_WEB_FILES_H
#define REFRACT_HTTP_WEB_FILES_H

#include <stddef.h>

struct http_web_file {
    const char *name;           /* base name, e.g. "viewer.js" */
    const unsigned char *bytes; /* static; `length` bytes (plus a NUL not counted) */
    size_t length;              /* bytes */
    const char *content_type;   /* from the extension: "text/javascript; charset=utf-8" */
    const char *etag;           /* quoted strong ETag: FNV-1a 64 of the bytes, in hex */
};

extern const struct http_web_file http_web_files[];
extern const size_t http_web_file_count;

/* The embedded file of that base name, or NULL. Borrows nothing; the result is static. */
const struct http_web_file *http_web_file_find(const char *name);

#endif
