/*
 * shader_source.c - assembling a compute kernel's GLSL from the embedded files (or a
 * development folder): `#include "x.glsl"` expansion with #line bookkeeping, and the
 * mapping of driver messages back to file names. See shader_source.h.
 *
 * Not a GLSL preprocessor: only whole-line `#include "name"` directives are handled;
 * everything else is left to the driver's preprocessor.
 */
#include "shader_source.h"

#include <stdio.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

struct text_buf {
    char *data;
    size_t len, cap;
};

static bool buf_append(struct text_buf *b, const char *s, size_t n)
{
    if (b->len + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap * 2 : 8192;
        while (cap < b->len + n + 1)
            cap *= 2;
        char *grown = realloc(b->data, cap);
        if (grown == NULL)
            return false;
        b->data = grown;
        b->cap = cap;
    }
    memcpy(b->data + b->len, s, n);
    b->len += n;
    b->data[b->len] = '\0';
    return true;
}

static bool buf_printf(struct text_buf *b, const char *fmt, int a, int c)
{
    char line[64];
    int n = snprintf(line, sizeof line, fmt, a, c);
    return n > 0 && buf_append(b, line, (size_t)n);
}

/* The name a shader file is known by: its path below shaders/ ("geom/mesh.glsl"). A bare
 * name that only a file in a subfolder has ("mesh.glsl") means that file, so both
 * spellings find it and it is included once whichever is used. The embedded table lists
 * every file, so it also maps names for a --shader-dir folder. */
static const char *canonical_name(const char *name)
{
    for (int i = 0; i < gpu_embedded_shader_count; i++) {
        if (strcmp(gpu_embedded_shaders[i].name, name) == 0)
            return gpu_embedded_shaders[i].name;
    }
    if (strchr(name, '/') == NULL) {
        for (int i = 0; i < gpu_embedded_shader_count; i++) {
            const char *base = strrchr(gpu_embedded_shaders[i].name, '/');
            if (base != NULL && strcmp(base + 1, name) == 0)
                return gpu_embedded_shaders[i].name;
        }
    }
    return name;
}

/* Returns the text of `name` (new string the caller frees), or NULL. */
static char *load_text(const char *name, const char *shader_dir)
{
    if (shader_dir == NULL) {
        for (int i = 0; i < gpu_embedded_shader_count; i++) {
            if (strcmp(gpu_embedded_shaders[i].name, name) == 0)
                return strdup(gpu_embedded_shaders[i].text);
        }
        return NULL;
    }
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", shader_dir, name);
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    struct text_buf b = {0};
    char chunk[4096];
    size_t n;
    while ((n = fread(chunk, 1, sizeof chunk, f)) > 0) {
        if (!buf_append(&b, chunk, n)) {
            free(b.data);
            fclose(f);
            return NULL;
        }
    }
    fclose(f);
    if (b.data == NULL)
        b.data = strdup("");
    return b.data;
}

static int find_file(const struct shader_source *s, const char *name)
{
    for (int i = 0; i < s->file_count; i++) {
        if (strcmp(s->file_names[i], name) == 0)
            return i;
    }
    return -1;
}

/* Parses `#include "name"` at the start of line (after spaces); writes name. */
static bool parse_include(const char *line, size_t len, char *name, size_t size)
{
    size_t i = 0;
    while (i < len && (line[i] == ' ' || line[i] == '\t'))
        i++;
    const char *kw = "#include";
    size_t kwlen = strlen(kw);
    if (len - i < kwlen || strncmp(line + i, kw, kwlen) != 0)
        return false;
    i += kwlen;
    while (i < len && (line[i] == ' ' || line[i] == '\t'))
        i++;
    if (i >= len || line[i] != '"')
        return false;
    size_t start = ++i;
    while (i < len && line[i] != '"')
        i++;
    if (i >= len || i - start + 1 > size)
        return false;
    memcpy(name, line + start, i - start);
    name[i - start] = '\0';
    return true;
}

static enum refract_code expand_file(struct shader_source *s, struct text_buf *out,
                                     const char *name, const char *shader_dir,
                                     const char *preamble, int depth, struct err *e);

static enum refract_code expand_text(struct shader_source *s, struct text_buf *out,
                                     const char *text, int file_no, const char *shader_dir,
                                     const char *preamble, int depth, struct err *e)
{
    int line_no = 1;
    const char *p = text;
    while (*p) {
        const char *eol = strchr(p, '\n');
        size_t len = eol ? (size_t)(eol - p) : strlen(p);
        char inc[128];
        bool is_version = depth == 0 && line_no == 1 && strncmp(p, "#version", 8) == 0;
        if (parse_include(p, len, inc, sizeof inc)) {
            const char *name = canonical_name(inc);
            if (find_file(s, name) < 0) {
                enum refract_code rc = expand_file(s, out, name, shader_dir, NULL, depth + 1, e);
                if (rc != REFRACT_E_OK)
                    return rc;
            }
            if (!buf_printf(out, "#line %d %d\n", line_no + 1, file_no))
                return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory expanding shaders");
        } else {
            if (!buf_append(out, p, len) || !buf_append(out, "\n", 1))
                return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory expanding shaders");
            if (is_version) {
                if (preamble && (!buf_append(out, preamble, strlen(preamble)) ||
                                 !buf_append(out, "\n", 1)))
                    return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory");
                if (!buf_printf(out, "#line %d %d\n", 2, file_no))
                    return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory");
            }
        }
        line_no++;
        p = eol ? eol + 1 : p + len;
    }
    return REFRACT_E_OK;
}

static enum refract_code expand_file(struct shader_source *s, struct text_buf *out,
                                     const char *name, const char *shader_dir,
                                     const char *preamble, int depth, struct err *e)
{
    if (depth > 8)
        return err_set(e, REFRACT_E_INTERNAL, "shader includes nest deeper than 8 at %s", name);
    if (s->file_count >= SHADER_SOURCE_MAX_FILES)
        return err_set(e, REFRACT_E_INTERNAL, "more than %d shader files in one program",
                       SHADER_SOURCE_MAX_FILES);
    char *text = load_text(name, shader_dir);
    if (text == NULL)
        return err_set(e, REFRACT_E_INTERNAL, "shader file \"%s\" not found in %s", name,
                       shader_dir ? shader_dir : "the embedded shaders");
    int file_no = s->file_count++;
    s->owned_names[file_no] = strdup(name);
    s->file_names[file_no] = s->owned_names[file_no];
    if (s->owned_names[file_no] == NULL) {
        free(text);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory");
    }
    enum refract_code rc = REFRACT_E_OK;
    if (depth > 0 && !buf_printf(out, "#line %d %d\n", 1, file_no))
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory");
    if (rc == REFRACT_E_OK)
        rc = expand_text(s, out, text, file_no, shader_dir, preamble, depth, e);
    free(text);
    return rc;
}

enum refract_code shader_source_expand(const char *main_name, const char *shader_dir,
                                       const char *preamble, struct shader_source *out,
                                       struct err *e)
{
    memset(out, 0, sizeof *out);
    struct text_buf b = {0};
    enum refract_code rc = expand_file(out, &b, main_name, shader_dir, preamble, 0, e);
    if (rc != REFRACT_E_OK) {
        free(b.data);
        shader_source_fini(out);
        return rc;
    }
    out->text = b.data;
    return REFRACT_E_OK;
}

void shader_source_fini(struct shader_source *s)
{
    free(s->text);
    for (int i = 0; i < s->file_count; i++)
        free(s->owned_names[i]);
    memset(s, 0, sizeof *s);
}

char *shader_source_map_log(const struct shader_source *s, const char *log)
{
    struct text_buf b = {0};
    const char *p = log;
    while (*p) {
        /* Mesa and NVIDIA both start messages with "N:L(C)" or "N(L)". */
        char *end = NULL;
        long file_no = strtol(p, &end, 10);
        bool at_line_start = (p == log) || p[-1] == '\n';
        if (at_line_start && end != p && (*end == ':' || *end == '(') && file_no >= 0 &&
            file_no < s->file_count) {
            buf_append(&b, s->file_names[file_no], strlen(s->file_names[file_no]));
            p = end;
            continue;
        }
        buf_append(&b, p, 1);
        p++;
    }
    if (b.data == NULL)
        b.data = strdup("");
    return b.data;
}
