/*
 * bench_upload.c - refract-upload: upload throughput of a running refractd for a
 * side^3 float32 volume (default 256^3 = 64 MiB), as raw float32 and as NRRD gzip,
 * through HTTP on loopback with librefract: the time from the first byte sent to the
 * 201, which covers receiving into <data>/tmp with SHA-256 on the way, decoding and
 * validating from the mapped file, fsync, rename and the SQLite commit.
 *
 *     build/refractd --data-dir /tmp/bench-data --port 8750 &
 *     build/refract-upload --url http://127.0.0.1:8750 --side 256 --repeat 3
 *
 * Each repeat changes one voxel so that every upload is new content (no dedupe). The
 * gzip files are made before the clock starts. MB/s is volume bytes (side^3 * 4) per
 * second; the NRRD row also gives the bytes on the wire.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <zlib.h>

#include "refract.h"

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int compare(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static unsigned char *nrrd_gzip(const float *v, size_t count, int side, size_t *len)
{
    char head[256];
    int h = snprintf(head, sizeof head,
                     "NRRD0004\ntype: float\ndimension: 3\nsizes: %d %d %d\nendian: little\n"
                     "encoding: gzip\n\n",
                     side, side, side);
    z_stream z = {0};
    deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
    size_t cap = deflateBound(&z, (uLong)(count * 4)) + (size_t)h;
    unsigned char *out = malloc(cap);
    memcpy(out, head, (size_t)h);
    z.next_in = (Bytef *)v;
    z.avail_in = (uInt)(count * 4);
    z.next_out = out + h;
    z.avail_out = (uInt)(cap - (size_t)h);
    deflate(&z, Z_FINISH);
    *len = (size_t)h + z.total_out;
    deflateEnd(&z);
    return out;
}

static void cpu_model(char *out, size_t size)
{
    snprintf(out, size, "unknown CPU");
    FILE *f = fopen("/proc/cpuinfo", "r");
    char line[256];
    while (f && fgets(line, sizeof line, f)) {
        if (strncmp(line, "model name", 10) == 0) {
            char *c = strchr(line, ':');
            snprintf(out, size, "%.100s", c ? c + 2 : line);
            out[strcspn(out, "\n")] = '\0';
            break;
        }
    }
    if (f)
        fclose(f);
}

int main(int argc, char **argv)
{
    const char *url = "http://127.0.0.1:8750";
    int side = 256, repeat = 3;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--url") == 0)
            url = argv[i + 1];
        else if (strcmp(argv[i], "--side") == 0)
            side = atoi(argv[i + 1]);
        else if (strcmp(argv[i], "--repeat") == 0)
            repeat = atoi(argv[i + 1]);
    }
    if (side < 2 || side > 1024 || repeat < 1 || repeat > 50) {
        fprintf(stderr, "usage: %s [--url URL] [--side N] [--repeat N]\n", argv[0]);
        return 2;
    }
    refract_client *c = refract_client_create(url);
    char id[REFRACT_ID_SIZE];
    const char *scene = "{\"name\": \"upload bench\", \"objects\": [{\"bounds\": {\"min\": [-1, "
                        "-1, -1], \"max\": [1, 1, 1]}, \"resolution\": 4, \"ior\": 1.5}]}";
    if (c == NULL || refract_scene_create(c, scene, strlen(scene), id, sizeof id) != REFRACT_E_OK) {
        fprintf(stderr, "refract-upload: cannot create a scene at %s: %s\n", url,
                c ? refract_errmsg(c) : "no client");
        return 1;
    }
    size_t count = (size_t)side * side * side;
    float *v = malloc(count * sizeof *v);
    for (size_t i = 0; i < count; i++) /* a smooth GRIN-like field: compresses like CT data */
        v[i] = 1.3f + 0.2f * sinf(0.05f * (float)(i % (size_t)side)) *
                          cosf(0.03f * (float)((i / (size_t)side) % (size_t)side));
    char cpu[128], date[64];
    cpu_model(cpu, sizeof cpu);
    time_t t = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", gmtime(&t));
    printf("date: %s\nCPU: %s\ncommand:", date, cpu);
    for (int i = 0; i < argc; i++)
        printf(" %s", argv[i]);
    printf("\n\n| format | volume | bytes sent | median time | MB/s (volume) |\n| --- | --- | "
           "--- | --- | --- |\n");
    for (int format = 0; format < 2; format++) {
        double *times = calloc((size_t)repeat, sizeof *times);
        size_t wire = 0;
        for (int r = 0; r < repeat; r++) {
            v[0] = 1.3f + 1e-4f * (float)(r + 1 + format * 100);
            unsigned char *gz = NULL;
            char path[256];
            if (format == 1) {
                gz = nrrd_gzip(v, count, side, &wire);
                snprintf(path, sizeof path, "/v1/scenes/%s/volumes/bench", id);
            } else {
                wire = count * 4;
                snprintf(path, sizeof path, "/v1/scenes/%s/volumes/bench?dims=%d,%d,%d", id, side,
                         side, side);
            }
            struct refract_response resp;
            double t0 = now_s();
            int rc = refract_request(c, "PUT", path, gz ? (const void *)gz : (const void *)v, wire,
                                     "application/octet-stream", &resp);
            times[r] = now_s() - t0;
            if (rc != REFRACT_E_OK || resp.status != 201) {
                fprintf(stderr, "upload failed: %s %s\n", refract_errmsg(c),
                        rc == REFRACT_E_OK ? resp.body : "");
                return 1;
            }
            refract_response_free(&resp);
            free(gz);
        }
        qsort(times, (size_t)repeat, sizeof *times, compare);
        double med = times[repeat / 2];
        printf("| %s | %d^3 float32 (%.1f MiB) | %.1f MiB | %.0f ms | %.0f |\n",
               format ? "NRRD gzip" : "raw float32", side, (double)count * 4 / 1048576.0,
               (double)wire / 1048576.0, med * 1000.0, (double)count * 4 / 1e6 / med);
        free(times);
    }
    char del[128];
    snprintf(del, sizeof del, "/v1/scenes/%s", id);
    struct refract_response resp;
    if (refract_request(c, "DELETE", del, NULL, 0, NULL, &resp) == REFRACT_E_OK)
        refract_response_free(&resp);
    refract_client_destroy(c);
    free(v);
    return 0;
}
