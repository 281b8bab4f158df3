/*
 * example_scene.h - the benchmarks' scenes: an example document (proto/examples/) with
 * every object's voxel resolution replaced, parsed under limits large enough for 512^3.
 */
#ifndef REFRACT_BENCH_EXAMPLE_SCENE_H
#define REFRACT_BENCH_EXAMPLE_SCENE_H

#include "scene/scene.h"

/* Returns the parsed scene (scene_destroy) or NULL after printing why, prefixed by
 * `program`. */
struct scene *bench_load_example(const char *program, const char *path, int resolution);

#endif
