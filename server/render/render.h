/*
 * render.h - the view renderer and the ray tracer on the GPU, and the GPU-side copies of
 * scenes they need (tevs2007 ch. 5-6; docs/tracing.md).
 *
 * DESIGN: struct render lives on the GPU thread. It keeps a cache of built scenes keyed by
 * scene id: the channel atlases (ior+gradient, attenuation, emission, opaque) and the
 * environment map. A scene is built on first use, or ahead of use with
 * render_scene_prepare, and rebuilt when its generation changes (an upload, a new
 * document). Least recently used scenes are evicted when the cache exceeds its GPU memory
 * budget. HTTP threads never call anything here; they queue gpu_work items whose run
 * functions do (server/http/).
 *
 * Ownership: render owns every GL object it makes (the scene cache owns the atlases;
 * per-request buffers are freed before a call returns). Callers own the results they get
 * (render_view_result.rgba: free()).
 * Thread: GPU thread only, except where a comment says otherwise.
 */
#ifndef REFRACT_RENDER_H
#define REFRACT_RENDER_H

#include <stddef.h>
#include <stdbool.h>
#include <stdint.h>

#include "../core/err.h"
#include "../gpu/queue.h"
#include "../scene/scene.h"

struct irradiance_gpu; /* server/lightsim/gpu/lightsim_gpu.h */

struct render;

struct render_desc {
    size_t scene_budget_bytes; /* GPU memory for cached scenes; 0 = 2 GiB */
    /* Benchmark knobs (bench/bench_features.c; not reachable from the HTTP API): */
    bool all_variant_bits; /* compile every optional channel and the lights into the march
                              whatever the scene uses (the "all-features path") */
    int skip_cell_voxels;  /* macro cell edge of the empty-space maps; 0: the default */
    bool photons_on_cpu;   /* trace caustic photons on CPU threads even on a hardware GPU
                              (tests that compare with the CPU double twin's very map; on
                              Mesa's software device the CPU always traces them: faster) */
};

/* Everything needed to build a scene's GPU data; borrowed for the call. */
struct render_scene_source {
    const char *id;      /* scene id: the cache key */
    uint64_t generation; /* changes whenever the document or an upload changes */
    const struct scene *scene;
    scene_volume_lookup_fn lookup; /* uploaded volumes */
    void *lookup_ctx;
    const float *env_rgba; /* uploaded equirectangular environment (linear RGBA), or NULL */
    int env_width, env_height;
};

struct render_scene_status {
    size_t gpu_bytes; /* atlases + environment + empty-space map */
    double build_ms;  /* time of the last build (field evaluation + GPU precomputation) */
    bool built_now;   /* this call built it */
};

/* One light as the view renderer sees it (tevs2007 eqs. 5.4-5.8). The irradiance volume
 * is borrowed from the irradiance cache for the call (GPU thread). */
struct photon_grid; /* core/photon.h */

struct render_light {
    enum scene_light_kind kind;
    vec3 position, direction;            /* world; direction unit, the way light travels */
    double cos_spot;                     /* spot: cos of the cone half angle */
    double scale[3];                     /* colour * intensity: multiplies the unit-light volume */
    const struct irradiance_gpu *volume; /* NULL: no irradiance for this light (yet) */
    double radius;      /* point: > 0, the lamp's sphere is seen by rays leaving the scene
                           (docs/tracing.md "Lamps"); 0: a point, never seen */
    bool camera_hidden; /* the sphere is not seen by camera rays that met nothing */
    /* receiver.caustics "photons" with render_view_request.photons_cached: this light's
     * photon map at unit intensity (scale multiplies it) and its key, borrowed like volume;
     * NULL: no caustic from this light (yet). */
    const struct photon_grid *photons;
    uint64_t photon_key;
};

struct render_view_request {
    struct scene_camera camera;
    struct scene_render_settings settings; /* exposure and tonemap are not used here */
    /* Lights with their irradiance volumes (may be 0). A light whose volume is NULL
     * contributes nothing: the renderer never invents light it has not simulated, except
     * in scenes that need no light simulation (scene_needs_light_simulation false), where
     * boundary reflections L_r use the unshadowed direct light (docs/tracing.md "Light"). At
     * most SCENE_MAX_LIGHTS are used; the rest are ignored. */
    const struct render_light *lights;
    int light_count;
    /* receiver.caustics "photons": the lights' photon maps come with the lights (the
     * irradiance cache's, docs/photons.md "The cache"); false: render_view traces each
     * light's map itself, at once, and keeps it with the scene (tools and tests). */
    bool photons_cached;
};

struct render_view_result {
    float *rgba; /* width * height * 4 linear floats, row 0 at the top; caller frees */
    int width, height;
    double gpu_ms;   /* dispatch to completion */
    double total_ms; /* including scene build and read-back */
    struct render_scene_status scene;
};

struct render_trace_ray {
    double origin[3];
    double direction[3]; /* unit */
    /* The set of the scene's surfaces whose solids contain the origin
     * (scene_surfaces_inside), when inside_known. Otherwise render_trace works it out itself,
     * on the GPU thread: a caller with many rays (the HTTP handler) fills it beforehand, off
     * that thread, since a mesh surface costs a winding number per ray. */
    uint32_t inside;
    bool inside_known;
};

struct render_trace_hit {
    int status; /* enum ray_status */
    double exit_origin[3];
    double exit_direction[3];
    double transmittance[3];
    double optical_path_length;
    int steps;
    int event_count; /* surface events of the ray (the first RENDER_TRACE_MAX_EVENTS are kept) */
};

/* One surface event of a traced ray (docs/api.md "Trace", "events": true). */
#define RENDER_TRACE_MAX_EVENTS 16 /* = TRACE_MAX_EVENTS (shaders/bindings.h) */
struct render_trace_event {
    int kind; /* TRACE_EVENT_REFRACTED or TRACE_EVENT_REFLECTED (total internal reflection) */
    double point[3];
    double normal[3];           /* unit, facing the incoming ray */
    double fresnel_R;           /* reflectance at the event; 1 under total internal reflection */
    int surface;                /* index in the scene's surfaces (priority order) */
    int medium_from, medium_to; /* surface whose medium, -1 the ambient medium */
    double n_from, n_to;
};

/* Makes a renderer on the GPU thread. Returns a new render (destroy with
 * render_destroy on the GPU thread) or NULL with e filled. */
struct render *render_create(struct gpu *gpu, const struct render_desc *desc, struct err *e);
void render_destroy(struct render *r);

/* Builds (or finds) the scene's GPU data. */
enum refract_code render_scene_prepare(struct render *r, const struct render_scene_source *src,
                                       struct render_scene_status *out, struct err *e);
/* Drops a scene's GPU data (after DELETE, or before a rebuild). Unknown ids are ignored. */
void render_scene_forget(struct render *r, const char *id);
/* Bytes held by the scene cache. */
size_t render_cache_bytes(const struct render *r);

/* Renders a view: linear radiance per pixel. */
enum refract_code render_view(struct render *r, const struct render_scene_source *src,
                              const struct render_view_request *req, struct render_view_result *out,
                              struct err *e);

/* One tile of a view: renders rows [row0, row0 + rows) of req's image into out->rgba, which
 * the caller allocated for the whole image (width * height * 4 floats) and owns. The rows
 * are bit for bit those render_view would make, so a render split into tiles run as
 * separate GPU work items, with other work between them, equals one made at once
 * (server/http/h_render.c tiles large renders this way). Adds the dispatch time to
 * out->gpu_ms; sets out->width, out->height and out->scene (this call's build status);
 * leaves total_ms alone. */
enum refract_code render_view_rows(struct render *r, const struct render_scene_source *src,
                                   const struct render_view_request *req, int row0, int rows,
                                   struct render_view_result *out, struct err *e);

/* render_trace, also recording each ray's surface events: events has
 * count * RENDER_TRACE_MAX_EVENTS entries (ray i's at i * RENDER_TRACE_MAX_EVENTS), or is
 * NULL (none recorded). */
enum refract_code render_trace_events(struct render *r, const struct render_scene_source *src,
                                      const struct scene_render_settings *settings,
                                      const struct render_trace_ray *rays, size_t count,
                                      struct render_trace_hit *hits,
                                      struct render_trace_event *events, double *gpu_ms,
                                      struct err *e);

/* Traces `count` rays with the view renderer's march (trace_rays.comp). hits has count
 * entries. */
enum refract_code render_trace(struct render *r, const struct render_scene_source *src,
                               const struct scene_render_settings *settings,
                               const struct render_trace_ray *rays, size_t count,
                               struct render_trace_hit *hits, double *gpu_ms, struct err *e);

#endif
