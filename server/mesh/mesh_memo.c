/*
 * mesh_memo.c - a mesh keeps its last voxelization (mesh.h, mesh_voxelize_memo).
 *
 * Why: one mesh usually shapes several channels of the same object (a coloured glass:
 * ior and attenuation; a gem: ior and scattering), and the GPU build, the light
 * simulator's input fields and the CPU reference each evaluate them. Every one of those
 * asks for the same grid, and a 100k-triangle mesh costs over a second per voxelization
 * at 128^3 on one core (BENCHMARKS.md), so the first computes it and the others copy it.
 *
 * The memo is keyed by the grid and the transform (the thread count is not part of the
 * result), held under the mesh's own lock while it is computed, so concurrent callers
 * with the same grid wait for the first and then copy; grids above MESH_MEMO_MAX_VOXELS
 * are computed every time rather than kept. The mesh stays immutable in every other
 * respect, and the memo goes with it (mesh_destroy).
 */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "mesh_internal.h"

struct mesh_memo {
    pthread_mutex_t lock;
    bool valid;
    struct mesh_voxelize_desc desc; /* threads zeroed */
    float *coverage;
    size_t count;
    long long hits, computed;
};

struct mesh_memo *mesh_memo_create(void)
{
    struct mesh_memo *mm = calloc(1, sizeof *mm);
    if (mm)
        pthread_mutex_init(&mm->lock, NULL);
    return mm;
}

void mesh_memo_destroy(struct mesh_memo *mm)
{
    if (mm == NULL)
        return;
    pthread_mutex_destroy(&mm->lock);
    free(mm->coverage);
    free(mm);
}

/* Field by field: no padding bytes are compared. */
static bool same_grid(const struct mesh_voxelize_desc *a, const struct mesh_voxelize_desc *b)
{
    for (int i = 0; i < 3; i++)
        if (a->resolution[i] != b->resolution[i])
            return false;
    const struct xform *p = &a->object_from_mesh, *q = &b->object_from_mesh;
    if (memcmp(&a->bounds_min, &b->bounds_min, sizeof a->bounds_min) != 0 ||
        memcmp(&a->voxel_size, &b->voxel_size, sizeof a->voxel_size) != 0 ||
        memcmp(&p->translate, &q->translate, sizeof p->translate) != 0 ||
        memcmp(p->rot, q->rot, sizeof p->rot) != 0 || memcmp(&p->scale, &q->scale, sizeof p->scale))
        return false;
    return true;
}

enum refract_code mesh_voxelize_memo(const struct mesh *m, const struct mesh_voxelize_desc *d,
                                     float *coverage, struct err *e)
{
    struct mesh_memo *mm = m->memo;
    if (mm == NULL)
        return mesh_voxelize(m, d, coverage, e);
    size_t count = (size_t)d->resolution[0] * (size_t)d->resolution[1] * (size_t)d->resolution[2];
    struct mesh_voxelize_desc key = *d;
    key.threads = 0;
    pthread_mutex_lock(&mm->lock);
    if (mm->valid && same_grid(&mm->desc, &key)) {
        memcpy(coverage, mm->coverage, count * sizeof *coverage);
        mm->hits++;
        pthread_mutex_unlock(&mm->lock);
        return REFRACT_E_OK;
    }
    enum refract_code rc = mesh_voxelize(m, d, coverage, e);
    mm->computed++;
    if (rc == REFRACT_E_OK && count <= MESH_MEMO_MAX_VOXELS) {
        float *copy = count == mm->count ? mm->coverage : malloc(count * sizeof *copy);
        if (copy) {
            if (copy != mm->coverage)
                free(mm->coverage);
            memcpy(copy, coverage, count * sizeof *copy);
            mm->coverage = copy;
            mm->count = count;
            mm->desc = key;
            mm->valid = true;
        }
    }
    pthread_mutex_unlock(&mm->lock);
    return rc;
}

void mesh_memo_counts(const struct mesh *m, long long *hits, long long *computed)
{
    *hits = *computed = 0;
    if (m->memo == NULL)
        return;
    pthread_mutex_lock(&m->memo->lock);
    *hits = m->memo->hits;
    *computed = m->memo->computed;
    pthread_mutex_unlock(&m->memo->lock);
}
