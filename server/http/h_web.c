/*
 * h_web.c - the web viewer's pages and assets (docs/views.md, "The web viewer"):
 *
 *     GET /                  index.html: the scene list
 *     GET /viewer/{id}       viewer.html, for a scene that exists (404 otherwise; with a
 *                            --token-file, for any id: the page asks for the token)
 *     GET /assets/{file}     the viewer's scripts, styles and icon
 *
 * The files are compiled into refractd (tools/embed_files.c -> web_files.h); nothing is
 * read from disk and nothing refers to another host. The pages are static: the scripts
 * read the scene id from the URL and talk to API v1 like any other client. This file
 * deliberately renders no HTML of its own apart from the 404 page a browser gets for an
 * unknown scene.
 *
 * Caching: every answer carries the file's ETag and `Cache-Control: no-cache`, so a
 * browser revalidates each time (a 304 costs a few bytes) and a rebuilt refractd's new
 * viewer is seen at once, never a stale script next to a new page.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/log.h"
#include "http_internal.h"
#include "web_files.h"

/* The pages load only what refractd serves: no CDN, no inline script. The stream is an
 * <img> from the same origin; the browser test decodes screenshots from data: URLs. */
static const char content_security_policy[] =
    "default-src 'self'; img-src 'self' data: blob:; style-src 'self'; script-src 'self'; "
    "connect-src 'self'; frame-ancestors 'none'; base-uri 'none'; form-action 'none'";

const struct http_web_file *http_web_file_find(const char *name)
{
    for (size_t i = 0; i < http_web_file_count; i++) {
        if (strcmp(http_web_files[i].name, name) == 0)
            return &http_web_files[i];
    }
    return NULL;
}

static bool is_page(const struct http_web_file *f)
{
    return strncmp(f->content_type, "text/html", 9) == 0;
}

/* True when the client's Accept header asks for HTML (a browser's navigation does). */
static bool wants_html(struct http_request *req)
{
    const char *accept = MHD_lookup_connection_value(req->conn, MHD_HEADER_KIND, "Accept");
    return accept != NULL && strstr(accept, "text/html") != NULL;
}

static enum MHD_Result respond_file(struct http_request *req, const struct http_web_file *f)
{
    const char *headers[] = {"Cache-Control",
                             "no-cache",
                             "ETag",
                             f->etag,
                             "Content-Security-Policy",
                             content_security_policy,
                             "Referrer-Policy",
                             "same-origin",
                             NULL};
    const char *known = MHD_lookup_connection_value(req->conn, MHD_HEADER_KIND, "If-None-Match");
    if (known != NULL && strstr(known, f->etag) != NULL)
        return http_respond_bytes(req, MHD_HTTP_NOT_MODIFIED, NULL, 0, NULL, headers);
    /* respond.c hands the body to libmicrohttpd with free(): give it a copy. The files are
     * tens of kilobytes, fetched once per page view and then revalidated with 304s. */
    void *copy = malloc(f->length ? f->length : 1);
    if (copy == NULL)
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory serving %s",
                                  f->name);
    memcpy(copy, f->bytes, f->length);
    return http_respond_bytes(req, MHD_HTTP_OK, copy, f->length, f->content_type, headers);
}

/* A page must be embedded: its absence is a build bug, reported as such. */
static enum MHD_Result respond_page(struct http_request *req, const char *name)
{
    const struct http_web_file *f = http_web_file_find(name);
    if (f == NULL)
        return http_respond_error(req, REFRACT_E_INTERNAL,
                                  "%s is not embedded in this refractd; rebuild it from a "
                                  "checkout that has server/web/%s",
                                  name, name);
    return respond_file(req, f);
}

/* Writes text with & < > " ' escaped into out (NUL-terminated; truncated to size). */
static void html_escape(const char *text, char *out, size_t size)
{
    size_t used = 0;
    for (const char *p = text; *p && used + 7 < size; p++) {
        const char *rep = NULL;
        switch (*p) {
        case '&':
            rep = "&amp;";
            break;
        case '<':
            rep = "&lt;";
            break;
        case '>':
            rep = "&gt;";
            break;
        case '"':
            rep = "&quot;";
            break;
        case '\'':
            rep = "&#39;";
            break;
        default:
            break;
        }
        if (rep) {
            size_t n = strlen(rep);
            memcpy(out + used, rep, n);
            used += n;
        } else {
            out[used++] = *p;
        }
    }
    out[used] = '\0';
}

/* The 404 a browser shows for /viewer/<unknown>: says what was asked and where the list
 * is. Uses the viewer's stylesheet, so it looks like the rest. */
static enum MHD_Result respond_unknown_scene_html(struct http_request *req, const char *id)
{
    char safe[HTTP_PARAM_MAX * 6];
    html_escape(id, safe, sizeof safe);
    static const char fmt[] =
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
        "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
        "<title>No such scene - Refract</title>"
        "<link rel=\"icon\" href=\"/assets/favicon.svg\">"
        "<link rel=\"stylesheet\" href=\"/assets/viewer.css\"></head>"
        "<body class=\"page\"><main class=\"notice\"><h1>No scene "
        "&ldquo;%s&rdquo;</h1><p>refractd has no scene with this id. "
        "<a href=\"/\">See the scenes it has</a>, or create one with "
        "<code>POST /v1/scenes</code>.</p></main></body></html>\n";
    size_t size = sizeof fmt + strlen(safe);
    char *page = malloc(size);
    if (page == NULL)
        return http_respond_error(req, REFRACT_E_OUT_OF_MEMORY, "out of memory");
    int n = snprintf(page, size, fmt, safe);
    if (n < 0) {
        free(page);
        return http_respond_error(req, REFRACT_E_INTERNAL, "cannot format the 404 page");
    }
    log_info("http", "404 scene_not_found /viewer/{id}: no scene \"%s\" (HTML page)", id);
    const char *headers[] = {"Cache-Control",
                             "no-store",
                             "Content-Security-Policy",
                             content_security_policy,
                             NULL};
    return http_respond_bytes(req, MHD_HTTP_NOT_FOUND, page, (size_t)n, "text/html; charset=utf-8",
                              headers);
}

/* "a.js, b.css, ..." of the files /assets/ serves, for the 404 message. */
static void asset_names(char *out, size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (size_t i = 0; i < http_web_file_count; i++) {
        if (is_page(&http_web_files[i]))
            continue;
        int w = snprintf(out + used, size - used, "%s%s", used ? ", " : "", http_web_files[i].name);
        if (w < 0 || (size_t)w >= size - used)
            break;
        used += (size_t)w;
    }
}

enum MHD_Result http_handle_web_index(struct http_request *req)
{
    return respond_page(req, "index.html");
}

enum MHD_Result http_handle_web_viewer(struct http_request *req)
{
    const char *id = req->params[0];
    /* With a token the page is served without it (access.c), so it must not tell who has
     * no token which scene ids exist: the page's own API calls, with the token, say so. */
    if (req->cfg->token != NULL && req->cfg->token[0] != '\0')
        return respond_page(req, "viewer.html");
    struct store_scene *v = store_scene_get(req->app->store, id);
    if (v == NULL) {
        if (wants_html(req))
            return respond_unknown_scene_html(req, id);
        return http_respond_error(req, REFRACT_E_SCENE_NOT_FOUND,
                                  "no scene with id \"%s\" to view; GET /v1/scenes (or the page "
                                  "at /) lists the scenes",
                                  id);
    }
    store_scene_release(v);
    return respond_page(req, "viewer.html");
}

enum MHD_Result http_handle_web_asset(struct http_request *req)
{
    const char *name = req->params[0];
    const struct http_web_file *f = http_web_file_find(name);
    /* The pages have their own URLs; /assets/ serves only what they load. */
    if (f == NULL || is_page(f)) {
        char names[512];
        asset_names(names, sizeof names);
        return http_respond_error(req, REFRACT_E_NOT_FOUND,
                                  "no file /assets/%s in refractd's web viewer; it has: %s", name,
                                  names);
    }
    return respond_file(req, f);
}
