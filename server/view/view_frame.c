/*
 * view_frame.c - reference-counted immutable JPEG frames (view_frame.h).
 */
#include <stdlib.h>

#include "view_frame.h"

const char *view_frame_kind_name(enum view_frame_kind k)
{
    return k == VIEW_FRAME_PREVIEW ? "preview" : "full";
}

struct view_frame *view_frame_create(unsigned char *jpeg, size_t len)
{
    struct view_frame *f = calloc(1, sizeof *f);
    if (f == NULL) {
        free(jpeg);
        return NULL;
    }
    atomic_init(&f->refs, 1);
    f->jpeg = jpeg;
    f->len = len;
    f->irradiance = "missing";
    return f;
}

void view_frame_retain(struct view_frame *f)
{
    atomic_fetch_add(&f->refs, 1);
}

void view_frame_release(struct view_frame *f)
{
    if (f == NULL || atomic_fetch_sub(&f->refs, 1) != 1)
        return;
    free(f->jpeg);
    free(f);
}
