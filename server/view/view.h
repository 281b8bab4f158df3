/*
 * view.h - view sessions (docs/views.md): a camera, an image size and settings on one
 * scene, whose newest frame (a JPEG) is kept up to date while something it shows changes,
 * for any number of frame streams to send.
 *
 * DESIGN. One registry holds every session (at most max_views). Three kinds of thread
 * work for it, none of them busy-waiting:
 *   - the scheduler thread (view_scheduler.c) sleeps on a condition variable until a
 *     session is dirty and its max_fps spacing allows a frame, or a session's idle
 *     timeout comes; it starts frames as GPU work items at GPU_PRIORITY_INTERACTIVE, one
 *     in flight per session, and ends idle sessions;
 *   - the GPU thread renders (render_tiles.h, shared with POST .../render) and
 *     hands the float image to
 *   - the encoder threads (view_encode.c), which tone-map and encode the JPEG, make it the
 *     session's newest frame (an immutable, reference-counted view_frame) and wake the
 *     session's watchers (the HTTP streams).
 * Changes come from the HTTP threads (PATCH) and from the event hub (scene.updated,
 * irradiance.ready mark the scene's sessions dirty; scene.deleted ends them). Changes
 * made while a frame renders are coalesced into one next frame.
 *
 * Lock order: registry lock, then a session's lock; a session's watcher lock is taken
 * alone (watchers' wake functions run under it and must not call back into the session).
 *
 * Ownership: functions that return a struct view_session * return a new reference
 * (view_session_release). The registry holds one reference per listed session, each GPU
 * or encode job one, each watcher's owner one (its stream). Thread: any, unless a
 * comment says otherwise.
 */
#ifndef REFRACT_VIEW_H
#define REFRACT_VIEW_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../cache/irradiance_cache.h"
#include "../core/err.h"
#include "../gpu/queue.h"
#include "../render/render.h"
#include "../scene/scene.h"
#include "../store/store.h"
#include "view_frame.h"

#define VIEW_ID_LEN 17 /* "v" + 16 lowercase hex digits */

struct event_hub;

struct view_registry_desc {
    struct store *store;                 /* borrowed */
    struct gpu *gpu;                     /* borrowed */
    struct render *render;               /* borrowed; GPU thread only */
    struct irradiance_cache *irradiance; /* borrowed */
    struct event_hub *events;            /* borrowed; NULL = no change notification */
    int max_views;                       /* 0 = 64 (--max-views) */
    double idle_timeout_s;               /* 0 = 120 (--view-idle-timeout) */
    int encoder_threads;                 /* 0 = 2 (--view-encoder-threads) */
    int request_timeout_ms;              /* deadline of a frame's GPU work; 0 = 120000 */
    long long tile_pixels; /* frames larger than this are drawn in tiles of rows, one per
                              GPU turn, other work between (--render-tile-pixels); 0 = 65536 */
};

enum view_quality {
    VIEW_QUALITY_NORMAL = 0, /* the scene's render settings */
    VIEW_QUALITY_DRAFT = 1,  /* step doubled (at most 8 voxels), euler */
    VIEW_QUALITY_FINAL = 2,  /* step halved (at least 0.01 voxels), rk4 */
};
/* The least samples_per_pixel of the "final" quality preset (a square: 2 x 2). */
#define VIEW_FINAL_SAMPLES_PER_PIXEL 4

/* "normal", "draft", "final"; NULL-terminated, indexed by enum view_quality. */
extern const char *const view_quality_names[];

/* What a session shows. The render settings are the quality preset applied to the
 * scene's settings, then the explicit overrides (has_*) on top. */
struct view_settings {
    struct scene_camera camera; /* with width and height */
    double exposure_ev;
    enum scene_tonemap tonemap;
    enum view_quality quality;
    bool has_stepper, has_step, has_max_steps, has_boundary_threshold, has_samples_per_pixel;
    struct scene_render_settings overrides; /* only the has_* members count */
    int jpeg_quality;                       /* 1..100 */
    double max_fps;                         /* 0.1..120 */
    bool progressive;
    /* "mode": "reference": frames by the reference path tracer on CPU threads, refined
     * while the view is open until each pixel has reference_samples paths (docs/views.md
     * "Reference mode"). */
    bool reference;
    int reference_samples; /* 1..--max-reference-samples; default 256 */
};

/* The defaults for a new session on scene s: its camera and size, exposure and tonemap,
 * quality normal, no overrides, jpeg_quality 80, max_fps 30, progressive on. */
void view_settings_defaults(const struct scene *s, struct view_settings *out);
/* The render settings a frame of scene s uses under st. */
void view_settings_render(const struct view_settings *st, const struct scene *s,
                          struct scene_render_settings *out);

struct view_registry;
struct view_session;

/* Starts the scheduler and encoder threads and listens to desc->events. Returns a new
 * registry (view_registry_stop, then view_registry_destroy) or NULL with e filled. */
struct view_registry *view_registry_create(const struct view_registry_desc *desc, struct err *e);
/* Shutdown, before gpu_stop: stops listening, ends every session (their watchers are woken
 * so that streams finish), waits for the frames in flight (the GPU thread must still be
 * running), stops the threads. Later calls that would open a session answer
 * SHUTTING_DOWN. A second call is a no-op, as is NULL. */
void view_registry_stop(struct view_registry *r);
/* Frees the registry (after view_registry_stop and after the HTTP server stopped, so no
 * stream holds a session). NULL is a no-op. */
void view_registry_destroy(struct view_registry *r);
/* The settings in effect (defaults filled in). */
const struct view_registry_desc *view_registry_settings(const struct view_registry *r);

/* Opens a session on version v (borrowed) showing st; its first frame is scheduled at
 * once. *out gets a new reference. LIMIT_EXCEEDED (names --max-views), SHUTTING_DOWN,
 * OUT_OF_MEMORY. */
enum refract_code view_session_open(struct view_registry *r, struct store_scene *v,
                                    const struct view_settings *st, struct view_session **out,
                                    struct err *e);
/* The session with this id as a new reference, or NULL (unknown, ended or expired). A
 * lookup counts as a request: it restarts the idle timeout. */
struct view_session *view_session_find(struct view_registry *r, const char *id);
/* Ends the session (DELETE): it leaves the registry, its streams end. False when there
 * was no such session. */
bool view_session_end(struct view_registry *r, const char *id);
/* Every listed session, by creation order: *out is a new array of new references;
 * release each and free the array with view_session_list_free. Returns the count. */
size_t view_session_list(struct view_registry *r, struct view_session ***out);
void view_session_list_free(struct view_session **list, size_t count);

void view_session_retain(struct view_session *s);
void view_session_release(struct view_session *s);

/* Borrowed strings, valid while the caller holds its reference. */
const char *view_session_id(const struct view_session *s);
const char *view_session_scene(const struct view_session *s);

/* Copies the settings. */
void view_session_settings(struct view_session *s, struct view_settings *out);
/* Replaces the settings (PATCH; validated by the caller) and schedules a frame, unless
 * they equal the current ones (a PATCH that changes nothing renders nothing). */
void view_session_update(struct view_session *s, const struct view_settings *st);

/* The view status object (docs/views.md) as a new cJSON tree; scene (may be NULL: then
 * the render settings are those of the last frame) resolves the quality preset. */
struct cJSON;
struct cJSON *view_session_status_json(struct view_session *s, const struct scene *scene);

/* ---- watchers: what streams use ---- */

/* A watcher is told (wake(ctx), on an encoder or registry thread, under the session's
 * watcher lock: be quick, do not call into the session) when the session has a new
 * frame and when it ends. The struct is the caller's; the session borrows it between
 * view_session_watch and view_session_unwatch. */
struct view_watcher {
    void (*wake)(void *ctx);
    void *ctx;
    struct view_watcher *next; /* session-private */
};
/* Adds w; false (w not added) when the session has ended. */
bool view_session_watch(struct view_session *s, struct view_watcher *w);
/* Removes w; returns only when w->wake is not running and will not be called again. The
 * session's idle timeout restarts when its last watcher leaves. */
void view_session_unwatch(struct view_session *s, struct view_watcher *w);
/* The newest frame as a new reference (view_frame_release), or NULL before the first;
 * *ended (may be NULL) tells whether the session has ended. */
struct view_frame *view_session_frame(struct view_session *s, bool *ended);

#endif
