/*
 * mesh_voxelize.c - a mesh's inside fraction on a voxel grid, in parallel on the CPU.
 *
 * Per voxel centre p (object space), mapped into mesh space: d = the distance to the
 * nearest triangle, inside = |w(p)| >= 1/2 with w the generalized winding number
 * (mesh_winding.c), sd = inside ? -d : d, and coverage = clamp(0.5 - sd / h_min, 0, 1):
 * the one-voxel anti-aliased edge of the procedural shapes (scene_field.c, shapes.c), so
 * a voxelized mesh sphere and the sphere shape agree to well within a voxel. |w| rather
 * than w makes the result independent of the mesh's global orientation; a few flipped
 * triangles or small holes change w only near them (and the distance, which sets the
 * boundary's position, does not depend on orientation at all).
 *
 * Work saved:
 *   - Voxels whose centres lie more than one voxel outside the mesh's box (mapped to
 *     object space) are outside: 0, no query.
 *   - Along a row, the distance is 1-Lipschitz: a voxel at distance d from the surface
 *     has every voxel within d - h/2 along the row on the same side and at least h/2
 *     away, so they share its coverage (0 or 1) and the winding number is evaluated once
 *     per run. Queries then scale with the surface's area in voxels, not with the volume.
 *   - For a closed mesh (mesh.closed: w is an integer that changes only across the
 *     surface) the winding number is needed only where the side may have changed: two
 *     centres vs apart whose distances sum to more than vs are joined by a segment that
 *     misses the surface, so the second is on the first's side. Then w is evaluated only
 *     near crossings and once per row. A mesh with holes or flipped triangles has a w
 *     that varies off the surface (through a hole, |w| crosses 1/2 in empty space), so
 *     there w is evaluated at every run start.
 *   The winding number uses the BVH's far field (Barill et al. 2018).
 *   The run rule assumes the side does not change within a run, which holds off the
 *   surface for closed meshes; for open ones w is smooth there, and a run is at most
 *   as long as the distance to the surface.
 *
 * DESIGN, threads: z-slices are handed out through an atomic counter to desc.threads
 * pthreads; each writes only its slices, the mesh is read-only, so nothing is locked.
 *
 * Why the CPU and not the GPU: the scene's fields are evaluated on the CPU
 * (scene_field.c) and uploaded afterwards, and this daemon's GL is Mesa llvmpipe, which
 * runs compute shaders on the same CPU cores, in float, and without the BVH walks that
 * make each query O(log n). Measured (BENCHMARKS.md, 2-core AMD EPYC VM, a torus of
 * 100,352 triangles): 128^3 takes 1.1-1.4 s and 256^3 4.9-5.5 s of CPU time on one
 * thread, since the work follows the surface; a brute-force kernel (every voxel against every triangle,
 * what a BVH-less GPU port does) needs 128^3 x 100,352 = 2.1e11 solid angles, minutes even
 * at llvmpipe's few GFLOP/s. On a real GPU a port could pay off for frequent
 * re-voxelization, but fields are built once per scene version and object.
 */
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <math.h>
#include <unistd.h>

#include "mesh_internal.h"

#define MESH_MAX_THREADS 64

struct job {
    const struct mesh *m;
    const struct mesh_voxelize_desc *d;
    float *coverage;
    double h_min;
    int i0, i1, j0, j1, k0, k1; /* voxel ranges whose centres are near the mesh's box */
    atomic_int next_k;
};

static vec3 centre(const struct mesh_voxelize_desc *d, int i, int j, int k)
{
    return vec3_make(d->bounds_min.x + (i + 0.5) * d->voxel_size.x,
                     d->bounds_min.y + (j + 0.5) * d->voxel_size.y,
                     d->bounds_min.z + (k + 0.5) * d->voxel_size.z);
}

static void row(struct job *jb, int j, int k)
{
    const struct mesh_voxelize_desc *d = jb->d;
    size_t base = ((size_t)k * (size_t)d->resolution[1] + (size_t)j) * (size_t)d->resolution[0];
    double h = jb->h_min, half = 0.5 * h, scale = d->object_from_mesh.scale, vs = d->voxel_size.x;
    bool inside = false;
    double prev_lower = -1.0; /* lower bound of the distance at the previous voxel; < 0: none */
    for (int i = jb->i0; i <= jb->i1;) {
        vec3 p = xform_point_to_object(&d->object_from_mesh, centre(d, i, j, k));
        double dist = scale * mesh_distance(jb->m, p);
        /* The segment between two centres vs apart touches the surface only if their
         * distances sum to vs or less; otherwise this voxel is on the previous one's side
         * and the winding number is not needed. */
        if (!(jb->m->closed && prev_lower >= 0.0 && prev_lower + dist > vs))
            inside = fabs(mesh_winding_number(jb->m, p)) >= 0.5;
        double sd = inside ? -dist : dist;
        float c = (float)fmin(fmax(0.5 - sd / h, 0.0), 1.0);
        double skip = dist > half ? floor((dist - half) / vs) : 0.0;
        int last = skip >= (double)(jb->i1 - i) ? jb->i1 : i + (int)skip;
        for (int t = i; t <= last; t++)
            jb->coverage[base + (size_t)t] = c;
        prev_lower = dist - (last - i) * vs;
        i = last + 1;
    }
}

static void *worker(void *arg)
{
    struct job *jb = arg;
    for (;;) {
        int k = atomic_fetch_add(&jb->next_k, 1);
        if (k > jb->k1)
            break;
        for (int j = jb->j0; j <= jb->j1; j++)
            row(jb, j, k);
    }
    return NULL;
}

/* Voxel index range [lo, hi] along an axis whose centres fall in [a, b]. */
static bool index_range(double a, double b, double bmin, double vs, int n, int *lo, int *hi)
{
    double fa = ceil((a - bmin) / vs - 0.5), fb = floor((b - bmin) / vs - 0.5);
    fa = fmax(fa, 0.0);
    fb = fmin(fb, (double)(n - 1));
    if (!(fa <= fb))
        return false;
    *lo = (int)fa;
    *hi = (int)fb;
    return true;
}

/* The object-space box of the mesh's box (its 8 corners mapped), grown by `grow`. */
static void object_box(const struct mesh *m, const struct xform *x, double grow, vec3 *lo, vec3 *hi)
{
    *lo = vec3_make(INFINITY, INFINITY, INFINITY);
    *hi = vec3_make(-INFINITY, -INFINITY, -INFINITY);
    for (int c = 0; c < 8; c++) {
        vec3 q = {(c & 1) ? m->hi.x : m->lo.x, (c & 2) ? m->hi.y : m->lo.y,
                  (c & 4) ? m->hi.z : m->lo.z};
        vec3 p = xform_point_to_world(x, q);
        *lo = vec3_make(fmin(lo->x, p.x), fmin(lo->y, p.y), fmin(lo->z, p.z));
        *hi = vec3_make(fmax(hi->x, p.x), fmax(hi->y, p.y), fmax(hi->z, p.z));
    }
    *lo = vec3_sub(*lo, vec3_make(grow, grow, grow));
    *hi = vec3_add(*hi, vec3_make(grow, grow, grow));
}

static int thread_count(int asked)
{
    long n = asked > 0 ? asked : sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > MESH_MAX_THREADS ? MESH_MAX_THREADS : (int)n;
}

enum refract_code mesh_voxelize(const struct mesh *m, const struct mesh_voxelize_desc *d,
                                float *coverage, struct err *e)
{
    size_t count = (size_t)d->resolution[0] * (size_t)d->resolution[1] * (size_t)d->resolution[2];
    for (size_t i = 0; i < count; i++)
        coverage[i] = 0.0f;
    struct job jb = {.m = m, .d = d, .coverage = coverage};
    jb.h_min = fmin(d->voxel_size.x, fmin(d->voxel_size.y, d->voxel_size.z));
    vec3 lo, hi;
    object_box(m, &d->object_from_mesh, jb.h_min, &lo, &hi);
    if (!index_range(lo.x, hi.x, d->bounds_min.x, d->voxel_size.x, d->resolution[0], &jb.i0,
                     &jb.i1) ||
        !index_range(lo.y, hi.y, d->bounds_min.y, d->voxel_size.y, d->resolution[1], &jb.j0,
                     &jb.j1) ||
        !index_range(lo.z, hi.z, d->bounds_min.z, d->voxel_size.z, d->resolution[2], &jb.k0,
                     &jb.k1))
        return REFRACT_E_OK; /* the mesh lies outside the grid */
    atomic_init(&jb.next_k, jb.k0);
    int n = thread_count(d->threads);
    pthread_t tid[MESH_MAX_THREADS];
    int started = 0;
    for (; started < n - 1; started++) {
        if (pthread_create(&tid[started], NULL, worker, &jb) != 0)
            break;
    }
    worker(&jb); /* the calling thread works too; with threads = 1 it works alone */
    for (int t = 0; t < started; t++)
        pthread_join(tid[t], NULL);
    (void)e;
    return REFRACT_E_OK;
}
