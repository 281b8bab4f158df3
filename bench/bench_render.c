/*
 * bench_render.c - refract-bench: the view renderer's speed on the render core alone (no
 * HTTP, no encoding), for BENCHMARKS.md. Not a test: it asserts nothing and prints a
 * Markdown table.
 *
 *     build/refract-bench [--scenes glass_sphere_voxels,luneburg_lens] [--resolutions 64,128,256]
 *                         [--sizes 320x240,640x480,1280x720,1920x1080]
 *                         [--steppers rk4,euler] [--steps 0.5] [--budget-ms 3000]
 *
 * For every scene, voxel resolution, stepper, step (voxels) and image size it renders
 * once to warm
 * up (llvmpipe compiles a shader variant on its first dispatch), then repeats while the
 * time budget lasts (at least once, at most 7 times) and reports the median GPU time
 * (dispatch to glFinish, no read-back) and million rays per second. Scene build time
 * (field evaluation on the CPU plus smoothing and gradient on the GPU) is reported per
 * scene and resolution. Scenes are read from proto/examples/<name>.json with every
 * object's resolution replaced.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "example_scene.h"
#include "gpu/queue.h"
#include "render/render.h"
#include "scene/scene.h"

#define MAX_LIST 16

struct list {
    char item[MAX_LIST][64];
    int count;
};

struct options {
    struct list scenes, resolutions, sizes, steppers, steps;
    double budget_ms;
    const char *examples_dir;
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

/* The example scene with every object's resolution set to res. */
static struct scene *load_scene(const struct options *o, const char *name, int res)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s.json", o->examples_dir, name);
    return bench_load_example("refract-bench", path, res);
}

struct bench_ctx {
    struct gpu_work work;
    struct render *render;
    struct render_scene_source src;
    struct render_view_request req;
    struct render_view_result result;
    struct render_scene_status status;
    int op; /* 0 create, 1 prepare, 2 render, 3 forget, 4 destroy */
};

static void bench_run(struct gpu_work *w, struct gpu *gpu)
{
    struct bench_ctx *c = w->user;
    switch (c->op) {
    case 0:
        c->render = render_create(gpu, &(struct render_desc){0}, &w->err);
        break;
    case 1:
        render_scene_prepare(c->render, &c->src, &c->status, &w->err);
        break;
    case 2:
        free(c->result.rgba);
        c->result.rgba = NULL;
        render_view(c->render, &c->src, &c->req, &c->result, &w->err);
        break;
    case 3:
        render_scene_forget(c->render, c->src.id);
        break;
    default:
        render_destroy(c->render);
        break;
    }
}

static enum refract_code on_gpu(struct gpu *gpu, struct bench_ctx *c, int op)
{
    c->op = op;
    c->work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = bench_run, .user = c};
    enum refract_code rc = gpu_run_sync(gpu, &c->work);
    if (rc != REFRACT_E_OK)
        fprintf(stderr, "refract-bench: %s\n", c->work.err.msg);
    return rc;
}

static void bench_scene(struct gpu *gpu, struct bench_ctx *c, const struct options *o,
                        const char *name, int res)
{
    struct scene *s = load_scene(o, name, res);
    if (s == NULL)
        return;
    char id[96];
    snprintf(id, sizeof id, "%s-%d", name, res);
    c->src = (struct render_scene_source){.id = id, .generation = 1, .scene = s};
    if (on_gpu(gpu, c, 1) != REFRACT_E_OK) {
        scene_destroy(s);
        return;
    }
    printf("| %s | %d^3 | build | | | %.0f | | %.1f MiB |\n", name, res, c->status.build_ms,
           (double)c->status.gpu_bytes / 1048576.0);
    for (int k = 0; k < o->steppers.count; k++) {
        for (int st = 0; st < o->steps.count; st++) {
            for (int z = 0; z < o->sizes.count; z++) {
                int w = 0, h = 0;
                if (sscanf(o->sizes.item[z], "%dx%d", &w, &h) != 2)
                    continue;
                c->req.camera = s->camera;
                c->req.camera.width = w;
                c->req.camera.height = h;
                c->req.settings = s->render;
                c->req.settings.step_voxels = atof(o->steps.item[st]);
                c->req.settings.stepper = strcmp(o->steppers.item[k], "euler") == 0
                                              ? SCENE_STEPPER_EULER
                                              : SCENE_STEPPER_RK4;
                if (on_gpu(gpu, c, 2) != REFRACT_E_OK) /* warm-up: variant compile */
                    continue;
                double times[7];
                int runs = 0;
                double spent = 0.0;
                while (runs < 7 && (runs == 0 || spent < o->budget_ms)) {
                    if (on_gpu(gpu, c, 2) != REFRACT_E_OK)
                        break;
                    times[runs++] = c->result.gpu_ms;
                    spent += c->result.gpu_ms;
                }
                if (runs == 0)
                    continue;
                qsort(times, (size_t)runs, sizeof times[0], bench_compare_doubles);
                double median = times[runs / 2];
                printf("| %s | %d^3 | %dx%d | %s | %s | %.1f | %.2f | %d runs |\n", name, res, w, h,
                       o->steppers.item[k], o->steps.item[st], median,
                       (double)w * h / (median * 1000.0), runs);
                fflush(stdout);
            }
        }
    }
    on_gpu(gpu, c, 3);
    scene_destroy(s);
}

int main(int argc, char **argv)
{
    struct options o = {.budget_ms = 3000, .examples_dir = "proto/examples"};
    split("0.5", &o.steps);
    split("glass_sphere_voxels,luneburg_lens", &o.scenes);
    split("64,128,256", &o.resolutions);
    split("320x240,640x480,1280x720,1920x1080", &o.sizes);
    split("rk4,euler", &o.steppers);
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--scenes"))
            split(argv[i + 1], &o.scenes);
        else if (!strcmp(argv[i], "--resolutions"))
            split(argv[i + 1], &o.resolutions);
        else if (!strcmp(argv[i], "--sizes"))
            split(argv[i + 1], &o.sizes);
        else if (!strcmp(argv[i], "--steppers"))
            split(argv[i + 1], &o.steppers);
        else if (!strcmp(argv[i], "--steps"))
            split(argv[i + 1], &o.steps);
        else if (!strcmp(argv[i], "--budget-ms"))
            o.budget_ms = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--examples"))
            o.examples_dir = argv[i + 1];
        else {
            fprintf(stderr, "refract-bench: unknown option %s (see bench/bench_render.c)\n",
                    argv[i]);
            return 2;
        }
    }
    struct err e = {0};
    struct gpu_desc desc = {.context = {.device_index = -1}};
    struct gpu *gpu = gpu_create(&desc, &e);
    if (gpu == NULL) {
        fprintf(stderr, "refract-bench: %s\n", e.msg);
        return 1;
    }
    struct bench_ctx c = {0};
    if (on_gpu(gpu, &c, 0) != REFRACT_E_OK)
        return 1;
    bench_print_header(gpu, argc, argv);
    printf("| scene | voxels | image | stepper | step | GPU ms (median) | Mrays/s | notes |\n");
    printf("|---|---|---|---|---|---|---|---|\n");
    for (int si = 0; si < o.scenes.count; si++)
        for (int ri = 0; ri < o.resolutions.count; ri++)
            bench_scene(gpu, &c, &o, o.scenes.item[si], atoi(o.resolutions.item[ri]));
    free(c.result.rgba);
    on_gpu(gpu, &c, 4);
    gpu_destroy(gpu, NULL);
    return 0;
}
