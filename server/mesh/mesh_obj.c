/*
 * mesh_obj.c - the Wavefront OBJ reader: geometry only.
 *
 * Read: "v x y z [w]" (w and any further numbers, such as vertex colours, are ignored)
 * and "f i i i ..." whose references are i, i/t, i//n or i/t/n; an index is 1-based,
 * or negative to count back from the last vertex defined so far. A polygon of k vertices
 * becomes the k - 2 triangles of a fan about its first vertex (exact for convex planar
 * polygons, which is what exporters write). Ignored: comments (#), texture coordinates
 * and normals (vt, vn, vp), grouping and materials (o, g, s, usemtl, mtllib), and the
 * non-surface elements l and p. Anything else is an error that names the line: a
 * statement we would silently drop could be geometry the user expects to see.
 *
 * Not supported: free-form geometry (curv, surf, ...), line continuations with '\'.
 * The text need not be NUL-terminated; a NUL byte is an error (binary data).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"

struct obj_reader {
    const char *s;
    size_t len, pos;
    size_t line; /* 1-based number of the current line */
    struct mesh_builder b;
};

static bool blank(char c)
{
    return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v';
}

/* The next token of the current line into [*tok, *tok + *n); false at the line's end. */
static bool next_token(struct obj_reader *r, size_t end, const char **tok, size_t *n)
{
    while (r->pos < end && blank(r->s[r->pos]))
        r->pos++;
    if (r->pos >= end || r->s[r->pos] == '#')
        return false;
    size_t start = r->pos;
    while (r->pos < end && !blank(r->s[r->pos]))
        r->pos++;
    *tok = r->s + start;
    *n = r->pos - start;
    return true;
}

/* Copies a token into a NUL-terminated buffer for strtod/strtoll; false when too long. */
static bool token_copy(const char *tok, size_t n, char *buf, size_t size)
{
    if (n + 1 > size)
        return false;
    memcpy(buf, tok, n);
    buf[n] = '\0';
    return true;
}

static enum refract_code read_vertex(struct obj_reader *r, size_t end, struct err *e)
{
    double xyz[3];
    int got = 0;
    const char *tok;
    size_t n;
    while (next_token(r, end, &tok, &n)) {
        char buf[64], *stop = NULL;
        if (!token_copy(tok, n, buf, sizeof buf))
            return err_set(e, REFRACT_E_INVALID_MESH,
                           "line %zu: a vertex value of %zu characters is not a number; write "
                           "\"v x y z\" with decimal numbers",
                           r->line, n);
        double v = strtod(buf, &stop);
        if (stop == buf || *stop != '\0')
            return err_set(e, REFRACT_E_INVALID_MESH,
                           "line %zu: vertex value %d \"%s\" is not a number; write \"v x y "
                           "z\" with decimal numbers",
                           r->line, got + 1, buf);
        if (got < 3 && !isfinite(v))
            return err_set(e, REFRACT_E_INVALID_MESH,
                           "line %zu: vertex coordinate %c is \"%s\", not a finite number; "
                           "every coordinate must be finite",
                           r->line, "xyz"[got], buf);
        if (got < 3)
            xyz[got] = v;
        got++;
    }
    if (got < 3)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "line %zu: a vertex needs 3 coordinates \"v x y z\", got %d", r->line, got);
    if (!mesh_builder_vertex(&r->b, xyz[0], xyz[1], xyz[2]))
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "line %zu: out of memory for %zu vertices",
                       r->line, r->b.nv + 1);
    return REFRACT_E_OK;
}

/* Resolves one face reference ("7", "7/1", "7//3", "-1/2/3") to a 0-based index. */
static enum refract_code face_index(struct obj_reader *r, const char *tok, size_t n, int corner,
                                    uint32_t *out, struct err *e)
{
    size_t vlen = 0;
    while (vlen < n && tok[vlen] != '/')
        vlen++;
    char buf[32], *stop = NULL;
    if (vlen == 0 || !token_copy(tok, vlen, buf, sizeof buf))
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "line %zu: face vertex %d \"%.*s\" is not a vertex index; write \"f i j "
                       "k\" with 1-based (or negative) indices, optionally i/t/n",
                       r->line, corner + 1, (int)(n < 40 ? n : 40), tok);
    errno = 0;
    long long i = strtoll(buf, &stop, 10);
    if (stop == buf || *stop != '\0' || errno != 0)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "line %zu: face vertex %d \"%s\" is not an integer index", r->line,
                       corner + 1, buf);
    long long count = (long long)r->b.nv;
    if (i == 0)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "line %zu: face vertex %d has index 0; OBJ indices start at 1 (or count "
                       "back from -1)",
                       r->line, corner + 1);
    long long resolved = i > 0 ? i - 1 : count + i;
    if (resolved < 0 || resolved >= count)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "line %zu: face vertex %d refers to vertex %lld, but only %lld vertices "
                       "are defined before this line; indices must be 1..%lld or -1..-%lld",
                       r->line, corner + 1, i, count, count, count);
    *out = (uint32_t)resolved;
    return REFRACT_E_OK;
}

static enum refract_code read_face(struct obj_reader *r, size_t end, struct err *e)
{
    uint32_t first = 0, prev = 0;
    int k = 0;
    const char *tok;
    size_t n;
    while (next_token(r, end, &tok, &n)) {
        uint32_t cur = 0;
        enum refract_code rc = face_index(r, tok, n, k, &cur, e);
        if (rc != REFRACT_E_OK)
            return rc;
        if (k == 0)
            first = cur;
        if (k >= 2) {
            char where[48];
            snprintf(where, sizeof where, "line %zu", r->line);
            if (mesh_builder_full(&r->b))
                return mesh_limit_error(&r->b, where, e);
            if (!mesh_builder_triangle(&r->b, first, prev, cur))
                return err_set(e, REFRACT_E_OUT_OF_MEMORY, "%s: out of memory for %zu triangles",
                               where, r->b.nt + 1);
        }
        prev = cur;
        k++;
    }
    if (k < 3)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "line %zu: a face needs at least 3 vertices, got %d", r->line, k);
    return REFRACT_E_OK;
}

static bool word_is(const char *tok, size_t n, const char *w)
{
    return n == strlen(w) && memcmp(tok, w, n) == 0;
}

static enum refract_code read_line(struct obj_reader *r, size_t end, struct err *e)
{
    static const char *const ignored[] = {"vt",     "vn",     "vp", "o", "g", "s",
                                          "usemtl", "mtllib", "l",  "p", NULL};
    const char *tok;
    size_t n;
    if (!next_token(r, end, &tok, &n))
        return REFRACT_E_OK;
    if (word_is(tok, n, "v"))
        return read_vertex(r, end, e);
    if (word_is(tok, n, "f"))
        return read_face(r, end, e);
    for (const char *const *w = ignored; *w; w++) {
        if (word_is(tok, n, *w))
            return REFRACT_E_OK;
    }
    return err_set(e, REFRACT_E_INVALID_MESH,
                   "line %zu: unknown statement \"%.*s\"; a mesh OBJ holds v and f (vt, vn, "
                   "vp, o, g, s, usemtl, mtllib, l, p and # comments are ignored)",
                   r->line, (int)(n < 40 ? n : 40), tok);
}

enum refract_code mesh_parse_obj(const char *text, size_t len, const struct mesh_limits *limits,
                                 struct mesh **out, struct err *e)
{
    *out = NULL;
    struct obj_reader r = {.s = text, .len = len, .line = 1};
    mesh_builder_init(&r.b, limits);
    const char *nul = len > 0 ? memchr(text, '\0', len) : NULL;
    enum refract_code rc = REFRACT_E_OK;
    if (nul != NULL) {
        size_t line = 1;
        for (const char *c = text; c < nul; c++)
            line += *c == '\n';
        rc = err_set(e, REFRACT_E_INVALID_MESH,
                     "line %zu: the file contains a NUL byte (binary data?); an OBJ file is "
                     "text: send binary meshes as PLY",
                     line);
    }
    while (rc == REFRACT_E_OK && r.pos < len) {
        const char *nl = memchr(text + r.pos, '\n', len - r.pos);
        size_t end = nl ? (size_t)(nl - text) : len;
        rc = read_line(&r, end, e);
        r.pos = end + 1;
        r.line++;
    }
    if (rc != REFRACT_E_OK) {
        mesh_builder_fini(&r.b);
        return rc;
    }
    if (r.b.nt == 0) {
        rc = err_set(e, REFRACT_E_INVALID_MESH,
                     "the OBJ file has %zu vertices and no faces; add \"f i j k\" lines (a mesh "
                     "needs at least one triangle)",
                     r.b.nv);
        mesh_builder_fini(&r.b);
        return rc;
    }
    return mesh_builder_finish(&r.b, limits, out, e);
}
