/*
 * test_jobs_concurrent_view.c - concurrent uploads and jobs while a viewer renders (issue
 * 5, "Tests"): one thread reads a view session's MJPEG stream (librefract's
 * refract_view_stream) while another orbits its camera with PATCHes, and meanwhile, on
 * other scenes, one thread uploads volumes (PUT .../volumes/{name}, raw float32), another
 * uploads meshes (POST .../meshes, OBJ) and a batch job renders. Checked:
 *   - the viewer keeps receiving frames while the uploads and the job run (at least
 *     MIN_VIEW_FRAMES of them arrive in that window);
 *   - every upload answers 201 with the checksum and SHA-256 computed here from the bytes;
 *   - the job finishes with every frame exactly once (frames 0..N-1 readable, N not; the
 *     archive holds each once);
 *   - no request fails: every PATCH, upload and status poll is answered 2xx and the
 *     stream ends cleanly when the session is deleted.
 * Everything is tiny (64x48 view and job frames, 16^3 and smaller grids) so that it
 * runs in seconds on llvmpipe.
 */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>

#include "core/sha256.h"
#include "jobs_util.h"
#include "upload_util.h"
#include "view_util.h"

#define JOB_FRAMES 24
#define MIN_VIEW_FRAMES 2
#define MIN_UPLOADS 8
#define MAX_UPLOADS 40

struct shared {
    const char *url;
    char view_id[32];
    char upload_scene[REFRACT_ID_SIZE];
    atomic_bool busy;      /* uploads or the job still running: the window viewer frames count in */
    atomic_bool work_done; /* the job ended and the uploaders stopped */
    atomic_bool viewer_done; /* the stream reader returned */
    atomic_int frames_total, frames_busy;
    int stream_code;
    char stream_msg[256];
    int patches, patch_failures;
    char patch_msg[256];
};

struct uploader {
    struct shared *sh;
    bool mesh; /* meshes, else volumes */
    int count, failures;
    char msg[1024];
};

static int on_frame(const struct refract_frame *f, void *user)
{
    struct shared *sh = user;
    (void)f;
    atomic_fetch_add(&sh->frames_total, 1);
    if (atomic_load(&sh->busy))
        atomic_fetch_add(&sh->frames_busy, 1);
    return 0; /* until the session is deleted */
}

static void *viewer(void *arg)
{
    struct shared *sh = arg;
    refract_client *c = refract_client_create(sh->url);
    refract_set_timeout_ms(c, 30000);
    sh->stream_code = refract_view_stream(c, sh->view_id, on_frame, sh);
    if (sh->stream_code != REFRACT_E_OK)
        snprintf(sh->stream_msg, sizeof sh->stream_msg, "%s", refract_errmsg(c));
    refract_client_destroy(c);
    atomic_store(&sh->viewer_done, true);
    return NULL;
}

/* Orbits the camera (a person dragging) until the work is done. */
static void *patcher(void *arg)
{
    struct shared *sh = arg;
    refract_client *c = refract_client_create(sh->url);
    for (int i = 0; !atomic_load(&sh->work_done); i++) {
        double a = 0.15 * i;
        char patch[160];
        snprintf(patch, sizeof patch, "{\"camera\": {\"eye\": [%.4f, 0.5, %.4f]}}", 4 * sin(a),
                 4 * cos(a));
        int code = refract_view_patch(c, sh->view_id, patch, NULL);
        sh->patches++;
        if (code != REFRACT_E_OK) {
            sh->patch_failures++;
            snprintf(sh->patch_msg, sizeof sh->patch_msg, "%s", refract_errmsg(c));
        }
        view_sleep_ms(30);
    }
    refract_client_destroy(c);
    return NULL;
}

/* A request that answered; its status and body (new). */
static long send_bytes(refract_client *c, const char *method, const char *path, const void *bytes,
                       size_t len, char **body)
{
    struct refract_response r;
    *body = NULL;
    if (refract_request(c, method, path, bytes, len, "application/octet-stream", &r) !=
        REFRACT_E_OK)
        return -1;
    *body = r.body;
    r.body = NULL;
    long status = r.status;
    refract_response_free(&r);
    return status;
}

static void sha256_hex(const void *bytes, size_t len, char hex[SHA256_HEX_SIZE])
{
    struct sha256 h;
    sha256_init(&h);
    sha256_update(&h, bytes, len);
    sha256_final_hex(&h, hex);
}

/* Upload i: a volume of n^3 float32 in 1..2 (ior-like), or an OBJ octahedron of radius
 * 0.2 + 0.05 i. The bytes are new (caller frees). */
static void *upload_bytes(bool mesh, int i, size_t *len, char *query, size_t qsize)
{
    if (mesh) {
        double s = 0.2 + 0.05 * (i % 10);
        char *obj = malloc(1024);
        int n = snprintf(obj, 1024,
                         "# octahedron %d\nv %g 0 0\nv %g 0 0\nv 0 %g 0\nv 0 %g 0\nv 0 0 %g\n"
                         "v 0 0 %g\nf 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\nf 3 1 6\nf 2 3 6\n"
                         "f 4 2 6\nf 1 4 6\n",
                         i, s, -s, s, -s, s, -s);
        *len = (size_t)n;
        snprintf(query, qsize, "meshes?name=gem%d&format=obj", i % 4);
        return obj;
    }
    int dim = 4 + 2 * (i % 7); /* 4 .. 16 */
    size_t count = (size_t)dim * dim * dim;
    float *v = malloc(count * sizeof *v);
    for (size_t k = 0; k < count; k++)
        v[k] = 1.0f + (float)((k * 2654435761u + (unsigned)i * 40503u) % 1000u) / 1000.0f;
    *len = count * sizeof *v;
    snprintf(query, qsize, "volumes/v%d?dims=%d,%d,%d&type=float32", i % 4, dim, dim, dim);
    return v;
}

static void *upload_loop(void *arg)
{
    struct uploader *u = arg;
    refract_client *c = refract_client_create(u->sh->url);
    for (int i = 0; i < MAX_UPLOADS && (i < MIN_UPLOADS || !atomic_load(&u->sh->work_done)); i++) {
        char query[128], path[256], want_sum[17], want_sha[SHA256_HEX_SIZE], got_sum[32],
            got_sha[80];
        size_t len = 0;
        void *bytes = upload_bytes(u->mesh, i, &len, query, sizeof query);
        snprintf(path, sizeof path, "/v1/scenes/%s/%s", u->sh->upload_scene, query);
        snprintf(want_sum, sizeof want_sum, "%016llx",
                 (unsigned long long)upload_fnv1a64(bytes, len));
        sha256_hex(bytes, len, want_sha);
        char *body = NULL;
        long status = send_bytes(c, u->mesh ? "POST" : "PUT", path, bytes, len, &body);
        upload_json_string(body, u->mesh ? "checksum" : "checksum_fnv1a64", got_sum,
                           sizeof got_sum);
        upload_json_string(body, "sha256", got_sha, sizeof got_sha);
        u->count++;
        if (status != 201 || strcmp(got_sum, want_sum) != 0 || strcmp(got_sha, want_sha) != 0) {
            u->failures++;
            snprintf(u->msg, sizeof u->msg, "%s %s: %ld, checksum %s (expected %s), %.200s",
                     u->mesh ? "POST" : "PUT", path, status, got_sum, want_sum,
                     body ? body : refract_errmsg(c));
        }
        free(body);
        free(bytes);
    }
    refract_client_destroy(c);
    return NULL;
}

/* The archive of job id holds frames 0..n-1 once each. */
static void archive_has_each_frame_once(struct test_daemon *d, const char *id, int n)
{
    char path[128];
    snprintf(path, sizeof path, "/v1/jobs/%s/archive", id);
    struct refract_response r;
    CHECK_INT(refract_request(d->client, "GET", path, NULL, 0, NULL, &r), 0);
    CHECK_INT(r.status, 200);
    int seen[JOB_FRAMES] = {0}, entries = 0;
    for (size_t off = 0; r.body && off + 512 <= r.body_len && r.body[off] != '\0';) {
        const char *h = r.body + off;
        int k = -1;
        const char *slash = strchr(h, '/');
        if (slash && sscanf(slash, "/frame_%d.png", &k) == 1 && k >= 0 && k < JOB_FRAMES)
            seen[k]++;
        entries++;
        off += 512 + (strtoull(h + 124, NULL, 8) + 511) / 512 * 512;
    }
    CHECK_INT(entries, n);
    for (int k = 0; k < n; k++)
        CHECK_MSG(seen[k] == 1, "frame %d is in the archive %d times", k, seen[k]);
    refract_response_free(&r);
}

static const char *const upload_scene_json =
    "{\"name\": \"uploads\", \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, "
    "1]}, \"resolution\": 8, \"ior\": {\"volume\": \"v0\"}}]}";

int main(void)
{
    struct test_daemon d;
    if (!test_daemon_start(&d, NULL))
        test_setup_failed("test_jobs_concurrent_view", d.why);
    struct shared sh = {.url = d.url};
    char view_scene[REFRACT_ID_SIZE] = "", job_scene[REFRACT_ID_SIZE] = "";
    if (!test_create_scene(&d, view_sphere_scene, view_scene) ||
        !test_create_scene(&d, view_sphere_scene, job_scene) ||
        !test_create_scene(&d, upload_scene_json, sh.upload_scene))
        test_setup_failed("test_jobs_concurrent_view", "could not create the scenes");
    if (view_open(&d, view_scene, "{\"width\": 64, \"height\": 48, \"max_fps\": 30}", sh.view_id,
                  NULL) != 201)
        test_setup_failed("test_jobs_concurrent_view", "could not open the view session");

    /* The viewer first: its stream is open and the camera moving before the work starts. */
    pthread_t view_thread, patch_thread, volume_thread, mesh_thread;
    CHECK_INT(pthread_create(&view_thread, NULL, viewer, &sh), 0);
    CHECK_INT(pthread_create(&patch_thread, NULL, patcher, &sh), 0);
    for (int i = 0; i < 500 && atomic_load(&sh.frames_total) < 1; i++)
        view_sleep_ms(10);
    CHECK_MSG(atomic_load(&sh.frames_total) >= 1, "the viewer got no first frame");

    atomic_store(&sh.busy, true);
    double busy_start_ms = view_now_ms();
    struct uploader volumes = {.sh = &sh, .mesh = false}, meshes = {.sh = &sh, .mesh = true};
    CHECK_INT(pthread_create(&volume_thread, NULL, upload_loop, &volumes), 0);
    CHECK_INT(pthread_create(&mesh_thread, NULL, upload_loop, &meshes), 0);
    char spec[256], id[64] = "";
    snprintf(spec, sizeof spec,
             "{\"scene\": \"%s\", \"width\": 64, \"height\": 48, \"turntable\": {\"frames\": %d}}",
             job_scene, JOB_FRAMES);
    CHECK(job_submit_json(&d, spec, id));
    cJSON *st = job_wait(&d, id, 120);
    CHECK_MSG(st != NULL, "GET /v1/jobs/%s failed", id);
    CHECK_STR(job_str(st, "state"), "done");
    CHECK_INT(job_int(st, "frames_done"), JOB_FRAMES);
    cJSON_Delete(st);
    atomic_store(&sh.work_done, true);
    pthread_join(volume_thread, NULL);
    pthread_join(mesh_thread, NULL);
    atomic_store(&sh.busy, false);
    double busy_ms = view_now_ms() - busy_start_ms;
    int busy_frames = atomic_load(&sh.frames_busy);
    pthread_join(patch_thread, NULL);

    /* The session's end ends its stream. */
    CHECK_INT(refract_view_delete(d.client, sh.view_id), REFRACT_E_OK);
    pthread_join(view_thread, NULL);

    CHECK_MSG(busy_frames >= MIN_VIEW_FRAMES,
              "the viewer got %d frames while %d + %d uploads and the job ran (%d in all)",
              busy_frames, volumes.count, meshes.count, atomic_load(&sh.frames_total));
    CHECK_MSG(sh.stream_code == REFRACT_E_OK, "the stream ended with %d: %s", sh.stream_code,
              sh.stream_msg);
    CHECK_MSG(sh.patch_failures == 0, "%d of %d PATCHes failed; the last: %s", sh.patch_failures,
              sh.patches, sh.patch_msg);
    CHECK_MSG(volumes.count >= MIN_UPLOADS && volumes.failures == 0,
              "%d of %d volume uploads failed; the last: %s", volumes.failures, volumes.count,
              volumes.msg);
    CHECK_MSG(meshes.count >= MIN_UPLOADS && meshes.failures == 0,
              "%d of %d mesh uploads failed; the last: %s", meshes.failures, meshes.count,
              meshes.msg);
    printf("viewer: %d frames during the %.0f ms of work (%d in all); %d volume and %d mesh "
           "uploads; %d PATCHes\n",
           busy_frames, busy_ms, atomic_load(&sh.frames_total), volumes.count, meshes.count,
           sh.patches);

    /* Every frame of the job exactly once. */
    for (int n = 0; n < JOB_FRAMES; n++) {
        struct io_image img = {0};
        CHECK_MSG(job_frame_image(&d, id, n, 64, 48, &img), "frame %d", n);
        io_image_free(&img);
    }
    char path[128];
    snprintf(path, sizeof path, "/v1/jobs/%s/frames/%d", id, JOB_FRAMES);
    CHECK_INT(test_request(&d, "GET", path, NULL, NULL), 404);
    archive_has_each_frame_once(&d, id, JOB_FRAMES);

    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_jobs_concurrent_view");
}
