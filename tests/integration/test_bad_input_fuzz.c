/*
 * test_bad_input_fuzz.c - refractd answers every random or mutated request with either a
 * success or a well-formed error, never a dropped connection, and keeps serving:
 *   - random byte strings and mutated scene documents to POST /v1/scenes (byte-level
 *     mutations such as cuts, inserted tokens and flipped bytes, and tree-level mutations
 *     such as a value of another type, a deleted key, an unknown key, a repeated element);
 *     every scene that is accepted is rendered once and deleted;
 *   - mutated render and trace requests against a valid scene;
 *   - broken HTTP on a raw socket: a body cut short, a garbage request line, a bad chunk,
 *     a client that leaves while its render waits for the GPU;
 *   - afterwards /v1/health answers, a normal render works and the daemon exits cleanly.
 *
 * "Well-formed" means: an answer arrived; a 2xx carries what the route promises (a scene
 * id, an image, traced rays); anything else is a 4xx whose body is exactly
 * {"error": {"code", "message"}} with a code from proto/refract_errors.h whose status is
 * the HTTP status. A 5xx is a daemon bug here, since nothing in these inputs is the
 * server's fault.
 *
 * The generator is deterministic: the seed is printed and REFRACT_FUZZ_SEED=<n> repeats a
 * run. A failure prints the route, the case number and the input (escaped).
 *
 * This file deliberately checks no message texts: test_bad_input_scenes.c and
 * test_bad_input_requests.c check each error's exact identity.
 */
#include <arpa/inet.h>
#include <cjson/cJSON.h>
#include <netinet/in.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include "daemon.h"
#include "test.h"

/* Small limits keep every accepted scene and render cheap (16^3..32^3 voxels, <= 64 px). */
/* clang-format off */
static const char *const daemon_args[] = {
    "--max-resolution", "32",
    "--max-objects", "3",
    "--max-image-dim", "64",
    "--max-steps", "2000",
    "--max-layers", "8",
    "--max-profile-points", "64",
    "--max-text-length", "16",
    "--max-rays", "16",
    "--max-json-bytes", "65536",
    "--max-scenes", "64",
    NULL,
};
/* clang-format on */

#define SCENE_CASES_RANDOM 100
#define SCENE_CASES_BYTES 150
#define SCENE_CASES_TREE 200
#define RENDER_CASES 150
#define TRACE_CASES 80
#define RENDERS_OF_ACCEPTED_SCENES 40
#define FAILURES_SHOWN 25

/* Valid scene documents the mutations start from; between them they use every kind of
 * layer, shape and profile. */
static const char *const scene_seeds[] = {
    "{\"name\": \"sphere\", \"camera\": {\"eye\": [0, 0, 4], \"look_at\": [0, 0, 0], \"up\": [0, "
    "1, "
    "0], \"fov_y_deg\": 40, \"width\": 32, \"height\": 24}, \"objects\": [{\"bounds\": {\"min\": "
    "[-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, \"ior\": {\"shape\": \"sphere\", "
    "\"center\": [0, 0, 0], \"radius\": 0.8, \"inside\": 1.5, \"outside\": 1.0}}]}",

    "{\"name\": \"layers\", \"ambient_ior\": 1.0, \"environment\": {\"type\": \"procedural\", "
    "\"intensity\": 1.5, \"rotation_deg\": 30}, \"render\": {\"stepper\": \"euler\", \"step\": "
    "1, \"max_steps\": 500, \"exposure\": 0.5, \"boundary_threshold\": 0.05, \"tonemap\": "
    "\"filmic\"}, \"camera\": {\"width\": 24, \"height\": 16}, \"objects\": [{\"name\": \"block\", "
    "\"bounds\": {\"min\": [-1, -0.5, -0.5], \"max\": [1, 0.5, 0.5]}, \"resolution\": [16, 8, 8], "
    "\"smoothing_sigma\": 0.5, \"ior\": [1.2, {\"shape\": \"box\", \"center\": [0, 0, 0], "
    "\"size\": [1, 0.5, 0.5], \"inside\": 1.6}], \"attenuation\": [0.1, 0.2, 0.3], \"emission\": "
    "{\"shape\": \"cylinder\", \"radius\": 0.2, \"height\": 0.5, \"axis\": \"x\", \"inside\": [1, "
    "0, 0]}, \"opaque\": {\"shape\": \"text\", \"text\": \"AB\", \"center\": [0, 0, 0], "
    "\"height\": 0.3, \"depth\": 0.1, \"inside\": [1, 1, 0]}, \"opaque_ior\": 1.4}]}",

    "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, "
    "\"transform\": {\"translate\": [0, 0.1, 0], \"rotate\": {\"axis\": [0, 1, 0], \"angle_deg\": "
    "20}, \"scale\": 0.9}, \"ior\": {\"shape\": \"lathe\", \"base\": [0, -0.8, 0], \"axis\": "
    "\"y\", "
    "\"profile\": [[0, 0], [0.5, 0], [0.6, 0.8], [0.4, 1.4], [0, 1.4]], \"inside\": 1.5}}]}",

    "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 16, "
    "\"ior\": {\"profile\": \"luneburg\", \"center\": [0, 0, 0], \"radius\": 0.9}}, {\"bounds\": "
    "{\"min\": [1.5, -1, -1], \"max\": [3.5, 1, 1]}, \"resolution\": 8, \"ior\": [{\"profile\": "
    "\"gaussian\", \"center\": [2.5, 0, 0], \"n_peak\": 1.6, \"sigma\": 0.3}, {\"profile\": "
    "\"linear\", \"center\": [2.5, 0, 0], \"n0\": 1.2, \"gradient\": [0.05, 0, 0]}, {\"profile\": "
    "\"maxwell_fisheye\", \"radius\": 0.5, \"n0\": 1.8, \"center\": [2.5, 0, 0]}]}]}",

    "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]}, \"resolution\": 8, "
    "\"ior\": [{\"shape\": \"rounded_box\", \"size\": [1, 1, 1], \"radius\": 0.2, \"inside\": "
    "1.4}, {\"volume\": \"density\", \"scale\": 0.5, \"offset\": 1.0}]}]}",
};

static const char *const render_seed =
    "{\"format\": \"png\", \"width\": 32, \"height\": 24, \"camera\": {\"eye\": [0, 0, 4], "
    "\"look_at\": [0, 0, 0], \"up\": [0, 1, 0], \"fov_y_deg\": 40}, \"exposure\": 0.5, "
    "\"tonemap\": \"filmic\", \"stepper\": \"rk4\", \"step\": 0.5, \"max_steps\": 1000, "
    "\"jpeg_quality\": 80, \"boundary_threshold\": 0.05}";

static const char *const trace_seed =
    "{\"rays\": [{\"origin\": [0, 0, 4], \"direction\": [0, 0, -1]}, {\"origin\": [0.3, 0.2, 4], "
    "\"direction\": [0, -0.1, -1]}], \"step\": 0.5, \"stepper\": \"euler\", \"max_steps\": "
    "500, \"boundary_threshold\": 0.05}";

/* Text that byte-level mutations insert: JSON punctuation, numbers at and past the
 * ranges, escapes, and key names. */
/* clang-format off */
static const char *const tokens[] = {
    "{",         "}",        "[",        "]",          ",",        ":",         "\"",
    "\\",        "null",     "true",     "false",      "0",        "-1",        "1e999",
    "-1e999",    "1e308",    "1e-320",   "2147483648", "64.5",     "-0",        "NaN",
    "Infinity",  "\\u0000",  "\\ud800",  "\\uZZZZ",    "\xff\xfe", "\x01",      "\t\n",
    "\"\":",     "\"x\":1,", "\"objects\"", "\"shape\"", "\"volume\"", "\"profile\"", "[[[[",
    "]]]]",      "{}",       "[]",       "1,2,3",      "\"ior\":",  "\"resolution\": 1000",
};
/* clang-format on */

/* Keys that tree mutations add to objects: every schema key, and some that are not. */
/* clang-format off */
static const char *const keys[] = {
    "name",      "description", "ambient_ior", "environment", "camera",     "render",
    "objects",   "bounds",      "min",         "max",         "resolution", "transform",
    "translate", "rotate",      "axis",        "angle_deg",   "scale",      "smoothing_sigma",
    "ior",       "attenuation", "emission",    "opaque",      "opaque_ior", "shape",
    "center",    "radius",      "size",        "height",      "base",       "profile",
    "text",      "depth",       "inside",      "outside",     "volume",     "offset",
    "n0",        "gradient",    "n_peak",      "n_out",       "sigma",      "type",
    "intensity", "rotation_deg", "eye",        "look_at",     "up",         "fov_y_deg",
    "width",     "format",      "exposure",    "tonemap",     "stepper", "step",
    "max_steps", "jpeg_quality", "boundary_threshold", "rays", "origin",   "direction",
    "bogus",     "Name",        "",
};
/* clang-format on */

/* clang-format off */
static const double numbers[] = {0,    -1,     1,     2,      0.5,   1e-320, 1e308, -1e308,
                                 64.5, 1e6,    1.5e6, 4096,   65,    33,     3,     0.01,
                                 180,  -360.5, 1e-13, 1.0001, 100000, 2001, 17,    -0.0};
/* clang-format on */

/* clang-format off */
static const char *const strings[] = {
    "",       "x",      "sphere",   "box",    "rounded_box", "cylinder", "lathe",
    "text",   "luneburg", "maxwell_fisheye", "linear", "gaussian", "image", "procedural",
    "rk4",    "euler",  "filmic",   "clamp",  "png",         "jpeg",     "exr",
    "y",      "density", "a b",     "\x01\x7f", "\xc3\xbc",
    "0123456789abcdef0123456789abcdef0123456789abcdef0123456789abcdef0123456789",
};
/* clang-format on */

/* ---- deterministic randomness (splitmix64) ------------------------------------------------ */

static uint64_t rng_state;

static uint64_t rng_next(void)
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

/* Uniform in 0..n-1 (n > 0). */
static size_t rng_below(size_t n)
{
    return (size_t)(rng_next() % n);
}

#define PICK(array) (array[rng_below(sizeof array / sizeof array[0])])

/* ---- a growable byte buffer --------------------------------------------------------------- */

struct buf {
    char *data;
    size_t len, cap;
};

static void buf_reserve(struct buf *b, size_t extra)
{
    if (b->len + extra + 1 <= b->cap)
        return;
    size_t cap = b->cap ? b->cap : 256;
    while (cap < b->len + extra + 1)
        cap *= 2;
    char *grown = realloc(b->data, cap);
    if (grown == NULL)
        abort(); /* a test out of memory has nothing better to do */
    b->data = grown;
    b->cap = cap;
}

static void buf_set(struct buf *b, const char *data, size_t len)
{
    b->len = 0;
    buf_reserve(b, len);
    memcpy(b->data, data, len);
    b->len = len;
    b->data[len] = '\0';
}

/* Replaces bytes [pos, pos + del) with ins_len bytes of ins. */
static void buf_splice(struct buf *b, size_t pos, size_t del, const char *ins, size_t ins_len)
{
    if (pos > b->len)
        pos = b->len;
    if (del > b->len - pos)
        del = b->len - pos;
    buf_reserve(b, ins_len);
    memmove(b->data + pos + ins_len, b->data + pos + del, b->len - pos - del);
    memcpy(b->data + pos, ins, ins_len);
    b->len = b->len - del + ins_len;
    b->data[b->len] = '\0';
}

/* ---- generators --------------------------------------------------------------------------- */

static void random_bytes(struct buf *b)
{
    size_t n = rng_below(257);
    bool printable = rng_below(2) == 0;
    b->len = 0;
    buf_reserve(b, n + 1);
    if (rng_below(3) == 0 && n > 0)
        b->data[b->len++] = '{';
    while (b->len < n) {
        unsigned char c = (unsigned char)rng_next();
        b->data[b->len++] = (char)(printable ? 0x20 + c % 0x5f : c);
    }
    b->data[b->len] = '\0';
}

/* 1..4 byte-level edits of the text in b. */
static void mutate_bytes(struct buf *b)
{
    int edits = 1 + (int)rng_below(4);
    for (int i = 0; i < edits; i++) {
        size_t pos = b->len ? rng_below(b->len + 1) : 0;
        const char *t = PICK(tokens);
        char c;
        switch (rng_below(6)) {
        case 0: /* one byte becomes another */
            c = (char)(rng_below(2) ? (int)"{}[]\",:.-+eE0123456789 \\"[rng_below(25)]
                                    : (int)(unsigned char)rng_next());
            buf_splice(b, pos, 1, &c, 1);
            break;
        case 1: /* a span disappears */
            buf_splice(b, pos, 1 + rng_below(16), "", 0);
            break;
        case 2: /* a token appears */
        case 3:
            buf_splice(b, pos, 0, t, strlen(t));
            break;
        case 4: { /* a span repeats */
            size_t n = 1 + rng_below(32);
            if (pos + n <= b->len) {
                char *copy = malloc(n);
                memcpy(copy, b->data + pos, n);
                buf_splice(b, pos, 0, copy, n);
                free(copy);
            }
            break;
        }
        default: /* the document is cut short */
            b->len = pos;
            b->data[pos] = '\0';
            break;
        }
    }
}

static cJSON *random_value(int depth)
{
    switch (rng_below(depth > 1 ? 6 : 9)) {
    case 0:
    case 1:
        return cJSON_CreateNumber(PICK(numbers));
    case 2:
        return cJSON_CreateString(PICK(strings));
    case 3:
        return rng_below(3) == 0 ? cJSON_CreateNull() : cJSON_CreateBool(rng_below(2));
    case 4: {
        double v[3] = {PICK(numbers), PICK(numbers), PICK(numbers)};
        return cJSON_CreateDoubleArray(v, (int)rng_below(5) % 4);
    }
    case 5:
        return rng_below(2) ? cJSON_CreateObject() : cJSON_CreateArray();
    default: { /* a small nested value */
        cJSON *o = rng_below(2) ? cJSON_CreateObject() : cJSON_CreateArray();
        int n = 1 + (int)rng_below(3);
        for (int i = 0; i < n; i++) {
            cJSON *v = random_value(depth + 1);
            if (cJSON_IsObject(o))
                cJSON_AddItemToObject(o, PICK(keys), v);
            else
                cJSON_AddItemToArray(o, v);
        }
        return o;
    }
    }
}

/* Every node of the tree under root (root excluded), with its parent. */
struct node_list {
    cJSON *node[512], *parent[512];
    size_t n;
};

static void collect(cJSON *parent, struct node_list *l)
{
    for (cJSON *c = parent->child; c != NULL && l->n < 512; c = c->next) {
        l->node[l->n] = c;
        l->parent[l->n] = parent;
        l->n++;
        collect(c, l);
    }
}

/* One edit of the tree: a value replaced, a key removed or added, an element repeated,
 * a number pushed to a boundary. */
static void mutate_tree_once(cJSON *root)
{
    struct node_list *l = calloc(1, sizeof *l);
    collect(root, l);
    if (l->n == 0) {
        free(l);
        return;
    }
    size_t i = rng_below(l->n);
    cJSON *node = l->node[i], *parent = l->parent[i];
    switch (rng_below(6)) {
    case 0:
    case 1:
        cJSON_ReplaceItemViaPointer(parent, node, random_value(0));
        break;
    case 2:
        cJSON_Delete(cJSON_DetachItemViaPointer(parent, node));
        break;
    case 3: /* a key joins an object */
        if (cJSON_IsObject(node))
            cJSON_AddItemToObject(node, PICK(keys), random_value(0));
        else
            cJSON_AddItemToObject(root, PICK(keys), random_value(0));
        break;
    case 4: /* an element repeats */
        if (cJSON_IsArray(parent)) {
            int copies = 1 + (int)rng_below(rng_below(4) == 0 ? 40 : 3);
            for (int k = 0; k < copies; k++)
                cJSON_AddItemToArray(parent, cJSON_Duplicate(node, true));
        }
        break;
    default: /* a number moves to or past a boundary */
        if (cJSON_IsNumber(node)) {
            double v = node->valuedouble;
            double choices[] = {-v, v * 1e6, v + 0.5, v * 0.999, 0.0, v - 1};
            cJSON_SetNumberValue(node, PICK(choices));
        }
        break;
    }
    free(l);
}

/* 1..3 tree edits of seed; writes the printed document into b. */
static void mutate_tree(const char *seed, struct buf *b)
{
    cJSON *root = cJSON_Parse(seed);
    int edits = 1 + (int)rng_below(3);
    for (int i = 0; i < edits; i++)
        mutate_tree_once(root);
    char *text = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    buf_set(b, text, strlen(text));
    free(text);
}

/* ---- what a well-formed answer is --------------------------------------------------------- */

enum expect_ok { OK_SCENE, OK_IMAGE, OK_TRACE };

/* The HTTP status of an error code's row in the shared table, or -1. */
static int table_status(const char *code)
{
#define ROW_STATUS(name, num, http, json, text)                                                    \
    if (strcmp(code, json) == 0)                                                                   \
        return http;
    REFRACT_ERROR_TABLE(ROW_STATUS)
#undef ROW_STATUS
    return -1;
}

/* Empty why when r is a well-formed answer (see the file comment); else the reason. */
static void judge(const struct refract_response *r, enum expect_ok ok, char *why, size_t size)
{
    why[0] = '\0';
    bool json = strncmp(r->content_type, "application/json", 16) == 0;
    cJSON *root = json ? cJSON_ParseWithLength(r->body, r->body_len) : NULL;
    if (r->status >= 200 && r->status < 300) {
        bool good = false;
        if (ok == OK_SCENE)
            good = r->status == 201 && cJSON_IsString(cJSON_GetObjectItemCaseSensitive(root, "id"));
        else if (ok == OK_TRACE)
            good =
                r->status == 200 && cJSON_IsArray(cJSON_GetObjectItemCaseSensitive(root, "rays"));
        else
            good =
                r->status == 200 && r->body_len > 0 && strncmp(r->content_type, "image/", 6) == 0;
        if (!good)
            snprintf(why, size, "a %ld answer without what the route promises", r->status);
        cJSON_Delete(root);
        return;
    }
    const cJSON *err = cJSON_GetObjectItemCaseSensitive(root, "error");
    const cJSON *code = cJSON_GetObjectItemCaseSensitive(err, "code");
    const cJSON *msg = cJSON_GetObjectItemCaseSensitive(err, "message");
    if (root == NULL)
        snprintf(why, size, "an error that is not JSON");
    else if (cJSON_GetArraySize(root) != 1 || !cJSON_IsObject(err) ||
             cJSON_GetArraySize(err) != 2 || !cJSON_IsString(code) || !cJSON_IsString(msg) ||
             msg->valuestring[0] == '\0')
        snprintf(why, size, "not exactly {\"error\": {\"code\", \"message\"}}");
    else if (table_status(code->valuestring) != r->status)
        snprintf(why, size, "code \"%s\" does not go with HTTP %ld", code->valuestring, r->status);
    else if (r->status >= 500)
        snprintf(why, size, "a server error for a client's mistake");
    cJSON_Delete(root);
}

static int failures_shown;

/* Prints up to 200 bytes of data, escaped. */
static void print_escaped(const char *data, size_t len)
{
    for (size_t i = 0; i < len && i < 200; i++) {
        unsigned char c = (unsigned char)data[i];
        if (c >= 0x20 && c < 0x7f && c != '\\')
            fputc(c, stderr);
        else
            fprintf(stderr, "\\x%02x", c);
    }
    if (len > 200)
        fprintf(stderr, "... (%zu bytes)", len);
}

/* Sends one fuzz case and checks its answer; returns the response in *out when the caller
 * wants it (status, body), else frees it. */
static bool fuzz_case(struct test_daemon *d, const char *what, int index, const char *path,
                      const struct buf *body, enum expect_ok ok, struct refract_response *out)
{
    struct refract_response r;
    char why[200];
    int rc =
        refract_request(d->client, "POST", path, body->data, body->len, "application/json", &r);
    if (rc != REFRACT_E_OK)
        snprintf(why, sizeof why, "no HTTP answer: %s", refract_errmsg(d->client));
    else
        judge(&r, ok, why, sizeof why);
    bool good = why[0] == '\0';
    if (good) {
        test_passed_count++;
    } else {
        test_failed_count++;
        if (failures_shown++ < FAILURES_SHOWN) {
            fprintf(stderr, "%s case %d: POST %s: %s\n    input: ", what, index, path, why);
            print_escaped(body->data, body->len);
            fprintf(stderr, "\n    answer: %ld %s\n", rc == REFRACT_E_OK ? r.status : -1L,
                    rc == REFRACT_E_OK ? r.body : "");
        }
    }
    if (rc == REFRACT_E_OK && out != NULL && good)
        *out = r;
    else if (rc == REFRACT_E_OK)
        refract_response_free(&r);
    return good && rc == REFRACT_E_OK && out != NULL;
}

/* ---- the runs ----------------------------------------------------------------------------- */

struct tally {
    int accepted, rejected, rendered;
};

/* Renders an accepted scene once (small), then deletes it. */
static void render_and_delete(struct test_daemon *d, const char *id, struct tally *t)
{
    char path[160];
    if (t->rendered < RENDERS_OF_ACCEPTED_SCENES) {
        struct buf req = {0};
        buf_set(&req, "{\"width\": 16, \"height\": 12}", 27);
        snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
        fuzz_case(d, "render of an accepted scene", t->rendered, path, &req, OK_IMAGE, NULL);
        free(req.data);
        t->rendered++;
    }
    CHECK_INT(refract_scene_delete(d->client, id), REFRACT_E_OK);
}

static void post_scene(struct test_daemon *d, const char *what, int index, const struct buf *b,
                       struct tally *t)
{
    struct refract_response r;
    if (!fuzz_case(d, what, index, "/v1/scenes", b, OK_SCENE, &r))
        return;
    if (r.status == 201) {
        cJSON *root = cJSON_ParseWithLength(r.body, r.body_len);
        const cJSON *id = cJSON_GetObjectItemCaseSensitive(root, "id");
        t->accepted++;
        render_and_delete(d, id->valuestring, t);
        cJSON_Delete(root);
    } else {
        t->rejected++;
    }
    refract_response_free(&r);
}

static void random_and_mutated_scenes_get_well_formed_answers(struct test_daemon *d)
{
    struct buf b = {0};
    struct tally t = {0};
    int n = 0;
    for (int i = 0; i < SCENE_CASES_RANDOM; i++, n++) {
        random_bytes(&b);
        post_scene(d, "random bytes", n, &b, &t);
    }
    for (int i = 0; i < SCENE_CASES_BYTES; i++, n++) {
        const char *seed = PICK(scene_seeds);
        buf_set(&b, seed, strlen(seed));
        mutate_bytes(&b);
        post_scene(d, "byte-mutated scene", n, &b, &t);
    }
    for (int i = 0; i < SCENE_CASES_TREE; i++, n++) {
        mutate_tree(PICK(scene_seeds), &b);
        post_scene(d, "tree-mutated scene", n, &b, &t);
    }
    printf("POST /v1/scenes: %d cases, %d accepted (%d of them rendered), %d rejected\n", n,
           t.accepted, t.rendered, t.rejected);
    CHECK(t.rejected > n / 2); /* the mutations do reach the validators */
    free(b.data);
}

static void mutated_requests_get_well_formed_answers(struct test_daemon *d, const char *id)
{
    struct buf b = {0};
    char path[160];
    int ok = 0;
    snprintf(path, sizeof path, "/v1/scenes/%s/render", id);
    for (int i = 0; i < RENDER_CASES; i++) {
        if (rng_below(3) == 0) {
            buf_set(&b, render_seed, strlen(render_seed));
            mutate_bytes(&b);
        } else {
            mutate_tree(render_seed, &b);
        }
        struct refract_response r;
        if (fuzz_case(d, "render request", i, path, &b, OK_IMAGE, &r)) {
            ok += r.status == 200;
            refract_response_free(&r);
        }
    }
    printf("POST /v1/scenes/{id}/render: %d cases, %d rendered\n", RENDER_CASES, ok);
    ok = 0;
    snprintf(path, sizeof path, "/v1/scenes/%s/trace", id);
    for (int i = 0; i < TRACE_CASES; i++) {
        if (rng_below(3) == 0) {
            buf_set(&b, trace_seed, strlen(trace_seed));
            mutate_bytes(&b);
        } else {
            mutate_tree(trace_seed, &b);
        }
        struct refract_response r;
        if (fuzz_case(d, "trace request", i, path, &b, OK_TRACE, &r)) {
            ok += r.status == 200;
            refract_response_free(&r);
        }
    }
    printf("POST /v1/scenes/{id}/trace: %d cases, %d traced\n", TRACE_CASES, ok);
    free(b.data);
}

/* ---- broken HTTP on a raw socket ---------------------------------------------------------- */

/* Sends bytes on a new connection, optionally waits up to 2 s for an answer, and closes. */
static void raw_exchange(const struct test_daemon *d, const char *bytes, size_t len, bool wait)
{
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in addr = {.sin_family = AF_INET, .sin_port = htons((uint16_t)d->port)};
    inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
    if (fd < 0 || connect(fd, (const struct sockaddr *)&addr, sizeof addr) != 0) {
        CHECK_MSG(false, "cannot connect to 127.0.0.1:%d", d->port);
        if (fd >= 0)
            close(fd);
        return;
    }
    struct timeval tv = {.tv_sec = 2};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    ssize_t sent = send(fd, bytes, len, MSG_NOSIGNAL);
    (void)sent;
    if (wait) {
        shutdown(fd, SHUT_WR);
        char sink[4096];
        while (recv(fd, sink, sizeof sink, 0) > 0)
            ;
    }
    close(fd);
}

static void broken_http_leaves_the_daemon_serving(struct test_daemon *d, const char *id)
{
    static const char cut_short[] = "POST /v1/scenes HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
                                    "application/json\r\nContent-Length: 100\r\n\r\n{\"na";
    static const char garbage[] = "GARBAGE\r\n\r\n";
    static const char bad_chunk[] =
        "POST /v1/scenes HTTP/1.1\r\nHost: 127.0.0.1\r\nTransfer-Encoding: "
        "chunked\r\n\r\nzz\r\nabc\r\n0\r\n\r\n";
    static const char bad_length[] =
        "POST /v1/scenes HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Length: "
        "abc\r\n\r\n{}";
    raw_exchange(d, cut_short, sizeof cut_short - 1, false);
    raw_exchange(d, cut_short, sizeof cut_short - 1, true);
    raw_exchange(d, garbage, sizeof garbage - 1, true);
    raw_exchange(d, bad_chunk, sizeof bad_chunk - 1, true);
    raw_exchange(d, bad_length, sizeof bad_length - 1, true);
    /* Clients that leave while their render is suspended, waiting for the GPU. */
    char leave[512];
    const char *json = "{\"width\": 64, \"height\": 64, \"step\": 0.05, \"max_steps\": 2000}";
    int n = snprintf(leave, sizeof leave,
                     "POST /v1/scenes/%s/render HTTP/1.1\r\nHost: 127.0.0.1\r\nContent-Type: "
                     "application/json\r\nContent-Length: %zu\r\n\r\n%s",
                     id, strlen(json), json);
    for (int i = 0; i < 6; i++)
        raw_exchange(d, leave, (size_t)n, false);
    char *health = NULL;
    CHECK_MSG(refract_health(d->client, &health) == REFRACT_E_OK, "health after broken HTTP: %s",
              refract_errmsg(d->client));
    refract_free(health);
}

int main(void)
{
    const char *env = getenv("REFRACT_FUZZ_SEED");
    uint64_t seed = env ? strtoull(env, NULL, 0) : 0x5eed2026ull;
    rng_state = seed;
    printf("test_bad_input_fuzz: seed %llu (repeat with REFRACT_FUZZ_SEED=%llu)\n",
           (unsigned long long)seed, (unsigned long long)seed);
    struct test_daemon d;
    if (!test_daemon_start(&d, daemon_args))
        test_setup_failed("test_bad_input_fuzz", d.why);
    char id[REFRACT_ID_SIZE] = "";
    CHECK(test_create_scene(&d, scene_seeds[0], id));

    random_and_mutated_scenes_get_well_formed_answers(&d);
    mutated_requests_get_well_formed_answers(&d, id);
    broken_http_leaves_the_daemon_serving(&d, id);

    /* Still serving: health, and a normal render of the untouched scene. */
    char *health = NULL;
    CHECK(refract_health(d.client, &health) == REFRACT_E_OK);
    refract_free(health);
    struct refract_image img = {0};
    int rc = refract_render(d.client, id, "{\"format\": \"exr\"}", &img);
    CHECK_MSG(rc == REFRACT_E_OK, "render after the fuzzing: %s", refract_errmsg(d.client));
    CHECK_STR(img.content_type, "image/x-exr");
    refract_image_free(&img);
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_bad_input_fuzz");
}
