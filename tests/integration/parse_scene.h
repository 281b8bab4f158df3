/*
 * parse_scene.h - the tests' twin of what refractd does with a scene document: parse it
 * under the default limits, for the CPU reference (scene/scene_reference.h). Header-only.
 */
#ifndef REFRACT_TEST_PARSE_SCENE_H
#define REFRACT_TEST_PARSE_SCENE_H

#include <stdio.h>
#include <string.h>

#include "scene/scene.h"

/* The parsed scene (scene_destroy) or NULL after printing why. */
static inline struct scene *test_parse_scene(const char *json)
{
    struct scene *s = NULL;
    struct scene_limits lim = scene_limits_default();
    struct err e = {0};
    if (scene_parse(json, strlen(json), &lim, &s, &e) != REFRACT_E_OK)
        fprintf(stderr, "scene: %s\n", e.msg);
    return s;
}

#endif
