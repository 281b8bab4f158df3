/*
 * shader_source.h - GLSL sources embedded at build time, and the include expansion
 * that turns a kernel file into one compilable string.
 *
 * tools/embed_shaders.c writes gpu_embedded_shaders[] from shaders/. A `--shader-dir`
 * flag makes refractd read the same names from a folder instead (development).
 *
 * Expansion: `#include "name.glsl"` lines are replaced by the named file, once per
 * file (include guards are not needed), recursively. A name is a path below shaders/
 * ("geom/mesh.glsl"), whichever file includes it: a file in geom/ still includes
 * "bindings.h", not "../bindings.h". A bare name that only a file in a subfolder has
 * ("mesh.glsl") finds it too, and a file is included once under either spelling (a test
 * kernel includes both). Each file gets a source-string
 * number and `#line` directives, so a driver message "3:41(7): error ..." maps back to
 * the file number 3's line 41; shader_source_file_name() names the file for a number.
 */
#ifndef REFRACT_SHADER_SOURCE_H
#define REFRACT_SHADER_SOURCE_H

#include <stddef.h>

#include "../core/err.h"

struct gpu_embedded_shader {
    const char *name; /* path below shaders/, e.g. "render_view.comp", "geom/mesh.glsl" */
    const char *text; /* NUL-terminated GLSL */
};

extern const struct gpu_embedded_shader gpu_embedded_shaders[];
extern const int gpu_embedded_shader_count;

#define SHADER_SOURCE_MAX_FILES 32

/* Result of an expansion: the text to compile and the table of file numbers. */
struct shader_source {
    char *text;                                  /* owned; free with shader_source_fini */
    const char *file_names[SHADER_SOURCE_MAX_FILES]; /* number -> name (static or owned) */
    char *owned_names[SHADER_SOURCE_MAX_FILES];
    int file_count;
};

/* Expands `main_name` with its includes. shader_dir NULL = embedded sources, else
 * files are read from that directory. Prepends `preamble` (e.g. "#define TRACE_ONLY 1")
 * after the #version line. On failure returns REFRACT_E_INTERNAL with the missing
 * file's name. */
enum refract_code shader_source_expand(const char *main_name, const char *shader_dir,
                                       const char *preamble, struct shader_source *out,
                                       struct err *e);
void shader_source_fini(struct shader_source *s);

/* Rewrites a driver info log so "N:L(C)" prefixes read "file.glsl:L(C)". Returns a new
 * string the caller frees with free(). */
char *shader_source_map_log(const struct shader_source *s, const char *log);

#endif
