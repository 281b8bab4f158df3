/*
 * test_gpu_queue.c - the GPU thread: the context comes up on EGL's device platform with
 * GL 4.5 core, every embedded compute program compiles, and the queue keeps its promises
 * (priority order, FIFO within a priority, deadlines, shutdown completes pending items,
 * an item that asks for more turns goes to the back of its line each time, an abandoned
 * item is not run).
 */
#include <stdatomic.h>
#include <stdbool.h>
#include <string.h>
#include <unistd.h>

#include "gpu/queue.h"
#include "test.h"

static struct gpu *start_gpu(void)
{
    struct gpu_desc desc = {.context = {.device = GPU_DEVICE_AUTO, .device_index = -1}};
    struct err e = {0};
    struct gpu *g = gpu_create(&desc, &e);
    if (g == NULL) {
        fprintf(stderr, "gpu_create failed: %s\n", e.msg);
        test_setup_failed("test_gpu_queue", "no EGL/GL 4.5 context could be made on this machine");
    }
    return g;
}

static void context_reports_gl45_core_and_renderer(struct gpu *g)
{
    const struct gpu_context_info *info = gpu_info(g);
    CHECK(strlen(info->renderer) > 0);
    CHECK_CONTAINS(info->version, "4.");
    CHECK(info->max_3d_texture_size >= 256);
    CHECK(strcmp(info->device_kind, "hardware") == 0 || strcmp(info->device_kind, "software") == 0);
    printf("renderer: %s | %s | %s (%s)\n", info->vendor, info->renderer, info->version,
           info->device_kind);
}

static void all_programs_compiled(struct gpu *g);

struct order_work {
    struct gpu_work w;
    int tag;
    int *log;
    atomic_int *count;
};

static void blocker_run(struct gpu_work *w, struct gpu *g)
{
    (void)g;
    (void)w;
    usleep(100 * 1000); /* hold the GPU thread while the others queue up */
}

static void order_run(struct gpu_work *w, struct gpu *g)
{
    (void)g;
    struct order_work *o = (struct order_work *)w;
    int i = atomic_fetch_add(o->count, 1);
    o->log[i] = o->tag;
}

/* Which kernel variants the test compiles. Each switch alone, every pair of the voxel
 * switches and all of them together: the #if blocks that could clash are pairs, and
 * compiling all 256 voxel variants cost about 500 s of a fresh CI machine's 2 cores (Mesa's
 * shader cache starts empty there; measured 2026-12-03). With GPU_VARIANT_SURFACES, the
 * surfaces code with each other bit alone and with all of them (the surfaces code is one
 * block that does not depend on the voxel switches). The sanitizer build, whose C this
 * test is there to check and whose GLSL is the same, compiles each switch alone and all
 * together. */
static bool variant_checked(unsigned v)
{
    if (test_sanitized())
        return (v & (v - 1)) == 0 || v == GPU_VARIANT_COUNT - 1;
    unsigned rest = v & ~GPU_VARIANT_SURFACES, all = (GPU_VARIANT_COUNT - 1) - GPU_VARIANT_SURFACES;
    int bits = __builtin_popcount(rest);
    if (v & GPU_VARIANT_SURFACES)
        return bits <= 1 || rest == all;
    return bits <= 2 || rest == all;
}

static void programs_run(struct gpu_work *w, struct gpu *g)
{
    const struct gpu_programs *p = gpu_programs_get(g);
    int ok = 1;
    for (int k = 0; k < GPU_KERNEL_COUNT; k++) {
        for (unsigned v = 0; v < GPU_VARIANT_COUNT; v++) {
            if (!variant_checked(v))
                continue;
            GLuint prog = gpu_program_get(p, (enum gpu_kernel)k, v);
            ok &= prog != 0 && glIsProgram(prog);
        }
    }
    if (!ok)
        err_set(&w->err, REFRACT_E_GPU_ERROR, "a program is missing");
}

static void all_programs_compiled(struct gpu *g)
{
    struct gpu_work w = {.priority = GPU_PRIORITY_INTERACTIVE, .run = programs_run};
    CHECK_INT(gpu_run_sync(g, &w), REFRACT_E_OK);
}

static void interactive_runs_before_batch_and_fifo_within_priority(struct gpu *g)
{
    int log[8] = {0};
    atomic_int count = 0;
    struct gpu_work blocker = {.priority = GPU_PRIORITY_INTERACTIVE, .run = blocker_run};
    struct err e;
    CHECK_INT(gpu_submit(g, &blocker, &e), REFRACT_E_OK);
    usleep(20 * 1000);
    struct order_work items[4] = {
        {.w = {.priority = GPU_PRIORITY_BATCH, .run = order_run}, .tag = 1},
        {.w = {.priority = GPU_PRIORITY_LIGHTSIM, .run = order_run}, .tag = 2},
        {.w = {.priority = GPU_PRIORITY_INTERACTIVE, .run = order_run}, .tag = 3},
        {.w = {.priority = GPU_PRIORITY_INTERACTIVE, .run = order_run}, .tag = 4},
    };
    for (int i = 0; i < 4; i++) {
        items[i].log = log;
        items[i].count = &count;
        CHECK_INT(gpu_submit(g, &items[i].w, &e), REFRACT_E_OK);
    }
    /* A sync item at the lowest priority runs after all of them. */
    struct gpu_work last = {.priority = GPU_PRIORITY_MAINTENANCE, .run = blocker_run};
    CHECK_INT(gpu_run_sync(g, &last), REFRACT_E_OK);
    CHECK_INT(atomic_load(&count), 4);
    CHECK_INT(log[0], 3);
    CHECK_INT(log[1], 4);
    CHECK_INT(log[2], 2);
    CHECK_INT(log[3], 1);
}

static void expired_item_is_not_run_and_reports_timeout(struct gpu *g)
{
    int log[2] = {0};
    atomic_int count = 0;
    struct order_work o = {.w = {.priority = GPU_PRIORITY_INTERACTIVE,
                                 .deadline_ms = gpu_now_ms() - 1,
                                 .label = "test item",
                                 .run = order_run},
                           .tag = 9,
                           .log = log,
                           .count = &count};
    CHECK_INT(gpu_run_sync(g, &o.w), REFRACT_E_TIMEOUT);
    CHECK_INT(atomic_load(&count), 0);
    CHECK_CONTAINS(o.w.err.msg, "deadline");
}

/* An item that needs three turns (a render of three tiles). */
static void turns_run(struct gpu_work *w, struct gpu *g)
{
    struct order_work *o = (struct order_work *)w;
    order_run(w, g);
    o->tag += 10; /* turn 1 logs 5, turn 2 logs 15, turn 3 logs 25 */
    w->again = o->tag < 30;
}

static bool always_abandoned(struct gpu_work *w)
{
    (void)w;
    return true;
}

static atomic_int abandoned_code;
static void abandoned_done(struct gpu_work *w)
{
    atomic_store(&abandoned_code, (int)w->err.code);
}

static void turns_take_their_place_in_line_and_abandoned_items_are_dropped(struct gpu *g)
{
    int log[8] = {0};
    atomic_int count = 0;
    atomic_store(&abandoned_code, -1);
    struct gpu_work blocker = {.priority = GPU_PRIORITY_INTERACTIVE, .run = blocker_run};
    struct err e;
    CHECK_INT(gpu_submit(g, &blocker, &e), REFRACT_E_OK);
    usleep(20 * 1000);
    struct order_work items[4] = {
        {.w = {.priority = GPU_PRIORITY_INTERACTIVE, .run = turns_run}, .tag = 5},
        {.w = {.priority = GPU_PRIORITY_INTERACTIVE, .run = order_run}, .tag = 1},
        {.w = {.priority = GPU_PRIORITY_INTERACTIVE, .run = order_run}, .tag = 2},
        {.w = {.priority = GPU_PRIORITY_INTERACTIVE,
               .label = "gone item",
               .run = order_run,
               .abandoned = always_abandoned,
               .done = abandoned_done},
         .tag = 3},
    };
    for (int i = 0; i < 4; i++) {
        items[i].log = log;
        items[i].count = &count;
        CHECK_INT(gpu_submit(g, &items[i].w, &e), REFRACT_E_OK);
    }
    struct gpu_work last = {.priority = GPU_PRIORITY_MAINTENANCE, .run = blocker_run};
    CHECK_INT(gpu_run_sync(g, &last), REFRACT_E_OK);
    /* the long item's turns alternate with the items queued behind it */
    CHECK_INT(atomic_load(&count), 5);
    CHECK_INT(log[0], 5);
    CHECK_INT(log[1], 1);
    CHECK_INT(log[2], 2);
    CHECK_INT(log[3], 15);
    CHECK_INT(log[4], 25);
    CHECK_INT(atomic_load(&abandoned_code), REFRACT_E_TIMEOUT);
    CHECK_CONTAINS(items[3].w.err.msg, "closed the connection");
}

static atomic_int shutdown_codes[3];
static void record_done(struct gpu_work *w)
{
    struct order_work *o = (struct order_work *)w;
    atomic_store(&shutdown_codes[o->tag], (int)w->err.code);
}

static void shutdown_completes_pending_items(void)
{
    struct gpu *g = start_gpu();
    int log[4] = {0};
    atomic_int count = 0;
    struct gpu_work blocker = {.priority = GPU_PRIORITY_INTERACTIVE, .run = blocker_run};
    struct err e;
    gpu_submit(g, &blocker, &e);
    usleep(20 * 1000);
    struct order_work pending = {
        .w = {.priority = GPU_PRIORITY_INTERACTIVE, .run = order_run, .done = record_done},
        .tag = 0,
        .log = log,
        .count = &count};
    struct order_work maint = {
        .w = {.priority = GPU_PRIORITY_MAINTENANCE, .run = order_run, .done = record_done},
        .tag = 1,
        .log = log,
        .count = &count};
    /* Ahead-of-use maintenance (a scene build nobody waits for) is dropped at shutdown. */
    struct order_work ahead = {.w = {.priority = GPU_PRIORITY_MAINTENANCE,
                                     .skip_on_shutdown = true,
                                     .run = order_run,
                                     .done = record_done},
                               .tag = 2,
                               .log = log,
                               .count = &count};
    for (int i = 0; i < 3; i++)
        atomic_store(&shutdown_codes[i], -1);
    CHECK_INT(gpu_submit(g, &pending.w, &e), REFRACT_E_OK);
    CHECK_INT(gpu_submit(g, &maint.w, &e), REFRACT_E_OK);
    CHECK_INT(gpu_submit(g, &ahead.w, &e), REFRACT_E_OK);
    gpu_destroy(g, NULL);
    CHECK_INT(atomic_load(&shutdown_codes[0]), REFRACT_E_SHUTTING_DOWN);
    CHECK_INT(atomic_load(&shutdown_codes[1]), REFRACT_E_OK);
    CHECK_INT(atomic_load(&shutdown_codes[2]), REFRACT_E_SHUTTING_DOWN);
    CHECK_INT(atomic_load(&count), 1); /* only the needed maintenance item ran */
}

int main(void)
{
    struct gpu *g = start_gpu();
    context_reports_gl45_core_and_renderer(g);
    all_programs_compiled(g);
    interactive_runs_before_batch_and_fifo_within_priority(g);
    expired_item_is_not_run_and_reports_timeout(g);
    turns_take_their_place_in_line_and_abandoned_items_are_dropped(g);
    gpu_destroy(g, NULL);
    shutdown_completes_pending_items();
    return test_summary("test_gpu_queue");
}
