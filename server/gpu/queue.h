/*
 * queue.h - the GPU thread and its priority queue of work items.
 *
 * DESIGN (docs/ARCHITECTURE.md, "One thread owns the GPU"): a GL context belongs to one
 * thread, so refractd runs exactly one GPU thread. It takes work items from a queue with
 * four priorities, interactive renders first, then light-simulation chunks, then batch
 * frames, then maintenance, FIFO within a priority. Items never preempt one another:
 * long work is split into bounded chunks by its owner and resubmitted, or runs one
 * chunk per turn (`again`: a large render's tiles), going to the back of its priority's
 * line after each, so the items queued behind it take turns with it (round robin).
 *
 * Each item carries a deadline. When the thread pops an item whose deadline has passed
 * (its requester may be gone: a suspended HTTP client can leave unnoticed), the item is
 * not run; its `done` is called with err.code = REFRACT_E_TIMEOUT. The same happens when
 * its `abandoned` says that nobody waits for it any more. On shutdown every
 * pending item except maintenance not marked skip_on_shutdown is completed with
 * REFRACT_E_SHUTTING_DOWN, so every suspended connection gets resumed.
 *
 * Ownership: a submitted item is borrowed by the queue until its `done` has been called;
 * the submitter must keep it alive until then and may free it inside `done`.
 * Thread: gpu_submit from any thread; run/done are called on the GPU thread.
 */
#ifndef REFRACT_GPU_QUEUE_H
#define REFRACT_GPU_QUEUE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"
#include "context.h"
#include "program.h"

enum gpu_priority {
    GPU_PRIORITY_INTERACTIVE = 0, /* renders and traces a person waits for */
    GPU_PRIORITY_LIGHTSIM = 1,    /* chunks of light simulation */
    GPU_PRIORITY_BATCH = 2,       /* batch job frames */
    GPU_PRIORITY_MAINTENANCE = 3, /* scene builds ahead of use, frees; always run */
    GPU_PRIORITY_COUNT = 4,
};

struct gpu;

struct gpu_work {
    enum gpu_priority priority;
    int64_t deadline_ms; /* gpu_now_ms() clock; 0 = no deadline */
    const char *label;   /* for logs */
    /* Maintenance that only works ahead of use (a scene build nobody waits for): at
     * shutdown it is completed with SHUTTING_DOWN instead of run, so stopping does not
     * wait for builds whose results would be thrown away. Frees leave it false. */
    bool skip_on_shutdown;
    /* Runs on the GPU thread; reports failure through w->err. */
    void (*run)(struct gpu_work *w, struct gpu *gpu);
    /* Called on the GPU thread after run, or instead of it with w->err.code set to
     * TIMEOUT or SHUTTING_DOWN. Must not block. */
    void (*done)(struct gpu_work *w);
    /* Optional: true when nobody waits for the result any more (an HTTP client closed
     * its connection while the item was queued). Called on the GPU thread before every
     * turn; such an item is not run, and done gets REFRACT_E_TIMEOUT. */
    bool (*abandoned)(struct gpu_work *w);
    /* The log's reason when abandoned said true (NULL: "its client closed the
     * connection"). */
    const char *abandoned_why;
    /* Set by run (it starts each turn false) to ask for another turn: the item goes to
     * the back of its priority's line instead of done being called. An error ends it. */
    bool again;
    struct err err;
    void *user; /* the submitter's context */
    /* queue-private */
    struct gpu_work *next;
    int64_t queued_ms; /* submitted (the deadline's message counts from here) */
    int64_t turn_ms;   /* entered the line for this turn (the wait /metrics counts) */
};

struct gpu_desc {
    struct gpu_context_desc context;
    const char *shader_dir; /* NULL = embedded shaders */
    size_t max_queued;      /* 0 = 256; gpu_submit answers BUSY beyond it */
};

/* Starts the GPU thread, which creates the EGL context and builds every program, and
 * waits for that to finish. Returns a new gpu (destroy with gpu_destroy) or NULL with e
 * filled by the context or shader failure. */
struct gpu *gpu_create(const struct gpu_desc *desc, struct err *e);

/* Stops the thread: pending items are completed (maintenance runs, others get
 * SHUTTING_DOWN), then `final` (may be NULL) runs on the GPU thread so its owner can
 * release GL objects, then the context is destroyed and the thread joined. The struct
 * stays valid: gpu_info still answers and gpu_submit answers SHUTTING_DOWN, so HTTP
 * threads that were resumed by the drain can finish their answers. A second call is a
 * no-op, as is NULL. */
void gpu_stop(struct gpu *g, struct gpu_work *final);

/* gpu_stop (if not yet done), then frees g. Call it only when no other thread can use
 * g any more (after http_server_stop). NULL is a no-op. */
void gpu_destroy(struct gpu *g, struct gpu_work *final);

/* Queues w. Returns OK, or BUSY when the queue is full, or SHUTTING_DOWN; then w is not
 * queued and its done will not be called. */
enum refract_code gpu_submit(struct gpu *g, struct gpu_work *w, struct err *e);

/* Queues w and waits until its done has been called; returns w->err.code. w->done may
 * be NULL; w->again is honoured (w takes turns until it asks for none: `refractd --batch`
 * draws its frames in tiles this way). For tests, benchmarks, start-up and the one-shot
 * batch mode; never call it from the GPU thread. */
enum refract_code gpu_run_sync(struct gpu *g, struct gpu_work *w);

/* Borrowed; valid for the gpu's lifetime. */
const struct gpu_context_info *gpu_info(const struct gpu *g);
/* GPU thread only. */
const struct gpu_programs *gpu_programs_get(const struct gpu *g);

size_t gpu_queue_length(struct gpu *g);
/* Monotonic milliseconds. */
int64_t gpu_now_ms(void);
/* Monotonic milliseconds with sub-millisecond resolution, for timings. */
double gpu_time_ms(void);

#endif
