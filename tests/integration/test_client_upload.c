/*
 * test_client_upload.c - librefract's streamed uploads (refract_upload_file,
 * refract_upload_stream) against a real refractd:
 *   - the progress callback starts at 0, never goes back, and ends at the file's size,
 *     with total_bytes the size throughout; the stored volume is the file (sha256sum);
 *   - the body is streamed, not read whole first: a pipe is fed half of a volume, and
 *     refractd must have been sent a good part of it (progress) before the other half
 *     is written; a client that read to the end before sending would never get there
 *     (the writer gives up after 30 s, and the check fails). Once with the size given
 *     (Content-Length) and once without (chunked);
 *   - a pipe that ends before the size it promised is REFRACT_E_IO naming the bytes;
 *   - wrong arguments are REFRACT_E_USAGE (volume fields on a mesh, a name for the
 *     environment, bad dims), a missing file REFRACT_E_IO, a missing scene
 *     REFRACT_E_SCENE_NOT_FOUND with refractd's message;
 *   - a mesh goes by POST with ?name and ?format, a uint8 volume with ?type and ?scale;
 *   - a file over --max-upload-bytes (4 MiB here) gets refractd's 413 body_too_large
 *     before its body goes: the size is sent first and libcurl waits for refractd's
 *     "100 Continue", which never comes, so less than half of it was sent.
 */
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "daemon.h"
#include "test.h"
#include "upload_util.h"

#define N 96 /* 96^3 float32 = 3.4 MiB */

static struct test_daemon d;
static char scene[REFRACT_ID_SIZE];

/* What the progress callback saw. */
struct seen {
    int calls;
    long long first, last, total;
    bool monotone, total_constant;
    _Atomic long long sent; /* read by the pipe writer thread */
};

static void on_progress(long long sent, long long total, void *user)
{
    struct seen *s = user;
    if (s->calls == 0) {
        s->first = sent;
        s->total = total;
    }
    s->monotone = s->monotone && sent >= s->last;
    s->total_constant = s->total_constant && total == s->total;
    s->last = sent;
    s->calls++;
    atomic_store(&s->sent, sent);
}

static float *volume(size_t count)
{
    float *v = malloc(count * sizeof *v);
    for (size_t i = 0; i < count; i++)
        v[i] = 1.0f + (float)(i % 1000) / 2000.0f;
    return v;
}

static void progress_is_monotone_and_ends_at_the_size(void)
{
    size_t count = (size_t)N * N * N, bytes = count * sizeof(float);
    float *v = volume(count);
    char path[400];
    snprintf(path, sizeof path, "%s/big.raw", d.dir);
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL && fwrite(v, 1, bytes, f) == bytes);
    fclose(f);
    struct seen s = {.last = -1, .monotone = true, .total_constant = true};
    struct refract_upload_desc up = {.kind = REFRACT_UPLOAD_VOLUME,
                                     .name = "big",
                                     .format = "raw",
                                     .dims = {N, N, N},
                                     .progress = on_progress,
                                     .user = &s};
    char *json = NULL;
    int rc = refract_upload_file(d.client, scene, path, &up, &json);
    CHECK_MSG(rc == REFRACT_E_OK, "upload: %s", refract_errmsg(d.client));
    CHECK(s.calls >= 3);
    CHECK_INT(s.first, 0);
    CHECK(s.monotone);
    CHECK(s.total_constant);
    CHECK_INT(s.total, (long long)bytes);
    CHECK_INT(s.last, (long long)bytes);
    char want[65], got[80];
    upload_sha256sum(path, want);
    upload_json_string(json, "sha256", got, sizeof got);
    CHECK_STR(got, want);
    printf("progress: %d calls for %zu bytes\n", s.calls, bytes);
    refract_free(json);
    free(v);
}

/* The pipe's writer: half the bytes, then (once the client has sent a quarter) the rest. */
struct feeder {
    int fd;
    const unsigned char *bytes;
    size_t len;
    struct seen *seen;
    bool sent_before_the_end; /* the client had sent len/4 bytes with len/2 written */
    bool short_by_one;        /* write len - 1 bytes and close */
};

static bool write_all(int fd, const unsigned char *p, size_t n)
{
    while (n > 0) {
        ssize_t w = write(fd, p, n);
        if (w <= 0)
            return false;
        p += w;
        n -= (size_t)w;
    }
    return true;
}

static void *feed(void *arg)
{
    struct feeder *fd = arg;
    size_t half = fd->len / 2;
    write_all(fd->fd, fd->bytes, half);
    for (int i = 0; i < 3000; i++) { /* 30 s */
        if (atomic_load(&fd->seen->sent) >= (long long)(fd->len / 4)) {
            fd->sent_before_the_end = true;
            break;
        }
        nanosleep(&(struct timespec){0, 10 * 1000 * 1000}, NULL);
    }
    write_all(fd->fd, fd->bytes + half, fd->len - half - (fd->short_by_one ? 1 : 0));
    close(fd->fd);
    return NULL;
}

/* Uploads len bytes through a pipe; size -1 = unknown (chunked). */
static int upload_through_pipe(const void *bytes, size_t len, long long size, bool short_by_one,
                               struct feeder *out, char **json)
{
    int fds[2];
    CHECK(pipe(fds) == 0);
    struct seen s = {.last = -1, .monotone = true, .total_constant = true};
    *out = (struct feeder){
        .fd = fds[1], .bytes = bytes, .len = len, .seen = &s, .short_by_one = short_by_one};
    pthread_t t;
    pthread_create(&t, NULL, feed, out);
    FILE *in = fdopen(fds[0], "rb");
    struct refract_upload_desc up = {.kind = REFRACT_UPLOAD_VOLUME,
                                     .name = "piped",
                                     .format = "raw",
                                     .dims = {N, N, N},
                                     .progress = on_progress,
                                     .user = &s};
    int rc = refract_upload_stream(d.client, scene, in, size, &up, json);
    pthread_join(t, NULL);
    fclose(in);
    CHECK(s.monotone);
    return rc;
}

static void the_body_is_streamed(void)
{
    size_t count = (size_t)N * N * N, bytes = count * sizeof(float);
    float *v = volume(count);
    char want[17], got[32];
    upload_fnv_hex(v, count, want);
    for (int chunked = 0; chunked < 2; chunked++) {
        struct feeder fd;
        char *json = NULL;
        int rc = upload_through_pipe(v, bytes, chunked ? -1 : (long long)bytes, false, &fd, &json);
        CHECK_MSG(rc == REFRACT_E_OK, "%s pipe: %s", chunked ? "chunked" : "sized",
                  refract_errmsg(d.client));
        CHECK_MSG(fd.sent_before_the_end,
                  "%s pipe: nothing was sent before the whole file was there",
                  chunked ? "chunked" : "sized");
        upload_json_string(json, "checksum_fnv1a64", got, sizeof got);
        CHECK_STR(got, want);
        refract_free(json);
    }
    /* a pipe that ends one byte short of the size it promised */
    struct feeder fd;
    char *json = NULL;
    int rc = upload_through_pipe(v, bytes, (long long)bytes, true, &fd, &json);
    CHECK_INT(rc, REFRACT_E_IO);
    CHECK_CONTAINS(refract_errmsg(d.client), "ended after");
    CHECK(json == NULL);
    free(v);
}

static void arguments_are_checked(void)
{
    char *json = NULL;
    struct refract_upload_desc mesh_with_dims = {
        .kind = REFRACT_UPLOAD_MESH, .name = "m", .dims = {2, 2, 2}};
    CHECK_INT(refract_upload_file(d.client, scene, "/dev/null", &mesh_with_dims, &json),
              REFRACT_E_USAGE);
    CHECK_CONTAINS(refract_errmsg(d.client), "apply to volumes only");
    struct refract_upload_desc named_env = {.kind = REFRACT_UPLOAD_ENVIRONMENT, .name = "sky"};
    CHECK_INT(refract_upload_file(d.client, scene, "/dev/null", &named_env, &json),
              REFRACT_E_USAGE);
    struct refract_upload_desc bad_dims = {
        .kind = REFRACT_UPLOAD_VOLUME, .name = "v", .dims = {4, 0, 4}};
    CHECK_INT(refract_upload_file(d.client, scene, "/dev/null", &bad_dims, &json), REFRACT_E_USAGE);
    struct refract_upload_desc nameless = {.kind = REFRACT_UPLOAD_VOLUME};
    CHECK_INT(refract_upload_file(d.client, scene, "/dev/null", &nameless, &json), REFRACT_E_USAGE);
    CHECK_INT(refract_upload_file(d.client, scene, "/dev/null", NULL, &json), REFRACT_E_USAGE);
    struct refract_upload_desc ok = {.kind = REFRACT_UPLOAD_VOLUME, .name = "v"};
    CHECK_INT(refract_upload_file(d.client, scene, "/no/such/file.raw", &ok, &json), REFRACT_E_IO);
    CHECK_CONTAINS(refract_errmsg(d.client), "/no/such/file.raw");
    CHECK_INT(refract_upload_file(d.client, scene, d.dir, &ok, &json), REFRACT_E_IO);
    CHECK_CONTAINS(refract_errmsg(d.client), "directory");
    CHECK(json == NULL);
}

static void each_route_gets_its_query(void)
{
    char path[400];
    snprintf(path, sizeof path, "%s/u8.raw", d.dir);
    unsigned char u8[8] = {0, 51, 102, 153, 204, 255, 0, 255};
    FILE *f = fopen(path, "wb");
    fwrite(u8, 1, sizeof u8, f);
    fclose(f);
    char *json = NULL;
    struct refract_upload_desc up = {.kind = REFRACT_UPLOAD_VOLUME,
                                     .name = "u8",
                                     .format = "raw",
                                     .dims = {2, 2, 2},
                                     .type = "uint8",
                                     .components = 1,
                                     .has_scale = 1,
                                     .scale = 2.0 / 255.0,
                                     .has_offset = 1,
                                     .offset = 1.0};
    CHECK_INT(refract_upload_file(d.client, scene, path, &up, &json), REFRACT_E_OK);
    CHECK_CONTAINS(json, "\"type\":\"uint8\"");
    CHECK_NEAR(upload_json_number(json, "min"), 1.0, 1e-6);
    CHECK_NEAR(upload_json_number(json, "max"), 3.0, 1e-6);
    refract_free(json);

    snprintf(path, sizeof path, "%s/tri.ply", d.dir);
    static const char ply[] = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                              "property float y\nproperty float z\nelement face 1\n"
                              "property list uchar int vertex_indices\nend_header\n"
                              "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    f = fopen(path, "wb");
    fwrite(ply, 1, strlen(ply), f);
    fclose(f);
    struct refract_upload_desc mesh = {.kind = REFRACT_UPLOAD_MESH, .name = "tri", .format = "ply"};
    CHECK_INT(refract_upload_file(d.client, scene, path, &mesh, &json), REFRACT_E_OK);
    CHECK_CONTAINS(json, "\"format\":\"ply\"");
    CHECK_CONTAINS(json, "\"triangles\":1");
    refract_free(json);
    /* the format named is checked against the file */
    struct refract_upload_desc lie = {.kind = REFRACT_UPLOAD_MESH, .name = "tri", .format = "obj"};
    CHECK_INT(refract_upload_file(d.client, scene, path, &lie, &json), REFRACT_E_INVALID_MESH);

    CHECK_INT(refract_upload_file(d.client, "no_such_scene", path, &mesh, &json),
              REFRACT_E_SCENE_NOT_FOUND);
    CHECK_CONTAINS(refract_errmsg(d.client), "no_such_scene");
}

static void an_oversized_file_is_refused_before_its_body_goes(void)
{
    size_t bytes = 8u << 20;
    char path[400];
    snprintf(path, sizeof path, "%s/huge.raw", d.dir);
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL && fseek(f, (long)bytes - 1, SEEK_SET) == 0 && fputc(0, f) == 0);
    fclose(f);
    struct seen s = {.last = -1, .monotone = true, .total_constant = true};
    struct refract_upload_desc up = {.kind = REFRACT_UPLOAD_VOLUME,
                                     .name = "huge",
                                     .format = "raw",
                                     .dims = {128, 128, 128},
                                     .progress = on_progress,
                                     .user = &s};
    char *json = NULL;
    CHECK_INT(refract_upload_file(d.client, scene, path, &up, &json), REFRACT_E_BODY_TOO_LARGE);
    CHECK_CONTAINS(refract_errmsg(d.client), "--max-upload-bytes");
    CHECK_MSG(s.last < (long long)bytes / 2, "%lld of %zu bytes were sent before the 413", s.last,
              bytes);
    CHECK(json == NULL);
}

int main(void)
{
    if (!test_daemon_start(&d, (const char *const[]){"--max-upload-bytes", "4M", NULL}))
        test_setup_failed("test_client_upload", d.why);
    if (!test_create_scene(&d,
                           "{\"objects\": [{\"bounds\": {\"min\": [-1, -1, -1], \"max\": [1, 1, "
                           "1]}, \"resolution\": 8, \"ior\": 1.3}]}",
                           scene))
        test_setup_failed("test_client_upload", "could not create the scene");
    progress_is_monotone_and_ends_at_the_size();
    the_body_is_streamed();
    arguments_are_checked();
    each_route_gets_its_query();
    an_oversized_file_is_refused_before_its_body_goes();
    CHECK_INT(test_daemon_stop(&d), 0);
    test_daemon_cleanup(&d);
    return test_summary("test_client_upload");
}
