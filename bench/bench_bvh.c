/*
 * bench_bvh.c - refract-bvh: how long the ray-tracing hierarchy of a mesh takes to build
 * (mesh_rt_build, single-threaded, done once per mesh in mesh_create), what it costs on
 * the GPU in bytes per triangle, its SAH cost, and how fast the double-precision
 * reference traces it. Prints a Markdown report for BENCHMARKS.md.
 *
 *   refract-bvh [--runs 3] [--rays 200000]
 *
 * Meshes of about a million triangles: a torus of 708 x 708 quads (1,002,528 triangles),
 * an icosphere of 8 subdivisions (1,310,720) and a soup of 1,000,000 random triangles
 * (overlapping, a harder case for SAH). Each build time is the median of `runs` builds,
 * wall (CLOCK_MONOTONIC) and the process's CPU time: on a shared machine the wall time
 * grows with the load, the CPU time much less.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "example_scene.h"
#include "mesh/mesh.h"
#include "mesh/mesh_rt.h"

static double clock_ms(clockid_t id)
{
    struct timespec t;
    clock_gettime(id, &t);
    return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

static uint64_t rng = 0x853c49e6748fea9bull;
static double uniform(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static vec3 unit(void)
{
    double z = 2 * uniform() - 1, phi = 6.283185307179586 * uniform(), s = sqrt(1 - z * z);
    return vec3_make(s * cos(phi), s * sin(phi), z);
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
        for (int j = 0; j < seg; j++) {
            double u = two_pi * i / seg, w = two_pi * j / seg, r = big + small * cos(w);
            double *p = v[(size_t)i * seg + j];
            p[0] = r * cos(u);
            p[1] = small * sin(w);
            p[2] = r * sin(u);
        }
    }
    size_t k = 0;
    for (int i = 0; i < seg; i++) {
        for (int j = 0; j < seg; j++) {
            uint32_t a = (uint32_t)(i * seg + j), b = (uint32_t)(((i + 1) % seg) * seg + j),
                     c = (uint32_t)(((i + 1) % seg) * seg + (j + 1) % seg),
                     d = (uint32_t)(i * seg + (j + 1) % seg);
            t[k][0] = a, t[k][1] = c, t[k][2] = b, k++;
            t[k][0] = a, t[k][1] = d, t[k][2] = c, k++;
        }
    }
    struct mesh_limits lim = {.max_triangles = nt};
    struct mesh *m = NULL;
    mesh_create(v, nv, t, nt, &lim, &m, e);
    return m;
}

static struct mesh *soup(size_t n, struct err *e)
{
    double(*v)[3] = malloc(3 * n * sizeof *v);
    uint32_t(*t)[3] = malloc(n * sizeof *t);
    if (v == NULL || t == NULL) {
        free(v);
        free(t);
        err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the soup");
        return NULL;
    }
    for (size_t i = 0; i < n; i++) {
        vec3 c = vec3_make(2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1);
        double size = 0.002 + 0.02 * uniform() * uniform();
        for (int k = 0; k < 3; k++) {
            vec3 p = vec3_madd(c, unit(), size);
            v[3 * i + (size_t)k][0] = p.x;
            v[3 * i + (size_t)k][1] = p.y;
            v[3 * i + (size_t)k][2] = p.z;
            t[i][k] = (uint32_t)(3 * i + (size_t)k);
        }
    }
    struct mesh_limits lim = {.max_triangles = n};
    struct mesh *m = NULL;
    mesh_create(v, 3 * n, t, n, &lim, &m, e);
    return m;
}

static double node_area(const struct mesh_rt_node *n)
{
    double dx = n->hi[0] - n->lo[0], dy = n->hi[1] - n->lo[1], dz = n->hi[2] - n->lo[2];
    return dx * dy + dy * dz + dz * dx;
}

/* SAH cost with unit traversal and intersection costs, relative to the root's area: the
 * expected node visits plus triangle tests of a random ray that hits the root. */
static double sah_cost(const struct mesh_rt *rt, double *mean_leaf)
{
    double root = node_area(&rt->nodes[0]), cost = 0.0;
    size_t leaves = 0;
    for (size_t i = 0; i < rt->node_count; i++) {
        const struct mesh_rt_node *n = &rt->nodes[i];
        double a = node_area(n) / root;
        cost += n->count ? a * n->count : a;
        leaves += n->count > 0;
    }
    *mean_leaf = (double)rt->tri_count / (double)leaves;
    return cost;
}

static void bench(const char *name, struct mesh *m, double create_ms, int runs, int rays)
{
    double wall[16], cpu[16];
    for (int r = 0; r < runs; r++) {
        struct mesh_rt *rt = NULL;
        struct err e = {0};
        double w0 = clock_ms(CLOCK_MONOTONIC), c0 = clock_ms(CLOCK_PROCESS_CPUTIME_ID);
        if (mesh_rt_build(m, &rt, &e) != REFRACT_E_OK) {
            fprintf(stderr, "refract-bvh: %s\n", e.msg);
            exit(1);
        }
        wall[r] = clock_ms(CLOCK_MONOTONIC) - w0;
        cpu[r] = clock_ms(CLOCK_PROCESS_CPUTIME_ID) - c0;
        mesh_rt_destroy(rt);
    }
    qsort(wall, (size_t)runs, sizeof wall[0], bench_compare_doubles);
    qsort(cpu, (size_t)runs, sizeof cpu[0], bench_compare_doubles);
    const struct mesh_rt *rt = m->rt;
    struct mesh_rt_gpu g = mesh_rt_gpu_arrays(rt);
    double mean_leaf, sah = sah_cost(rt, &mean_leaf);
    /* rays from a sphere around the mesh at random points of its box */
    vec3 c = vec3_scale(vec3_add(m->lo, m->hi), 0.5), ext = vec3_sub(m->hi, m->lo);
    int hits = 0;
    double t0 = clock_ms(CLOCK_PROCESS_CPUTIME_ID);
    for (int i = 0; i < rays; i++) {
        vec3 o = vec3_madd(c, unit(), vec3_length(ext));
        vec3 p = vec3_add(c, vec3_make((uniform() - 0.5) * ext.x, (uniform() - 0.5) * ext.y,
                                       (uniform() - 0.5) * ext.z));
        struct mesh_rt_hit h;
        hits += mesh_rt_intersect(rt, o, vec3_sub(p, o), 0.0, INFINITY, -1, &h);
    }
    double trace_ms = clock_ms(CLOCK_PROCESS_CPUTIME_ID) - t0;
    printf("| %s | %zu | %.0f | %.0f | %.0f | %zu | %d | %.2f | %.1f | %.1f | %.2f |\n", name,
           m->triangle_count, wall[runs / 2], cpu[runs / 2], create_ms, rt->node_count, rt->depth,
           mean_leaf, sah, (double)g.total_bytes / (double)m->triangle_count,
           rays / trace_ms * 1e-3);
    (void)hits;
}

int main(int argc, char **argv)
{
    int runs = 3, rays = 200000;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--runs") == 0 && i + 1 < argc)
            runs = atoi(argv[++i]);
        else if (strcmp(argv[i], "--rays") == 0 && i + 1 < argc)
            rays = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: refract-bvh [--runs 3] [--rays 200000]\n");
            return 2;
        }
    }
    if (runs < 1 || runs > 16 || rays < 1) {
        fprintf(stderr, "refract-bvh: --runs must be 1..16 and --rays positive\n");
        return 2;
    }
    bench_print_header(NULL, argc, argv);
    printf("| mesh | triangles | build ms (wall, median) | build ms (CPU) | mesh_create ms | "
           "nodes | depth | triangles/leaf | SAH cost | GPU bytes/triangle | Mrays/s (CPU, "
           "double, 1 core) |\n|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int k = 0; k < 3; k++) {
        struct err e = {0};
        double t0 = clock_ms(CLOCK_MONOTONIC);
        struct mesh *m = NULL;
        const char *name = k == 0 ? "torus 708x708" : k == 1 ? "icosphere s=8" : "random soup";
        if (k == 0)
            m = torus(708, &e);
        else if (k == 1)
            mesh_make_icosphere(8, 1.0, &m, &e);
        else
            m = soup(1000000, &e);
        double create_ms = clock_ms(CLOCK_MONOTONIC) - t0;
        if (m == NULL) {
            fprintf(stderr, "refract-bvh: %s: %s\n", name, e.msg);
            return 1;
        }
        bench(name, m, create_ms, runs, rays);
        fflush(stdout);
        mesh_destroy(m);
    }
    printf("\nbuild: mesh_rt_build alone (SAH, flattening, vertex normals and their packing), "
           "one thread; mesh_create: the whole making of the mesh (generation included for "
           "the icosphere: validation, the winding-number BVH, the closedness test and "
           "mesh_rt_build).\n");
    return 0;
}
