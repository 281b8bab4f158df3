/*
 * embed_files.c - build tool: turns the web viewer's files (server/web/) into a C source
 * file holding each file's name, bytes, length, Content-Type and ETag, so refractd serves
 * its pages without reading anything from disk and without a build step that needs the
 * internet.
 *
 *     refract_embed_files OUTPUT.c server/web/index.html server/web/viewer.js ...
 *
 * The output defines `const struct http_web_file http_web_files[]` and
 * `http_web_file_count` (see server/http/web_files.h). Only the base name of each file is
 * kept: the pages refer to each other as /assets/<name>. The Content-Type comes from the
 * file's extension; an extension this table does not know fails the build (say which
 * type it is here) rather than being served as something a browser may misread. The ETag
 * is the FNV-1a 64-bit hash of the bytes, so a browser revalidates cheaply and sees a new
 * file as soon as refractd is rebuilt with it.
 *
 * It is not tools/embed_shaders.c: shaders are NUL-terminated text looked up by the GPU
 * module; these are byte arrays with HTTP metadata looked up by the HTTP module.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const struct {
    const char *extension;
    const char *content_type;
} content_types[] = {
    {".html", "text/html; charset=utf-8"},
    {".js", "text/javascript; charset=utf-8"},
    {".css", "text/css; charset=utf-8"},
    {".svg", "image/svg+xml"},
    {".png", "image/png"},
    {".json", "application/json"},
};

static const char *content_type_of(const char *name)
{
    size_t len = strlen(name);
    for (size_t i = 0; i < sizeof content_types / sizeof content_types[0]; i++) {
        size_t ext = strlen(content_types[i].extension);
        if (len > ext && strcmp(name + len - ext, content_types[i].extension) == 0)
            return content_types[i].content_type;
    }
    return NULL;
}

static const char *base_name(const char *path)
{
    const char *slash = strrchr(path, '/');
    return slash ? slash + 1 : path;
}

/* Names go into C string literals and URLs unescaped: keep them to a safe alphabet. */
static int name_ok(const char *name)
{
    if (name[0] == '\0' || name[0] == '.')
        return 0;
    for (const char *p = name; *p; p++) {
        char c = *p;
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                 c == '.' || c == '_' || c == '-';
        if (!ok)
            return 0;
    }
    return 1;
}

/* Writes the file's bytes as an array; fills its length and hash. Returns 0 on success. */
static int emit_bytes(FILE *out, const char *path, int index, size_t *length, uint64_t *hash)
{
    FILE *in = fopen(path, "rb");
    if (in == NULL) {
        fprintf(stderr, "refract_embed_files: cannot open %s\n", path);
        return 1;
    }
    fprintf(out, "static const unsigned char file_bytes_%d[] = {\n", index);
    uint64_t h = 1469598103934665603ULL; /* FNV-1a 64 offset basis */
    size_t n = 0;
    int c;
    while ((c = fgetc(in)) != EOF) {
        fprintf(out, "%d,", c);
        if (++n % 24 == 0)
            fputc('\n', out);
        h = (h ^ (uint64_t)c) * 1099511628211ULL; /* FNV-1a 64 prime */
    }
    /* A trailing 0 keeps the array non-empty for an empty file; length excludes it. */
    fprintf(out, "0};\n");
    int failed = ferror(in);
    fclose(in);
    if (failed) {
        fprintf(stderr, "refract_embed_files: error reading %s\n", path);
        return 1;
    }
    *length = n;
    *hash = h;
    return 0;
}

static int emit_all(FILE *out, int count, char **paths)
{
    size_t *lengths = calloc((size_t)count + 1, sizeof *lengths);
    uint64_t *hashes = calloc((size_t)count + 1, sizeof *hashes);
    int rc = lengths == NULL || hashes == NULL;
    for (int i = 0; rc == 0 && i < count; i++) {
        const char *name = base_name(paths[i]);
        if (!name_ok(name)) {
            fprintf(stderr, "refract_embed_files: %s: use only A-Z a-z 0-9 . _ - in names\n",
                    paths[i]);
            rc = 1;
        } else if (content_type_of(name) == NULL) {
            fprintf(stderr,
                    "refract_embed_files: %s: unknown extension; add its Content-Type to the "
                    "table in tools/embed_files.c\n",
                    paths[i]);
            rc = 1;
        } else {
            rc = emit_bytes(out, paths[i], i, &lengths[i], &hashes[i]);
        }
    }
    if (rc == 0) {
        fprintf(out, "\nconst struct http_web_file http_web_files[] = {\n");
        for (int i = 0; i < count; i++) {
            const char *name = base_name(paths[i]);
            fprintf(out, "    {\"%s\", file_bytes_%d, %zu, \"%s\", \"\\\"%016llx\\\"\"},\n", name,
                    i, lengths[i], content_type_of(name), (unsigned long long)hashes[i]);
        }
        fprintf(out, "};\nconst size_t http_web_file_count = %d;\n", count);
    }
    free(lengths);
    free(hashes);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: refract_embed_files OUTPUT.c FILE...\n");
        return 2;
    }
    FILE *out = fopen(argv[1], "w");
    if (out == NULL) {
        fprintf(stderr, "refract_embed_files: cannot write %s\n", argv[1]);
        return 1;
    }
    fprintf(out, "/* Generated by tools/embed_files.c from server/web/. Do not edit. */\n");
    fprintf(out, "#include \"http/web_files.h\"\n\n");
    int rc = emit_all(out, argc - 2, argv + 2);
    if (fclose(out) != 0)
        rc = 1;
    if (rc != 0)
        remove(argv[1]);
    return rc;
}
