/*
 * jobs.h - batch jobs (docs/api.md "Batch jobs"): a list of frames of one scene, given
 * explicitly or made by a generator (a camera turntable), rendered one frame per GPU work
 * item at GPU_PRIORITY_BATCH (below interactive renders and light simulation), a tile of
 * --render-tile-pixels per turn (render_tiles.h: an interactive render queued meanwhile
 * waits for one tile, not for the whole frame; the frame equals one drawn at once), and kept in
 * the data directory, so a job survives a restart or a kill -9.
 *
 * DESIGN. One runner thread (job_runner.c) owns the order of work: it takes the oldest
 * unfinished job, asks the irradiance cache for its lights, waits (on its own condition
 * variable, never on the GPU thread) until every light's volume is ready so that every
 * frame is lit, submits one frame to the GPU thread, encodes the image when the GPU is done
 * (on the runner thread, off the GPU thread) and commits it with store_job_frame_commit:
 * the frame's blob and frames_done in one transaction. A restart resumes each job at
 * frames_done, the first unfinished frame; no frame is lost or stored twice.
 *
 * The specification (job_spec.c) is stored as received and expanded again at start-up
 * against the scene's current camera. Its "scene" is a scene id or a whole document (an
 * inline scene): then the job holds a private version of it (store_scene_private, named
 * "job:<id>", never installed), made again from the stored specification at start-up, and
 * its GPU copy and irradiance slot, under that name, are forgotten when the job ends.
 *
 * Thread: every function may be called from any thread; the registry locks internally.
 */
#ifndef REFRACT_JOBS_H
#define REFRACT_JOBS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../core/err.h"
#include "../scene/scene.h"
#include "../store/store.h"

#define JOB_ID_LEN 17 /* "j" + 16 lowercase hex digits */

enum job_format { JOB_FORMAT_PNG = 0, JOB_FORMAT_JPEG = 1, JOB_FORMAT_EXR = 2 };
/* "png", "jpeg", "exr"; NULL-terminated, indexed by enum job_format. */
extern const char *const job_format_names[];

/* What a frame changes of one light: its direction or its position. */
enum job_light_field { JOB_LIGHT_NONE = 0, JOB_LIGHT_DIRECTION = 1, JOB_LIGHT_POSITION = 2 };

struct job_light_override {
    enum job_light_field field;
    char light[SCENE_LIGHT_NAME_MAX]; /* the light it moves */
    vec3 value;                       /* unit direction or position */
};

/* One frame to render. */
struct job_frame {
    struct scene_camera camera; /* with width and height */
    enum job_format format;
    double exposure_ev;
    /* Light poses that differ from the scene's (a light path's one light, or a frame's
     * "lights" list); 0 = the scene's lights. */
    struct job_light_override lights[SCENE_MAX_LIGHTS];
    int light_count;
    /* "mode": "reference" (docs/jobs in docs/api.md): the path tracer's paths per pixel and
     * seed; 0 = the fast renderer. */
    int reference_samples;
    uint64_t reference_seed;
};

struct job_limits {
    int max_frames;             /* --max-job-frames */
    int max_image_dim;          /* the scene limits' camera width/height */
    long long max_image_pixels; /* --max-image-pixels */
    int max_reference_samples;  /* --max-reference-samples (0: 65536) */
};

/* ---- job_spec.c ---- */

struct cJSON;

/* The scene a specification names (root must be an object): "scene", required, is either
 * a scene id (out gets it, *inline_doc = NULL) or a whole scene document (an "inline
 * scene": *inline_doc points at it, borrowed from root; out = ""). */
enum refract_code job_spec_scene(const struct cJSON *root, char out[STORE_ID_MAX],
                                 const struct cJSON **inline_doc, struct err *e);
/* INVALID_FIELD when the parsed inline scene s refers to an upload (a volume layer, a mesh
 * shape, an image environment), naming its JSON path: uploads belong to a scene id. */
enum refract_code job_spec_inline_check(const struct scene *s, struct err *e);
/* Rewrites a scene_parse error of an inline scene so that its path starts at the job's
 * "scene" field ("objects[0].resolution: ..." -> "scene.objects[0].resolution: ..."). */
void job_spec_inline_error(struct err *e);
/* Expands a specification (docs/api.md "Batch jobs") against scene s (its camera, exposure
 * and size are the defaults): *frames is a new array (caller frees) of *count frames.
 * Every bad field is INVALID_FIELD / UNKNOWN_FIELD / MISSING_FIELD naming its JSON path;
 * more than lim->max_frames frames is LIMIT_EXCEEDED naming --max-job-frames. */
enum refract_code job_spec_expand(const struct cJSON *root, const struct scene *s,
                                  const struct job_limits *lim, struct job_frame **frames,
                                  int *count, struct err *e);
/* Spherical linear interpolation of unit vectors a and b at t in [0, 1] (the shorter
 * arc; nearly opposite vectors turn through a perpendicular). For light_path directions. */
vec3 job_slerp(vec3 a, vec3 b, double t);
/* Rotates p about the axis through center with unit direction axis by angle (radians;
 * right-handed), Rodrigues' formula. For the turntable. */
vec3 job_rotate_about(vec3 p, vec3 center, vec3 axis, double angle);

/* ---- job_runner.c ---- */

struct gpu;
struct render;
struct irradiance_cache;
struct event_hub;

struct job_runner_desc {
    struct store *store;                 /* borrowed */
    struct gpu *gpu;                     /* borrowed */
    struct render *render;               /* borrowed; GPU thread only */
    struct irradiance_cache *irradiance; /* borrowed */
    struct event_hub *events;            /* borrowed; NULL = no job.progress events */
    struct job_limits limits;
    long long tile_pixels; /* --render-tile-pixels: a frame is drawn a tile per GPU turn
                              (render_tiles.h); <= 0 = the default */
};

/* What GET /v1/jobs/{id} reports. */
struct job_status {
    char id[STORE_ID_MAX];
    char scene[STORE_ID_MAX]; /* "" for an inline scene */
    bool inline_scene;        /* the specification holds its scene document */
    char state[16];           /* queued, running, done, failed, cancelled */
    int frames_total, frames_done;
    double eta_s;                                                    /* < 0: unknown */
    int64_t created_unix, updated_unix, started_unix, finished_unix; /* 0 = not yet */
    char message[ERR_MSG_MAX];
};

struct job_runner;

/* Loads the jobs of the data directory (unfinished ones resume) and starts the runner
 * thread. NULL with e filled on failure. */
struct job_runner *job_runner_create(const struct job_runner_desc *desc, struct err *e);
/* Shutdown, before gpu_stop: waits for the tile in flight (if any; its frame is dropped)
 * and stops the thread.
 * Unfinished jobs stay queued/running in the database and resume at the next start. A
 * second call is a no-op, as is NULL. */
void job_runner_stop(struct job_runner *r);
void job_runner_destroy(struct job_runner *r);

/* Parses, validates and stores a job (POST /v1/jobs): out gets its status (state queued).
 * Errors: the spec's 400s, SCENE_NOT_FOUND, LIMIT_EXCEEDED, STORAGE, SHUTTING_DOWN. */
enum refract_code job_submit(struct job_runner *r, const char *body, size_t len,
                             struct job_status *out, struct err *e);
/* False when there is no such job. */
bool job_get(struct job_runner *r, const char *id, struct job_status *out);
/* Every job (oldest first) matching state and scene (NULL or "" = any): *out is a new
 * array (caller frees). Returns the count. */
size_t job_list(struct job_runner *r, const char *state, const char *scene,
                struct job_status **out);
/* DELETE: an unfinished job is cancelled (its finished frames stay readable); a finished,
 * failed or cancelled one is deleted with its frames. *deleted says which. NOT_FOUND. */
enum refract_code job_cancel_or_delete(struct job_runner *r, const char *id, bool *deleted,
                                       struct job_status *out, struct err *e);
/* The format of an encoded frame from its first bytes (PNG, JPEG or OpenEXR signature);
 * false when it is none of them. */
bool job_format_sniff(const void *bytes, size_t len, enum job_format *out);
/* "image/png", "image/jpeg", "image/x-exr"; and the file extension "png", "jpg", "exr". */
const char *job_format_content_type(enum job_format f);
const char *job_format_extension(enum job_format f);

/* ---- job_frame.c: one frame, for the runner and the one-shot batch mode ---- */

struct render_view_result;
struct irradiance_source;
struct irradiance_cache;

/* The version frame f renders: base itself, or for a light-path frame a private version of
 * store whose document moves f's lights (store_scene_derive). *out is a new reference.
 * CONFLICT when base no longer has a light that f moves. */
enum refract_code job_frame_version(struct store *store, struct store_scene *base,
                                    const struct job_frame *f, struct store_scene **out,
                                    struct err *e);
/* The irradiance source of frame f's version v. Light-path frames use a cache slot of the
 * job's own (slot_id, "job:<id>", borrowed until out is used), so that moving the light
 * neither disturbs the scene's slot (views and renders) nor is cancelled by it; volumes are
 * shared by key. */
void job_frame_source(struct store_scene *v, const struct job_frame *f, const char *slot_id,
                      struct irradiance_source *out);
/* True when some light of src failed its simulation (msg says which and where to look):
 * the frame can never be lit. */
bool job_frame_lights_failed(struct irradiance_cache *c, const struct irradiance_source *src,
                             char *msg, size_t size);
/* Frame f of version v by the reference path tracer ("mode": "reference": f's samples and
 * seed, every CPU, no time budget; request/reference_render.h): out->rgba is the mean (new,
 * caller frees). BUSY when another reference render holds the CPUs (one at a time in the
 * process), SHUTTING_DOWN when the daemon stops meanwhile, CONFLICT for a scene the path
 * tracer cannot render yet (its message names why). Any thread but the GPU thread. */
enum refract_code job_frame_reference(struct store_scene *v, const struct job_frame *f,
                                      struct render_view_result *out, struct err *e);
/* Encodes a rendered frame in f's format and exposure: *bytes is new (caller frees). */
enum refract_code job_frame_encode(const struct render_view_result *res, const struct job_frame *f,
                                   enum scene_tonemap tonemap, void **bytes, size_t *len,
                                   struct err *e);

/* ---- job_batch.c: `refractd --batch`, one array task of a job (docs/slurm.md) ---- */

struct gpu;
struct render;

struct job_batch_desc {
    struct store *store;                 /* borrowed; scenes of --scene-dir are in it */
    struct gpu *gpu;                     /* borrowed */
    struct render *render;               /* borrowed; GPU thread only */
    struct irradiance_cache *irradiance; /* borrowed */
    struct job_limits limits;
    long long tile_pixels; /* --render-tile-pixels, as the daemon draws frames; <= 0 = default */
    const char *spec_path; /* the job specification, a JSON file as POST /v1/jobs takes */
    const char *frames;    /* "A-B" (inclusive, 0-based) or NULL */
    const char *task;      /* "I/N": task I (0-based) of N takes its share; or NULL */
    const char *out_dir;   /* where frame_NNNNN.<ext> and progress.json go */
    /* Polled between frames, before each tile and while waiting for lights: true stops the
     * task, dropping the frame in flight (SIGTERM from a scheduler). NULL = never. */
    bool (*stop)(void *user);
    void *stop_user;
};

/* What one run did (the log's summary line). */
struct job_batch_report {
    int frames_total;      /* frames of the whole job */
    int first, last;       /* this task's range, inclusive; last < first: empty */
    int rendered, skipped; /* skipped: already complete in out_dir */
    int temps_removed;     /* partial files of a killed earlier run of this range */
    bool stopped;          /* desc->stop said so before the range was finished */
};

/* Renders frames first..last of the job in desc->spec_path into desc->out_dir, each frame
 * written to a temporary file, fsynced and renamed to frame_NNNNN.<ext> (the names of GET
 * /v1/jobs/{id}/archive), so a frame either is complete or is not there. Frames already
 * there are skipped; this range's leftover temporary files are removed first. Progress:
 * out_dir/progress.d/frames_A-B.json (this task's own record) and out_dir/progress.json
 * (the whole job, rebuilt from the directory), both replaced atomically after each frame.
 * Thread: the caller's (not the GPU thread); it waits for each frame. Errors: the
 * specification's (path first, as POST /v1/jobs says them), USAGE for a bad range, IO for
 * the output directory, the renderer's. A stop is not an error (report->stopped). */
enum refract_code job_batch_run(const struct job_batch_desc *desc, struct job_batch_report *report,
                                struct err *e);
/* The frame range from --frames "A-B" or --task "I/N" (exactly one of them non-NULL) for a
 * job of total frames: task I of N takes frames [I*total/N, (I+1)*total/N - 1] (integer
 * division: shares differ by at most one frame; a task beyond total frames gets none:
 * *last < *first). USAGE naming the flag and what it accepts. */
enum refract_code job_batch_range(const char *frames, const char *task, int total, int *first,
                                  int *last, struct err *e);

/* ---- job_batch_dir.c: the output directory of batch tasks ---- */

/* out gets DIR/frame_NNNNN.<ext> (5 digits at least, the archive's names). */
void job_batch_frame_path(const char *dir, int n, enum job_format f, char *out, size_t size);
/* True when frame n is complete in dir: a non-empty regular file under its final name
 * (only a rename puts one there). */
bool job_batch_frame_exists(const char *dir, int n, enum job_format f);
/* Writes frame n atomically: DIR/.frame_NNNNN.<ext>.<host>.<pid>.tmp, fsync, rename to
 * its final name, fsync dir. IO naming the file and the system's reason. */
enum refract_code job_batch_frame_write(const char *dir, int n, enum job_format f,
                                        const void *bytes, size_t len, struct err *e);
/* Removes the temporary files a killed run of range first..last left: its frames'
 * (.frame_NNNNN.*.tmp) and its progress files' (progress.json.frames_A-B.*.tmp,
 * progress.d/frames_A-B.json.*.tmp). Returns how many. Only this range's: other tasks may
 * be writing theirs. */
int job_batch_clean_temps(const char *dir, int first, int last);
/* Creates dir and its parents (mode 0755) and dir/progress.d. IO when it cannot. */
enum refract_code job_batch_dir_prepare(const char *dir, struct err *e);

/* A task's record (progress.d/frames_A-B.json). */
struct job_batch_task {
    int first, last;
    int done;          /* frames of its range complete in the directory */
    const char *state; /* "running", "done", "failed", "stopped" */
    const char *message;
};
/* Replaces the task's record, then rebuilds progress.json from the frames present and
 * every task record (temporary file + rename: a reader sees the old or the new file). Every
 * task calls it after each frame; it rebuilds until what it wrote matches the directory,
 * so the last writer leaves the final state. IO on failure. */
enum refract_code job_batch_progress_write(const char *dir, const struct job_batch_task *t,
                                           const struct job_frame *frames, int total,
                                           struct err *e);

#endif
