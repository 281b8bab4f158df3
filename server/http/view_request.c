/*
 * view_request.c - the body of POST /v1/scenes/{id}/views and PATCH /v1/views/{vid}
 * (docs/views.md) into view settings, with the render request's readers (request_parse.c)
 * for the camera, the render settings and the image options, so both say the same thing
 * about the same mistake.
 */
#include <string.h>

#include "../scene/json_read.h"
#include "http_internal.h"

static bool has(const cJSON *root, const char *key)
{
    return cJSON_GetObjectItemCaseSensitive(root, key) != NULL;
}

/* The render-setting overrides: the preset's values are the defaults; what the body names
 * becomes an explicit override. A body that names "quality" chooses the preset anew, so
 * it drops the overrides it does not name again. */
static enum refract_code parse_overrides(const cJSON *root, const struct scene *scene,
                                         const struct http_config *cfg, struct view_settings *st,
                                         struct err *e)
{
    if (has(root, "quality"))
        st->has_stepper = st->has_step = st->has_max_steps = st->has_boundary_threshold =
            st->has_samples_per_pixel = false;
    struct scene_render_settings preset, parsed;
    view_settings_render(st, scene, &preset);
    enum refract_code rc = http_parse_settings(root, &preset, cfg, &parsed, e);
    if (rc != REFRACT_E_OK)
        return rc;
    if (has(root, "stepper") || has(root, SCENE_STEPPER_OLD_KEY)) {
        st->has_stepper = true;
        st->overrides.stepper = parsed.stepper;
    }
    if (has(root, "step")) {
        st->has_step = true;
        st->overrides.step_voxels = parsed.step_voxels;
    }
    if (has(root, "max_steps")) {
        st->has_max_steps = true;
        st->overrides.max_steps = parsed.max_steps;
    }
    if (has(root, "boundary_threshold")) {
        st->has_boundary_threshold = true;
        st->overrides.boundary_threshold = parsed.boundary_threshold;
    }
    if (has(root, "samples_per_pixel")) {
        st->has_samples_per_pixel = true;
        st->overrides.samples_per_pixel = parsed.samples_per_pixel;
    }
    return REFRACT_E_OK;
}

enum refract_code http_parse_view_settings(const char *body, size_t len, const struct scene *scene,
                                           const struct http_config *cfg,
                                           const struct view_settings *current,
                                           struct view_settings *out, struct err *e)
{
    static const char *const keys[] = {"camera",
                                       "width",
                                       "height",
                                       "exposure",
                                       "tonemap",
                                       "quality",
                                       "stepper",
                                       "step",
                                       "max_steps",
                                       "boundary_threshold",
                                       "jpeg_quality",
                                       "max_fps",
                                       "progressive",
                                       "samples_per_pixel",
                                       "mode",
                                       "samples",
                                       SCENE_STEPPER_OLD_KEY,
                                       NULL};
    static const char *const modes[] = {"fast", "reference", NULL};
    *out = *current;
    cJSON *root = NULL;
    enum refract_code rc = http_parse_body(body, len, &root, e);
    if (rc != REFRACT_E_OK)
        return rc;
    rc = jr_check_object(root, "", keys, e);
    if (rc == REFRACT_E_OK)
        rc = http_parse_camera(root, &current->camera, cfg, &out->camera, e);
    if (rc == REFRACT_E_OK)
        rc =
            http_parse_image_options(root, &out->exposure_ev, &out->tonemap, &out->jpeg_quality, e);
    int quality = (int)out->quality;
    if (rc == REFRACT_E_OK)
        rc = jr_enum(root, "", "quality", false, quality, view_quality_names, &quality, e);
    out->quality = (enum view_quality)quality;
    if (rc == REFRACT_E_OK)
        rc = parse_overrides(root, scene, cfg, out, e);
    if (rc == REFRACT_E_OK)
        rc = jr_number(root, "", "max_fps", false, out->max_fps, 0.1, 120.0, &out->max_fps, e);
    if (rc == REFRACT_E_OK)
        rc = jr_bool(root, "", "progressive", false, out->progressive, &out->progressive, e);
    int mode = out->reference ? 1 : 0;
    if (rc == REFRACT_E_OK)
        rc = jr_enum(root, "", "mode", false, mode, modes, &mode, e);
    out->reference = mode == 1;
    int max_samples = cfg->max_reference_samples > 0 ? cfg->max_reference_samples : 65536;
    if (out->reference_samples > max_samples)
        out->reference_samples = max_samples;
    if (rc == REFRACT_E_OK)
        rc = jr_int(root, "", "samples", false, out->reference_samples, 1, max_samples,
                    &out->reference_samples, e);
    cJSON_Delete(root);
    return rc;
}
