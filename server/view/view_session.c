/*
 * view_session.c - one view session: its settings and quality presets, its newest frame,
 * its watchers, and its status object (docs/views.md "View status"). Scheduling lives in
 * view_scheduler.c; the table of sessions in view_registry.c.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "view_internal.h"

const char *const view_quality_names[] = {"normal", "draft", "final", NULL};

void view_settings_defaults(const struct scene *s, struct view_settings *out)
{
    *out = (struct view_settings){.camera = s->camera,
                                  .exposure_ev = s->render.exposure_ev,
                                  .tonemap = s->render.tonemap,
                                  .quality = VIEW_QUALITY_NORMAL,
                                  .jpeg_quality = 80,
                                  .max_fps = 30.0,
                                  .progressive = true,
                                  .reference_samples = 256};
}

void view_settings_render(const struct view_settings *st, const struct scene *s,
                          struct scene_render_settings *out)
{
    *out = s->render;
    /* The step limits are those of a render request (request_parse.c: 0.01..8 voxels). */
    if (st->quality == VIEW_QUALITY_DRAFT) {
        out->step_voxels = out->step_voxels * 2.0 > 8.0 ? 8.0 : out->step_voxels * 2.0;
        out->stepper = SCENE_STEPPER_EULER;
    } else if (st->quality == VIEW_QUALITY_FINAL) {
        out->step_voxels = out->step_voxels * 0.5 < 0.01 ? 0.01 : out->step_voxels * 0.5;
        out->stepper = SCENE_STEPPER_RK4;
        /* Final frames are looked at still: 2 x 2 jittered rays per pixel at least. */
        if (out->samples_per_pixel < VIEW_FINAL_SAMPLES_PER_PIXEL)
            out->samples_per_pixel = VIEW_FINAL_SAMPLES_PER_PIXEL;
    }
    if (st->has_stepper)
        out->stepper = st->overrides.stepper;
    if (st->has_step)
        out->step_voxels = st->overrides.step_voxels;
    if (st->has_max_steps)
        out->max_steps = st->overrides.max_steps;
    if (st->has_boundary_threshold)
        out->boundary_threshold = st->overrides.boundary_threshold;
    if (st->has_samples_per_pixel)
        out->samples_per_pixel = st->overrides.samples_per_pixel;
    out->exposure_ev = st->exposure_ev;
    out->tonemap = st->tonemap;
}

struct view_session *view_session_new(struct view_registry *r, const char *scene,
                                      const struct view_settings *st, int64_t now_ms)
{
    struct view_session *s = calloc(1, sizeof *s);
    if (s == NULL)
        return NULL;
    atomic_init(&s->refs, 1);
    snprintf(s->scene, sizeof s->scene, "%s", scene);
    s->reg = r;
    pthread_mutex_init(&s->mu, NULL);
    pthread_mutex_init(&s->watch_mu, NULL);
    s->settings = *st;
    s->change_gen = 1; /* the first frame is due */
    s->last_activity_ms = now_ms;
    return s;
}

void view_session_retain(struct view_session *s)
{
    atomic_fetch_add(&s->refs, 1);
}

void view_session_release(struct view_session *s)
{
    if (s == NULL || atomic_fetch_sub(&s->refs, 1) != 1)
        return;
    view_frame_release(s->frame);
    free(s->hdr);
    view_reference_free(s->ref);
    pthread_mutex_destroy(&s->mu);
    pthread_mutex_destroy(&s->watch_mu);
    free(s);
}

const char *view_session_id(const struct view_session *s)
{
    return s->id;
}

const char *view_session_scene(const struct view_session *s)
{
    return s->scene;
}

void view_session_settings(struct view_session *s, struct view_settings *out)
{
    pthread_mutex_lock(&s->mu);
    *out = s->settings;
    pthread_mutex_unlock(&s->mu);
}

void view_session_changed_locked(struct view_session *s)
{
    s->change_gen++;
}

static bool vec3_equal(vec3 a, vec3 b)
{
    return a.x == b.x && a.y == b.y && a.z == b.z;
}

/* Field by field (the structs have padding): the settings that shape the linear image. */
static bool render_settings_equal(const struct view_settings *a, const struct view_settings *b)
{
    const struct scene_camera *ca = &a->camera, *cb = &b->camera;
    const struct scene_render_settings *oa = &a->overrides, *ob = &b->overrides;
    return vec3_equal(ca->eye, cb->eye) && vec3_equal(ca->look_at, cb->look_at) &&
           vec3_equal(ca->up, cb->up) && ca->fov_y_deg == cb->fov_y_deg && ca->width == cb->width &&
           ca->height == cb->height && a->quality == b->quality &&
           a->has_stepper == b->has_stepper && (!a->has_stepper || oa->stepper == ob->stepper) &&
           a->has_step == b->has_step && (!a->has_step || oa->step_voxels == ob->step_voxels) &&
           a->has_max_steps == b->has_max_steps &&
           (!a->has_max_steps || oa->max_steps == ob->max_steps) &&
           a->has_boundary_threshold == b->has_boundary_threshold &&
           (!a->has_boundary_threshold || oa->boundary_threshold == ob->boundary_threshold) &&
           a->has_samples_per_pixel == b->has_samples_per_pixel &&
           (!a->has_samples_per_pixel || oa->samples_per_pixel == ob->samples_per_pixel) &&
           a->reference == b->reference && a->reference_samples == b->reference_samples;
}

static bool settings_equal(const struct view_settings *a, const struct view_settings *b)
{
    return render_settings_equal(a, b) && a->exposure_ev == b->exposure_ev &&
           a->tonemap == b->tonemap && a->jpeg_quality == b->jpeg_quality &&
           a->max_fps == b->max_fps && a->progressive == b->progressive;
}

void view_session_update(struct view_session *s, const struct view_settings *st)
{
    pthread_mutex_lock(&s->mu);
    bool changed = !settings_equal(&s->settings, st);
    if (changed) {
        /* Only tone mapping or encoding changed, and the newest full frame shows the rest:
         * its image is encoded again (milliseconds) instead of rendered (docs/views.md). */
        bool encode_only = s->hdr != NULL && s->hdr_gen == s->change_gen &&
                           render_settings_equal(&s->settings, st);
        s->settings = *st;
        view_session_changed_locked(s);
        if (encode_only)
            s->hdr_gen = s->change_gen;
    }
    pthread_mutex_unlock(&s->mu);
    if (changed)
        view_registry_kick(s->reg);
}

void view_session_wake_watchers(struct view_session *s)
{
    pthread_mutex_lock(&s->watch_mu);
    for (struct view_watcher *w = s->watchers; w != NULL; w = w->next)
        w->wake(w->ctx);
    pthread_mutex_unlock(&s->watch_mu);
}

void view_session_mark_ended(struct view_session *s)
{
    pthread_mutex_lock(&s->mu);
    s->ended = true;
    pthread_mutex_unlock(&s->mu);
    view_session_wake_watchers(s);
}

bool view_session_watch(struct view_session *s, struct view_watcher *w)
{
    pthread_mutex_lock(&s->mu);
    bool ended = s->ended;
    if (!ended)
        s->watcher_count++;
    pthread_mutex_unlock(&s->mu);
    if (ended)
        return false;
    pthread_mutex_lock(&s->watch_mu);
    w->next = s->watchers;
    s->watchers = w;
    pthread_mutex_unlock(&s->watch_mu);
    return true;
}

void view_session_unwatch(struct view_session *s, struct view_watcher *w)
{
    bool found = false;
    pthread_mutex_lock(&s->watch_mu);
    for (struct view_watcher **p = &s->watchers; *p != NULL; p = &(*p)->next) {
        if (*p == w) {
            *p = w->next;
            found = true;
            break;
        }
    }
    pthread_mutex_unlock(&s->watch_mu);
    if (!found)
        return;
    pthread_mutex_lock(&s->mu);
    s->watcher_count--;
    if (s->watcher_count == 0)
        s->last_activity_ms = gpu_now_ms(); /* the idle timeout counts from here */
    pthread_mutex_unlock(&s->mu);
    view_registry_kick(s->reg); /* its expiry may be due now */
}

struct view_frame *view_session_frame(struct view_session *s, bool *ended)
{
    pthread_mutex_lock(&s->mu);
    struct view_frame *f = s->frame;
    if (f)
        view_frame_retain(f);
    if (ended)
        *ended = s->ended;
    pthread_mutex_unlock(&s->mu);
    return f;
}

/* ---- status ---------------------------------------------------------------------------- */

static void add_vec3(cJSON *o, const char *name, vec3 v)
{
    const double a[3] = {v.x, v.y, v.z};
    cJSON_AddItemToObject(o, name, cJSON_CreateDoubleArray(a, 3));
}

static cJSON *frame_json(const struct view_frame *f, int64_t now_ms)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddNumberToObject(o, "seq", (double)f->seq);
    cJSON_AddStringToObject(o, "kind", view_frame_kind_name(f->kind));
    cJSON_AddNumberToObject(o, "width", f->width);
    cJSON_AddNumberToObject(o, "height", f->height);
    cJSON_AddNumberToObject(o, "render_ms", f->render_ms);
    cJSON_AddBoolToObject(o, "reencoded", f->reencoded);
    cJSON_AddNumberToObject(o, "encode_ms", f->encode_ms);
    cJSON_AddNumberToObject(o, "bytes", (double)f->len);
    cJSON_AddNumberToObject(o, "age_ms", (double)(now_ms - f->made_ms));
    cJSON_AddStringToObject(o, "irradiance", f->irradiance);
    cJSON_AddNumberToObject(o, "scene_generation", (double)f->scene_generation);
    return o;
}

static void add_settings(cJSON *o, const struct view_settings *st,
                         const struct scene_render_settings *rs)
{
    cJSON *cam = cJSON_AddObjectToObject(o, "camera");
    add_vec3(cam, "eye", st->camera.eye);
    add_vec3(cam, "look_at", st->camera.look_at);
    add_vec3(cam, "up", st->camera.up);
    cJSON_AddNumberToObject(cam, "fov_y_deg", st->camera.fov_y_deg);
    cJSON_AddNumberToObject(o, "width", st->camera.width);
    cJSON_AddNumberToObject(o, "height", st->camera.height);
    cJSON_AddNumberToObject(o, "exposure", st->exposure_ev);
    cJSON_AddStringToObject(o, "tonemap", scene_tonemap_words[st->tonemap]);
    cJSON_AddStringToObject(o, "quality", view_quality_names[st->quality]);
    cJSON_AddStringToObject(o, "stepper", scene_stepper_words[rs->stepper]);
    cJSON_AddNumberToObject(o, "step", rs->step_voxels);
    cJSON_AddNumberToObject(o, "max_steps", rs->max_steps);
    cJSON_AddNumberToObject(o, "boundary_threshold", rs->boundary_threshold);
    cJSON_AddNumberToObject(o, "samples_per_pixel", rs->samples_per_pixel);
    cJSON_AddNumberToObject(o, "jpeg_quality", st->jpeg_quality);
    cJSON_AddNumberToObject(o, "max_fps", st->max_fps);
    cJSON_AddBoolToObject(o, "progressive", st->progressive);
    cJSON_AddStringToObject(o, "mode", st->reference ? "reference" : "fast");
    cJSON_AddNumberToObject(o, "samples", st->reference_samples);
}

cJSON *view_session_status_json(struct view_session *s, const struct scene *scene)
{
    const struct view_registry_desc *d = view_registry_settings(s->reg);
    int64_t now = gpu_now_ms();
    cJSON *o = cJSON_CreateObject();
    if (o == NULL)
        return NULL;
    char path[128];
    cJSON_AddStringToObject(o, "id", s->id);
    cJSON_AddStringToObject(o, "scene", s->scene);
    pthread_mutex_lock(&s->mu);
    struct scene_render_settings rs = s->last_render;
    if (scene)
        view_settings_render(&s->settings, scene, &rs);
    add_settings(o, &s->settings, &rs);
    snprintf(path, sizeof path, "/v1/views/%s/stream", s->id);
    cJSON_AddStringToObject(o, "stream", path);
    snprintf(path, sizeof path, "/viewer/%s?view=%s", s->scene, s->id);
    cJSON_AddStringToObject(o, "viewer", path);
    cJSON_AddNumberToObject(o, "streams", s->watcher_count);
    bool rendering = s->in_flight || s->change_gen != s->full_gen || s->ref_refining;
    if (s->settings.reference) /* docs/views.md "Reference mode" */
        cJSON_AddNumberToObject(o, "samples_done", s->ref_samples);
    cJSON_AddStringToObject(o, "state", rendering ? "rendering" : "idle");
    cJSON_AddNumberToObject(o, "idle_timeout_s", d->idle_timeout_s);
    /* While a stream is open the session does not expire: the countdown starts when the
     * last one leaves. */
    double expires = d->idle_timeout_s;
    if (s->watcher_count == 0)
        expires -= (double)(now - s->last_activity_ms) / 1000.0;
    cJSON_AddNumberToObject(o, "expires_in_s", expires > 0 ? expires : 0);
    cJSON_AddStringToObject(o, "renderer", gpu_info(d->gpu)->renderer);
    cJSON *counts = cJSON_AddObjectToObject(o, "frames");
    cJSON_AddNumberToObject(counts, "rendered", (double)s->frames_rendered);
    cJSON_AddNumberToObject(counts, "reencoded", (double)s->frames_reencoded);
    if (s->frame)
        cJSON_AddItemToObject(o, "frame", frame_json(s->frame, now));
    else
        cJSON_AddNullToObject(o, "frame");
    if (s->last_error.code != REFRACT_E_OK) {
        cJSON *err = cJSON_AddObjectToObject(o, "error");
        cJSON_AddStringToObject(err, "code", err_code_json(s->last_error.code));
        cJSON_AddStringToObject(err, "message", s->last_error.msg);
    } else {
        cJSON_AddNullToObject(o, "error");
    }
    pthread_mutex_unlock(&s->mu);
    return o;
}
