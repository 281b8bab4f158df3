/*
 * example_scene.c - see example_scene.h.
 */
#include "example_scene.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (f == NULL)
        return NULL;
    fseek(f, 0, SEEK_END);
    long n = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *buf = n >= 0 ? malloc((size_t)n + 1) : NULL;
    if (buf && fread(buf, 1, (size_t)n, f) == (size_t)n) {
        buf[n] = '\0';
    } else {
        free(buf);
        buf = NULL;
    }
    fclose(f);
    return buf;
}

struct scene *bench_load_example(const char *program, const char *path, int resolution)
{
    char *text = read_file(path);
    if (text == NULL) {
        fprintf(stderr, "%s: cannot read %s\n", program, path);
        return NULL;
    }
    cJSON *root = cJSON_Parse(text);
    free(text);
    cJSON *obj;
    cJSON_ArrayForEach(obj, cJSON_GetObjectItemCaseSensitive(root, "objects"))
    {
        cJSON_DeleteItemFromObjectCaseSensitive(obj, "resolution");
        cJSON_AddNumberToObject(obj, "resolution", resolution);
    }
    char *json = cJSON_PrintUnformatted(root);
    cJSON_Delete(root);
    struct scene *s = NULL;
    struct scene_limits lim = scene_limits_default();
    lim.max_voxels = (int64_t)1 << 30;
    struct err e = {0};
    if (json == NULL || scene_parse(json, strlen(json), &lim, &s, &e) != REFRACT_E_OK)
        fprintf(stderr, "%s: %s: %s\n", program, path, json ? e.msg : "not JSON");
    free(json);
    return s;
}
