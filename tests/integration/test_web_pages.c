/*
 * test_web_pages.c - the web viewer's pages and assets through a real refractd
 * (docs/api.md "The web viewer", server/http/h_web.c):
 *   - every file of server/web/ is served byte for byte as compiled in (GET / for
 *     index.html, GET /viewer/{id} for viewer.html, GET /assets/{file} for the rest), with
 *     the Content-Type of its extension, Cache-Control: no-cache, an ETag,
 *     X-Content-Type-Options and a Content-Security-Policy of 'self' only;
 *   - an If-None-Match with the ETag answers 304 with no body;
 *   - every /assets/ URL the pages refer to is served (a typo in a page fails here);
 *   - an unknown scene's viewer is 404 scene_not_found as JSON, or an HTML page for a
 *     browser (Accept: text/html) that names the id HTML-escaped;
 *   - the pages are not served under /assets/, and an unknown asset is 404 not_found.
 * The browser test (tests/browser/viewer_test.mjs) checks what the pages do.
 */
#include <curl/curl.h>
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "daemon.h"
#include "test.h"

struct answer {
    long status;
    char *body; /* owned, NUL-terminated */
    size_t len;
    char content_type[128];
    char cache_control[64];
    char etag[64];
    char nosniff[32];
    char csp[512];
};

static size_t on_body(char *data, size_t size, size_t n, void *user)
{
    struct answer *a = user;
    size_t add = size * n;
    char *grown = realloc(a->body, a->len + add + 1);
    if (grown == NULL)
        return 0;
    a->body = grown;
    memcpy(a->body + a->len, data, add);
    a->len += add;
    a->body[a->len] = '\0';
    return add;
}

/* Copies the value of header `name` from a raw header line into out, if it is that one. */
static void header_value(const char *line, size_t len, const char *name, char *out, size_t size)
{
    size_t n = strlen(name);
    if (len <= n + 1 || strncasecmp(line, name, n) != 0 || line[n] != ':')
        return;
    const char *v = line + n + 1;
    const char *end = line + len;
    while (v < end && *v == ' ')
        v++;
    while (end > v && (end[-1] == '\r' || end[-1] == '\n'))
        end--;
    snprintf(out, size, "%.*s", (int)(end - v), v);
}

static size_t on_header(char *line, size_t size, size_t n, void *user)
{
    struct answer *a = user;
    size_t len = size * n;
    header_value(line, len, "Cache-Control", a->cache_control, sizeof a->cache_control);
    header_value(line, len, "ETag", a->etag, sizeof a->etag);
    header_value(line, len, "X-Content-Type-Options", a->nosniff, sizeof a->nosniff);
    header_value(line, len, "Content-Security-Policy", a->csp, sizeof a->csp);
    header_value(line, len, "Content-Type", a->content_type, sizeof a->content_type);
    return len;
}

/* GET path with an optional extra request header ("Accept: text/html"). */
static struct answer get(const struct test_daemon *d, const char *path, const char *header)
{
    struct answer a = {0};
    char url[512];
    snprintf(url, sizeof url, "%s%s", d->url, path);
    CURL *curl = curl_easy_init();
    struct curl_slist *headers = header ? curl_slist_append(NULL, header) : NULL;
    curl_easy_setopt(curl, CURLOPT_URL, url);
    curl_easy_setopt(curl, CURLOPT_HTTPHEADER, headers);
    curl_easy_setopt(curl, CURLOPT_WRITEFUNCTION, on_body);
    curl_easy_setopt(curl, CURLOPT_WRITEDATA, &a);
    curl_easy_setopt(curl, CURLOPT_HEADERFUNCTION, on_header);
    curl_easy_setopt(curl, CURLOPT_HEADERDATA, &a);
    curl_easy_setopt(curl, CURLOPT_TIMEOUT, 30L);
    if (curl_easy_perform(curl) == CURLE_OK)
        curl_easy_getinfo(curl, CURLINFO_RESPONSE_CODE, &a.status);
    else
        a.status = -1;
    curl_slist_free_all(headers);
    curl_easy_cleanup(curl);
    return a;
}

static const char *expected_type(const char *name)
{
    const char *dot = strrchr(name, '.');
    if (dot == NULL)
        return "?";
    if (strcmp(dot, ".html") == 0)
        return "text/html; charset=utf-8";
    if (strcmp(dot, ".js") == 0)
        return "text/javascript; charset=utf-8";
    if (strcmp(dot, ".css") == 0)
        return "text/css; charset=utf-8";
    if (strcmp(dot, ".svg") == 0)
        return "image/svg+xml";
    return "?";
}

/* The URL that serves server/web/<name>. */
static void url_of(const char *name, const char *scene, char *out, size_t size)
{
    if (strcmp(name, "index.html") == 0)
        snprintf(out, size, "/");
    else if (strcmp(name, "viewer.html") == 0)
        snprintf(out, size, "/viewer/%s", scene);
    else
        snprintf(out, size, "/assets/%s", name);
}

/* One file: served as on disk, with its headers; its ETag revalidates to a 304. */
static void file_is_served_as_compiled_in(const struct test_daemon *d, const char *name,
                                          const char *scene)
{
    char rel[300], path[300];
    snprintf(rel, sizeof rel, "server/web/%s", name);
    size_t disk_len = 0;
    char *disk = test_read_source_file(rel, &disk_len);
    CHECK_MSG(disk != NULL, "cannot read %s", rel);
    url_of(name, scene, path, sizeof path);
    struct answer a = get(d, path, NULL);
    CHECK_MSG(a.status == 200, "GET %s: %ld", path, a.status);
    CHECK_MSG(disk && a.len == disk_len && memcmp(a.body, disk, disk_len) == 0,
              "GET %s: %zu bytes, not the %zu of %s", path, a.len, disk_len, rel);
    CHECK_MSG(strcmp(a.content_type, expected_type(name)) == 0, "GET %s: Content-Type \"%s\"", path,
              a.content_type);
    CHECK_MSG(strcmp(a.cache_control, "no-cache") == 0, "GET %s: Cache-Control \"%s\"", path,
              a.cache_control);
    CHECK_MSG(strcmp(a.nosniff, "nosniff") == 0, "GET %s: X-Content-Type-Options \"%s\"", path,
              a.nosniff);
    CHECK_MSG(strncmp(a.csp, "default-src 'self';", 19) == 0 && strstr(a.csp, "http") == NULL,
              "GET %s: Content-Security-Policy \"%s\"", path, a.csp);
    CHECK_MSG(a.etag[0] == '"' && strlen(a.etag) == 18, "GET %s: ETag \"%s\"", path, a.etag);

    char if_none_match[128];
    snprintf(if_none_match, sizeof if_none_match, "If-None-Match: %s", a.etag);
    struct answer again = get(d, path, if_none_match);
    CHECK_MSG(again.status == 304 && again.len == 0, "GET %s with its ETag: %ld, %zu bytes", path,
              again.status, again.len);
    CHECK_MSG(strcmp(again.etag, a.etag) == 0, "GET %s: the 304's ETag \"%s\"", path, again.etag);
    free(again.body);
    free(a.body);
    free(disk);
}

/* Every "/assets/NAME" a page mentions is served. */
static int referenced_assets_are_served(const struct test_daemon *d, const char *page)
{
    int found = 0;
    for (const char *p = strstr(page, "\"/assets/"); p; p = strstr(p + 1, "\"/assets/")) {
        const char *start = p + 1;
        const char *end = strchr(start, '"');
        if (end == NULL || end - start > 200)
            break;
        char path[256];
        snprintf(path, sizeof path, "%.*s", (int)(end - start), start);
        struct answer a = get(d, path, NULL);
        CHECK_MSG(a.status == 200, "a page refers to %s, which answers %ld", path, a.status);
        free(a.body);
        found++;
    }
    return found;
}

static void every_web_file_is_served(const struct test_daemon *d, const char *scene)
{
    const char *src = getenv("REFRACT_SOURCE_DIR");
    char dir[1024];
    snprintf(dir, sizeof dir, "%s/server/web", src ? src : ".");
    DIR *dd = opendir(dir);
    CHECK_MSG(dd != NULL, "cannot list %s", dir);
    if (dd == NULL)
        return;
    int files = 0;
    struct dirent *ent;
    while ((ent = readdir(dd)) != NULL) {
        if (ent->d_name[0] == '.')
            continue;
        file_is_served_as_compiled_in(d, ent->d_name, scene);
        files++;
    }
    closedir(dd);
    printf("  %d files of server/web served as compiled in\n", files);
    CHECK(files >= 6);
}

static void pages_refer_only_to_served_assets(const struct test_daemon *d, const char *scene)
{
    char viewer[128];
    snprintf(viewer, sizeof viewer, "/viewer/%s", scene);
    const char *pages[] = {"/", viewer};
    for (int i = 0; i < 2; i++) {
        struct answer a = get(d, pages[i], NULL);
        int n = a.body ? referenced_assets_are_served(d, a.body) : 0;
        CHECK_MSG(n >= 3, "%s refers to %d assets", pages[i], n);
        free(a.body);
    }
}

static void unknown_scene_viewer_is_404(const struct test_daemon *d)
{
    struct answer json = get(d, "/viewer/no_such_scene", NULL);
    CHECK_INT(json.status, 404);
    CHECK(strcmp(json.content_type, "application/json") == 0);
    CHECK(test_error_is(json.body, "scene_not_found", "no_such_scene"));
    free(json.body);

    /* A browser gets a page; the id, which came from the URL, is escaped in it. */
    struct answer html = get(d, "/viewer/%3Cb%3Ex%26y", "Accept: text/html,*/*;q=0.8");
    CHECK_INT(html.status, 404);
    CHECK(strcmp(html.content_type, "text/html; charset=utf-8") == 0);
    CHECK(html.body && strstr(html.body, "No scene") != NULL);
    CHECK_MSG(html.body && strstr(html.body, "&lt;b&gt;x&amp;y") != NULL &&
                  strstr(html.body, "<b>x") == NULL,
              "the id is not escaped: %s", html.body ? html.body : "");
    CHECK(html.body && strstr(html.body, "href=\"/\"") != NULL);
    free(html.body);
}

static void pages_are_not_assets(const struct test_daemon *d)
{
    const char *paths[] = {"/assets/index.html", "/assets/viewer.html", "/assets/nope.js"};
    for (int i = 0; i < 3; i++) {
        struct answer a = get(d, paths[i], NULL);
        CHECK_MSG(a.status == 404, "GET %s: %ld", paths[i], a.status);
        CHECK(test_error_is(a.body, "not_found", paths[i]));
        CHECK(a.body && strstr(a.body, "viewer.js") != NULL); /* lists what there is */
        free(a.body);
    }
}

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_web_pages", d.why);
    char id[REFRACT_ID_SIZE];
    size_t len = 0;
    char *scene = test_read_source_file("proto/examples/glass_sphere.json", &len);
    CHECK(scene != NULL && test_create_scene(&d, scene, id));
    free(scene);

    every_web_file_is_served(&d, id);
    pages_refer_only_to_served_assets(&d, id);
    unknown_scene_viewer_is_404(&d);
    pages_are_not_assets(&d);

    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_web_pages");
}
