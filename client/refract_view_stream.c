/*
 * refract_view_stream.c - refract_view_stream(): a view session's MJPEG stream read as
 * frames. The transport is refract_stream.c's streaming GET; the bytes go through the
 * multipart parser (multipart_parse.c); each complete part is checked to be a whole JPEG
 * and handed to the caller as a struct refract_frame.
 *
 * The JPEG check (SOI at the start, EOI at the end) is what catches a Content-Length that
 * is too short before the caller sees a broken image: the parser delivers a part as soon
 * as its declared length has come, and would only notice the lie at the next boundary.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "multipart_parse.h"
#include "refract_internal.h"
#include "refract_url.h"

/* JPEG frames larger than this are refused: 1 GiB is beyond any --max-image-pixels. */
#define FRAME_MAX_BYTES ((size_t)1 << 30)

struct frame_reader {
    struct refract_multipart parser;
    refract_frame_fn fn;
    void *user;
    long frames;    /* delivered to fn */
    bool bad_frame; /* a part was not a JPEG; why says how */
    char why[REFRACT_MULTIPART_WHY_SIZE + 64];
};

static bool is_whole_jpeg(const unsigned char *b, size_t n)
{
    return n >= 4 && b[0] == 0xFF && b[1] == 0xD8 && b[2] == 0xFF && b[n - 2] == 0xFF &&
           b[n - 1] == 0xD9;
}

static bool on_part(void *user, const struct refract_multipart_part *part)
{
    struct frame_reader *r = user;
    struct refract_frame f = {
        .bytes = part->body,
        .len = part->len,
        .index = r->frames,
        .seq = part->seq,
        .render_ms = part->render_ms,
        .repeat = part->repeat,
        .arrival_ms = part->start_ms,
    };

    if (part->content_type[0] != '\0' && strcasecmp(part->content_type, "image/jpeg") != 0) {
        snprintf(r->why, sizeof(r->why),
                 "part %ld (seq %lld) has Content-Type \"%s\", not "
                 "image/jpeg",
                 part->index + 1, part->seq, part->content_type);
        r->bad_frame = true;
        return false;
    }
    if (!is_whole_jpeg(part->body, part->len)) {
        snprintf(r->why, sizeof(r->why),
                 "frame %ld (seq %lld, %zu bytes) is not a whole JPEG (it must start with "
                 "FF D8 and end with FF D9): a wrong Content-Length?",
                 part->index + 1, part->seq, part->len);
        r->bad_frame = true;
        return false;
    }
    snprintf(f.kind, sizeof(f.kind), "%s", part->kind);
    snprintf(f.irradiance, sizeof(f.irradiance), "%s", part->irradiance);
    snprintf(f.content_type, sizeof(f.content_type), "%s",
             part->content_type[0] != '\0' ? part->content_type : "image/jpeg");
    r->frames++;
    return r->fn(&f, r->user) == 0;
}

static bool frames_begin(void *user, const char *content_type, char *why, size_t why_size)
{
    struct frame_reader *r = user;
    char boundary[REFRACT_MULTIPART_BOUNDARY_MAX + 1];

    if (!refract_multipart_boundary(content_type, boundary, sizeof(boundary), why, why_size))
        return false;
    if (!refract_multipart_init(&r->parser, boundary, FRAME_MAX_BYTES)) {
        snprintf(why, why_size, "%s", r->parser.why);
        return false;
    }
    return true;
}

static int frames_chunk(void *user, const char *data, size_t len, double now_ms, char *why,
                        size_t why_size)
{
    struct frame_reader *r = user;
    enum refract_multipart_result result;

    r->parser.now_ms = now_ms;
    result = refract_multipart_feed(&r->parser, data, len, on_part, r);
    if (r->bad_frame) {
        snprintf(why, why_size, "%s", r->why);
        return -1;
    }
    if (result == REFRACT_MULTIPART_ERROR) {
        snprintf(why, why_size, "after %ld frames: %s", r->frames, r->parser.why);
        return -1;
    }
    return result == REFRACT_MULTIPART_STOPPED ? 1 : 0;
}

static bool frames_end(void *user, char *why, size_t why_size)
{
    struct frame_reader *r = user;

    if (refract_multipart_finish(&r->parser) == REFRACT_MULTIPART_ERROR) {
        snprintf(why, why_size, "refractd closed the frame stream after %ld whole frames: %s",
                 r->frames, r->parser.why);
        return false;
    }
    return true;
}

static long frames_delivered(void *user)
{
    return ((struct frame_reader *)user)->frames;
}

int refract_view_stream(refract_client *c, const char *view_id, refract_frame_fn fn, void *user)
{
    struct frame_reader r = {.fn = fn, .user = user};
    const struct refract_stream_sink sink = {
        .content_type = "multipart/",
        .begin = frames_begin,
        .chunk = frames_chunk,
        .end = frames_end,
        .delivered = frames_delivered,
        .item = "frame",
        .user = &r,
    };
    char *id;
    char *path;
    int code = refract_begin(c, NULL);

    if (code != REFRACT_E_OK)
        return code;
    code = refract_check_segment(c, "refract_view_stream", "view id", view_id);
    if (code == REFRACT_E_OK && fn == NULL)
        code = refract_fail(c, REFRACT_E_USAGE, "refract_view_stream: the frame callback is NULL");
    if (code != REFRACT_E_OK)
        return code;
    id = refract_url_escape_dup(view_id);
    path = id != NULL ? refract_path_printf("/v1/views/%s/stream", id) : NULL;
    free(id);
    if (path == NULL)
        return refract_out_of_memory(c, "building the stream's path");
    code = refract_stream_get(c, path, NULL, &sink);
    refract_multipart_fini(&r.parser);
    free(path);
    return code;
}
