/*
 * view_internal.h - what the view module's files share: the registry and session
 * structs, the frame job that travels scheduler -> GPU thread -> encoder, and the calls
 * between the files. Not used outside server/view/.
 *
 * INVARIANTS (session, under its lock `mu`):
 *   - change_gen counts the changes of what the session shows; full_gen is the change_gen
 *     of the newest full frame started (or the newest change a failed frame gave up on),
 *     preview_gen that of the newest preview. The session needs a frame exactly when
 *     change_gen != full_gen.
 *   - in_flight: a frame job exists (queued on the GPU, rendering, or encoding); at most
 *     one per session.
 */
#ifndef REFRACT_VIEW_INTERNAL_H
#define REFRACT_VIEW_INTERNAL_H

#include <pthread.h>
#include <stdatomic.h>
#include <stdbool.h>

#include "../request/render_tiles.h"
#include "view.h"

struct view_encoder;

struct view_session {
    atomic_int refs;
    char id[VIEW_ID_LEN + 1];
    char scene[STORE_ID_MAX];
    struct view_registry *reg; /* borrowed: sessions end before the registry goes */

    pthread_mutex_t mu; /* everything below except the watchers */
    struct view_settings settings;
    struct scene_render_settings last_render; /* of the newest frame started */
    bool ended;
    uint64_t change_gen, full_gen, preview_gen;
    bool in_flight;
    int64_t next_start_ms;      /* max_fps spacing: no frame starts before this */
    double last_full_render_ms; /* progressive: previews only when full frames are slow */
    int64_t last_activity_ms;   /* the last request, or when the last stream left */
    int watcher_count;
    struct view_frame *frame; /* the newest; owned reference or NULL */
    uint64_t seq;
    struct err last_error; /* of the newest frame that failed; code OK = none */
    /* The newest full frame's linear image (its render result, 16 bytes a pixel): while
     * hdr_gen == change_gen it is what the settings show but for the encode-only ones
     * (exposure, tonemap, jpeg_quality, max_fps, progressive), and the next frame is
     * encoded from it instead of rendered (view_session_update, the scheduler). Replaced
     * only when a full render finishes; a re-encode job borrows it (one frame in flight
     * per session, so nothing replaces it meanwhile). */
    float *hdr;
    int hdr_width, hdr_height;
    double hdr_render_ms;
    const char *hdr_irradiance;
    uint64_t hdr_gen;
    long long frames_rendered, frames_reencoded;
    /* Reference mode (docs/views.md "Reference mode"): the path-traced image being refined
     * (touched only by the session's one job in flight), the fewest paths a pixel had in
     * the newest frame, and whether it is below the target for the current change (then
     * the session needs another frame although change_gen == full_gen). */
    struct view_reference *ref;
    uint32_t ref_samples;
    bool ref_refining;

    pthread_mutex_t watch_mu; /* the watcher list */
    struct view_watcher *watchers;
};

/* One frame on its way: made by the scheduler, rendered on the GPU thread, encoded on an
 * encoder thread, then freed. Owns a session reference and a version reference. */
struct view_job {
    struct gpu_work work;
    struct view_session *session;
    struct store_scene *version;
    struct render_view_request request;
    struct render_light lights[SCENE_MAX_LIGHTS];
    struct render_view_result result;
    const char *irradiance;
    enum view_frame_kind kind;
    bool reencode;                 /* from the session's hdr (result.rgba borrows it): no GPU
                                      work */
    uint64_t change_gen;           /* what the frame shows */
    /* A large frame is drawn in tiles, one per GPU turn (render_tiles.h), so that other
     * work runs between them (docs/api.md "Fair sharing"). */
    struct render_tiles tiles;
    struct view_settings settings; /* snapshot at the frame's start */
    struct view_job *next;         /* encoder queue */
    uint32_t ref_samples;          /* reference mode: the fewest paths a pixel has now */
};

struct view_registry {
    struct view_registry_desc desc;
    int event_token; /* 0 = not listening */

    pthread_mutex_t mu;
    pthread_cond_t wake;            /* the scheduler: something changed (CLOCK_MONOTONIC) */
    pthread_cond_t idle;            /* in_flight reached 0 */
    struct view_session **sessions; /* desc.max_views slots, in creation order */
    int count;
    int in_flight; /* frame jobs alive */
    bool stopping, stopped;
    pthread_t scheduler;
    bool scheduler_started;

    struct view_encoder *encoder;
};

/* ---- view_session.c ---- */
/* A new session (one reference) for scene id on registry r; NULL when out of memory. */
struct view_session *view_session_new(struct view_registry *r, const char *scene,
                                      const struct view_settings *st, int64_t now_ms);
/* Marks the session ended and wakes its watchers. Does not touch the registry. */
void view_session_mark_ended(struct view_session *s);
/* A change of what the session shows (caller holds s->mu). */
void view_session_changed_locked(struct view_session *s);
/* Calls every watcher's wake. */
void view_session_wake_watchers(struct view_session *s);

/* ---- view_registry.c ---- */
/* Wakes the scheduler (takes the registry lock). */
void view_registry_kick(struct view_registry *r);
/* Removes s from the table (caller holds r->mu) and returns the table's reference, or
 * NULL when it was not listed. */
struct view_session *view_registry_unlist_locked(struct view_registry *r, struct view_session *s);

/* ---- view_scheduler.c ---- */
/* The scheduler thread's body; arg is the registry. */
void *view_scheduler_main(void *arg);
/* A frame job finished (encoded, or failed with e): publishes frame (consumed; may be
 * NULL), updates the session's state, frees the job, wakes the scheduler. Encoder
 * threads (and the scheduler for jobs that never reached the GPU). */
void view_job_finish(struct view_registry *r, struct view_job *job, struct view_frame *frame,
                     const struct err *e);

/* ---- view_reference.c ---- */
struct view_reference;
/* Reference mode: renders the job's next slice on a thread of its own (the path tracer on
 * every CPU, request/reference_render.h), then hands the job to the encoder; BUSY (retried
 * by the scheduler) while another reference render runs. */
void view_reference_start(struct view_registry *r, struct view_job *job);
void view_reference_free(struct view_reference *ref);

/* ---- view_encode.c ---- */
/* Starts `threads` encoder threads. NULL with e filled on failure. */
struct view_encoder *view_encoder_create(struct view_registry *r, int threads, struct err *e);
/* Queues a rendered job (GPU thread: never blocks beyond a short lock). */
void view_encoder_submit(struct view_encoder *enc, struct view_job *job);
/* Encodes what is queued, then joins the threads and frees. NULL is a no-op. */
void view_encoder_destroy(struct view_encoder *enc);

#endif
