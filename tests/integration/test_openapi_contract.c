/*
 * test_openapi_contract.c - proto/openapi.yaml is the contract of API v1; this checks it
 * against the code and against a real refractd:
 *   - the documented (method, path) pairs equal the route table (http_routes()), and
 *     every operation has a unique operationId;
 *   - a real refractd answers every documented pair (not 404 not_found, not 405), answers
 *     404 not_found on undocumented paths and 405 method_not_allowed, listing exactly the
 *     documented methods, on a wrong method;
 *   - every request example is one line of JSON that refractd accepts: scene examples
 *     give 201, render examples 200 with the Content-Type and magic bytes of their format,
 *     trace examples 200 with one documented status per ray sent; the volume upload's
 *     `dims` example uploads;
 *   - components/schemas/ErrorCode lists exactly the codes of proto/refract_errors.h, and
 *     its table gives each code's number and HTTP status as the header does.
 *
 * The YAML is read by a small line reader that knows only the layout openapi.yaml keeps
 * (its header comment states it): paths 2 spaces under `paths:`, methods 4, operation
 * keys 6; block scalars (`|`, `>`) are text. It is not a YAML parser and does not try to
 * be one: a file that leaves this layout fails the test rather than being misread.
 */
#include <cjson/cJSON.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "daemon.h"
#include "http/http.h"
#include "refract_errors.h"
#include "test.h"

#define MAX_LINES 8192
#define MAX_OPS 64
#define MAX_EXAMPLES 16
#define MAX_ENUMS 32
#define MAX_ENUM_VALUES 64
#define MAX_ROWS 64

/* Like CHECK_MSG, but usable as a condition: returns cond. */
#define CHECK_OK(cond, ...) check_ok((cond), __FILE__, __LINE__, #cond, __VA_ARGS__)

__attribute__((format(printf, 5, 6))) static bool check_ok(bool cond, const char *file, int line,
                                                           const char *what, const char *fmt, ...)
{
    if (cond) {
        test_passed_count++;
        return true;
    }
    test_failed_count++;
    fprintf(stderr, "%s:%d: CHECK failed: %s: ", file, line, what);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    return false;
}

/* ---- the line reader ------------------------------------------------------------------ */

struct yline {
    int no;     /* 1-based line number, for messages */
    int indent; /* leading spaces */
    char *text; /* after the indentation, trailing space removed; points into the file */
    bool block; /* inside a block scalar (text, not structure) */
};

struct example {
    const char *name;
    const char *json; /* the one-line value; NULL when the example had none */
    int line;
};

struct operation {
    char method[8]; /* upper case */
    const char *path;
    int line;
    const char *operation_id;
    bool json_body; /* requestBody has application/json content */
    struct example examples[MAX_EXAMPLES];
    int example_count;
    const char *dims_example; /* the `dims` query parameter's example, if any */
};

struct yenum {
    const char *schema; /* components/schemas/<schema> */
    const char *values[MAX_ENUM_VALUES];
    int count;
};

struct contract {
    char *text; /* owned: the file, cut into lines in place */
    struct yline lines[MAX_LINES];
    int line_count;
    struct operation ops[MAX_OPS];
    int op_count;
    struct yenum enums[MAX_ENUMS];
    int enum_count;
    const char *error_rows[MAX_ROWS]; /* "| `code` | ..." rows of ErrorCode's description */
    int error_row_count;
};

static const char *const http_methods[] = {"get",  "put",     "post",  "delete", "patch",
                                           "head", "options", "trace", NULL};

static bool is_block_start(const char *value)
{
    return value && (value[0] == '|' || value[0] == '>');
}

/* Removes one pair of matching quotes around s, in place. Returns the start. */
static char *unquote(char *s)
{
    size_t len = strlen(s);
    if (len >= 2 && (s[0] == '\'' || s[0] == '"') && s[len - 1] == s[0]) {
        s[len - 1] = '\0';
        return s + 1;
    }
    return s;
}

/* Splits "key: value" or "key:" in place. Returns the key (unquoted) and sets *value to
 * the rest ("" when none), or returns NULL when the text is not a mapping key. */
static char *split_key(char *text, char **value)
{
    char *colon = strchr(text, ':');
    while (colon != NULL && colon[1] != '\0' && colon[1] != ' ')
        colon = strchr(colon + 1, ':');
    if (colon == NULL || colon == text)
        return NULL;
    *colon = '\0';
    *value = colon[1] ? colon + 2 : colon + 1;
    return unquote(text);
}

/* Cuts c->text into lines, dropping blank and comment lines outside block scalars. */
static void cut_lines(struct contract *c)
{
    int block_indent = -1; /* indent of the key that opened a block scalar */
    char *p = c->text;
    for (int no = 1; *p; no++) {
        char *end = strchr(p, '\n');
        char *next = end ? end + 1 : p + strlen(p);
        if (end)
            *end = '\0';
        int indent = 0;
        while (p[indent] == ' ')
            indent++;
        char *text = p + indent;
        size_t len = strlen(text);
        while (len > 0 && (text[len - 1] == ' ' || text[len - 1] == '\r'))
            text[--len] = '\0';
        bool in_block = block_indent >= 0 && (len == 0 || indent > block_indent);
        if (!in_block)
            block_indent = -1;
        if ((len > 0 && (in_block || text[0] != '#')) && c->line_count < MAX_LINES) {
            c->lines[c->line_count++] = (struct yline){no, indent, text, in_block};
            const char *colon = in_block ? NULL : strstr(text, ": ");
            if (colon && is_block_start(colon + 2))
                block_indent = indent;
        }
        p = next;
    }
    CHECK_MSG(c->line_count < MAX_LINES, "openapi.yaml has more than %d lines", MAX_LINES);
}

/* ---- reading `paths:` ----------------------------------------------------------------- */

struct path_state {
    const char *path;
    struct operation *op;
    const char *section; /* operation key at indent 6: requestBody, parameters, ... */
    bool json_media;     /* inside requestBody.content.application/json */
    int examples_indent; /* indent of `examples:` under application/json, or -1 */
    bool param_is_dims;  /* inside the `- name: dims` parameter */
};

static void start_operation(struct contract *c, struct path_state *st, const char *method, int line)
{
    st->op = NULL;
    if (!CHECK_OK(c->op_count < MAX_OPS, "more than %d operations", MAX_OPS))
        return;
    struct operation *op = &c->ops[c->op_count++];
    memset(op, 0, sizeof *op);
    for (size_t i = 0; method[i] && i + 1 < sizeof op->method; i++)
        op->method[i] = (char)(method[i] - 'a' + 'A');
    op->path = st->path;
    op->line = line;
    st->op = op;
}

/* A line inside requestBody (indent > 6). */
static void request_body_line(const struct yline *l, struct path_state *st, char *key,
                              const char *value)
{
    struct operation *op = st->op;
    if (l->indent == 10)
        st->json_media = strcmp(key, "application/json") == 0;
    if (st->json_media && l->indent == 10)
        op->json_body = true;
    if (!st->json_media)
        return;
    if (l->indent == 12 && strcmp(key, "examples") == 0) {
        st->examples_indent = l->indent;
        return;
    }
    if (st->examples_indent < 0 || l->indent <= st->examples_indent) {
        st->examples_indent = -1;
        return;
    }
    if (l->indent == st->examples_indent + 2 &&
        CHECK_OK(op->example_count < MAX_EXAMPLES, "line %d: too many examples", l->no))
        op->examples[op->example_count++] = (struct example){key, NULL, l->no};
    else if (l->indent == st->examples_indent + 4 && strcmp(key, "value") == 0 &&
             op->example_count > 0)
        op->examples[op->example_count - 1].json = value;
}

static void operation_line(struct yline *l, struct path_state *st, char *key, char *value)
{
    struct operation *op = st->op;
    if (l->indent == 6) {
        st->section = key;
        st->json_media = false;
        st->examples_indent = -1;
        st->param_is_dims = false;
        if (strcmp(key, "operationId") == 0)
            op->operation_id = value;
        return;
    }
    if (strcmp(st->section, "requestBody") == 0)
        request_body_line(l, st, key, value);
    if (strcmp(st->section, "parameters") == 0) {
        if (strcmp(key, "- name") == 0)
            st->param_is_dims = strcmp(unquote(value), "dims") == 0;
        else if (st->param_is_dims && strcmp(key, "example") == 0)
            op->dims_example = unquote(value);
    }
}

static void paths_line(struct contract *c, struct yline *l, struct path_state *st)
{
    char *value = NULL;
    char *key = split_key(l->text, &value);
    if (key == NULL)
        return; /* list items without a key ("- $ref" has one), flow text */
    if (l->indent == 2) {
        CHECK_MSG(key[0] == '/', "openapi.yaml:%d: path \"%s\" does not start with /", l->no, key);
        st->path = key;
        st->op = NULL;
    } else if (l->indent == 4) {
        st->op = NULL;
        for (int i = 0; http_methods[i]; i++) {
            if (strcmp(key, http_methods[i]) == 0)
                start_operation(c, st, key, l->no);
        }
    } else if (l->indent > 4 && st->op) {
        operation_line(l, st, key, value);
    }
}

/* ---- reading `components:` ------------------------------------------------------------ */

static void enum_values(struct contract *c, const char *schema, char *flow)
{
    if (!CHECK_OK(c->enum_count < MAX_ENUMS, "more than %d enums", MAX_ENUMS))
        return;
    struct yenum *e = &c->enums[c->enum_count++];
    e->schema = schema;
    e->count = 0;
    if (flow == NULL || flow[0] != '[')
        return; /* a block list follows */
    char *save = NULL;
    for (char *tok = strtok_r(flow + 1, ",]", &save); tok; tok = strtok_r(NULL, ",]", &save)) {
        while (*tok == ' ')
            tok++;
        if (*tok && e->count < MAX_ENUM_VALUES)
            e->values[e->count++] = unquote(tok);
    }
}

static void components_line(struct contract *c, struct yline *l, const char **section,
                            const char **schema, int *enum_indent)
{
    if (l->block) {
        if (*schema && strcmp(*schema, "ErrorCode") == 0 && strncmp(l->text, "| `", 3) == 0 &&
            c->error_row_count < MAX_ROWS)
            c->error_rows[c->error_row_count++] = l->text;
        return;
    }
    if (*enum_indent >= 0 && l->indent > *enum_indent && strncmp(l->text, "- ", 2) == 0) {
        struct yenum *e = &c->enums[c->enum_count - 1];
        if (e->count < MAX_ENUM_VALUES)
            e->values[e->count++] = unquote(l->text + 2);
        return;
    }
    *enum_indent = -1;
    char *value = NULL;
    char *key = split_key(l->text, &value);
    if (key == NULL)
        return;
    if (l->indent == 2)
        *section = key;
    if (l->indent == 4)
        *schema = strcmp(*section, "schemas") == 0 ? key : NULL;
    if (l->indent == 6 && *schema && strcmp(key, "enum") == 0) {
        enum_values(c, *schema, value);
        *enum_indent = l->indent;
    }
}

/* Reads proto/openapi.yaml into c. Returns false when the file cannot be read. */
static bool contract_read(struct contract *c)
{
    memset(c, 0, sizeof *c);
    c->text = test_read_source_file("proto/openapi.yaml", NULL);
    if (!CHECK_OK(c->text != NULL, "cannot read proto/openapi.yaml under $REFRACT_SOURCE_DIR"))
        return false;
    cut_lines(c);
    const char *top = "";
    struct path_state st = {.examples_indent = -1};
    const char *section = "", *schema = NULL;
    int enum_indent = -1;
    for (int i = 0; i < c->line_count; i++) {
        struct yline *l = &c->lines[i];
        if (l->indent == 0 && !l->block) {
            char *value = NULL;
            char *key = split_key(l->text, &value);
            top = key ? key : "";
            continue;
        }
        if (strcmp(top, "paths") == 0 && !l->block)
            paths_line(c, l, &st);
        else if (strcmp(top, "components") == 0)
            components_line(c, l, &section, &schema, &enum_indent);
    }
    return true;
}

static const struct yenum *contract_enum(const struct contract *c, const char *schema)
{
    for (int i = 0; i < c->enum_count; i++) {
        if (strcmp(c->enums[i].schema, schema) == 0)
            return &c->enums[i];
    }
    return NULL;
}

static const struct operation *contract_op(const struct contract *c, const char *method,
                                           const char *path)
{
    for (int i = 0; i < c->op_count; i++) {
        if (strcasecmp(c->ops[i].method, method) == 0 && strcmp(c->ops[i].path, path) == 0)
            return &c->ops[i];
    }
    return NULL;
}

/* ---- (a) the documented routes are the served routes ---------------------------------- */

static bool route_served(const struct http_route_info *routes, size_t n, const char *method,
                         const char *path)
{
    for (size_t i = 0; i < n; i++) {
        if (strcmp(routes[i].method, method) == 0 && strcmp(routes[i].pattern, path) == 0)
            return true;
    }
    return false;
}

static void documented_routes_equal_the_route_table(const struct contract *c)
{
    const struct http_route_info *routes = NULL;
    size_t n = http_routes(&routes);
    CHECK(n > 0);
    for (size_t i = 0; i < n; i++)
        CHECK_MSG(contract_op(c, routes[i].method, routes[i].pattern) != NULL,
                  "%s %s is served (server/http/routes.c) but missing from proto/openapi.yaml",
                  routes[i].method, routes[i].pattern);
    for (int i = 0; i < c->op_count; i++) {
        const struct operation *op = &c->ops[i];
        CHECK_MSG(route_served(routes, n, op->method, op->path),
                  "%s %s (openapi.yaml:%d) is documented but refractd has no such route",
                  op->method, op->path, op->line);
    }
    CHECK_MSG((size_t)c->op_count == n,
              "openapi.yaml documents %d operations, refractd serves "
              "%zu (a path or method documented twice?)",
              c->op_count, n);
}

static void every_operation_has_a_unique_operation_id(const struct contract *c)
{
    for (int i = 0; i < c->op_count; i++) {
        const struct operation *op = &c->ops[i];
        if (!CHECK_OK(op->operation_id && op->operation_id[0],
                      "%s %s (openapi.yaml:%d) has no "
                      "operationId",
                      op->method, op->path, op->line))
            continue;
        for (int j = 0; j < i; j++) {
            CHECK_MSG(c->ops[j].operation_id == NULL ||
                          strcmp(c->ops[j].operation_id, op->operation_id) != 0,
                      "operationId %s is used by %s %s and %s %s", op->operation_id,
                      c->ops[j].method, c->ops[j].path, op->method, op->path);
        }
    }
}

/* ---- (d) ErrorCode is proto/refract_errors.h ------------------------------------------ */

struct code_row {
    const char *json;
    int number;
    int http_status; /* 0: client only */
};

static const struct code_row code_rows[] = {
#define ROW(name, num, http, json, text) {json, num, http},
    REFRACT_ERROR_TABLE(ROW)
#undef ROW
};
#define CODE_ROW_COUNT (int)(sizeof code_rows / sizeof code_rows[0])

static bool enum_has(const struct yenum *e, const char *value)
{
    for (int i = 0; e && i < e->count; i++) {
        if (strcmp(e->values[i], value) == 0)
            return true;
    }
    return false;
}

/* True when ErrorCode's description has the row "| `json` | number | status |". */
static bool table_has_row(const struct contract *c, const struct code_row *row)
{
    char prefix[128], status[16];
    if (row->http_status)
        snprintf(status, sizeof status, "%d", row->http_status);
    else
        snprintf(status, sizeof status, "none");
    snprintf(prefix, sizeof prefix, "| `%s` | %d | %s |", row->json, row->number, status);
    for (int i = 0; i < c->error_row_count; i++) {
        if (strncmp(c->error_rows[i], prefix, strlen(prefix)) == 0)
            return true;
    }
    fprintf(stderr, "ErrorCode's table lacks the row \"%s ...\"\n", prefix);
    return false;
}

static void error_codes_equal_refract_errors_h(const struct contract *c)
{
    const struct yenum *e = contract_enum(c, "ErrorCode");
    if (!CHECK_OK(e != NULL, "components/schemas/ErrorCode has no enum"))
        return;
    for (int i = 0; i < CODE_ROW_COUNT; i++) {
        CHECK_MSG(enum_has(e, code_rows[i].json),
                  "code %s (%d) of proto/refract_errors.h is "
                  "missing from ErrorCode's enum",
                  code_rows[i].json, code_rows[i].number);
        CHECK(table_has_row(c, &code_rows[i]));
    }
    for (int i = 0; i < e->count; i++) {
        bool known = false;
        for (int j = 0; j < CODE_ROW_COUNT; j++)
            known |= strcmp(code_rows[j].json, e->values[i]) == 0;
        CHECK_MSG(known,
                  "ErrorCode's enum lists \"%s\", which proto/refract_errors.h does not "
                  "define",
                  e->values[i]);
    }
    CHECK_INT(e->count, CODE_ROW_COUNT);
    CHECK_INT(c->error_row_count, CODE_ROW_COUNT);
}

/* ---- examples: one line of JSON each -------------------------------------------------- */

/* The example as a cJSON tree (caller deletes), or NULL after failing the test. */
static cJSON *example_json(const struct operation *op, const struct example *ex)
{
    const char *text = ex->json ? ex->json : "";
    const char *end = NULL;
    /* The length includes the NUL, so text after the JSON (a second line's start, a
     * comment) is an error. */
    cJSON *root = cJSON_ParseWithLengthOpts(text, strlen(text) + 1, &end, true);
    CHECK_MSG(root != NULL,
              "openapi.yaml:%d: example \"%s\" of %s %s: `value:` is not one line "
              "of valid JSON (near byte %td of \"%s\")",
              ex->line, ex->name, op->method, op->path, end ? end - text : (ptrdiff_t)0, text);
    return root;
}

static void request_examples_are_present(const struct contract *c)
{
    for (int i = 0; i < c->op_count; i++) {
        const struct operation *op = &c->ops[i];
        int want = 0;
        if (op->json_body)
            want = 1;
        if (strcmp(op->path, "/v1/scenes/{id}/render") == 0 ||
            strcmp(op->path, "/v1/scenes/{id}/trace") == 0)
            want = 2;
        CHECK_MSG(op->example_count >= want,
                  "%s %s (openapi.yaml:%d) has %d request examples "
                  "under requestBody.content.application/json.examples; give at least %d",
                  op->method, op->path, op->line, op->example_count, want);
        for (int k = 0; k < op->example_count; k++)
            cJSON_Delete(example_json(op, &op->examples[k]));
    }
    const struct operation *put = contract_op(c, "PUT", "/v1/scenes/{id}/volumes/{name}");
    CHECK_MSG(put && put->dims_example, "the dims query parameter of PUT "
                                        "/v1/scenes/{id}/volumes/{name} has no `example:`");
}

/* ---- (b) and (c): a real refractd ------------------------------------------------------ */

#define VOLUME_NAME "density"
#define LIGHT_NAME "sun"
#define ASSET_NAME "viewer.js" /* the {file} of GET /assets/{file} */

/* A small glass sphere whose default view is 64x48, so renders take milliseconds; its one
 * light is the {light} of the irradiance routes (it needs no light simulation, so those
 * answer without computing anything). */
static const char *const test_scene =
    "{\"name\": \"contract\", \"camera\": {\"eye\": [0, 1, 3.7], \"width\": 64, \"height\": 48}, "
    "\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 32, "
    "\"ior\": {\"shape\": \"sphere\", \"radius\": 0.8, \"inside\": 1.5}}], "
    "\"lights\": [{\"name\": \"sun\", \"type\": \"directional\", \"direction\": [0, -1, 0]}]}";

/* The {vid} of the view routes: a session on the test scene, and one of its own for
 * DELETE (main opens both). */
static char view_id[32], scratch_view_id[32];

/* Writes tmpl with {id}, {name}, {light}, {vid} and {file} filled in. False (test failed) for
 * another parameter. */
static bool fill_path_view(const char *tmpl, const char *id, const char *fill_vid, char *out,
                           size_t size)
{
    size_t used = 0;
    out[0] = '\0';
    for (const char *p = tmpl; *p;) {
        const char *piece = p;
        size_t len = 1;
        if (strncmp(p, "{id}", 4) == 0) {
            piece = id;
            len = strlen(id);
            p += 4;
        } else if (strncmp(p, "{name}", 6) == 0) {
            piece = VOLUME_NAME;
            len = strlen(VOLUME_NAME);
            p += 6;
        } else if (strncmp(p, "{light}", 7) == 0) {
            piece = LIGHT_NAME;
            len = strlen(LIGHT_NAME);
            p += 7;
        } else if (strncmp(p, "{file}", 6) == 0) {
            piece = ASSET_NAME;
            len = strlen(ASSET_NAME);
            p += 6;
        } else if (strncmp(p, "{vid}", 5) == 0) {
            piece = fill_vid;
            len = strlen(fill_vid);
            p += 5;
        } else if (*p == '{') {
            CHECK_MSG(false, "path %s: unknown parameter at \"%s\"", tmpl, p);
            return false;
        } else {
            p++;
        }
        if (used + len >= size) {
            CHECK_MSG(false, "path %s too long", tmpl);
            return false;
        }
        memcpy(out + used, piece, len);
        used += len;
        out[used] = '\0';
    }
    return true;
}

static bool fill_path(const char *tmpl, const char *id, char *out, size_t size)
{
    return fill_path_view(tmpl, id, view_id, out, size);
}

/* One exchange; returns the HTTP status, or -1 (test failed) when none came. */
static long exchange(struct test_daemon *d, const char *method, const char *path, const void *body,
                     size_t len, const char *content_type, struct refract_response *r)
{
    memset(r, 0, sizeof *r);
    int rc = refract_request(d->client, method, path, body, len, content_type, r);
    if (!CHECK_OK(rc == REFRACT_E_OK, "%s %s: no answer: %s", method, path,
                  refract_errmsg(d->client)))
        return -1;
    return r->status;
}

static void documented_routes_are_answered(struct test_daemon *d, const struct contract *c,
                                           const char *scene, const char *scratch)
{
    for (int i = 0; i < c->op_count; i++) {
        const struct operation *op = &c->ops[i];
        char path[256];
        /* DELETE takes a scene of its own so the others keep theirs. */
        bool del = strcmp(op->method, "DELETE") == 0;
        if (!fill_path_view(op->path, del ? scratch : scene, del ? scratch_view_id : view_id, path,
                            sizeof path))
            continue;
        /* A frame stream runs until its session ends: ask for one frame. */
        size_t vlen = strlen(path);
        if (vlen >= 7 && strcmp(path + vlen - 7, "/stream") == 0)
            snprintf(path + vlen, sizeof path - vlen, "?frames=1");
        /* An event stream never ends by itself: a resume point that is not a number
         * makes it answer (400) at once instead. */
        size_t plen = strlen(path);
        if (plen >= 7 && strcmp(path + plen - 7, "/events") == 0)
            snprintf(path + plen, sizeof path - plen, "?since=x");
        struct refract_response r;
        long status = exchange(d, op->method, path, NULL, 0, NULL, &r);
        CHECK_MSG(status > 0 && status != 404 && status != 405, "documented %s %s answered %ld: %s",
                  op->method, path, status, r.body ? r.body : "");
        refract_response_free(&r);
    }
}

/* The "allowed: GET, DELETE" list of a 405 message names exactly the documented methods. */
static void check_allowed_list(const struct contract *c, const char *tmpl, const char *body)
{
    const char *allowed = body ? strstr(body, "allowed: ") : NULL;
    if (!CHECK_OK(allowed != NULL, "405 on %s does not list the allowed methods: %s", tmpl,
                  body ? body : ""))
        return;
    int documented = 0, listed = 1;
    for (const char *p = allowed; *p && *p != '"'; p++)
        listed += *p == ',';
    for (int i = 0; i < c->op_count; i++) {
        if (strcmp(c->ops[i].path, tmpl) != 0)
            continue;
        documented++;
        CHECK_MSG(strstr(allowed, c->ops[i].method) != NULL,
                  "405 on %s does not list documented method %s: %s", tmpl, c->ops[i].method, body);
    }
    CHECK_MSG(listed == documented, "405 on %s lists %d methods, openapi.yaml documents %d: %s",
              tmpl, listed, documented, body);
}

static void wrong_method_gives_405(struct test_daemon *d, const struct contract *c,
                                   const char *scene)
{
    static const char *const candidates[] = {"GET", "POST", "PUT", "DELETE", "PATCH", NULL};
    for (int i = 0; i < c->op_count; i++) {
        const char *tmpl = c->ops[i].path;
        bool seen = false;
        for (int j = 0; j < i; j++)
            seen |= strcmp(c->ops[j].path, tmpl) == 0;
        if (seen)
            continue; /* each path once */
        const char *wrong = NULL;
        for (int k = 0; candidates[k] && wrong == NULL; k++) {
            if (contract_op(c, candidates[k], tmpl) == NULL)
                wrong = candidates[k];
        }
        char path[256];
        if (wrong == NULL || !fill_path(tmpl, scene, path, sizeof path))
            continue;
        struct refract_response r;
        long status = exchange(d, wrong, path, NULL, 0, NULL, &r);
        CHECK_MSG(status == 405, "%s %s: expected 405, got %ld: %s", wrong, path, status,
                  r.body ? r.body : "");
        CHECK(test_error_is(r.body, "method_not_allowed", wrong));
        check_allowed_list(c, tmpl, r.body);
        refract_response_free(&r);
    }
}

static void undocumented_paths_give_404(struct test_daemon *d, const char *scene)
{
    static const char *const paths[] = {"/index.html",
                                        "/viewer",
                                        "/viewer/{id}/x",
                                        "/assets/nope.js",
                                        "/assets/index.html",
                                        "/v1",
                                        "/v1/nope",
                                        "/v2/health",
                                        "/v1/health/x",
                                        "/v1/scenes/{id}/nope",
                                        "/v1/scenes/{id}/volumes",
                                        NULL};
    for (int i = 0; paths[i]; i++) {
        char path[256];
        if (!fill_path(paths[i], scene, path, sizeof path))
            continue;
        struct refract_response r;
        long status = exchange(d, "GET", path, NULL, 0, NULL, &r);
        CHECK_MSG(status == 404, "GET %s: expected 404, got %ld", path, status);
        CHECK(test_error_is(r.body, "not_found", path));
        refract_response_free(&r);
    }
}

static bool is_path(const struct operation *op, const char *method, const char *path)
{
    return strcmp(op->method, method) == 0 && strcmp(op->path, path) == 0;
}

/* A scene example gives 201 with an id, and the scene is then there. */
static void scene_example_is_created(struct test_daemon *d, const struct operation *op,
                                     const struct example *ex)
{
    struct refract_response r;
    long status = exchange(d, "POST", op->path, ex->json, strlen(ex->json), "application/json", &r);
    CHECK_MSG(status == 201, "example \"%s\" (openapi.yaml:%d): POST %s answered %ld: %s", ex->name,
              ex->line, op->path, status, r.body ? r.body : "");
    cJSON *root = status == 201 ? cJSON_ParseWithLengthOpts(r.body, r.body_len, NULL, 0) : NULL;
    const cJSON *id = cJSON_GetObjectItemCaseSensitive(root, "id");
    if (status == 201 && CHECK_OK(cJSON_IsString(id), "201 without an id: %s", r.body)) {
        char path[256];
        snprintf(path, sizeof path, "/v1/scenes/%s", id->valuestring);
        struct refract_response got;
        CHECK_INT(exchange(d, "GET", path, NULL, 0, NULL, &got), 200);
        refract_response_free(&got);
        CHECK_INT(exchange(d, "DELETE", path, NULL, 0, NULL, &got), 204);
        refract_response_free(&got);
    }
    cJSON_Delete(root);
    refract_response_free(&r);
}

/* The Content-Type and the first bytes of each format. */
static bool image_is(const struct refract_response *r, const char *format,
                     const char **content_type)
{
    static const struct {
        const char *format, *content_type, *magic;
        size_t magic_len;
    } kinds[] = {{"png", "image/png", "\x89PNG", 4},
                 {"jpeg", "image/jpeg", "\xFF\xD8\xFF", 3},
                 {"exr", "image/x-exr", "\x76\x2F\x31\x01", 4}};
    for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++) {
        if (strcmp(kinds[i].format, format) != 0)
            continue;
        *content_type = kinds[i].content_type;
        return r->body_len > kinds[i].magic_len &&
               memcmp(r->body, kinds[i].magic, kinds[i].magic_len) == 0;
    }
    *content_type = "(unknown format)";
    return false;
}

/* A render example gives 200 and an image in the format it asked for (png by default). */
static void render_example_renders(struct test_daemon *d, const char *path, const cJSON *req,
                                   const struct example *ex)
{
    const cJSON *fmt = cJSON_GetObjectItemCaseSensitive(req, "format");
    const char *format = cJSON_IsString(fmt) ? fmt->valuestring : "png";
    struct refract_response r;
    long status = exchange(d, "POST", path, ex->json, strlen(ex->json), "application/json", &r);
    CHECK_MSG(status == 200, "render example \"%s\" (openapi.yaml:%d) answered %ld: %s", ex->name,
              ex->line, status, status == 200 ? "" : (r.body ? r.body : ""));
    const char *content_type = NULL;
    bool magic = image_is(&r, format, &content_type);
    if (status == 200) {
        CHECK_STR(r.content_type, content_type);
        CHECK_MSG(magic, "render example \"%s\": the body is not a %s file", ex->name, format);
    }
    refract_response_free(&r);
}

/* A trace example gives 200 and one result per ray sent, each with a documented status. */
static void trace_example_traces(struct test_daemon *d, const struct contract *c, const char *path,
                                 const cJSON *req, const struct example *ex)
{
    int sent = cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(req, "rays"));
    struct refract_response r;
    long status = exchange(d, "POST", path, ex->json, strlen(ex->json), "application/json", &r);
    CHECK_MSG(status == 200, "trace example \"%s\" (openapi.yaml:%d) answered %ld: %s", ex->name,
              ex->line, status, r.body ? r.body : "");
    cJSON *root = status == 200 ? cJSON_ParseWithLengthOpts(r.body, r.body_len, NULL, 0) : NULL;
    const cJSON *rays = cJSON_GetObjectItemCaseSensitive(root, "rays");
    if (status == 200) {
        CHECK_MSG(cJSON_IsArray(rays) && cJSON_GetArraySize(rays) == sent,
                  "trace example \"%s\" sent %d rays, got back: %s", ex->name, sent, r.body);
        const struct yenum *statuses = contract_enum(c, "RayStatus");
        const cJSON *hit;
        cJSON_ArrayForEach(hit, rays)
        {
            const cJSON *st = cJSON_GetObjectItemCaseSensitive(hit, "status");
            CHECK_MSG(cJSON_IsString(st) && enum_has(statuses, st->valuestring),
                      "trace example \"%s\": status not in RayStatus's enum: %s", ex->name, r.body);
        }
    }
    cJSON_Delete(root);
    refract_response_free(&r);
}

static void request_examples_are_accepted(struct test_daemon *d, const struct contract *c,
                                          const char *scene)
{
    for (int i = 0; i < c->op_count; i++) {
        const struct operation *op = &c->ops[i];
        char path[256];
        if (op->example_count == 0 || !fill_path(op->path, scene, path, sizeof path))
            continue;
        for (int k = 0; k < op->example_count; k++) {
            const struct example *ex = &op->examples[k];
            cJSON *req = example_json(op, ex);
            if (req == NULL)
                continue;
            if (is_path(op, "POST", "/v1/scenes")) {
                scene_example_is_created(d, op, ex);
            } else if (is_path(op, "POST", "/v1/scenes/{id}/render")) {
                render_example_renders(d, path, req, ex);
            } else if (is_path(op, "POST", "/v1/scenes/{id}/trace")) {
                trace_example_traces(d, c, path, req, ex);
            } else {
                struct refract_response r;
                long status = exchange(d, op->method, path, ex->json, strlen(ex->json),
                                       "application/json", &r);
                CHECK_MSG(status >= 200 && status < 300,
                          "example \"%s\" of %s %s answered "
                          "%ld: %s",
                          ex->name, op->method, path, status, r.body ? r.body : "");
                refract_response_free(&r);
            }
            cJSON_Delete(req);
        }
    }
}

/* The dims example of the volume upload uploads a volume of those dimensions. */
static void volume_dims_example_uploads(struct test_daemon *d, const struct contract *c,
                                        const char *scene)
{
    const struct operation *op = contract_op(c, "PUT", "/v1/scenes/{id}/volumes/{name}");
    int dims[3] = {0, 0, 0};
    char path[256], query[320];
    if (op == NULL || op->dims_example == NULL || !fill_path(op->path, scene, path, sizeof path))
        return;
    if (!CHECK_OK(sscanf(op->dims_example, "%d,%d,%d", &dims[0], &dims[1], &dims[2]) == 3 &&
                      dims[0] > 0 && dims[1] > 0 && dims[2] > 0 &&
                      dims[0] * dims[1] * dims[2] <= 1 << 20,
                  "dims example \"%s\" is not X,Y,Z (small)", op->dims_example))
        return;
    size_t count = (size_t)dims[0] * dims[1] * dims[2];
    float *data = malloc(count * sizeof *data);
    for (size_t i = 0; data && i < count; i++)
        data[i] = 1.0f + 0.5f * (float)i / (float)count;
    snprintf(query, sizeof query, "%s?dims=%s", path, op->dims_example);
    struct refract_response r;
    long status = exchange(d, "PUT", query, data, data ? count * sizeof *data : 0,
                           "application/octet-stream", &r);
    CHECK_MSG(status == 201, "PUT %s answered %ld: %s", query, status, r.body ? r.body : "");
    cJSON *root = status == 201 ? cJSON_ParseWithLengthOpts(r.body, r.body_len, NULL, 0) : NULL;
    const cJSON *got = cJSON_GetObjectItemCaseSensitive(root, "dims");
    for (int a = 0; status == 201 && a < 3; a++)
        CHECK_INT(cJSON_GetArrayItem(got, a) ? cJSON_GetArrayItem(got, a)->valueint : -1, dims[a]);
    cJSON_Delete(root);
    refract_response_free(&r);
    free(data);
}

int main(void)
{
    static struct contract c; /* large: static, not on the stack */
    bool have_contract = contract_read(&c);
    if (have_contract) {
        printf("openapi.yaml: %d operations, %d enums, %d ErrorCode rows\n", c.op_count,
               c.enum_count, c.error_row_count);
        documented_routes_equal_the_route_table(&c);
        every_operation_has_a_unique_operation_id(&c);
        error_codes_equal_refract_errors_h(&c);
        request_examples_are_present(&c);
    }
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL)) {
        test_summary("test_openapi_contract (without refractd)");
        test_setup_failed("test_openapi_contract", d.why);
    }
    char scene[REFRACT_ID_SIZE] = "", scratch[REFRACT_ID_SIZE] = "";
    CHECK(test_create_scene(&d, test_scene, scene));
    CHECK(test_create_scene(&d, test_scene, scratch));
    for (int i = 0; i < 2 && scene[0]; i++) {
        char path[128], *answer = NULL;
        snprintf(path, sizeof path, "/v1/scenes/%s/views", scene);
        CHECK_INT(test_request(&d, "POST", path, "{}", &answer), 201);
        cJSON *root = answer ? cJSON_Parse(answer) : NULL;
        const cJSON *id = cJSON_GetObjectItemCaseSensitive(root, "id");
        snprintf(i == 0 ? view_id : scratch_view_id, sizeof view_id, "%s",
                 cJSON_IsString(id) ? id->valuestring : "");
        cJSON_Delete(root);
        free(answer);
    }
    if (have_contract && scene[0] && scratch[0]) {
        documented_routes_are_answered(&d, &c, scene, scratch);
        wrong_method_gives_405(&d, &c, scene);
        undocumented_paths_give_404(&d, scene);
        volume_dims_example_uploads(&d, &c, scene);
        request_examples_are_accepted(&d, &c, scene);
    }
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    free(c.text);
    return test_summary("test_openapi_contract");
}
