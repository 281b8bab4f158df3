/*
 * view_reference.c - view sessions in reference mode (docs/views.md "Reference mode"): each
 * frame adds a slice of path-traced samples to the session's image and shows its mean, so
 * the picture refines while the view is open, until every pixel has the target number of
 * paths; a change (camera, size, scene, lights, the target) starts a new image.
 *
 * DESIGN: a frame job of such a session runs on a thread of its own, never on the GPU
 * thread: it takes the process's one reference slot (request/reference_render.h; BUSY,
 * which the scheduler retries, while an HTTP reference render or a job's reference frame
 * holds it), renders for at most REF_SLICE_MS on every CPU, and hands the mean to the
 * view encoder like a rendered frame. The streams are (seed 1, pixel, sample), so the
 * finished image is the one POST .../render with "mode": "reference" and the same samples
 * gives. The session's image is touched only by its one job in flight (view_internal.h).
 */
#include <stdlib.h>
#include <string.h>

#include "../core/log.h"
#include "../request/reference_render.h"
#include "../request/render_request.h"
#include "../scene/scene_pathtrace.h"
#include "view_internal.h"

#define REF_SLICE_MS 250.0 /* a frame's share of samples: a refresh four times a second */

struct view_reference {
    struct scene_pathtrace pt; /* borrows version->scene */
    struct store_scene *version;
    struct pathtrace_camera cam;
    struct pathtrace_image img;
    uint64_t gen; /* the change_gen it shows */
    int samples;  /* its target */
    bool valid;
};

void view_reference_free(struct view_reference *ref)
{
    if (ref == NULL)
        return;
    pathtrace_image_fini(&ref->img);
    store_scene_release(ref->version);
    free(ref);
}

/* The session's image for the job's change: kept, or made anew. */
static enum refract_code image_for(struct view_session *s, struct view_job *job, struct err *e)
{
    struct view_reference *ref = s->ref;
    if (ref && ref->valid && ref->gen == job->change_gen &&
        ref->samples == job->settings.reference_samples)
        return REFRACT_E_OK;
    if (ref == NULL) {
        ref = calloc(1, sizeof *ref);
        if (ref == NULL)
            return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a reference view");
        pthread_mutex_lock(&s->mu);
        s->ref = ref;
        pthread_mutex_unlock(&s->mu);
    }
    ref->valid = false;
    pathtrace_image_fini(&ref->img);
    store_scene_release(ref->version);
    atomic_fetch_add(&job->version->refs, 1);
    ref->version = job->version;
    struct render_scene_source src = render_request_scene_source(job->version);
    enum refract_code rc =
        scene_pathtrace_init(job->version->scene, src.lookup, src.lookup_ctx, &ref->pt, e);
    if (rc != REFRACT_E_OK)
        return rc;
    const struct scene_camera *c = &job->settings.camera;
    ref->cam = (struct pathtrace_camera){c->eye,       c->look_at, c->up,
                                         c->fov_y_deg, c->width,   c->height};
    if (pathtrace_image_init(&ref->img, c->width, c->height) != 0)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "out of memory for a %dx%d reference view (52 bytes a pixel)", c->width,
                       c->height);
    ref->gen = job->change_gen;
    ref->samples = job->settings.reference_samples;
    ref->valid = true;
    return REFRACT_E_OK;
}

static void *slice_main(void *arg)
{
    struct view_job *job = arg;
    struct view_session *s = job->session;
    struct view_registry *r = s->reg;
    struct err e = {0};
    if (!reference_begin()) {
        err_set(&e, REFRACT_E_BUSY, "a reference render is running (one at a time)");
        view_job_finish(r, job, NULL, &e);
        return NULL;
    }
    enum refract_code rc = image_for(s, job, &e);
    if (rc == REFRACT_E_OK) {
        struct view_reference *ref = s->ref;
        bool cancelled = false;
        double ms = reference_render(&ref->pt.scene, &ref->cam, &ref->img, ref->samples,
                                     gpu_time_ms() + REF_SLICE_MS, 1, reference_threads(),
                                     &cancelled);
        uint32_t lo = 0, hi = 0;
        double noise = 0.0;
        if (cancelled)
            rc = err_set(&e, REFRACT_E_SHUTTING_DOWN, "refractd is stopping");
        else if (!reference_image_floats(&ref->img, &job->result.rgba, NULL, &lo, &hi, &noise))
            rc = err_set(&e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a reference frame");
        job->result.width = ref->cam.width;
        job->result.height = ref->cam.height;
        job->result.gpu_ms = ms;
        job->result.total_ms = ms;
        job->ref_samples = lo;
        job->irradiance = "not-needed";
    }
    reference_end();
    if (rc != REFRACT_E_OK) {
        if (s->ref)
            s->ref->valid = false;
        view_job_finish(r, job, NULL, &e);
        return NULL;
    }
    view_encoder_submit(r->encoder, job);
    return NULL;
}

void view_reference_start(struct view_registry *r, struct view_job *job)
{
    if (!reference_start_detached(slice_main, job)) {
        struct err e = {0};
        err_set(&e, REFRACT_E_BUSY, "could not start a reference view thread");
        view_job_finish(r, job, NULL, &e);
    }
}
