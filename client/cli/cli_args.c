/*
 * cli_args.c - argument parsing for the refract CLI: a small option scanner shared by
 * every command, and the parsers of the values options take.
 *
 * Everything here is a pure function of its arguments (no I/O, no globals, no locale
 * beyond the "C" one the CLI never changes), which is what lets the unit test include
 * this file. It does not know any command; the cmd_*.c files declare their options.
 */
#include "cli_args.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "refract_errors.h"

#include "../refract_say.h"

/* Edit distance between two short strings, capped: anything longer than 63 characters
 * counts as far away. Used only to suggest an option for a typo. */
static size_t edit_distance(const char *a, const char *b)
{
    size_t la = strlen(a);
    size_t lb = strlen(b);
    size_t row[64];

    if (la >= 64 || lb >= 64)
        return SIZE_MAX;
    for (size_t j = 0; j <= lb; j++)
        row[j] = j;
    for (size_t i = 1; i <= la; i++) {
        size_t diag = row[0];

        row[0] = i;
        for (size_t j = 1; j <= lb; j++) {
            size_t up = row[j];
            size_t best = diag + (a[i - 1] == b[j - 1] ? 0 : 1);

            if (up + 1 < best)
                best = up + 1;
            if (row[j - 1] + 1 < best)
                best = row[j - 1] + 1;
            row[j] = best;
            diag = up;
        }
    }
    return row[lb];
}

static struct cli_opt *find_opt(struct cli_opt *opts, size_t n_opts, const char *arg, size_t len)
{
    for (size_t i = 0; i < n_opts; i++) {
        const char *names[2] = {opts[i].name, opts[i].alias};

        for (size_t k = 0; k < 2; k++) {
            if (names[k] != NULL && strlen(names[k]) == len && strncmp(names[k], arg, len) == 0)
                return &opts[i];
        }
    }
    return NULL;
}

static int unknown_option(const struct cli_opt *opts, size_t n_opts, const char *arg, char *why,
                          size_t why_size)
{
    const char *closest = NULL;
    size_t best = 3; /* suggest only for up to two typos */

    for (size_t i = 0; i < n_opts; i++) {
        size_t d = edit_distance(arg, opts[i].name);

        if (d < best) {
            best = d;
            closest = opts[i].name;
        }
    }
    if (closest != NULL)
        refract_say(why, why_size, "unknown option '%s'; did you mean '%s'?", arg, closest);
    else
        refract_say(why, why_size, "unknown option '%s'", arg);
    return REFRACT_E_USAGE;
}

/* Handles argv[*i], an option; may consume the next argument as its value. */
static int take_option(int argc, char *const argv[], int *i, struct cli_opt *opts, size_t n_opts,
                       char *why, size_t why_size)
{
    const char *arg = argv[*i];
    const char *eq = arg[1] == '-' ? strchr(arg, '=') : NULL;
    size_t len = eq != NULL ? (size_t)(eq - arg) : strlen(arg);
    struct cli_opt *opt = find_opt(opts, n_opts, arg, len);

    if (opt == NULL) {
        char name[64];

        snprintf(name, sizeof(name), "%.*s", (int)(len < 63 ? len : 63), arg);
        return unknown_option(opts, n_opts, name, why, why_size);
    }
    if (opt->given) {
        refract_say(why, why_size, "%s is given twice", opt->name);
        return REFRACT_E_USAGE;
    }
    if (opt->takes_value && eq != NULL) {
        opt->value = eq + 1;
    } else if (opt->takes_value && *i + 1 < argc) {
        opt->value = argv[++*i]; /* may start with '-': "--exposure -1" */
    } else if (opt->takes_value) {
        refract_say(why, why_size, "%s needs a value", opt->name);
        return REFRACT_E_USAGE;
    } else if (eq != NULL) {
        refract_say(why, why_size, "%s takes no value", opt->name);
        return REFRACT_E_USAGE;
    }
    opt->given = true;
    return REFRACT_E_OK;
}

int cli_parse_args(int argc, char *const argv[], struct cli_opt *opts, size_t n_opts,
                   struct cli_parsed *out, char *why, size_t why_size)
{
    bool options_done = false;

    memset(out, 0, sizeof(*out));
    for (size_t k = 0; k < n_opts; k++) {
        opts[k].value = NULL;
        opts[k].given = false;
    }
    for (int i = 0; i < argc; i++) {
        const char *arg = argv[i];
        int code;

        if (!options_done && strcmp(arg, "--") == 0) {
            options_done = true;
        } else if (options_done || arg[0] != '-' || arg[1] == '\0') {
            if (out->n_pos == CLI_MAX_POSITIONALS) {
                refract_say(why, why_size, "unexpected argument '%s'", arg);
                return REFRACT_E_USAGE;
            }
            out->pos[out->n_pos++] = arg;
        } else if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            out->help = true;
        } else {
            code = take_option(argc, argv, &i, opts, n_opts, why, why_size);
            if (code != REFRACT_E_OK)
                return code;
        }
    }
    return REFRACT_E_OK;
}

static const char *skip_blanks(const char *p)
{
    while (*p == ' ' || *p == '\t')
        p++;
    return p;
}

bool cli_parse_vec3(const char *s, double out[3], char *why, size_t why_size)
{
    const char *p = s;

    for (int k = 0; k < 3; k++) {
        char *end;
        double v;

        p = skip_blanks(p);
        v = strtod(p, &end);
        if (end == p || !isfinite(v))
            return refract_say(why, why_size,
                               "expected three numbers separated by commas, such as "
                               "0,0,4; got \"%s\"",
                               s);
        out[k] = v;
        p = skip_blanks(end);
        if (k < 2 && *p != ',')
            return refract_say(why, why_size,
                               "expected three numbers separated by commas, such as "
                               "0,0,4; got \"%s\"",
                               s);
        if (k < 2)
            p++; /* past the comma */
    }
    if (*p != '\0')
        return refract_say(why, why_size,
                           "expected exactly three numbers, such as 0,0,4; got \"%s\"", s);
    return true;
}

bool cli_parse_dims(const char *s, int out[3], char *why, size_t why_size)
{
    const char *p = s;

    for (int k = 0; k < 3; k++) {
        char *end;
        long v;

        p = skip_blanks(p);
        errno = 0;
        v = strtol(p, &end, 10);
        if (end == p || errno != 0 || v < 1 || v > CLI_DIM_MAX)
            return refract_say(why, why_size,
                               "expected three whole numbers in 1..%d separated by "
                               "commas, such as 64,64,64; got \"%s\"",
                               CLI_DIM_MAX, s);
        out[k] = (int)v;
        p = skip_blanks(end);
        if (k < 2 && *p != ',')
            return refract_say(why, why_size,
                               "expected three whole numbers separated by commas, such "
                               "as 64,64,64; got \"%s\"",
                               s);
        if (k < 2)
            p++; /* past the comma */
    }
    if (*p != '\0')
        return refract_say(why, why_size,
                           "expected exactly three whole numbers, such as 64,64,64; "
                           "got \"%s\"",
                           s);
    return true;
}

bool cli_parse_long(const char *s, long min, long max, long *out, char *why, size_t why_size)
{
    char *end;
    long v;

    errno = 0;
    v = strtol(s, &end, 10);
    if (end == s || *end != '\0' || errno != 0 || v < min || v > max)
        return refract_say(why, why_size, "expected a whole number in %ld..%ld, got \"%s\"", min,
                           max, s);
    *out = v;
    return true;
}

bool cli_parse_double(const char *s, double *out, char *why, size_t why_size)
{
    char *end;
    double v = strtod(s, &end);

    if (end == s || *end != '\0' || !isfinite(v))
        return refract_say(why, why_size, "expected a finite number, got \"%s\"", s);
    *out = v;
    return true;
}

bool cli_parse_timeout(const char *s, long *timeout_ms, char *why, size_t why_size)
{
    const double max_seconds = 365.0 * 24 * 3600;
    double seconds = 0;

    if (!cli_parse_double(s, &seconds, NULL, 0) || seconds < 0 || seconds > max_seconds)
        return refract_say(why, why_size,
                           "expected seconds from 0 (no limit) to %.0f, such as 30 or "
                           "2.5; got \"%s\"",
                           max_seconds, s);
    *timeout_ms = (long)ceil(seconds * 1000.0);
    return true;
}

const char *cli_format_canonical(const char *name)
{
    if (strcasecmp(name, "png") == 0)
        return "png";
    if (strcasecmp(name, "jpeg") == 0 || strcasecmp(name, "jpg") == 0)
        return "jpeg";
    if (strcasecmp(name, "exr") == 0)
        return "exr";
    return NULL;
}

const char *cli_format_from_path(const char *path)
{
    const char *base = strrchr(path, '/');
    const char *dot;

    base = base != NULL ? base + 1 : path;
    dot = strrchr(base, '.');
    if (dot == NULL || dot == base)
        return NULL; /* "out" or ".png" (a hidden file, not an extension) */
    return cli_format_canonical(dot + 1);
}

const char *cli_format_from_content_type(const char *content_type)
{
    static const struct {
        const char *type;
        const char *format;
    } types[] = {{"image/png", "png"}, {"image/jpeg", "jpeg"}, {"image/x-exr", "exr"}};
    const char *p = skip_blanks(content_type);
    size_t len = strcspn(p, "; \t");

    for (size_t i = 0; i < sizeof(types) / sizeof(types[0]); i++) {
        if (strlen(types[i].type) == len && strncasecmp(p, types[i].type, len) == 0)
            return types[i].format;
    }
    return NULL;
}

bool cli_volume_bytes(const int dims[3], int components, uint64_t *bytes)
{
    return cli_raw_volume_bytes(dims, components, 4, bytes); /* 4 bytes per float32 */
}

bool cli_raw_volume_bytes(const int dims[3], int components, int sample_bytes, uint64_t *bytes)
{
    uint64_t n = sample_bytes > 0 ? (uint64_t)sample_bytes : 0;

    if (n == 0)
        return false;
    for (int i = 0; i < 4; i++) {
        int f = i < 3 ? dims[i] : components;

        if (f <= 0 || n > UINT64_MAX / (uint64_t)f)
            return false;
        n *= (uint64_t)f;
    }
    *bytes = n;
    return true;
}
