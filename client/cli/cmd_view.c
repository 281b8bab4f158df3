/*
 * cmd_view.c - `refract view`: watches a scene through a view session (docs/views.md)
 * and saves the frames of its stream as JPEG files, or prints the web viewer's address.
 *
 * A run creates its own session (progressive refinement off: a capture wants full
 * frames, not the quick half-size previews), reads the stream until N new frames came,
 * and deletes the session whatever happened, so an interrupted script leaves at most one
 * session behind until refractd's idle timeout ends it. Frames come only when something
 * changes; --orbit makes the change itself by turning the camera between frames (a PATCH
 * through a second client, since the first one is busy reading the stream). A frame sent
 * again with the seq it had (refractd's 15 s keep-alive) is not saved twice.
 */
#include <cjson/cJSON.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

#include "../refract_url.h"
#include "cli.h"
#include "cli_image.h"
#include "cli_view.h"

#define VIEW_USAGE                                                                                 \
    "usage: refract view SCENE [--frames N] [--out DIR] [options]\n"                               \
    "       refract view SCENE --print-url\n"                                                      \
    "\n"                                                                                           \
    "Opens a view session on scene SCENE, saves the next N frames of its stream as\n"              \
    "DIR/frame_0001.jpg, frame_0002.jpg, ..., prints one line per frame (seq, size, kind,\n"       \
    "bytes, render time, irradiance state) and ends the session. A new frame comes when\n"         \
    "something it shows changes (the camera, a light, the scene, an irradiance volume);\n"         \
    "--orbit turns the camera between frames so that each one is new. With --print-url it\n"       \
    "prints the web viewer's address (http://HOST:PORT/viewer/SCENE) and exits.\n"                 \
    "\n"                                                                                           \
    "  --frames N             how many frames to save (default 1)\n"                               \
    "  --out DIR              where to save them (default: the current directory;\n"               \
    "                         created when missing)\n"                                             \
    "  --width W, --height H  image size in pixels (default: the scene's camera)\n"                \
    "  --eye X,Y,Z            camera position, world space\n"                                      \
    "  --look-at X,Y,Z        the point the camera looks at, world space\n"                        \
    "  --up X,Y,Z             the camera's up direction\n"                                         \
    "  --fov DEG              vertical field of view in degrees\n"                                 \
    "  --exposure EV          exposure in stops\n"                                                 \
    "  --quality NAME         draft, normal (default) or final\n"                                  \
    "  --orbit DEG            after each frame, turn the eye DEG degrees around look-at\n"         \
    "                         (about up)\n"                                                        \
    "  --print-url            print the viewer's address and exit (the scene must exist)\n"        \
    "\n"                                                                                           \
    "--timeout bounds the wait for each new frame (default 120 s).\n"                              \
    "\n"                                                                                           \
    "Examples:\n"                                                                                  \
    "  refract view \"$ID\" --print-url\n"                                                         \
    "  refract view \"$ID\" --frames 36 --orbit 10 --out turntable --width 640 --height 480\n"

static int run_view(struct cli *cli, int argc, char **argv);

const struct cli_command cli_cmd_view = {
    .name = "view",
    .synopsis = "view SCENE [--frames N]",
    .summary = "save frames of a live view, or print the viewer's URL",
    .usage = VIEW_USAGE,
    .run = run_view,
};

enum view_opt {
    OPT_FRAMES,
    OPT_OUT,
    OPT_WIDTH,
    OPT_HEIGHT,
    OPT_EYE,
    OPT_LOOK_AT,
    OPT_UP,
    OPT_FOV,
    OPT_EXPOSURE,
    OPT_QUALITY,
    OPT_ORBIT,
    OPT_PRINT_URL,
    OPT_COUNT
};

/* One run's state, shared with the frame callback. */
struct view_run {
    struct cli *cli;
    refract_client *patcher; /* owned; PATCHes while cli->client reads the stream */
    const char *scene;
    char view_id[REFRACT_ID_SIZE];
    const char *dir;
    long want;                        /* frames to save */
    long saved;                       /* frames saved so far */
    long long last_seq;               /* seq of the last frame saved (-1 before the first) */
    double orbit_deg;                 /* 0 = no orbit */
    double eye[3], look_at[3], up[3]; /* the session's camera, for --orbit */
    long wait_ms;                     /* the longest wait for a new frame (0 = for ever) */
    double last_new_ms;               /* when the last new frame (or the stream) began */
    int code; /* set by the callback when it stops the stream on a failure */
};

static double now_ms(void)
{
    struct timespec ts;

    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1000.0 + (double)ts.tv_nsec / 1e6;
}

/* Parses the options into the session's create body. */
static int build_options(const struct cli_opt *opts, struct refract_view_options *o)
{
    char why[256] = "";
    long n;

    memset(o, 0, sizeof(*o));
    o->progressive = -1;
    if (opts[OPT_WIDTH].given) {
        if (!cli_parse_long(opts[OPT_WIDTH].value, 1, 65536, &n, why, sizeof(why)))
            return cli_usage_error(&cli_cmd_view, "view: --width: %s", why);
        o->width = (int)n;
    }
    if (opts[OPT_HEIGHT].given) {
        if (!cli_parse_long(opts[OPT_HEIGHT].value, 1, 65536, &n, why, sizeof(why)))
            return cli_usage_error(&cli_cmd_view, "view: --height: %s", why);
        o->height = (int)n;
    }
    o->has_eye = opts[OPT_EYE].given;
    if (o->has_eye && !cli_parse_vec3(opts[OPT_EYE].value, o->eye, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_view, "view: --eye: %s", why);
    o->has_look_at = opts[OPT_LOOK_AT].given;
    if (o->has_look_at && !cli_parse_vec3(opts[OPT_LOOK_AT].value, o->look_at, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_view, "view: --look-at: %s", why);
    o->has_up = opts[OPT_UP].given;
    if (o->has_up && !cli_parse_vec3(opts[OPT_UP].value, o->up, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_view, "view: --up: %s", why);
    if (opts[OPT_FOV].given &&
        !cli_parse_double(opts[OPT_FOV].value, &o->fov_y_deg, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_view, "view: --fov: %s", why);
    o->has_exposure = opts[OPT_EXPOSURE].given;
    if (o->has_exposure &&
        !cli_parse_double(opts[OPT_EXPOSURE].value, &o->exposure, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_view, "view: --exposure: %s", why);
    o->quality = opts[OPT_QUALITY].value; /* refractd names the allowed values */
    return REFRACT_E_OK;
}

/* `refract view SCENE --print-url`: the scene must exist, so a typo is not printed as an
 * address that shows nothing. */
static int print_url(struct cli *cli, const char *scene)
{
    char *json = NULL;
    char *id;
    char *path;
    char *url;
    int code = refract_scene_get(cli->client, scene, &json);

    refract_free(json);
    if (code != REFRACT_E_OK)
        return cli_call_failed(cli, code);
    id = refract_url_escape_dup(scene);
    path = id != NULL ? malloc(strlen(id) + sizeof("/viewer/")) : NULL;
    if (path != NULL)
        sprintf(path, "/viewer/%s", id);
    url = path != NULL ? refract_url_join(cli->url, path) : NULL;
    free(id);
    free(path);
    if (url == NULL)
        return cli_fail(REFRACT_E_OUT_OF_MEMORY, "view: out of memory");
    code = cli_print_json(url);
    free(url);
    return code;
}

/* Reads the camera of a view status JSON into r (for --orbit). */
static bool read_camera(const char *status_json, struct view_run *r)
{
    cJSON *root = cJSON_Parse(status_json);
    const cJSON *cam = cJSON_GetObjectItemCaseSensitive(root, "camera");
    const char *keys[3] = {"eye", "look_at", "up"};
    double *dst[3] = {r->eye, r->look_at, r->up};
    bool ok = cJSON_IsObject(cam);

    for (int k = 0; k < 3 && ok; k++) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(cam, keys[k]);

        ok = cJSON_IsArray(v) && cJSON_GetArraySize(v) == 3;
        for (int i = 0; i < 3 && ok; i++) {
            const cJSON *x = cJSON_GetArrayItem(v, i);

            ok = cJSON_IsNumber(x);
            dst[k][i] = ok ? x->valuedouble : 0;
        }
    }
    cJSON_Delete(root);
    return ok;
}

/* --orbit: turn the eye and PATCH it. */
static int orbit(struct view_run *r)
{
    char body[256];
    int code;

    if (!cli_orbit_eye(r->eye, r->look_at, r->up, r->orbit_deg, r->eye))
        return cli_fail(REFRACT_E_INVALID_FIELD, "view: --orbit: the camera's up is 0,0,0");
    snprintf(body, sizeof(body), "{\"camera\": {\"eye\": [%.17g, %.17g, %.17g]}}", r->eye[0],
             r->eye[1], r->eye[2]);
    code = refract_view_patch(r->patcher, r->view_id, body, NULL);
    if (code != REFRACT_E_OK)
        return cli_fail(code, "view: --orbit: %s", refract_errmsg(r->patcher));
    return REFRACT_E_OK;
}

static void report_frame(const struct view_run *r, const struct refract_frame *f, const char *path)
{
    long width = 0;
    long height = 0;
    char size[48] = "unknown size";
    char time[48] = "render time unknown";

    if (cli_image_size(f->bytes, f->len, &width, &height))
        snprintf(size, sizeof(size), "%ldx%ld", width, height);
    if (f->render_ms >= 0)
        snprintf(time, sizeof(time), "render %.1f ms", f->render_ms);
    printf("frame %ld: seq %lld, %s, %s, %zu bytes, %s, irradiance %s -> %s\n", r->saved, f->seq,
           size, f->kind[0] != '\0' ? f->kind : "full", f->len, time,
           f->irradiance[0] != '\0' ? f->irradiance : "unknown", path);
    fflush(stdout);
}

static int on_frame(const struct refract_frame *f, void *user)
{
    struct view_run *r = user;
    char path[4096];

    if (f->seq >= 0 && f->seq == r->last_seq) {
        /* A keep-alive resend: nothing changed. Give up after the wait limit. */
        if (r->wait_ms > 0 && now_ms() - r->last_new_ms > (double)r->wait_ms) {
            r->code = cli_fail(REFRACT_E_TIMEOUT,
                               "view: %ld of %ld frames in %.0f s: nothing the view shows "
                               "changed since; use --orbit, or change the camera or a light "
                               "meanwhile (raise --timeout to wait longer)",
                               r->saved, r->want, (now_ms() - r->last_new_ms) / 1000.0);
            return 1;
        }
        return 0;
    }
    r->last_seq = f->seq;
    r->last_new_ms = now_ms();
    r->saved++;
    if (!cli_frame_path(path, sizeof(path), r->dir, r->saved)) {
        r->code = cli_fail(REFRACT_E_USAGE, "view: --out: the directory name is too long");
        return 1;
    }
    r->code = cli_write_file(path, f->bytes, f->len);
    if (r->code != REFRACT_E_OK)
        return 1;
    report_frame(r, f, path);
    if (r->saved >= r->want)
        return 1;
    if (r->orbit_deg != 0) {
        r->code = orbit(r);
        if (r->code != REFRACT_E_OK)
            return 1;
    }
    return 0;
}

static int make_dir(const char *dir)
{
    struct stat st;

    if (dir[0] == '\0' || (stat(dir, &st) == 0 && S_ISDIR(st.st_mode)))
        return REFRACT_E_OK;
    if (mkdir(dir, 0777) != 0)
        return cli_fail(REFRACT_E_IO, "view: cannot create the directory '%s': %s", dir,
                        strerror(errno));
    return REFRACT_E_OK;
}

/* Creates the session, streams, and deletes the session. */
static int save_frames(struct view_run *r, const struct refract_view_options *o)
{
    struct refract_view view;
    int deleted;
    int code = refract_view_create_opts(r->cli->client, r->scene, o, &view);

    if (code != REFRACT_E_OK)
        return cli_call_failed(r->cli, code);
    snprintf(r->view_id, sizeof(r->view_id), "%s", view.id);
    if (r->orbit_deg != 0 && !read_camera(view.json, r))
        code = cli_fail(REFRACT_E_PROTOCOL, "view: --orbit: the session's status has no "
                                            "camera with eye, look_at and up");
    refract_view_free(&view);
    r->last_new_ms = now_ms();
    if (code == REFRACT_E_OK) {
        code = refract_view_stream(r->cli->client, r->view_id, on_frame, r);
        if (code == REFRACT_E_TIMEOUT && r->saved < r->want)
            code = cli_fail(code,
                            "view: %ld of %ld frames, then silence: nothing the view shows "
                            "changed; use --orbit, or change the camera or a light meanwhile "
                            "(%s)",
                            r->saved, r->want, refract_errmsg(r->cli->client));
        else if (code != REFRACT_E_OK)
            code = cli_call_failed(r->cli, code);
        else if (r->code != REFRACT_E_OK)
            code = r->code;
        else if (r->saved < r->want)
            code = cli_fail(REFRACT_E_NOT_FOUND,
                            "view: refractd ended the stream after %ld of %ld frames (the "
                            "session was deleted or expired)",
                            r->saved, r->want);
    }
    /* The session is ours: end it whatever happened. */
    deleted = refract_view_delete(r->patcher, r->view_id);
    if (deleted != REFRACT_E_OK && code == REFRACT_E_OK)
        code = cli_fail(deleted, "view: %s", refract_errmsg(r->patcher));
    return code;
}

static int run_view(struct cli *cli, int argc, char **argv)
{
    static const char *const names[] = {"the SCENE id"};
    struct cli_opt opts[OPT_COUNT] = {
        [OPT_FRAMES] = {.name = "--frames", .takes_value = true},
        [OPT_OUT] = {.name = "--out", .takes_value = true},
        [OPT_WIDTH] = {.name = "--width", .takes_value = true},
        [OPT_HEIGHT] = {.name = "--height", .takes_value = true},
        [OPT_EYE] = {.name = "--eye", .takes_value = true},
        [OPT_LOOK_AT] = {.name = "--look-at", .takes_value = true},
        [OPT_UP] = {.name = "--up", .takes_value = true},
        [OPT_FOV] = {.name = "--fov", .takes_value = true},
        [OPT_EXPOSURE] = {.name = "--exposure", .takes_value = true},
        [OPT_QUALITY] = {.name = "--quality", .takes_value = true},
        [OPT_ORBIT] = {.name = "--orbit", .takes_value = true},
        [OPT_PRINT_URL] = {.name = "--print-url"},
    };
    struct view_run r = {.cli = cli, .want = 1, .last_seq = -1, .dir = ""};
    struct refract_view_options o;
    struct cli_parsed p;
    char why[256] = "";
    int code = cli_parse_command(&cli_cmd_view, argc, argv, opts, OPT_COUNT, &p);

    if (code != REFRACT_E_OK || p.help)
        return code;
    code = cli_expect_args(&cli_cmd_view, &p, 1, 1, names);
    if (code != REFRACT_E_OK)
        return code;
    r.scene = p.pos[0];
    if (opts[OPT_FRAMES].given &&
        !cli_parse_long(opts[OPT_FRAMES].value, 1, 1000000, &r.want, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_view, "view: --frames: %s", why);
    if (opts[OPT_ORBIT].given &&
        !cli_parse_double(opts[OPT_ORBIT].value, &r.orbit_deg, why, sizeof(why)))
        return cli_usage_error(&cli_cmd_view, "view: --orbit: %s", why);
    if (opts[OPT_OUT].given)
        r.dir = opts[OPT_OUT].value;
    code = build_options(opts, &o);
    if (code == REFRACT_E_OK)
        code = cli_connect(cli);
    if (code != REFRACT_E_OK)
        return code;
    if (opts[OPT_PRINT_URL].given)
        return print_url(cli, r.scene);
    code = make_dir(r.dir);
    if (code != REFRACT_E_OK)
        return code;
    r.wait_ms = cli->timeout_ms >= 0 ? cli->timeout_ms : 120000;
    r.patcher = refract_client_create(cli->url);
    if (r.patcher == NULL)
        return cli_fail(REFRACT_E_OUT_OF_MEMORY, "view: out of memory");
    if (cli->timeout_ms >= 0)
        refract_set_timeout_ms(r.patcher, cli->timeout_ms);
    code = save_frames(&r, &o);
    refract_client_destroy(r.patcher);
    return code;
}
