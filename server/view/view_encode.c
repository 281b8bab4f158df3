/*
 * view_encode.c - the view encoder threads (--view-encoder-threads): tone mapping and
 * JPEG encoding of rendered view frames, off the GPU thread (docs/views.md).
 *
 * DESIGN. A FIFO of rendered jobs under one mutex and condition variable; the GPU
 * thread's done callback only appends (it must not block), the threads take jobs, encode
 * them (io_encode_frame, the path POST .../render and batch jobs use too) and
 * hand the frame to view_job_finish. A job whose GPU work failed passes through with its
 * error. The queue never holds more than one job per session (one frame in flight), so
 * it needs no bound of its own.
 */
#include <stdlib.h>
#include <string.h>

#include "../core/log.h"
#include "../io/io_image.h"
#include "view_internal.h"

struct view_encoder {
    struct view_registry *reg;
    pthread_mutex_t mu;
    pthread_cond_t ready;
    struct view_job *head, *tail;
    bool stop;
    int thread_count;
    pthread_t *threads;
};

/* Encodes job's image into a new frame; NULL with e filled on failure. */
static struct view_frame *encode(const struct view_job *job, struct err *e)
{
    const struct render_view_result *r = &job->result;
    double t0 = gpu_time_ms();
    void *bytes = NULL;
    size_t len = 0;
    enum refract_code rc = io_encode_frame(
        r->rgba, r->width, r->height, IO_FRAME_JPEG, job->settings.exposure_ev,
        job->settings.tonemap == SCENE_TONEMAP_FILMIC ? IO_TONEMAP_FILMIC : IO_TONEMAP_CLAMP,
        job->settings.jpeg_quality, &bytes, &len, e);
    if (rc != REFRACT_E_OK)
        return NULL;
    struct view_frame *f = view_frame_create(bytes, len);
    if (f == NULL) {
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a view frame");
        return NULL;
    }
    f->kind = job->kind;
    f->width = r->width;
    f->height = r->height;
    f->render_ms = r->gpu_ms;
    f->encode_ms = gpu_time_ms() - t0;
    f->irradiance = job->irradiance ? job->irradiance : "missing";
    f->scene_generation = job->version->generation;
    return f;
}

static void *encoder_main(void *arg)
{
    struct view_encoder *enc = arg;
    pthread_mutex_lock(&enc->mu);
    for (;;) {
        while (enc->head == NULL && !enc->stop)
            pthread_cond_wait(&enc->ready, &enc->mu);
        struct view_job *job = enc->head;
        if (job == NULL)
            break; /* stopping, and the queue is drained */
        enc->head = job->next;
        if (enc->head == NULL)
            enc->tail = NULL;
        pthread_mutex_unlock(&enc->mu);
        struct err e = job->work.err;
        struct view_frame *f = e.code == REFRACT_E_OK ? encode(job, &e) : NULL;
        view_job_finish(enc->reg, job, f, &e);
        pthread_mutex_lock(&enc->mu);
    }
    pthread_mutex_unlock(&enc->mu);
    return NULL;
}

struct view_encoder *view_encoder_create(struct view_registry *r, int threads, struct err *e)
{
    struct view_encoder *enc = calloc(1, sizeof *enc);
    pthread_t *ids = calloc((size_t)threads, sizeof *ids);
    if (enc == NULL || ids == NULL) {
        free(enc);
        free(ids);
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory starting the view encoders");
        return NULL;
    }
    enc->reg = r;
    enc->threads = ids;
    pthread_mutex_init(&enc->mu, NULL);
    pthread_cond_init(&enc->ready, NULL);
    for (int i = 0; i < threads; i++) {
        int rc = pthread_create(&enc->threads[i], NULL, encoder_main, enc);
        if (rc != 0) {
            err_set(e, REFRACT_E_INTERNAL, "cannot start view encoder thread %d of %d: %s", i + 1,
                    threads, strerror(rc));
            view_encoder_destroy(enc);
            return NULL;
        }
        enc->thread_count++;
    }
    return enc;
}

void view_encoder_submit(struct view_encoder *enc, struct view_job *job)
{
    job->next = NULL;
    pthread_mutex_lock(&enc->mu);
    if (enc->tail)
        enc->tail->next = job;
    else
        enc->head = job;
    enc->tail = job;
    pthread_cond_signal(&enc->ready);
    pthread_mutex_unlock(&enc->mu);
}

void view_encoder_destroy(struct view_encoder *enc)
{
    if (enc == NULL)
        return;
    pthread_mutex_lock(&enc->mu);
    enc->stop = true;
    pthread_cond_broadcast(&enc->ready);
    pthread_mutex_unlock(&enc->mu);
    for (int i = 0; i < enc->thread_count; i++)
        pthread_join(enc->threads[i], NULL);
    pthread_mutex_destroy(&enc->mu);
    pthread_cond_destroy(&enc->ready);
    free(enc->threads);
    free(enc);
}
