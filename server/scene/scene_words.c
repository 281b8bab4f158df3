/*
 * scene_words.c - the JSON words of the scene's enumerations, one table each, in the
 * order of their enums (scene.h). Every parser and every status answer uses these, so a
 * value that can be set can also be reported (a view's status once reported "euler" for
 * rk2 and adaptive from a two-entry copy).
 */
#include "scene.h"

const char *const scene_stepper_words[] = {"euler", "rk4", "rk2", "adaptive", NULL};
const char *const scene_ior_texture_words[] = {"float32", "float16", NULL};
const char *const scene_ior_filter_words[] = {"trilinear", "tricubic", NULL};
const char *const scene_tonemap_words[] = {"clamp", "filmic", NULL};
const char *const scene_caustics_words[] = {"volume", "photons", "auto", "none", NULL};

_Static_assert(SCENE_STEPPER_EULER == 0 && SCENE_STEPPER_RK4 == 1 && SCENE_STEPPER_RK2 == 2 &&
                   SCENE_STEPPER_ADAPTIVE == 3,
               "scene_stepper_words order");
_Static_assert(SCENE_IOR_FLOAT32 == 0 && SCENE_IOR_FLOAT16 == 1, "scene_ior_texture_words order");
_Static_assert(SCENE_FILTER_TRILINEAR == 0 && SCENE_FILTER_TRICUBIC == 1,
               "scene_ior_filter_words order");
_Static_assert(SCENE_TONEMAP_CLAMP == 0 && SCENE_TONEMAP_FILMIC == 1, "scene_tonemap_words order");
