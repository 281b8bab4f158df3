/*
 * example_scene.h - what every benchmark shares: its scenes (an example document from
 * proto/examples/ with every object's voxel resolution replaced, parsed under limits large
 * enough for 512^3) and the header of its Markdown report (machine, GL, command).
 */
#ifndef REFRACT_BENCH_EXAMPLE_SCENE_H
#define REFRACT_BENCH_EXAMPLE_SCENE_H

#include <stdio.h>

#include "scene/scene.h"

/* Returns the parsed scene (scene_destroy) or NULL after printing why, prefixed by
 * `program`. resolution <= 0 keeps the document's resolutions. */
struct scene *bench_load_example(const char *program, const char *path, int resolution);

struct gpu;

/* qsort's comparison of doubles, ascending (the benchmarks' medians). */
int bench_compare_doubles(const void *a, const void *b);

/* Prints the report's header: date, CPU model and cores, OS, the load average, GL_RENDERER
 * and GL_VERSION (gpu NULL: a CPU-only benchmark) and the command line (argv), as Markdown
 * list items. */
void bench_print_header(const struct gpu *gpu, int argc, char **argv);
/* The same, into a file. */
void bench_write_header(FILE *out, const struct gpu *gpu, int argc, char **argv);

#endif
