/*
 * view_frame.h - one encoded frame of a view session: the JPEG bytes and what the stream
 * headers and the view status say about it. Immutable once made and reference counted,
 * so a session's newest frame can be sent by any number of streams at their own pace
 * while the next one is made: each stream holds at most one frame (docs/views.md,
 * "Backpressure").
 *
 * Ownership: view_frame_create returns a frame holding one reference and consuming the
 * JPEG buffer; view_frame_retain/release count references; the last release frees it.
 * Thread: any.
 */
#ifndef REFRACT_VIEW_FRAME_H
#define REFRACT_VIEW_FRAME_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

enum view_frame_kind { VIEW_FRAME_FULL = 0, VIEW_FRAME_PREVIEW = 1 };

struct view_frame {
    atomic_int refs;
    uint64_t seq; /* 1, 2, ... per session */
    enum view_frame_kind kind;
    bool reencoded; /* encoded again from the previous full frame's image (an exposure,
                       tonemap or jpeg_quality change); render_ms is that frame's */
    int width, height;
    double render_ms, encode_ms;
    const char *irradiance; /* static: "ready", "stale", "missing", "not-needed" */
    uint64_t scene_generation;
    int64_t made_ms; /* gpu_now_ms() when it became the newest frame */
    unsigned char *jpeg;
    size_t len;
};

/* "full" or "preview". */
const char *view_frame_kind_name(enum view_frame_kind k);

/* A new frame (one reference) that consumes jpeg (malloc'd); NULL when out of memory
 * (then jpeg is freed). The caller fills in the other fields before sharing it. */
struct view_frame *view_frame_create(unsigned char *jpeg, size_t len);
void view_frame_retain(struct view_frame *f);
/* NULL is a no-op. */
void view_frame_release(struct view_frame *f);

#endif
