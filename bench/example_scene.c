/*
 * example_scene.c - see example_scene.h.
 */
#include "example_scene.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <time.h>
#include <unistd.h>

#include "gpu/queue.h"

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
        if (resolution <= 0)
            break; /* keep the document's own */
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

void bench_print_header(const struct gpu *gpu, int argc, char **argv)
{
    bench_write_header(stdout, gpu, argc, argv);
}

int bench_compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void bench_write_header(FILE *out, const struct gpu *gpu, int argc, char **argv)
{
    const struct gpu_context_info *info = gpu ? gpu_info(gpu) : NULL;
    struct utsname u;
    uname(&u);
    char cpu[300] = "unknown";
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[256];
    while (f && fgets(line, sizeof line, f)) {
        if (strncmp(line, "model name", 10) == 0) {
            char *colon = strchr(line, ':');
            snprintf(cpu, sizeof cpu, "%s", colon ? colon + 2 : line);
            cpu[strcspn(cpu, "\n")] = '\0';
            break;
        }
    }
    if (f)
        fclose(f);
    time_t now = time(NULL);
    char date[32];
    strftime(date, sizeof date, "%Y-%m-%d", gmtime(&now));
    double load[3] = {0, 0, 0};
    if (getloadavg(load, 3) < 1)
        load[0] = -1.0;
    fprintf(out, "- date: %s\n- machine: %s, %ld cores, %s %s\n- load average at start: %.2f\n",
            date, cpu, sysconf(_SC_NPROCESSORS_ONLN), u.sysname, u.machine, load[0]);
    if (info != NULL)
        fprintf(out, "- GL_RENDERER: %s\n- GL_VERSION: %s\n", info->renderer, info->version);
    else
        fprintf(out, "- GL_RENDERER: none (CPU only)\n");
    fprintf(out, "- command: `");
    for (int i = 0; i < argc; i++)
        fprintf(out, "%s%s", i ? " " : "", argv[i]);
    fprintf(out, "`\n\n");
}
