/*
 * cli_args.h - the refract CLI's argument parsing helpers: option scanning and the value
 * syntaxes (vectors "1,2,3", dims "64,64,64", numbers, timeouts, image formats).
 *
 * Pure functions on strings with no libcurl, no cJSON and no I/O, so that
 * tests/unit/test_cli_args.c can compile this file directly. A parser that fails
 * returns false (or REFRACT_E_USAGE) and writes into why a sentence that says what was
 * expected and what was found; the caller prefixes the option's name.
 */
#ifndef CLI_ARGS_H
#define CLI_ARGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* One option a command accepts. The command fills name, alias and takes_value (with
 * designated initializers); cli_parse_args() fills value and given. */
struct cli_opt {
    const char *name;  /* long form with its dashes: "--width" */
    const char *alias; /* short form ("-o") or NULL */
    bool takes_value;  /* "--width 640" or "--width=640"; otherwise a flag */
    const char *value; /* borrowed from argv; NULL when not given or a flag */
    bool given;
};

#define CLI_MAX_POSITIONALS 8

/* What cli_parse_args() found besides options. */
struct cli_parsed {
    const char *pos[CLI_MAX_POSITIONALS]; /* borrowed from argv, in order */
    size_t n_pos;
    bool help; /* -h or --help was given */
};

/* Scans argv[0..argc) for the options in opts and the positional arguments. "--" ends
 * the options; "-" alone is a positional (stdin or stdout). Returns REFRACT_E_OK, or
 * REFRACT_E_USAGE with why filled for an unknown option, an option given twice, a
 * missing value or more than CLI_MAX_POSITIONALS positionals. Borrows argv. */
int cli_parse_args(int argc, char *const argv[], struct cli_opt *opts, size_t n_opts,
                   struct cli_parsed *out, char *why, size_t why_size);

/* "x,y,z": three finite numbers separated by commas (blanks around them allowed). */
bool cli_parse_vec3(const char *s, double out[3], char *why, size_t why_size);

/* "X,Y,Z": three integers in 1..CLI_DIM_MAX separated by commas. */
#define CLI_DIM_MAX 65536
bool cli_parse_dims(const char *s, int out[3], char *why, size_t why_size);

/* A whole decimal integer in [min, max]. */
bool cli_parse_long(const char *s, long min, long max, long *out, char *why, size_t why_size);

/* A finite decimal number. */
bool cli_parse_double(const char *s, double *out, char *why, size_t why_size);

/* A timeout in seconds ("30", "2.5", "0" = none) -> milliseconds; at most one year. */
bool cli_parse_timeout(const char *s, long *timeout_ms, char *why, size_t why_size);

/* The canonical name of an image format given by the user: "png", "jpeg" (also "jpg")
 * or "exr", any letter case; NULL when unknown. Returns a static string. */
const char *cli_format_canonical(const char *name);

/* The image format implied by path's extension (.png, .jpg, .jpeg, .exr, any letter
 * case); NULL when the extension is missing or not one of those. Static string. */
const char *cli_format_from_path(const char *path);

/* The image format of a Content-Type (image/png, image/jpeg, image/x-exr; parameters
 * after ';' ignored); NULL when it is none of those. Static string. */
const char *cli_format_from_content_type(const char *content_type);

/* The byte size X*Y*Z*C*4 of a raw float32 volume; false when it overflows 64 bits. */
bool cli_volume_bytes(const int dims[3], int components, uint64_t *bytes);
/* The byte size X*Y*Z*C*sample_bytes of a raw volume; false when a factor is not
 * positive or the product overflows 64 bits. */
bool cli_raw_volume_bytes(const int dims[3], int components, int sample_bytes, uint64_t *bytes);

#endif
