/*
 * bench_voxelize.c - refract-voxelize: how long mesh voxelization takes (mesh_voxelize,
 * the CPU path every mesh layer goes through when a scene's fields are built), for a
 * generated torus of about 100k triangles filling most of a [-1, 1]^3 object, at each
 * resolution and thread count asked for. Prints a Markdown report for BENCHMARKS.md.
 *
 *   refract-voxelize [--resolutions 128,256] [--threads 1,2] [--runs 3] [--segments 224]
 *
 * A torus of `segments` x `segments` quads (2 * segments^2 triangles; 224 -> 100,352) with
 * major radius 0.6 and minor radius 0.3. Each cell is the median of `runs` voxelizations;
 * the BVH build (done once at upload) is timed separately. Wall time (CLOCK_MONOTONIC)
 * and the process's CPU time (all threads summed): on a shared machine the wall time
 * grows with the load, the CPU time much less, so both are printed with the load average.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "example_scene.h"
#include "mesh/mesh.h"

static double clock_ms(clockid_t id)
{
    struct timespec t;
    clock_gettime(id, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

static double now_ms(void)
{
    return clock_ms(CLOCK_MONOTONIC);
}

static struct mesh *torus(int seg, struct err *e)
{
    const double big = 0.6, small = 0.3, two_pi = 6.283185307179586;
    size_t nv = (size_t)seg * seg, nt = 2 * nv;
    double(*v)[3] = malloc(nv * sizeof *v);
    uint32_t(*t)[3] = malloc(nt * sizeof *t);
    if (v == NULL || t == NULL) {
        free(v);
        free(t);
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the torus");
        return NULL;
    }
    for (int i = 0; i < seg; i++) {
        double u = two_pi * i / seg;
        for (int j = 0; j < seg; j++) {
            double w = two_pi * j / seg, r = big + small * cos(w);
            double *p = v[(size_t)i * seg + j];
            p[0] = r * cos(u);
            p[1] = small * sin(w);
            p[2] = r * sin(u);
        }
    }
    size_t k = 0;
    for (int i = 0; i < seg; i++) {
        for (int j = 0; j < seg; j++) {
            uint32_t a = (uint32_t)(i * seg + j), b = (uint32_t)(((i + 1) % seg) * seg + j);
            uint32_t c = (uint32_t)(((i + 1) % seg) * seg + (j + 1) % seg);
            uint32_t d = (uint32_t)(i * seg + (j + 1) % seg);
            t[k][0] = a, t[k][1] = d, t[k][2] = c, k++;
            t[k][0] = a, t[k][1] = c, t[k][2] = b, k++;
        }
    }
    struct mesh_limits lim = {.max_triangles = nt};
    struct mesh *m = NULL;
    return mesh_create(v, nv, t, nt, &lim, &m, e) == REFRACT_E_OK ? m : NULL;
}

static int parse_list(const char *s, int *out, int max)
{
    int n = 0;
    while (*s && n < max) {
        char *end;
        long x = strtol(s, &end, 10);
        if (end == s || x < 1 || x > 4096)
            return -1;
        out[n++] = (int)x;
        s = *end == ',' ? end + 1 : end;
        if (*end != ',' && *end != '\0')
            return -1;
    }
    return n;
}

int main(int argc, char **argv)
{
    int res[8] = {128, 256}, nres = 2, thr[8] = {1, 2}, nthr = 2, runs = 3, seg = 224;
    for (int i = 1; i < argc; i++) {
        const char *val = i + 1 < argc ? argv[i + 1] : "";
        if (strcmp(argv[i], "--resolutions") == 0)
            nres = parse_list(val, res, 8), i++;
        else if (strcmp(argv[i], "--threads") == 0)
            nthr = parse_list(val, thr, 8), i++;
        else if (strcmp(argv[i], "--runs") == 0)
            runs = atoi(val), i++;
        else if (strcmp(argv[i], "--segments") == 0)
            seg = atoi(val), i++;
        else
            nres = -1;
        if (nres < 1 || nthr < 1 || runs < 1 || runs > 99 || seg < 3 || seg > 4096) {
            fprintf(stderr,
                    "usage: %s [--resolutions 128,256] [--threads 1,2] [--runs 3] "
                    "[--segments 224]\n",
                    argv[0]);
            return 2;
        }
    }
    struct err e = {0};
    double t0 = now_ms();
    struct mesh *m = torus(seg, &e);
    double build_ms = now_ms() - t0;
    if (m == NULL) {
        fprintf(stderr, "refract-voxelize: %s\n", e.msg);
        return 1;
    }
    bench_print_header(NULL, argc, argv);
    printf("Torus, %zu triangles, %zu vertices; validation + BVH build %.0f ms.\n\n",
           m->triangle_count, m->vertex_count, build_ms);
    double load[3] = {0, 0, 0};
    getloadavg(load, 3);
    printf("Load average at start: %.2f (other processes share the cores).\n\n", load[0]);
    printf(
        "| grid | threads | wall ms (median) | CPU ms (median, all threads) | Mvoxels/s (wall) | "
        "runs |\n|---|---|---|---|---|---|\n");
    for (int r = 0; r < nres; r++) {
        size_t n = (size_t)res[r] * res[r] * res[r];
        float *cov = malloc(n * sizeof *cov);
        if (cov == NULL) {
            fprintf(stderr, "refract-voxelize: out of memory for %d^3\n", res[r]);
            return 1;
        }
        for (int t = 0; t < nthr; t++) {
            struct mesh_voxelize_desc d = {
                .resolution = {res[r], res[r], res[r]},
                .bounds_min = {-1, -1, -1},
                .voxel_size = {2.0 / res[r], 2.0 / res[r], 2.0 / res[r]},
                .object_from_mesh = xform_identity(),
                .threads = thr[t],
            };
            double ms[99], cpu[99];
            for (int k = 0; k < runs; k++) {
                double s = now_ms(), c = clock_ms(CLOCK_PROCESS_CPUTIME_ID);
                mesh_voxelize(m, &d, cov, &e);
                ms[k] = now_ms() - s;
                cpu[k] = clock_ms(CLOCK_PROCESS_CPUTIME_ID) - c;
            }
            qsort(ms, (size_t)runs, sizeof ms[0], bench_compare_doubles);
            qsort(cpu, (size_t)runs, sizeof cpu[0], bench_compare_doubles);
            double med = ms[runs / 2];
            printf("| %d^3 | %d | %.0f | %.0f | %.1f | %d |\n", res[r], thr[t], med, cpu[runs / 2],
                   n / med / 1e3, runs);
            fflush(stdout);
        }
        free(cov);
    }
    mesh_destroy(m);
    return 0;
}
