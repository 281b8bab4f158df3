/*
 * bench_surfaces.c - refract-surfaces: the view renderer's speed on exact surfaces against
 * the same objects as voxels, on the render core alone (no HTTP, no encoding), for
 * BENCHMARKS.md ("Exact surfaces"). Not a test: it asserts nothing and prints a Markdown
 * table.
 *
 *     build/refract-surfaces [--sizes 320x240,1920x1080] [--budget-ms 3000]
 *
 * Scenes: glass_sphere.json (an exact sphere), glass_sphere_voxels.json (the same sphere
 * at 128^3), the same sphere as a 327,680-triangle icosphere mesh surface
 * (mesh_make_icosphere, 7 subdivisions), and wine_glass.json (the glass and the wine as
 * lathes; its receiver and light are dropped for this measurement, which times the
 * march alone), and the Luneburg lens as 128^3 voxels (luneburg_lens.json) and filling its
 * exact sphere (luneburg_lens_exact.json). Each is rendered once to warm up (the kernel variant compiles), then
 * repeated while the budget lasts (1..7 times); the median GPU time (dispatch to
 * glFinish) is reported, with the ratio to the voxel sphere at the same size.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "example_scene.h"
#include "gpu/queue.h"
#include "mesh/mesh.h"
#include "mesh/mesh_rt.h"
#include "render/render.h"
#include "scene/scene.h"

static struct scene_volume ico_volume;

static const struct scene_volume *lookup(void *ctx, const char *name)
{
    (void)ctx;
    return strcmp(name, SCENE_MESH_LOOKUP_PREFIX "ico") == 0 ? &ico_volume : NULL;
}

struct job {
    struct gpu_work work;
    struct render *render;
    struct render_scene_source src;
    struct render_view_request req;
    struct render_view_result result;
    int op; /* 0 create, 1 render, 2 destroy */
};

static void run(struct gpu_work *w, struct gpu *gpu)
{
    struct job *j = w->user;
    if (j->op == 0) {
        j->render = render_create(gpu, &(struct render_desc){0}, &w->err);
    } else if (j->op == 1) {
        free(j->result.rgba);
        j->result.rgba = NULL;
        render_view(j->render, &j->src, &j->req, &j->result, &w->err);
    } else {
        render_destroy(j->render);
    }
}

static int on_gpu(struct gpu *gpu, struct job *j, int op)
{
    j->op = op;
    j->work = (struct gpu_work){.priority = GPU_PRIORITY_INTERACTIVE, .run = run, .user = j};
    int rc = gpu_run_sync(gpu, &j->work);
    if (rc != REFRACT_E_OK)
        fprintf(stderr, "refract-surfaces: %s\n", j->work.err.msg);
    return rc;
}

/* Median GPU ms of rendering s at w x h, or -1. */
static double time_scene(struct gpu *gpu, struct job *j, const char *id, struct scene *s, int w,
                         int h, double budget_ms)
{
    j->src = (struct render_scene_source){.id = id, .generation = 1, .scene = s, .lookup = lookup};
    j->req = (struct render_view_request){.camera = s->camera, .settings = s->render};
    j->req.camera.width = w;
    j->req.camera.height = h;
    if (on_gpu(gpu, j, 1) != REFRACT_E_OK)
        return -1.0;
    double t[7], spent = 0.0;
    int n = 0;
    while (n < 7 && (n == 0 || spent < budget_ms)) {
        if (on_gpu(gpu, j, 1) != REFRACT_E_OK)
            return -1.0;
        t[n++] = j->result.gpu_ms;
        spent += j->result.gpu_ms;
    }
    qsort(t, (size_t)n, sizeof t[0], bench_compare_doubles);
    return t[n / 2];
}

int main(int argc, char **argv)
{
    const char *sizes = "320x240,1920x1080";
    double budget_ms = 3000;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--sizes") == 0 && i + 1 < argc)
            sizes = argv[++i];
        else if (strcmp(argv[i], "--budget-ms") == 0 && i + 1 < argc)
            budget_ms = atof(argv[++i]);
        else {
            fprintf(stderr, "usage: refract-surfaces [--sizes WxH,...] [--budget-ms MS]\n");
            return 2;
        }
    }
    struct err e = {0};
    struct mesh *ico = NULL;
    if (mesh_make_icosphere(7, 1.0, &ico, &e) != REFRACT_E_OK) {
        fprintf(stderr, "refract-surfaces: %s\n", e.msg);
        return 1;
    }
    ico_volume = (struct scene_volume){.mesh = ico};
    enum { SCENES = 6 };
    struct scene *scenes[SCENES] = {
        bench_load_example("refract-surfaces", "proto/examples/glass_sphere_voxels.json", 128),
        bench_load_example("refract-surfaces", "proto/examples/glass_sphere.json", 128),
        NULL,
        bench_load_example("refract-surfaces", "proto/examples/wine_glass.json", 0),
        bench_load_example("refract-surfaces", "proto/examples/luneburg_lens.json", 128),
        bench_load_example("refract-surfaces", "proto/examples/luneburg_lens_exact.json", 128),
    };
    const char *names[SCENES] = {"glass sphere, 128^3 voxels",
                                 "glass sphere, exact",
                                 "glass sphere, 327,680-triangle icosphere",
                                 "wine glass with wine",
                                 "Luneburg lens, 128^3 voxels",
                                 "Luneburg lens in its exact sphere (field inside)"};
    const char *ids[SCENES] = {"voxels", "sphere", "ico", "wine", "luneburg", "luneburg_exact"};
    /* The icosphere: glass_sphere.json's sphere with the mesh in its place. */
    if (scenes[1] != NULL) {
        const char *doc =
            "{\"camera\": {\"eye\": [0, 1.0, 3.7], \"look_at\": [0, 0, 0], \"fov_y_deg\": 40},"
            " \"surfaces\": [{\"shape\": \"mesh\", \"mesh\": \"ico\", \"scale\": 0.8,"
            " \"medium\": {\"ior\": 1.5, \"attenuation\": [0.02, 0.01, 0.02]}}]}";
        if (scene_parse(doc, strlen(doc), NULL, &scenes[2], &e) != REFRACT_E_OK)
            fprintf(stderr, "refract-surfaces: %s\n", e.msg);
    }
    if (scenes[3] != NULL) {
        scenes[3]->light_count = 0; /* the march alone (see above) */
        scenes[3]->receiver.enabled = false;
    }
    struct gpu_desc desc = {.context = {.device_index = -1}};
    struct gpu *gpu = gpu_create(&desc, &e);
    if (gpu == NULL) {
        fprintf(stderr, "refract-surfaces: %s\n", e.msg);
        return 1;
    }
    bench_print_header(gpu, argc, argv);
    struct job j = {0};
    if (on_gpu(gpu, &j, 0) != REFRACT_E_OK)
        return 1;
    printf("\n| scene | size | GPU ms (median) | Mrays/s | vs voxel sphere |\n");
    printf("| --- | --- | --- | --- | --- |\n");
    const char *p = sizes;
    while (*p) {
        int w = 0, h = 0;
        if (sscanf(p, "%dx%d", &w, &h) != 2)
            break;
        double base = -1.0;
        for (int k = 0; k < SCENES; k++) {
            if (scenes[k] == NULL)
                continue;
            double ms = time_scene(gpu, &j, ids[k], scenes[k], w, h, budget_ms);
            if (k == 0)
                base = ms;
            if (ms < 0)
                continue;
            printf("| %s | %dx%d | %.1f | %.2f | %s%.2fx |\n", names[k], w, h, ms,
                   (double)w * h / (ms * 1000.0), k == 0 ? "" : "", base > 0 ? base / ms : 0.0);
            fflush(stdout);
        }
        p += strcspn(p, ",");
        if (*p == ',')
            p++;
    }
    free(j.result.rgba);
    on_gpu(gpu, &j, 2);
    gpu_destroy(gpu, NULL);
    for (int k = 0; k < SCENES; k++)
        scene_destroy(scenes[k]);
    mesh_destroy(ico);
    return 0;
}
