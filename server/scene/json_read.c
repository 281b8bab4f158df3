/*
 * json_read.c - validated reads out of cJSON trees; see json_read.h for the message
 * forms.
 *
 * Every message starts with the JSON path of what was wrong, then the rule, then what
 * the document gave, so a user can fix the document without reading this code. Values
 * quoted back are escaped (non-printable bytes as \xNN) and shortened, because they
 * come from untrusted input and end up in logs and HTTP bodies.
 *
 * Keys are matched case-sensitively (cJSON_GetObjectItem is case-insensitive, which
 * would let "Radius" pass for "radius"). This file deliberately does not know any
 * schema: callers pass the allowed keys and ranges.
 *
 * Thread: any. cJSON's parser writes a global error position on failure; we never
 * read it (we use return_parse_end), so concurrent parses only race on a value nobody
 * uses.
 */
#include "json_read.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../core/utf8.h"

/* Longest excerpt of a string value or key that a message quotes back. */
#define QUOTE_MAX 48

const char *jr_path(char *buf, size_t size, const char *path, const char *key)
{
    if (path == NULL || path[0] == '\0')
        snprintf(buf, size, "%s", key);
    else
        snprintf(buf, size, "%s.%s", path, key);
    return buf;
}

const char *jr_path_index(char *buf, size_t size, const char *path, int index)
{
    snprintf(buf, size, "%s[%d]", path ? path : "", index);
    return buf;
}

/* The path as a message shows it: the document root has an empty path. */
static const char *shown(const char *path)
{
    return (path == NULL || path[0] == '\0') ? "(root)" : path;
}

/* Writes s (at most n bytes of it) as a double-quoted, shortened literal: a quote and a
 * backslash get a backslash, and what is not printable UTF-8 becomes \xNN through
 * utf8_escape (the one escaping function), so "gr\u00f6\u00dfe" reads as itself and a
 * control character as its byte. At most QUOTE_MAX bytes of s are shown, cut at a
 * character; "..." marks a cut. */
static void quote(char *buf, size_t size, const char *s, size_t n)
{
    if (size < 8)
        return;
    size_t len = strnlen(s, n), show = len < QUOTE_MAX ? len : QUOTE_MAX;
    /* Cut between characters, and leave room for the closing quote, "..." and the NUL. */
    while (show < len && show > 0 && ((unsigned char)s[show] & 0xc0) == 0x80)
        show--;
    size_t room = size - 5;
    size_t o = 0, i = 0;
    buf[o++] = '"';
    while (i < show) {
        if (s[i] == '"' || s[i] == '\\') {
            if (o + 2 > room)
                break;
            buf[o++] = '\\';
            buf[o++] = s[i++];
            continue;
        }
        size_t run = i, used = 0;
        while (run < show && s[run] != '"' && s[run] != '\\')
            run++;
        o += utf8_escape(buf + o, room - o + 1, s + i, run - i, &used);
        i += used;
        if (i < run)
            break; /* the rest does not fit */
    }
    if (i < len) {
        memcpy(buf + o, "...", 3);
        o += 3;
    }
    buf[o++] = '"';
    buf[o] = '\0';
}

/* Shortest text that reads back as the same double (so "got 0.0099999" never shows
 * as "0.01" next to a bound of 0.01). */
static const char *fmt_num(double v, char *buf, size_t size)
{
    if (isnan(v)) {
        snprintf(buf, size, "nan");
    } else if (isinf(v)) {
        snprintf(buf, size, "%s (too large for a double)", v > 0 ? "inf" : "-inf");
    } else {
        snprintf(buf, size, "%.15g", v);
        if (strtod(buf, NULL) != v)
            snprintf(buf, size, "%.17g", v);
    }
    return buf;
}

const char *jr_describe(const cJSON *item, char *buf, size_t size)
{
    if (item == NULL) {
        snprintf(buf, size, "nothing");
    } else if (cJSON_IsNumber(item)) {
        fmt_num(item->valuedouble, buf, size);
    } else if (cJSON_IsString(item)) {
        quote(buf, size, item->valuestring, strlen(item->valuestring));
    } else if (cJSON_IsTrue(item)) {
        snprintf(buf, size, "true");
    } else if (cJSON_IsFalse(item)) {
        snprintf(buf, size, "false");
    } else if (cJSON_IsNull(item)) {
        snprintf(buf, size, "null");
    } else if (cJSON_IsArray(item)) {
        int n = cJSON_GetArraySize(item);
        snprintf(buf, size, "an array of %d value%s", n, n == 1 ? "" : "s");
    } else if (cJSON_IsObject(item)) {
        snprintf(buf, size, "an object");
    } else {
        snprintf(buf, size, "an unreadable value");
    }
    return buf;
}

/* "in 0.01..8", "> 0 and <= 1000000", or "" for the whole finite line. */
static const char *range_text(double min, bool min_exclusive, double max, char *buf, size_t size)
{
    char a[40], b[40];
    if (min <= -DBL_MAX && max >= DBL_MAX)
        buf[0] = '\0';
    else if (min_exclusive)
        snprintf(buf, size, " > %s and <= %s", fmt_num(min, a, sizeof a),
                 fmt_num(max, b, sizeof b));
    else
        snprintf(buf, size, " in %s..%s", fmt_num(min, a, sizeof a), fmt_num(max, b, sizeof b));
    return buf;
}

static const cJSON *get(const cJSON *obj, const char *key)
{
    return cJSON_IsObject(obj) ? cJSON_GetObjectItemCaseSensitive(obj, key) : NULL;
}

static enum refract_code missing(const char *path, const char *key, struct err *e)
{
    return err_set(e, REFRACT_E_MISSING_FIELD, "%s: missing required field \"%s\"", shown(path),
                   key);
}

enum refract_code jr_check_number(const cJSON *item, const char *path, double min,
                                  bool min_exclusive, double max, double *out, struct err *e)
{
    char range[100], got[80];
    range_text(min, min_exclusive, max, range, sizeof range);
    if (!cJSON_IsNumber(item))
        return err_set(e, REFRACT_E_INVALID_FIELD, "%s: expected a finite number%s, got %s",
                       shown(path), range, jr_describe(item, got, sizeof got));
    double v = item->valuedouble;
    bool below = min_exclusive ? !(v > min) : !(v >= min);
    if (!isfinite(v) || below || !(v <= max))
        return err_set(e, REFRACT_E_INVALID_FIELD, "%s: expected a finite number%s, got %s",
                       shown(path), range, jr_describe(item, got, sizeof got));
    *out = v;
    return REFRACT_E_OK;
}

static enum refract_code number_in(const cJSON *obj, const char *path, const char *key,
                                   bool required, double def, double min, bool min_exclusive,
                                   double max, double *out, struct err *e)
{
    const cJSON *item = get(obj, key);
    if (item == NULL) {
        if (required)
            return missing(path, key, e);
        *out = def;
        return REFRACT_E_OK;
    }
    char p[256];
    return jr_check_number(item, jr_path(p, sizeof p, path, key), min, min_exclusive, max, out, e);
}

enum refract_code jr_number(const cJSON *obj, const char *path, const char *key, bool required,
                            double def, double min, double max, double *out, struct err *e)
{
    return number_in(obj, path, key, required, def, min, false, max, out, e);
}

enum refract_code jr_number_gt(const cJSON *obj, const char *path, const char *key, bool required,
                               double def, double min_exclusive, double max, double *out,
                               struct err *e)
{
    return number_in(obj, path, key, required, def, min_exclusive, true, max, out, e);
}

enum refract_code jr_int(const cJSON *obj, const char *path, const char *key, bool required,
                         int def, int min, int max, int *out, struct err *e)
{
    const cJSON *item = get(obj, key);
    if (item == NULL) {
        if (required)
            return missing(path, key, e);
        *out = def;
        return REFRACT_E_OK;
    }
    double v = cJSON_IsNumber(item) ? item->valuedouble : NAN;
    if (!isfinite(v) || v != floor(v) || v < min || v > max) {
        char p[256], got[80];
        return err_set(e, REFRACT_E_INVALID_FIELD, "%s: expected an integer in %d..%d, got %s",
                       jr_path(p, sizeof p, path, key), min, max,
                       jr_describe(item, got, sizeof got));
    }
    *out = (int)v;
    return REFRACT_E_OK;
}

enum refract_code jr_bool(const cJSON *obj, const char *path, const char *key, bool required,
                          bool def, bool *out, struct err *e)
{
    const cJSON *item = get(obj, key);
    if (item == NULL) {
        if (required)
            return missing(path, key, e);
        *out = def;
        return REFRACT_E_OK;
    }
    if (!cJSON_IsBool(item)) {
        char p[256], got[80];
        return err_set(e, REFRACT_E_INVALID_FIELD, "%s: expected true or false, got %s",
                       jr_path(p, sizeof p, path, key), jr_describe(item, got, sizeof got));
    }
    *out = cJSON_IsTrue(item);
    return REFRACT_E_OK;
}

enum refract_code jr_string(const cJSON *obj, const char *path, const char *key, bool required,
                            const char *def, size_t max_len, char *out, size_t size, struct err *e)
{
    if (size == 0)
        return err_set(e, REFRACT_E_INTERNAL, "jr_string: no room for \"%s\"", key);
    if (max_len >= size)
        max_len = size - 1;
    const cJSON *item = get(obj, key);
    if (item == NULL) {
        if (required)
            return missing(path, key, e);
        snprintf(out, size, "%s", def ? def : "");
        return REFRACT_E_OK;
    }
    char p[256], got[80];
    if (!cJSON_IsString(item))
        return err_set(e, REFRACT_E_INVALID_FIELD, "%s: expected a string of 1..%zu bytes, got %s",
                       jr_path(p, sizeof p, path, key), max_len,
                       jr_describe(item, got, sizeof got));
    size_t n = strlen(item->valuestring);
    if (n == 0 || n > max_len)
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected a string of 1..%zu bytes, got %zu bytes",
                       jr_path(p, sizeof p, path, key), max_len, n);
    for (size_t i = 0; i < n; i++)
        if ((unsigned char)item->valuestring[i] < 0x20)
            return err_set(e, REFRACT_E_INVALID_FIELD,
                           "%s: control characters (U+0000..U+001F) are not allowed, found one "
                           "at character %zu",
                           jr_path(p, sizeof p, path, key), i);
    memcpy(out, item->valuestring, n + 1);
    return REFRACT_E_OK;
}

enum refract_code jr_renamed(const cJSON *obj, const char *path, const char *key,
                             const char *old_key, const char **use, struct err *e)
{
    bool now = get(obj, key) != NULL, before = get(obj, old_key) != NULL;
    *use = before && !now ? old_key : key;
    if (now && before) {
        char p[256];
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: \"%s\" is the old name of \"%s\"; give only \"%s\"",
                       jr_path(p, sizeof p, path, old_key), old_key, key, key);
    }
    return REFRACT_E_OK;
}

enum refract_code jr_enum(const cJSON *obj, const char *path, const char *key, bool required,
                          int def, const char *const *names, int *out, struct err *e)
{
    const cJSON *item = get(obj, key);
    if (item == NULL) {
        if (required)
            return missing(path, key, e);
        *out = def;
        return REFRACT_E_OK;
    }
    if (cJSON_IsString(item)) {
        for (int i = 0; names[i] != NULL; i++) {
            if (strcmp(item->valuestring, names[i]) == 0) {
                *out = i;
                return REFRACT_E_OK;
            }
        }
    }
    char list[256] = "", p[256], got[80];
    size_t o = 0;
    for (int i = 0; names[i] != NULL && o < sizeof list; i++)
        o += (size_t)snprintf(list + o, sizeof list - o, "%s\"%s\"", i ? ", " : "", names[i]);
    return err_set(e, REFRACT_E_INVALID_FIELD, "%s: expected one of %s, got %s",
                   jr_path(p, sizeof p, path, key), list, jr_describe(item, got, sizeof got));
}

/* Reads an array of exactly 3 numbers, each checked by jr_check_number. */
static enum refract_code triple(const cJSON *item, const char *path, double min, double max,
                                double v[3], struct err *e)
{
    if (!cJSON_IsArray(item) || cJSON_GetArraySize(item) != 3) {
        char range[100], got[80];
        range_text(min, false, max, range, sizeof range);
        return err_set(e, REFRACT_E_INVALID_FIELD, "%s: expected an array of 3 numbers%s, got %s",
                       path, range, jr_describe(item, got, sizeof got));
    }
    for (int i = 0; i < 3; i++) {
        char p[256];
        enum refract_code rc =
            jr_check_number(cJSON_GetArrayItem(item, i), jr_path_index(p, sizeof p, path, i), min,
                            false, max, &v[i], e);
        if (rc != REFRACT_E_OK)
            return rc;
    }
    return REFRACT_E_OK;
}

enum refract_code jr_vec3(const cJSON *obj, const char *path, const char *key, bool required,
                          vec3 def, double min, double max, vec3 *out, struct err *e)
{
    const cJSON *item = get(obj, key);
    if (item == NULL) {
        if (required)
            return missing(path, key, e);
        *out = def;
        return REFRACT_E_OK;
    }
    char p[256];
    double v[3];
    enum refract_code rc = triple(item, jr_path(p, sizeof p, path, key), min, max, v, e);
    if (rc == REFRACT_E_OK)
        *out = vec3_make(v[0], v[1], v[2]);
    return rc;
}

enum refract_code jr_direction(const cJSON *obj, const char *path, const char *key, bool required,
                               vec3 def, vec3 *out, struct err *e)
{
    const cJSON *item = get(obj, key);
    if (item == NULL) {
        if (required)
            return missing(path, key, e);
        *out = vec3_normalize(def);
        return REFRACT_E_OK;
    }
    char p[256];
    double v[3];
    jr_path(p, sizeof p, path, key);
    enum refract_code rc = triple(item, p, -DBL_MAX, DBL_MAX, v, e);
    if (rc != REFRACT_E_OK)
        return rc;
    /* Scale by the largest component first so that huge components cannot overflow. */
    double m = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
    vec3 d = m > 0.0 ? vec3_make(v[0] / m, v[1] / m, v[2] / m) : vec3_make(0, 0, 0);
    if (m * vec3_length(d) <= 1e-12) {
        char a[40], b[40], c[40];
        return err_set(e, REFRACT_E_INVALID_FIELD,
                       "%s: expected a non-zero direction (length > 1e-12), got [%s, %s, %s]", p,
                       fmt_num(v[0], a, sizeof a), fmt_num(v[1], b, sizeof b),
                       fmt_num(v[2], c, sizeof c));
    }
    *out = vec3_normalize(d);
    return REFRACT_E_OK;
}

static bool is_allowed(const char *key, const char *const *allowed)
{
    for (int i = 0; allowed[i] != NULL; i++) {
        if (strcmp(key, allowed[i]) == 0)
            return true;
    }
    return false;
}

enum refract_code jr_check_object(const cJSON *obj, const char *path, const char *const *allowed,
                                  struct err *e)
{
    char got[80];
    if (!cJSON_IsObject(obj))
        return err_set(e, REFRACT_E_INVALID_FIELD, "%s: expected an object, got %s", shown(path),
                       jr_describe(obj, got, sizeof got));
    for (const cJSON *c = obj->child; c != NULL; c = c->next) {
        const char *key = c->string ? c->string : "";
        if (!is_allowed(key, allowed)) {
            char list[400] = "", k[QUOTE_MAX * 4 + 8];
            size_t o = 0;
            for (int i = 0; allowed[i] != NULL && o < sizeof list; i++)
                o += (size_t)snprintf(list + o, sizeof list - o, "%s%s", i ? ", " : "", allowed[i]);
            quote(k, sizeof k, key, strlen(key));
            return err_set(e, REFRACT_E_UNKNOWN_FIELD, "%s: unknown field %s; allowed: %s",
                           shown(path), k, list);
        }
        /* Every earlier sibling is an allowed key seen once, so this scan is bounded by
         * the allowed list's length, not by the object's size. */
        for (const cJSON *d = obj->child; d != c; d = d->next) {
            if (d->string != NULL && strcmp(d->string, key) == 0) {
                char p[256];
                return err_set(e, REFRACT_E_INVALID_FIELD,
                               "%s: duplicate field; each field may appear only once",
                               jr_path(p, sizeof p, path, key));
            }
        }
    }
    return REFRACT_E_OK;
}

/* ---- parsing a whole document ---- */

static bool is_json_space(char c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

/* 1-based line and column (in bytes) of byte offset off. */
static void line_col(const char *text, size_t off, size_t *line, size_t *col)
{
    size_t l = 1, start = 0;
    for (size_t i = 0; i < off; i++) {
        if (text[i] == '\n') {
            l++;
            start = i + 1;
        }
    }
    *line = l;
    *col = off - start + 1;
}

/* The byte offset where bracket nesting first exceeds CJSON_NESTING_LIMIT, or len when
 * it never does. Used only to explain a failed parse. */
static size_t too_deep_at(const char *text, size_t len)
{
    size_t depth = 0;
    bool in_string = false;
    for (size_t i = 0; i < len; i++) {
        char c = text[i];
        if (in_string) {
            if (c == '\\')
                i++;
            else if (c == '"')
                in_string = false;
        } else if (c == '"') {
            in_string = true;
        } else if (c == '[' || c == '{') {
            if (++depth > CJSON_NESTING_LIMIT)
                return i;
        } else if ((c == ']' || c == '}') && depth > 0) {
            depth--;
        }
    }
    return len;
}

static enum refract_code syntax_error(const char *text, size_t len, size_t off, const char *what,
                                      struct err *e)
{
    size_t line, col;
    line_col(text, off, &line, &col);
    char near[QUOTE_MAX * 4 + 8];
    quote(near, sizeof near, text + off, len - off < 24 ? len - off : 24);
    return err_set(e, REFRACT_E_INVALID_JSON,
                   "invalid JSON at byte %zu (line %zu, column %zu): %s, near %s", off, line, col,
                   what, near);
}

/* One pass over the strings of a document, before cJSON sees it:
 *  - a raw control character inside a string is not JSON (RFC 8259 sect. 7) and a raw
 *    NUL would end the C string early: returns its offset as an error;
 *  - the escape \u0000 is valid JSON but cJSON decodes it into a C string that silently
 *    ends there ("a\u0000b" would become "a"). *nul_escapes counts them, and when
 *    `rewrite` (a same-length copy of text, or NULL) is given they become \u001f there,
 *    so the value keeps its length and jr_string rejects it as a control character by
 *    name.
 * Returns len when the strings are clean. */
static size_t scan_strings(const char *text, size_t len, size_t *nul_escapes, char *rewrite)
{
    bool in_string = false;
    *nul_escapes = 0;
    for (size_t i = 0; i < len; i++) {
        unsigned char c = (unsigned char)text[i];
        if (!in_string) {
            in_string = c == '"';
        } else if (c < 0x20) {
            return i;
        } else if (c == '"') {
            in_string = false;
        } else if (c == '\\' && i + 1 < len) {
            if (text[i + 1] == 'u' && i + 5 < len && memcmp(text + i + 2, "0000", 4) == 0) {
                (*nul_escapes)++;
                if (rewrite != NULL)
                    memcpy(rewrite + i + 2, "001f", 4);
            }
            i++;
        }
    }
    return len;
}

static enum refract_code parse_clean(const char *text, size_t len, cJSON **out, struct err *e);

enum refract_code jr_parse(const char *text, size_t len, cJSON **out, struct err *e)
{
    *out = NULL;
    if (text == NULL)
        return parse_clean(text, len, out, e);
    /* JSON text is UTF-8 (RFC 8259 sect. 8.1). cJSON copies other bytes into strings
     * unchecked; stored in a scene name they would make every later listing invalid JSON. */
    size_t invalid = utf8_invalid_at(text, len);
    if (invalid < len) {
        char what[160];
        snprintf(what, sizeof what,
                 "byte 0x%02x is not valid UTF-8 (JSON text must be UTF-8; non-ASCII "
                 "characters may also be sent as \\u escapes)",
                 (unsigned char)text[invalid]);
        return syntax_error(text, len, invalid, what, e);
    }
    size_t nul_escapes = 0, bad = scan_strings(text, len, &nul_escapes, NULL);
    if (bad < len) {
        char what[96];
        snprintf(what, sizeof what,
                 "raw control character 0x%02x inside a string (escape it, e.g. \\u%04x)",
                 (unsigned char)text[bad], (unsigned char)text[bad]);
        return syntax_error(text, len, bad, what, e);
    }
    if (nul_escapes == 0)
        return parse_clean(text, len, out, e);
    char *copy = malloc(len);
    if (copy == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory parsing JSON");
    memcpy(copy, text, len);
    scan_strings(text, len, &nul_escapes, copy);
    enum refract_code rc = parse_clean(copy, len, out, e);
    free(copy);
    return rc;
}

static enum refract_code parse_clean(const char *text, size_t len, cJSON **out, struct err *e)
{
    *out = NULL;
    size_t first = 0;
    while (text != NULL && first < len && is_json_space(text[first]))
        first++;
    if (text == NULL || first == len)
        return err_set(e, REFRACT_E_INVALID_JSON,
                       "invalid JSON: the body is empty; expected a JSON document");
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    if (root == NULL) {
        size_t deep = too_deep_at(text, len);
        if (deep < len)
            return syntax_error(text, len, deep, "nesting deeper than 1000 levels", e);
        size_t off = (end != NULL && end >= text && end <= text + len) ? (size_t)(end - text) : 0;
        const char *what =
            off + 1 >= len ? "syntax error (the document may be truncated)" : "syntax error";
        return syntax_error(text, len, off, what, e);
    }
    size_t off = (size_t)(end - text);
    while (off < len && is_json_space(text[off]))
        off++;
    if (off < len) {
        cJSON_Delete(root);
        return syntax_error(text, len, off, "unexpected text after the JSON document", e);
    }
    *out = root;
    return REFRACT_E_OK;
}
