/*
 * fuzz_scene.c - libFuzzer harness of the scene JSON parser (server/scene/scene_parse.c):
 * the bytes are a scene document, as the body of POST /v1/scenes. Each input either
 * parses into a scene or fails with an error message; anything else (a crash, a leak,
 * undefined behaviour) is a bug. docs/fuzzing.md says how to build and run it.
 */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* The parser reads len bytes and never past: a private copy without terminator makes
     * a read past the end a heap overflow ASan reports. */
    char *json = malloc(size ? size : 1);
    if (json == NULL)
        return 0;
    memcpy(json, data, size);
    /* refractd's default limits: parsing allocates no grid, so they cost no time. */
    struct scene_limits lim = scene_limits_default();
    struct scene *s = NULL;
    struct err e = {0};
    enum refract_code rc = scene_parse(json, size, &lim, &s, &e);
    if (rc == REFRACT_E_OK) {
        if (s == NULL)
            abort(); /* success must give a scene */
        scene_destroy(s);
    } else if (s != NULL || e.msg[0] == '\0') {
        abort(); /* failure must say why and give nothing */
    }
    free(json);
    return 0;
}
