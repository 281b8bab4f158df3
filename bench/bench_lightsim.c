/*
 * bench_lightsim.c - refract-lightsim: the GPU light simulator's speed and memory
 * (server/lightsim/gpu), for BENCHMARKS.md. Not a test: it asserts nothing and prints a
 * Markdown table.
 *
 *     build/refract-lightsim [--scenes glass_sphere_voxels,wine_glass_voxels,bumpy_sphere]
 *                            [--resolutions 64,128,256] [--patches 32,64,128]
 *                            [--max-patches 262144] [--chunk 64] [--object-resolution 64]
 *
 * For every scene, light-grid resolution and initial patch count (patches per side of
 * the initial wavefront) it builds the light fields on the CPU (lightsim_fields_build;
 * time reported), then runs the simulation of the scene's first light (a directional
 * light (0.2, -1, 0.1) when the document has none, e.g. glass_sphere_voxels) on the GPU in chunks
 * of --chunk steps, timed from the first upload to glFinish after the last chunk, and
 * reports the run's peak GPU memory (lightsim_gpu_run_peak_bytes) and its statistics.
 * On a software renderer (llvmpipe) the process CPU time over the run is printed as well:
 * on a shared machine it says more than the wall time. culled and reflected are
 * fractions of flux_in (green).
 * Scenes are read from proto/examples/<name>.json with every object's voxel resolution
 * replaced by --object-resolution and "lightsim" settings by the options. A name ending in
 * "@ico<S>" (e.g. ball_lens_caustic@ico5) is that scene with every sphere surface replaced
 * by a mesh surface of the same centre and radius: the unit icosphere of S subdivisions
 * (mesh_make_icosphere, 20 4^S triangles), so mesh and exact sphere compare in one run.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <cjson/cJSON.h>

#include "example_scene.h"
#include "gpu/queue.h"
#include "lightsim/gpu/lightsim_gpu.h"
#include "mesh/mesh.h"
#include "mesh/mesh_rt.h"
#include "scene/scene.h"

#define MAX_LIST 16

struct list {
    char item[MAX_LIST][64];
    int count;
};

static void split(const char *text, struct list *l)
{
    l->count = 0;
    const char *p = text;
    while (*p && l->count < MAX_LIST) {
        size_t n = strcspn(p, ",");
        snprintf(l->item[l->count++], sizeof l->item[0], "%.*s", (int)n, p);
        p += n;
        if (*p == ',')
            p++;
    }
}

struct run_work {
    struct gpu_work work;
    const struct lightsim_fields *fields;
    struct scene_light light;
    struct scene_lightsim set;
    int chunk;
    double ms, cpu_s; /* wall; CPU time of the whole process (every llvmpipe thread) */
    size_t peak_bytes;
    struct lightsim_stats stats;
};

static double process_cpu_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void run_on_gpu(struct gpu_work *w, struct gpu *gpu)
{
    struct run_work *r = w->user;
    if (lightsim_gpu_init(gpu, &w->err) != REFRACT_E_OK)
        return;
    glFinish();
    double t0 = gpu_time_ms(), c0 = process_cpu_s();
    struct lightsim_gpu_run *run = NULL;
    if (lightsim_gpu_begin(gpu, r->fields, &r->light, &r->set, &run, &w->err) != REFRACT_E_OK)
        return;
    bool done = false;
    while (!done && lightsim_gpu_advance(run, r->chunk, &done, &w->err) == REFRACT_E_OK)
        ;
    glFinish();
    r->ms = gpu_time_ms() - t0;
    r->cpu_s = process_cpu_s() - c0;
    r->peak_bytes = lightsim_gpu_run_peak_bytes(run);
    lightsim_gpu_stats(run, &r->stats);
    lightsim_gpu_run_destroy(run);
}

/* The icosphere of an "@ico<S>" scene, found as mesh "ico". */
static struct scene_volume ico_volume;

static const struct scene_volume *ico_lookup(void *ctx, const char *name)
{
    (void)ctx;
    return ico_volume.mesh && strcmp(name, SCENE_MESH_LOOKUP_PREFIX "ico") == 0 ? &ico_volume
                                                                               : NULL;
}

/* Example `base` (a file name without .json) with its sphere surfaces as mesh "ico". */
static struct scene *load_with_mesh_spheres(const char *dir, const char *base)
{
    char path[1200];
    snprintf(path, sizeof path, "%.600s/%.500s.json", dir, base);
    FILE *fp = fopen(path, "rb");
    char *text = NULL;
    long n = -1;
    if (fp && fseek(fp, 0, SEEK_END) == 0 && (n = ftell(fp)) >= 0 && fseek(fp, 0, SEEK_SET) == 0) {
        text = calloc((size_t)n + 1, 1);
        if (text && fread(text, 1, (size_t)n, fp) != (size_t)n)
            n = -1;
    }
    if (fp)
        fclose(fp);
    cJSON *root = n >= 0 && text ? cJSON_Parse(text) : NULL;
    free(text);
    cJSON *sf;
    cJSON_ArrayForEach(sf, cJSON_GetObjectItemCaseSensitive(root, "surfaces"))
    {
        const cJSON *shape = cJSON_GetObjectItemCaseSensitive(sf, "shape");
        const cJSON *radius = cJSON_GetObjectItemCaseSensitive(sf, "radius");
        if (!cJSON_IsString(shape) || strcmp(shape->valuestring, "sphere") != 0 ||
            !cJSON_IsNumber(radius))
            continue;
        double r = radius->valuedouble;
        cJSON_ReplaceItemInObjectCaseSensitive(sf, "shape", cJSON_CreateString("mesh"));
        cJSON_DeleteItemFromObjectCaseSensitive(sf, "radius");
        cJSON_AddStringToObject(sf, "mesh", "ico");
        cJSON_AddNumberToObject(sf, "scale", r);
    }
    char *json = root ? cJSON_PrintUnformatted(root) : NULL;
    cJSON_Delete(root);
    struct scene *s = NULL;
    struct err e = {0};
    if (json == NULL || scene_parse(json, strlen(json), NULL, &s, &e) != REFRACT_E_OK)
        fprintf(stderr, "refract-lightsim: %s: %s\n", path, json ? e.msg : "not read");
    free(json);
    return s;
}

static void bench_case(struct gpu *gpu, const char *dir, const char *name, int res, int obj_res,
                       const struct list *patches, int max_patches, int chunk)
{
    char path[1200], base[64];
    const char *at = strstr(name, "@ico");
    struct scene *s = NULL;
    struct mesh *ico = NULL;
    if (at) {
        struct err me = {0};
        snprintf(base, sizeof base, "%.*s", (int)(at - name), name);
        if (mesh_make_icosphere(atoi(at + 4), 1.0, &ico, &me) != REFRACT_E_OK) {
            fprintf(stderr, "refract-lightsim: %s: %s\n", name, me.msg);
            return;
        }
        ico_volume = (struct scene_volume){.mesh = ico};
        s = load_with_mesh_spheres(dir, base);
    } else {
        snprintf(path, sizeof path, "%.600s/%.500s.json", dir, name);
        s = bench_load_example("refract-lightsim", path, obj_res);
    }
    if (s == NULL) {
        mesh_destroy(ico);
        return;
    }
    s->lightsim.resolution = res;
    s->lightsim.max_patches = max_patches;
    struct scene_light light = {.kind = SCENE_LIGHT_DIRECTIONAL,
                                .direction = vec3_normalize(vec3_make(0.2, -1, 0.1)),
                                .color = {1, 1, 1},
                                .intensity = 1};
    if (s->light_count > 0)
        light = s->lights[0];
    struct err e = {0};
    struct lightsim_fields f;
    double t0 = gpu_time_ms();
    if (lightsim_fields_build_light(s, &light, ico_lookup, NULL, &f, &e) != REFRACT_E_OK) {
        fprintf(stderr, "refract-lightsim: %s: %s\n", name, e.msg);
        scene_destroy(s);
        mesh_destroy(ico);
        return;
    }
    double fields_ms = gpu_time_ms() - t0;
    for (int p = 0; p < patches->count; p++) {
        struct run_work r = {.fields = &f, .light = light, .set = s->lightsim, .chunk = chunk};
        r.set.initial_patches = atoi(patches->item[p]);
        r.work =
            (struct gpu_work){.priority = GPU_PRIORITY_LIGHTSIM, .run = run_on_gpu, .user = &r};
        if (gpu_run_sync(gpu, &r.work) != REFRACT_E_OK) {
            fprintf(stderr, "refract-lightsim: %s %d^3 N0 %d: %s\n", name, res,
                    r.set.initial_patches, r.work.err.msg);
            continue;
        }
        const struct lightsim_stats *st = &r.stats;
        double in = st->flux_in[1] > 0 ? st->flux_in[1] : 1;
        printf("| %s | %dx%dx%d | %d | %d | %.0f | %.0f | %.1f | %.1f | %lld | %d | %.2f | %.2f | "
               "%.1f | %.4f | %.4f |\n",
               name, f.grid.dims[0], f.grid.dims[1], f.grid.dims[2], r.set.initial_patches,
               st->patches_initial, fields_ms, r.ms, r.cpu_s, (double)r.peak_bytes / 1048576.0,
               st->steps, st->patches_peak, st->patch_steps / 1e6,
               r.ms > 0 ? st->patch_steps / (r.ms * 1e3) : 0, r.ms / (st->steps ? st->steps : 1),
               st->flux_culled[1] / in, st->flux_reflected[1] / in);
        fflush(stdout);
    }
    lightsim_fields_free(&f);
    scene_destroy(s);
    mesh_destroy(ico); /* the fields had their own copy */
    ico_volume.mesh = NULL;
}

int main(int argc, char **argv)
{
    struct list scenes, resolutions, patches;
    split("glass_sphere_voxels,wine_glass_voxels,bumpy_sphere", &scenes);
    split("64,128,256", &resolutions);
    split("32,64,128", &patches);
    int max_patches = 262144, chunk = 64, obj_res = 64;
    const char *src = getenv("REFRACT_SOURCE_DIR");
    char dir[512];
    snprintf(dir, sizeof dir, "%s/proto/examples", src ? src : ".");
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
        if (v && strcmp(a, "--scenes") == 0)
            split(v, &scenes), i++;
        else if (v && strcmp(a, "--resolutions") == 0)
            split(v, &resolutions), i++;
        else if (v && strcmp(a, "--patches") == 0)
            split(v, &patches), i++;
        else if (v && strcmp(a, "--max-patches") == 0)
            max_patches = atoi(v), i++;
        else if (v && strcmp(a, "--object-resolution") == 0)
            obj_res = atoi(v), i++;
        else if (v && strcmp(a, "--chunk") == 0)
            chunk = atoi(v), i++;
        else if (v && strcmp(a, "--examples") == 0)
            snprintf(dir, sizeof dir, "%s", v), i++;
        else {
            fprintf(
                stderr,
                "usage: refract-lightsim [--scenes a,b] [--resolutions 64,128,256] "
                "[--patches 32,64,128] [--max-patches N] [--chunk steps] [--object-resolution N] "
                "[--examples DIR]\n");
            return 2;
        }
    }
    struct gpu_desc desc = {.context = {.device = GPU_DEVICE_AUTO, .device_index = -1}};
    struct err e = {0};
    struct gpu *gpu = gpu_create(&desc, &e);
    if (gpu == NULL) {
        fprintf(stderr, "refract-lightsim: %s\n", e.msg);
        return 1;
    }
    bench_print_header(gpu, argc, argv);
    printf("| scene | light grid | N0 | patches in | fields ms (CPU) | simulation ms (wall) | "
           "process CPU s | peak GPU MiB | steps | peak patches | M patch-steps | M "
           "patch-steps/s | ms/step | culled | reflected |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int s = 0; s < scenes.count; s++)
        for (int r = 0; r < resolutions.count; r++)
            bench_case(gpu, dir, scenes.item[s], atoi(resolutions.item[r]), obj_res, &patches,
                       max_patches, chunk);
    gpu_destroy(gpu, NULL);
    return 0;
}
