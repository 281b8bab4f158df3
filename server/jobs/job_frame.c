/*
 * job_frame.c - what rendering one job frame needs, whoever renders it: the daemon's
 * runner thread (job_runner.c) and the one-shot batch mode (job_batch.c, `refractd
 * --batch`). Both render a frame through the same version, irradiance source and encoder,
 * so a frame of a Slurm array task is byte-identical to the same frame of a daemon's job.
 *
 * It is not a scheduler: it neither waits for lights nor submits GPU work.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cjson/cJSON.h>

#include "../cache/irradiance_cache.h"
#include "../io/io_image.h"
#include "../request/reference_render.h"
#include "../request/render_request.h"
#include "../scene/scene_pathtrace.h"
#include "jobs.h"

bool job_frame_lights_failed(struct irradiance_cache *c, const struct irradiance_source *src,
                             char *msg, size_t size)
{
    struct irradiance_light_status ls[SCENE_MAX_LIGHTS];
    int n = irradiance_cache_status(c, src, ls);
    for (int i = 0; i < n; i++) {
        if (ls[i].state == IRRADIANCE_FAILED) {
            snprintf(msg, size,
                     "the light simulation of light \"%s\" failed (GET /v1/scenes/{id}/irradiance"
                     " says why); a job renders only lit frames",
                     ls[i].name);
            return true;
        }
    }
    return false;
}

enum refract_code job_frame_reference(struct store_scene *v, const struct job_frame *f,
                                      struct render_view_result *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    if (!reference_begin()) /* first: a frame retried while BUSY allocates nothing */
        return err_set(e, REFRACT_E_BUSY, "a reference render is running (one at a time)");
    struct scene_pathtrace *pt = malloc(sizeof *pt);
    if (pt == NULL) {
        reference_end();
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for a reference frame");
    }
    struct render_scene_source src = render_request_scene_source(v);
    enum refract_code rc = scene_pathtrace_init(v->scene, src.lookup, src.lookup_ctx, pt, e);
    const struct scene_camera *c = &f->camera;
    struct pathtrace_camera cam = {c->eye, c->look_at, c->up, c->fov_y_deg, c->width, c->height};
    struct pathtrace_image img = {0};
    if (rc == REFRACT_E_OK && pathtrace_image_init(&img, c->width, c->height) != 0)
        rc = err_set(e, REFRACT_E_OUT_OF_MEMORY,
                     "out of memory for a %dx%d reference frame (52 bytes a pixel)", c->width,
                     c->height);
    if (rc == REFRACT_E_OK) {
        bool cancelled = false;
        double ms = reference_render(&pt->scene, &cam, &img, f->reference_samples, INFINITY,
                                     f->reference_seed, reference_threads(), &cancelled);
        uint32_t lo, hi;
        double noise;
        if (cancelled)
            rc = err_set(e, REFRACT_E_SHUTTING_DOWN, "refractd is stopping");
        else if (!reference_image_floats(&img, &out->rgba, NULL, &lo, &hi, &noise))
            rc = err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory encoding a reference frame");
        out->width = c->width;
        out->height = c->height;
        out->gpu_ms = 0.0;
        out->total_ms = ms;
    }
    reference_end();
    pathtrace_image_fini(&img);
    free(pt);
    return rc;
}

enum refract_code job_frame_encode(const struct render_view_result *res, const struct job_frame *f,
                                   enum scene_tonemap tonemap, void **bytes, size_t *len,
                                   struct err *e)
{
    enum io_frame_format format = f->format == JOB_FORMAT_EXR    ? IO_FRAME_EXR
                                  : f->format == JOB_FORMAT_JPEG ? IO_FRAME_JPEG
                                                                 : IO_FRAME_PNG;
    return io_encode_frame(res->rgba, res->width, res->height, format, f->exposure_ev,
                           tonemap == SCENE_TONEMAP_FILMIC ? IO_TONEMAP_FILMIC : IO_TONEMAP_CLAMP,
                           90, bytes, len, e);
}

enum refract_code job_frame_version(struct store *store, struct store_scene *base,
                                    const struct job_frame *f, struct store_scene **out,
                                    struct err *e)
{
    if (f->light_count == 0) {
        atomic_fetch_add(&base->refs, 1);
        *out = base;
        return REFRACT_E_OK;
    }
    cJSON *doc = cJSON_ParseWithLength(base->json, base->json_len);
    cJSON *lights = doc ? cJSON_GetObjectItemCaseSensitive(doc, "lights") : NULL;
    for (int k = 0; k < f->light_count; k++) {
        const struct job_light_override *o = &f->lights[k];
        cJSON *light = NULL, *item;
        cJSON_ArrayForEach(item, lights)
        {
            const cJSON *name = cJSON_GetObjectItemCaseSensitive(item, "name");
            if (cJSON_IsString(name) && strcmp(name->valuestring, o->light) == 0)
                light = item;
        }
        if (light == NULL) {
            cJSON_Delete(doc);
            return err_set(e, REFRACT_E_CONFLICT,
                           "the scene no longer has light \"%s\" that the job moves", o->light);
        }
        const double v[3] = {o->value.x, o->value.y, o->value.z};
        const char *key = o->field == JOB_LIGHT_DIRECTION ? "direction" : "position";
        cJSON_DeleteItemFromObjectCaseSensitive(light, key);
        cJSON_AddItemToObject(light, key, cJSON_CreateDoubleArray(v, 3));
    }
    char *json = cJSON_PrintUnformatted(doc);
    cJSON_Delete(doc);
    if (json == NULL)
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory moving a light");
    enum refract_code rc = store_scene_derive(store, base, json, strlen(json), out, e);
    free(json);
    return rc;
}

void job_frame_source(struct store_scene *v, const struct job_frame *f, const char *slot_id,
                      struct irradiance_source *out)
{
    render_request_irradiance_source(v, out);
    if (f->light_count > 0)
        out->scene_id = slot_id;
}
