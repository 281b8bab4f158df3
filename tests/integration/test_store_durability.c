/*
 * test_store_durability.c - the data directory keeps what it acknowledged and nothing
 * half-made (docs/ARCHITECTURE.md, "Data directory"), through real refractd processes
 * killed with SIGKILL:
 *   - kill -9 right after a 201: after a restart the upload is back with the same
 *     checksum and content address;
 *   - kill -9 in the middle of a large upload (a slow sender that sent half its body,
 *     which is already on disk in <data>/tmp): after a restart the upload is absent,
 *     <data>/tmp is empty and the storage report counts only what was committed;
 *   - an orphan blob (no row names it) and a stray temporary file are collected at
 *     start-up;
 *   - over --max-storage-bytes an upload gets 507 storage_error naming the flag and the
 *     use; the same content under a second name costs nothing (content addressing);
 *     DELETE of the scene frees the bytes and removes the blob files;
 *   - a data directory in the old file layout (a volume, and a mesh as branch mesh kept
 *     them) is converted on first open.
 */
#include <arpa/inet.h>
#include <dirent.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "daemon.h"
#include "test.h"
#include "upload_util.h"

#define SIDE 64
#define COUNT (SIDE * SIDE * SIDE)
#define BIG_SIDE 128

static const char *const scene_json =
    "{\"name\": \"durable\", \"objects\": [{\"bounds\": {\"min\": [-1, -1, -1],"
    " \"max\": [1, 1, 1]}, \"resolution\": 4, \"ior\": 1.5}]}";

static void sleep_ms(int ms)
{
    struct timespec ts = {ms / 1000, (long)(ms % 1000) * 1000000L};
    nanosleep(&ts, NULL);
}

static void kill9(struct test_daemon *d)
{
    refract_client_destroy(d->client);
    d->client = NULL;
    kill(d->pid, SIGKILL);
    int status;
    waitpid(d->pid, &status, 0);
    d->pid = 0;
}

/* Files in dir (recursively one level for blobs/<aa>/), and their total size. */
static int count_files(const char *dir, bool fanout, long long *bytes)
{
    DIR *dp = opendir(dir);
    if (dp == NULL)
        return 0;
    int n = 0;
    struct dirent *ent;
    while ((ent = readdir(dp)) != NULL) {
        if (ent->d_name[0] == '.')
            continue;
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", dir, ent->d_name);
        struct stat st;
        if (stat(path, &st) != 0)
            continue;
        if (S_ISDIR(st.st_mode) && fanout) {
            n += count_files(path, false, bytes);
        } else if (S_ISREG(st.st_mode)) {
            n++;
            if (bytes)
                *bytes += st.st_size;
        }
    }
    closedir(dp);
    return n;
}

static double storage_number(struct test_daemon *d, const char *key)
{
    char *body = NULL;
    CHECK_INT(test_request(d, "GET", "/v1/storage", NULL, &body), 200);
    double x = upload_json_number(body, key);
    free(body);
    return x;
}

static float *volume(float base)
{
    float *v = malloc(COUNT * sizeof *v);
    for (int i = 0; i < COUNT; i++)
        v[i] = base + 1e-6f * (float)(i % 1000);
    return v;
}

static long put_volume(struct test_daemon *d, const char *id, const char *name, const float *v,
                       char **body)
{
    char path[256];
    snprintf(path, sizeof path, "/v1/scenes/%s/volumes/%s?dims=%d,%d,%d", id, name, SIDE, SIDE,
             SIDE);
    return upload_put(d, path, v, COUNT * sizeof *v, body);
}

/* Sends the headers and the first half of a BIG_SIDE^3 float32 body, then waits until
 * refractd has put at least a quarter of the body into <data>/tmp. Returns the socket. */
static int slow_sender_half(struct test_daemon *d, const char *id, long long *tmp_bytes)
{
    size_t total = (size_t)BIG_SIDE * BIG_SIDE * BIG_SIDE * sizeof(float);
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    struct sockaddr_in addr = {.sin_family = AF_INET, .sin_port = htons((uint16_t)d->port)};
    inet_pton(AF_INET, "127.0.0.1", &addr.sin_addr);
    if (fd < 0 || connect(fd, (struct sockaddr *)&addr, sizeof addr) != 0)
        return -1;
    char head[512];
    int n = snprintf(head, sizeof head,
                     "PUT /v1/scenes/%s/volumes/big?dims=%d,%d,%d HTTP/1.1\r\nHost: 127.0.0.1\r\n"
                     "Content-Type: application/octet-stream\r\nContent-Length: %zu\r\n\r\n",
                     id, BIG_SIDE, BIG_SIDE, BIG_SIDE, total);
    CHECK(send(fd, head, (size_t)n, 0) == n);
    char *chunk = calloc(1, 1 << 20);
    for (size_t i = 0; i < 1 << 20; i++)
        chunk[i] = (char)(i * 7);
    for (size_t sent = 0; sent < total / 2; sent += 1 << 20)
        if (send(fd, chunk, 1 << 20, MSG_NOSIGNAL) != 1 << 20)
            break;
    free(chunk);
    char tmp[400];
    snprintf(tmp, sizeof tmp, "%s/tmp", d->data_dir);
    for (int waited = 0; waited < 20000; waited += 20) {
        *tmp_bytes = 0;
        count_files(tmp, false, tmp_bytes);
        if (*tmp_bytes >= (long long)total / 4)
            break;
        sleep_ms(20);
    }
    return fd;
}

static void plant_orphans(const char *data_dir)
{
    char path[600];
    const char *hash = "abababababababababababababababababababababababababababababababab";
    snprintf(path, sizeof path, "%s/blobs/ab", data_dir);
    mkdir(path, 0750);
    snprintf(path, sizeof path, "%s/blobs/ab/%s", data_dir, hash);
    FILE *f = fopen(path, "wb");
    if (f) {
        fputs("orphan", f);
        fclose(f);
    }
    snprintf(path, sizeof path, "%s/tmp/upload-stray", data_dir);
    f = fopen(path, "wb");
    if (f) {
        fputs("stray", f);
        fclose(f);
    }
}

static void durability(void)
{
    struct test_daemon a, b, c;
    if (!test_daemon_start(&a, NULL))
        test_setup_failed("test_store_durability", a.why);
    char id[REFRACT_ID_SIZE];
    CHECK(test_create_scene(&a, scene_json, id));
    float *kept = volume(1.25f);
    char *body = NULL, sum[32], sha[80], want[17];
    CHECK_INT(put_volume(&a, id, "kept", kept, &body), 201);
    upload_json_string(body, "checksum_fnv1a64", sum, sizeof sum);
    upload_json_string(body, "sha256", sha, sizeof sha);
    free(body);
    upload_fnv_hex(kept, COUNT, want);
    CHECK_STR(sum, want);
    kill9(&a); /* right after the 201 */

    if (!test_daemon_start_in(&b, a.data_dir, NULL))
        test_setup_failed("test_store_durability (restart 1)", b.why);
    char path[256];
    snprintf(path, sizeof path, "/v1/scenes/%s", id);
    CHECK_INT(test_request(&b, "GET", path, NULL, &body), 200);
    CHECK_CONTAINS(body, sum);
    CHECK_CONTAINS(body, sha);
    free(body);
    CHECK_NEAR(storage_number(&b, "used_bytes"), (double)COUNT * 4, 0.0);
    long long tmp_bytes = 0;
    int fd = slow_sender_half(&b, id, &tmp_bytes);
    CHECK(fd >= 0);
    printf("half-sent upload: %lld bytes in <data>/tmp when killed\n", tmp_bytes);
    CHECK_MSG(tmp_bytes > 0, "the upload should be streaming to <data>/tmp");
    kill9(&b); /* in the middle of the upload */
    if (fd >= 0)
        close(fd);
    plant_orphans(a.data_dir);

    const char *const limit[] = {"--max-storage-bytes", "1572864", NULL}; /* 1.5 MiB */
    if (!test_daemon_start_in(&c, a.data_dir, limit))
        test_setup_failed("test_store_durability (restart 2)", c.why);
    char dir[400];
    snprintf(dir, sizeof dir, "%s/tmp", a.data_dir);
    CHECK_INT(count_files(dir, false, NULL), 0);
    snprintf(dir, sizeof dir, "%s/blobs", a.data_dir);
    long long blob_bytes = 0;
    CHECK_INT(count_files(dir, true, &blob_bytes), 1); /* kept; the orphan is gone */
    CHECK_INT(blob_bytes, (long long)COUNT * 4);
    CHECK_NEAR(storage_number(&c, "uploads"), 1, 0.0);
    CHECK_NEAR(storage_number(&c, "used_bytes"), (double)COUNT * 4, 0.0);
    CHECK_INT(test_request(&c, "GET", path, NULL, &body), 200);
    CHECK_CONTAINS(body, "\"kept\"");
    CHECK(strstr(body, "\"big\"") == NULL);
    free(body);

    /* Over the limit: 507 with the flag and the use; a duplicate costs nothing. */
    float *other = volume(1.5f);
    CHECK_INT(put_volume(&c, id, "other", other, &body), 507);
    CHECK(test_error_is(body, "storage_error", "--max-storage-bytes"));
    CHECK_CONTAINS(body, "1048576 of 1572864 bytes are in use");
    free(body);
    CHECK_INT(put_volume(&c, id, "dup", kept, &body), 201);
    free(body);
    CHECK_NEAR(storage_number(&c, "used_bytes"), (double)COUNT * 4, 0.0);
    CHECK_NEAR(storage_number(&c, "uploads"), 2, 0.0);
    /* DELETE frees the bytes and the files. */
    CHECK_INT(test_request(&c, "DELETE", path, NULL, NULL), 204);
    CHECK_NEAR(storage_number(&c, "used_bytes"), 0, 0.0);
    CHECK_INT(count_files(dir, true, NULL), 0);
    CHECK(test_create_scene(&c, scene_json, id));
    CHECK_INT(put_volume(&c, id, "other", other, &body), 201);
    free(body);
    /* Replacing an upload frees its old blob. */
    CHECK_INT(put_volume(&c, id, "other", kept, &body), 201);
    free(body);
    CHECK_NEAR(storage_number(&c, "used_bytes"), (double)COUNT * 4, 0.0);
    CHECK_INT(count_files(dir, true, NULL), 1);
    CHECK_INT(test_daemon_stop(&c), 0);
    free(kept);
    free(other);
    test_daemon_cleanup(&b);
    test_daemon_cleanup(&c);
    test_daemon_cleanup(&a);
}

static void write_file(const char *path, const void *data, size_t len)
{
    FILE *f = fopen(path, "wb");
    if (f) {
        fwrite(data, 1, len, f);
        fclose(f);
    }
}

static void old_layout_is_converted(void)
{
    char root[256];
    test_temp_template(root, sizeof root, "refract-migrate");
    CHECK(mkdtemp(root) != NULL);
    char path[512];
    snprintf(path, sizeof path, "%s/scenes", root);
    mkdir(path, 0750);
    snprintf(path, sizeof path, "%s/scenes/old1", root);
    mkdir(path, 0750);
    snprintf(path, sizeof path, "%s/scenes/old1/volumes", root);
    mkdir(path, 0750);
    snprintf(path, sizeof path, "%s/scenes/old1/scene.json", root);
    write_file(path, scene_json, strlen(scene_json));
    float v[2 * 3 * 4];
    for (int i = 0; i < 24; i++)
        v[i] = 1.0f + 0.1f * (float)i;
    snprintf(path, sizeof path, "%s/scenes/old1/volumes/v.f32", root);
    write_file(path, v, sizeof v);
    const char *meta = "{\"dims\": [2, 3, 4], \"components\": 1}\n";
    snprintf(path, sizeof path, "%s/scenes/old1/volumes/v.json", root);
    write_file(path, meta, strlen(meta));
    /* A mesh in branch mesh's file layout. */
    const char *obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    snprintf(path, sizeof path, "%s/scenes/old1/meshes", root);
    mkdir(path, 0750);
    snprintf(path, sizeof path, "%s/scenes/old1/meshes/tri.obj", root);
    write_file(path, obj, strlen(obj));
    char mesh_sum[40];
    snprintf(mesh_sum, sizeof mesh_sum, "\"checksum\":\"%016llx\"",
             (unsigned long long)upload_fnv1a64(obj, strlen(obj)));
    struct test_daemon d;
    if (!test_daemon_start_in(&d, root, NULL))
        test_setup_failed("test_store_durability (migration)", d.why);
    char *body = NULL, want[17];
    CHECK_INT(test_request(&d, "GET", "/v1/scenes/old1", NULL, &body), 200);
    upload_fnv_hex(v, 24, want);
    CHECK_CONTAINS(body, want);
    CHECK_CONTAINS(body, "\"dims\":[2,3,4]");
    CHECK_CONTAINS(body, "\"name\":\"tri\",\"format\":\"obj\",\"triangles\":1");
    CHECK_CONTAINS(body, mesh_sum);
    free(body);
    struct stat st;
    snprintf(path, sizeof path, "%s/scenes.migrated/old1/scene.json", root);
    CHECK(stat(path, &st) == 0);
    snprintf(path, sizeof path, "%s/scenes", root);
    CHECK(stat(path, &st) != 0);
    CHECK_INT(test_daemon_stop(&d), 0);
    /* A second start reads the database alone. */
    struct test_daemon d2;
    if (!test_daemon_start_in(&d2, root, NULL))
        test_setup_failed("test_store_durability (migration restart)", d2.why);
    CHECK_INT(test_request(&d2, "GET", "/v1/scenes/old1", NULL, &body), 200);
    CHECK_CONTAINS(body, want);
    CHECK_CONTAINS(body, mesh_sum);
    free(body);
    CHECK_INT(test_daemon_stop(&d2), 0);
    test_daemon_cleanup(&d2);
    test_daemon_cleanup(&d);
    char cmd[600];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
    CHECK_INT(system(cmd), 0);
}

int main(void)
{
    durability();
    old_layout_is_converted();
    return test_summary("test_store_durability");
}
