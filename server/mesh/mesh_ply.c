/*
 * mesh_ply.c - the Stanford PLY reader: ascii, binary_little_endian and
 * binary_big_endian, version 1.0.
 *
 * Read: the "vertex" element's x, y, z (any scalar type; float and double in practice)
 * and the "face" element's list "vertex_indices" (or "vertex_index") with an integer count
 * type (uchar, int, ...) and an integer index type. Every other property and element
 * (normals, colours, edges, materials) is read past by its declared type and dropped.
 * Faces of k vertices become k - 2 triangles fanned about the first.
 *
 * The header is a promise about the bytes that follow, and hostile or broken files lie:
 * before an element is read, its declared count is checked against the bytes left (each
 * record needs at least the sum of its properties' smallest sizes), so a header that
 * claims 4 billion vertices fails at once instead of allocating; a file that ends early
 * names the element and record it ended in; bytes left over after the last declared
 * element are an error too (the counts were wrong). Errors name the header line or the
 * element and record number (0-based, as PLY tools count), what was wrong and what to do.
 *
 * Not here: obj_info, comment and any header content besides format/element/property are
 * ignored (comment and obj_info) or rejected (anything else).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"

#define PLY_MAX_ELEMENTS 16
#define PLY_MAX_PROPS 32
#define PLY_NAME_MAX 32

enum ply_type {
    PLY_NONE = 0,
    PLY_I8,
    PLY_U8,
    PLY_I16,
    PLY_U16,
    PLY_I32,
    PLY_U32,
    PLY_F32,
    PLY_F64
};
enum ply_encoding { PLY_ASCII, PLY_BINARY_LE, PLY_BINARY_BE };
enum ply_role { ROLE_OTHER, ROLE_VERTEX, ROLE_FACE };

static const struct {
    const char *name;
    enum ply_type type;
} type_names[] = {
    {"char", PLY_I8},   {"int8", PLY_I8},     {"uchar", PLY_U8},   {"uint8", PLY_U8},
    {"short", PLY_I16}, {"int16", PLY_I16},   {"ushort", PLY_U16}, {"uint16", PLY_U16},
    {"int", PLY_I32},   {"int32", PLY_I32},   {"uint", PLY_U32},   {"uint32", PLY_U32},
    {"float", PLY_F32}, {"float32", PLY_F32}, {"double", PLY_F64}, {"float64", PLY_F64},
};

static const size_t type_size[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};

struct ply_prop {
    char name[PLY_NAME_MAX];
    enum ply_type type;       /* scalar type, or the list's index type */
    enum ply_type count_type; /* PLY_NONE for scalars */
};

struct ply_element {
    char name[PLY_NAME_MAX];
    unsigned long long count;
    struct ply_prop props[PLY_MAX_PROPS];
    int prop_count;
    enum ply_role role;
    int xyz[3];  /* vertex: property index of x, y, z */
    int indices; /* face: property index of the index list */
};

struct ply_file {
    enum ply_encoding enc;
    struct ply_element el[PLY_MAX_ELEMENTS];
    int el_count;
    const struct ply_element *vertex, *face;
    const unsigned char *body; /* after end_header */
    size_t body_len, pos;
    size_t line; /* ascii: current line number in the file */
};

static bool is_int_type(enum ply_type t)
{
    return t >= PLY_I8 && t <= PLY_U32;
}

static enum ply_type parse_type(const char *s)
{
    for (size_t i = 0; i < sizeof type_names / sizeof type_names[0]; i++) {
        if (strcmp(type_names[i].name, s) == 0)
            return type_names[i].type;
    }
    return PLY_NONE;
}

/* ---- header ---- */

struct header_line {
    char text[256];
    char *word[8];
    int words;
};

/* Splits a header line (without its end) into words. */
static bool split_line(const char *s, size_t n, struct header_line *h)
{
    if (n >= sizeof h->text)
        return false;
    memcpy(h->text, s, n);
    h->text[n] = '\0';
    if (n > 0 && h->text[n - 1] == '\r')
        h->text[n - 1] = '\0';
    h->words = 0;
    char *save = NULL;
    for (char *w = strtok_r(h->text, " \t", &save); w && h->words < 8;
         w = strtok_r(NULL, " \t", &save))
        h->word[h->words++] = w;
    return true;
}

static enum refract_code header_element(struct ply_file *f, const struct header_line *h,
                                        size_t line, struct err *e)
{
    if (h->words != 3)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "header line %zu: expected \"element NAME COUNT\"", line);
    if (f->el_count == PLY_MAX_ELEMENTS)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "header line %zu: more than %d elements; a mesh needs vertex and face", line,
                       PLY_MAX_ELEMENTS);
    char *stop = NULL;
    errno = 0;
    unsigned long long count = strtoull(h->word[2], &stop, 10);
    if (stop == h->word[2] || *stop != '\0' || errno != 0 || h->word[2][0] == '-')
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "header line %zu: element count \"%s\" is not a non-negative integer", line,
                       h->word[2]);
    struct ply_element *el = &f->el[f->el_count++];
    memset(el, 0, sizeof *el);
    snprintf(el->name, sizeof el->name, "%s", h->word[1]);
    el->count = count;
    el->xyz[0] = el->xyz[1] = el->xyz[2] = -1;
    el->indices = -1;
    if (strcmp(el->name, "vertex") == 0 || strcmp(el->name, "face") == 0) {
        bool vertex = el->name[0] == 'v';
        if ((vertex && f->vertex) || (!vertex && f->face))
            return err_set(e, REFRACT_E_INVALID_MESH,
                           "header line %zu: a second \"%s\" element; declare it once", line,
                           el->name);
        el->role = vertex ? ROLE_VERTEX : ROLE_FACE;
        if (vertex)
            f->vertex = el;
        else
            f->face = el;
    }
    return REFRACT_E_OK;
}

static enum refract_code header_property(struct ply_file *f, const struct header_line *h,
                                         size_t line, struct err *e)
{
    if (f->el_count == 0)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "header line %zu: a property before any element; write \"element NAME "
                       "COUNT\" first",
                       line);
    struct ply_element *el = &f->el[f->el_count - 1];
    if (el->prop_count == PLY_MAX_PROPS)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "header line %zu: element \"%s\" has more than %d properties", line,
                       el->name, PLY_MAX_PROPS);
    bool list = h->words >= 2 && strcmp(h->word[1], "list") == 0;
    if ((list && h->words != 5) || (!list && h->words != 3))
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "header line %zu: expected \"property TYPE NAME\" or \"property list "
                       "COUNT_TYPE INDEX_TYPE NAME\"",
                       line);
    struct ply_prop *p = &el->props[el->prop_count];
    p->type = parse_type(h->word[list ? 3 : 1]);
    p->count_type = list ? parse_type(h->word[2]) : PLY_NONE;
    snprintf(p->name, sizeof p->name, "%s", h->word[list ? 4 : 2]);
    if (p->type == PLY_NONE || (list && p->count_type == PLY_NONE))
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "header line %zu: unknown type \"%s\"; PLY types are char uchar short "
                       "ushort int uint float double (or int8 ... float64)",
                       line, p->type == PLY_NONE ? h->word[list ? 3 : 1] : h->word[2]);
    if (list && !is_int_type(p->count_type))
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "header line %zu: list count type \"%s\" must be an integer type (uchar, "
                       "int, ...)",
                       line, h->word[2]);
    int idx = el->prop_count++;
    if (el->role == ROLE_VERTEX && !list) {
        for (int a = 0; a < 3; a++) {
            if (strcmp(p->name, (const char *[]){"x", "y", "z"}[a]) == 0)
                el->xyz[a] = idx;
        }
    }
    if (el->role == ROLE_FACE && list &&
        (strcmp(p->name, "vertex_indices") == 0 || strcmp(p->name, "vertex_index") == 0)) {
        if (!is_int_type(p->type))
            return err_set(e, REFRACT_E_INVALID_MESH,
                           "header line %zu: face indices of type \"%s\" must be an integer "
                           "type (int or uint)",
                           line, h->word[3]);
        el->indices = idx;
    }
    return REFRACT_E_OK;
}

static enum refract_code header_format(struct ply_file *f, const struct header_line *h, size_t line,
                                       struct err *e)
{
    if (h->words != 3 || strcmp(h->word[2], "1.0") != 0)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "header line %zu: expected \"format ascii|binary_little_endian|"
                       "binary_big_endian 1.0\"",
                       line);
    if (strcmp(h->word[1], "ascii") == 0)
        f->enc = PLY_ASCII;
    else if (strcmp(h->word[1], "binary_little_endian") == 0)
        f->enc = PLY_BINARY_LE;
    else if (strcmp(h->word[1], "binary_big_endian") == 0)
        f->enc = PLY_BINARY_BE;
    else
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "header line %zu: unknown format \"%s\"; use ascii, binary_little_endian "
                       "or binary_big_endian",
                       line, h->word[1]);
    return REFRACT_E_OK;
}

/* What the mesh needs of the header once it is read completely. */
static enum refract_code header_check(const struct ply_file *f, const struct mesh_limits *lim,
                                      struct err *e)
{
    if (f->vertex == NULL)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "the header declares no \"vertex\" element; a mesh PLY needs \"element "
                       "vertex N\" with properties x, y, z");
    for (int a = 0; a < 3; a++) {
        if (f->vertex->xyz[a] < 0)
            return err_set(e, REFRACT_E_INVALID_MESH,
                           "the \"vertex\" element has no property %c; declare \"property "
                           "float %c\"",
                           "xyz"[a], "xyz"[a]);
    }
    if (f->face == NULL || f->face->count == 0)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "the header declares %s; a mesh needs at least one face (\"element face "
                       "N\", N >= 1)",
                       f->face ? "0 faces" : "no \"face\" element");
    if (f->face->indices < 0)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "the \"face\" element has no list property vertex_indices; declare "
                       "\"property list uchar int vertex_indices\"");
    size_t max_t = lim && lim->max_triangles ? lim->max_triangles : MESH_DEFAULT_MAX_TRIANGLES;
    if (f->face->count > max_t)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "the header declares %llu faces, more than the limit max_mesh_triangles "
                       "= %zu; simplify the mesh or start refractd with --max-mesh-triangles to "
                       "raise it",
                       f->face->count, max_t);
    if (f->vertex->count > UINT32_MAX)
        return err_set(e, REFRACT_E_LIMIT_EXCEEDED,
                       "the header declares %llu vertices; at most 4294967295 can be indexed",
                       f->vertex->count);
    return REFRACT_E_OK;
}

static enum refract_code read_header(struct ply_file *f, const unsigned char *bytes, size_t len,
                                     const struct mesh_limits *lim, struct err *e)
{
    const char *s = (const char *)bytes;
    size_t pos = 0, line = 0;
    bool have_format = false;
    while (pos < len) {
        const char *nl = memchr(s + pos, '\n', len - pos);
        if (nl == NULL)
            break;
        size_t n = (size_t)(nl - (s + pos));
        line++;
        struct header_line h;
        if (!split_line(s + pos, n, &h))
            return err_set(e, REFRACT_E_INVALID_MESH,
                           "header line %zu: longer than 255 characters; is this a PLY header?",
                           line);
        pos += n + 1;
        enum refract_code rc = REFRACT_E_OK;
        const char *w = h.words ? h.word[0] : "";
        if (line == 1) {
            if (strcmp(w, "ply") != 0 || h.words != 1)
                return err_set(e, REFRACT_E_INVALID_MESH,
                               "header line 1: a PLY file starts with the line \"ply\"");
        } else if (strcmp(w, "format") == 0) {
            rc = header_format(f, &h, line, e);
            have_format = true;
        } else if (strcmp(w, "element") == 0) {
            rc = header_element(f, &h, line, e);
        } else if (strcmp(w, "property") == 0) {
            rc = header_property(f, &h, line, e);
        } else if (strcmp(w, "end_header") == 0) {
            if (!have_format)
                return err_set(e, REFRACT_E_INVALID_MESH,
                               "the header has no \"format\" line; add \"format ascii 1.0\" "
                               "(or binary_little_endian / binary_big_endian) after \"ply\"");
            f->body = bytes + pos;
            f->body_len = len - pos;
            f->line = line + 1;
            return header_check(f, lim, e);
        } else if (strcmp(w, "comment") != 0 && strcmp(w, "obj_info") != 0 && h.words > 0) {
            return err_set(e, REFRACT_E_INVALID_MESH,
                           "header line %zu: unknown keyword \"%.40s\"; a PLY header has "
                           "format, element, property, comment, obj_info and end_header",
                           line, w);
        }
        if (rc != REFRACT_E_OK)
            return rc;
    }
    return err_set(e, REFRACT_E_INVALID_MESH,
                   "the header has no \"end_header\" line (after %zu lines); the file is "
                   "truncated or not PLY",
                   line);
}

/* ---- values ---- */

/* Reads one binary value of type t; false when the body ends. */
static bool binary_value(struct ply_file *f, enum ply_type t, double *out)
{
    size_t n = type_size[t];
    if (f->body_len - f->pos < n)
        return false;
    const unsigned char *p = f->body + f->pos;
    uint64_t u = 0;
    for (size_t i = 0; i < n; i++) {
        size_t k = f->enc == PLY_BINARY_LE ? n - 1 - i : i;
        u = (u << 8) | p[k];
    }
    f->pos += n;
    switch (t) {
    case PLY_I8:
        *out = (int8_t)u;
        break;
    case PLY_U8:
        *out = (uint8_t)u;
        break;
    case PLY_I16:
        *out = (int16_t)u;
        break;
    case PLY_U16:
        *out = (uint16_t)u;
        break;
    case PLY_I32:
        *out = (int32_t)(uint32_t)u;
        break;
    case PLY_U32:
        *out = (uint32_t)u;
        break;
    case PLY_F32: {
        uint32_t w = (uint32_t)u;
        float fl;
        memcpy(&fl, &w, 4);
        *out = fl;
        break;
    }
    case PLY_F64:
        memcpy(out, &u, 8);
        break;
    case PLY_NONE:
        return false;
    }
    return true;
}

/* ascii: the record's line, split into tokens as it is consumed. */
struct ascii_cursor {
    const char *s;
    size_t end;
};

static bool ascii_value(struct ply_file *f, struct ascii_cursor *c, double *out, bool *garbage)
{
    const char *s = (const char *)f->body;
    *garbage = false;
    while (f->pos < c->end && (s[f->pos] == ' ' || s[f->pos] == '\t' || s[f->pos] == '\r'))
        f->pos++;
    if (f->pos >= c->end)
        return false;
    size_t start = f->pos;
    while (f->pos < c->end && s[f->pos] != ' ' && s[f->pos] != '\t' && s[f->pos] != '\r')
        f->pos++;
    char buf[64], *stop = NULL;
    size_t n = f->pos - start;
    *garbage = true;
    if (n >= sizeof buf)
        return false;
    memcpy(buf, s + start, n);
    buf[n] = '\0';
    *out = strtod(buf, &stop);
    if (stop == buf || *stop != '\0')
        return false;
    *garbage = false;
    return true;
}

/* Advances to the next non-empty line of an ascii body; false at the end. */
static bool ascii_next_line(struct ply_file *f, struct ascii_cursor *c)
{
    const char *s = (const char *)f->body;
    for (;;) {
        if (f->pos >= f->body_len)
            return false;
        const char *nl = memchr(s + f->pos, '\n', f->body_len - f->pos);
        c->end = nl ? (size_t)(nl - s) : f->body_len;
        size_t p = f->pos;
        while (p < c->end && (s[p] == ' ' || s[p] == '\t' || s[p] == '\r'))
            p++;
        if (p < c->end)
            return true;
        f->pos = c->end + 1;
        f->line++;
    }
}

/* ---- body ---- */

struct record_ctx {
    struct ply_file *f;
    const struct ply_element *el;
    unsigned long long index;
    struct ascii_cursor cur;
    struct mesh_builder *b;
    struct err *e;
};

static enum refract_code ended(const struct record_ctx *r, const char *what)
{
    if (r->f->enc == PLY_ASCII)
        return err_set(r->e, REFRACT_E_INVALID_MESH,
                       "line %zu (%s %llu of %llu): %s; each record is one line of its "
                       "properties' values, as the header declares them",
                       r->f->line, r->el->name, r->index, r->el->count, what);
    return err_set(r->e, REFRACT_E_INVALID_MESH,
                   "%s %llu of %llu: the file ends at byte %zu of the body; it is truncated or "
                   "its header's element counts are wrong",
                   r->el->name, r->index, r->el->count, r->f->body_len);
}

static bool value(struct record_ctx *r, enum ply_type t, double *out, bool *garbage)
{
    *garbage = false;
    if (r->f->enc == PLY_ASCII)
        return ascii_value(r->f, &r->cur, out, garbage);
    return binary_value(r->f, t, out);
}

static enum refract_code check_integer(const struct record_ctx *r, double v, const char *what)
{
    if (v != floor(v) || !isfinite(v))
        return err_set(r->e, REFRACT_E_INVALID_MESH, "%s %llu: %s %g is not an integer",
                       r->el->name, r->index, what, v);
    return REFRACT_E_OK;
}

static enum refract_code face_list(struct record_ctx *r, const struct ply_prop *p, double count)
{
    enum refract_code rc = check_integer(r, count, "the vertex count");
    if (rc != REFRACT_E_OK)
        return rc;
    if (count < 3)
        return err_set(r->e, REFRACT_E_INVALID_MESH,
                       "face %llu has %g vertices; a face needs at least 3", r->index, count);
    /* Every index takes at least one byte, so a count past the body's size is a lie; it is
     * refused before it becomes the loop's bound (an ascii count is not limited to the
     * list's count type, and 3e40 would overflow the conversion to long long). */
    if (count > (double)r->f->body_len)
        return err_set(r->e, REFRACT_E_INVALID_MESH,
                       "face %llu has %g vertices, more than the %zu bytes after the header "
                       "can hold; the face's vertex count is wrong",
                       r->index, count, r->f->body_len);
    uint32_t first = 0, prev = 0;
    unsigned long long nv = r->f->vertex->count;
    for (long long k = 0; k < (long long)count; k++) {
        double v;
        bool garbage;
        if (!value(r, p->type, &v, &garbage))
            return ended(r, garbage ? "a vertex index is not a number"
                                    : "fewer vertex indices than the face's count");
        rc = check_integer(r, v, "vertex index");
        if (rc != REFRACT_E_OK)
            return rc;
        if (v < 0 || v >= (double)nv)
            return err_set(r->e, REFRACT_E_INVALID_MESH,
                           "face %llu: vertex index %.0f is out of range; the header declares "
                           "%llu vertices (indices 0..%llu)",
                           r->index, v, nv, nv ? nv - 1 : 0);
        uint32_t cur = (uint32_t)v;
        if (k == 0)
            first = cur;
        if (k >= 2) {
            char where[48];
            snprintf(where, sizeof where, "face %llu", r->index);
            if (mesh_builder_full(r->b))
                return mesh_limit_error(r->b, where, r->e);
            if (!mesh_builder_triangle(r->b, first, prev, cur))
                return err_set(r->e, REFRACT_E_OUT_OF_MEMORY, "%s: out of memory", where);
        }
        prev = cur;
    }
    return REFRACT_E_OK;
}

static enum refract_code read_record(struct record_ctx *r)
{
    const struct ply_element *el = r->el;
    double xyz[3] = {0, 0, 0};
    if (r->f->enc == PLY_ASCII && !ascii_next_line(r->f, &r->cur))
        return ended(r, "the file ends before this record; it is truncated or the header's "
                        "element counts are wrong");
    for (int i = 0; i < el->prop_count; i++) {
        const struct ply_prop *p = &el->props[i];
        double v;
        bool garbage;
        if (!value(r, p->count_type ? p->count_type : p->type, &v, &garbage))
            return ended(r, garbage ? "a value is not a number" : "fewer values than declared");
        if (p->count_type != PLY_NONE) {
            enum refract_code rc;
            if (el->role == ROLE_FACE && i == el->indices) {
                rc = face_list(r, p, v);
            } else {
                rc = check_integer(r, v, "a list count");
                /* As for a face: a count past the body's size (or below zero) is a lie,
                 * refused before it becomes the loop's bound ((long long)3e40 is undefined). */
                if (rc == REFRACT_E_OK && (v < 0 || v > (double)r->f->body_len))
                    rc = err_set(r->e, REFRACT_E_INVALID_MESH,
                                 "%s %llu: a list count of %g is %s; the list's count is wrong",
                                 el->name, r->index, v,
                                 v < 0 ? "negative"
                                       : "more than the bytes after the header can hold");
                for (long long k = 0; rc == REFRACT_E_OK && k < (long long)v; k++) {
                    double skip;
                    if (!value(r, p->type, &skip, &garbage))
                        rc = ended(r, "fewer list values than the list's count");
                }
            }
            if (rc != REFRACT_E_OK)
                return rc;
            continue;
        }
        for (int a = 0; a < 3; a++) {
            if (el->role == ROLE_VERTEX && i == el->xyz[a]) {
                if (!isfinite(v))
                    return err_set(r->e, REFRACT_E_INVALID_MESH,
                                   "vertex %llu: coordinate %c is %g, not a finite number; every "
                                   "coordinate must be finite",
                                   r->index, "xyz"[a], v);
                xyz[a] = v;
            }
        }
    }
    if (r->f->enc == PLY_ASCII) {
        double extra;
        bool garbage;
        if (ascii_value(r->f, &r->cur, &extra, &garbage) || garbage)
            return ended(r, "more values than the element's properties declare");
        r->f->pos = r->cur.end + 1;
        r->f->line++;
    }
    if (el->role == ROLE_VERTEX && !mesh_builder_vertex(r->b, xyz[0], xyz[1], xyz[2]))
        return err_set(r->e, REFRACT_E_OUT_OF_MEMORY, "vertex %llu: out of memory", r->index);
    return REFRACT_E_OK;
}

/* Smallest size in bytes (binary) or characters (ascii: a digit and a separator per value)
 * of one record: a header whose count times this exceeds what is left is lying. */
static size_t min_record_bytes(const struct ply_file *f, const struct ply_element *el)
{
    size_t n = 0;
    for (int i = 0; i < el->prop_count; i++) {
        const struct ply_prop *p = &el->props[i];
        n += f->enc == PLY_ASCII ? 2 : type_size[p->count_type ? p->count_type : p->type];
    }
    return n ? n : 1;
}

static enum refract_code read_body(struct ply_file *f, struct mesh_builder *b, struct err *e)
{
    for (int k = 0; k < f->el_count; k++) {
        const struct ply_element *el = &f->el[k];
        size_t left = f->body_len - f->pos, need = min_record_bytes(f, el);
        if (el->count > left / need)
            return err_set(e, REFRACT_E_INVALID_MESH,
                           "the header declares %llu \"%s\" records of at least %zu bytes each, "
                           "but only %zu bytes follow; the header's counts are wrong or the "
                           "file is truncated",
                           el->count, el->name, need, left);
        struct record_ctx r = {.f = f, .el = el, .b = b, .e = e};
        for (r.index = 0; r.index < el->count; r.index++) {
            enum refract_code rc = read_record(&r);
            if (rc != REFRACT_E_OK)
                return rc;
        }
    }
    if (f->enc != PLY_ASCII && f->pos != f->body_len)
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "%zu bytes follow the last element the header declares; the header's "
                       "element counts are wrong (or the file has trailing data)",
                       f->body_len - f->pos);
    struct ascii_cursor c;
    if (f->enc == PLY_ASCII && ascii_next_line(f, &c))
        return err_set(e, REFRACT_E_INVALID_MESH,
                       "line %zu: data after the last element the header declares; the header's "
                       "element counts are wrong",
                       f->line);
    return REFRACT_E_OK;
}

enum refract_code mesh_parse_ply(const void *bytes, size_t len, const struct mesh_limits *limits,
                                 struct mesh **out, struct err *e)
{
    *out = NULL;
    struct ply_file *f = calloc(1, sizeof *f);
    if (f == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory reading a PLY header");
    struct mesh_builder b;
    mesh_builder_init(&b, limits);
    enum refract_code rc = read_header(f, bytes, len, limits, e);
    if (rc == REFRACT_E_OK)
        rc = read_body(f, &b, e);
    free(f);
    if (rc != REFRACT_E_OK) {
        mesh_builder_fini(&b);
        return rc;
    }
    return mesh_builder_finish(&b, limits, out, e);
}
