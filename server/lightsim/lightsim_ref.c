/*
 * lightsim_ref.c - the CPU double-precision reference of the light simulator
 * (docs/lightsim.md): the initial wavefront, time steps until no patch lives or the step
 * budget is spent, the capacity of the patch list, and the result volumes.
 *
 * The patch list keeps the specified order (patch i's survivors before patch i+1's), the
 * order the GPU's prefix-sum compaction produces, so both cull the same patches at
 * capacity.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lightsim.h"
#include "lightsim_init.h"
#include "lightsim_sample.h"
#include "lightsim_step.h"

struct lightsim_ref {
    const struct lightsim_fields *f;
    struct scene_lightsim set;
    struct ls_patch *list, *next;
    size_t count, cap; /* cap: allocated length of both lists, <= max_patches */
    double *acc_e, *acc_d;
    struct lightsim_stats st;
    double dt, energy_floor, t_sweep;
    long long max_steps;
};

static size_t voxel_count(const struct light_grid *g)
{
    return (size_t)g->dims[0] * (size_t)g->dims[1] * (size_t)g->dims[2];
}

/* Grows both lists to hold `need` patches (at most max_patches). */
static bool reserve(struct lightsim_ref *r, size_t need)
{
    if (need <= r->cap)
        return true;
    size_t cap = r->cap ? r->cap : 1024;
    while (cap < need)
        cap *= 2;
    size_t max = (size_t)r->set.max_patches;
    cap = cap > max ? max : cap;
    struct ls_patch *a = realloc(r->list, cap * sizeof *a);
    if (a == NULL)
        return false;
    r->list = a;
    struct ls_patch *b = realloc(r->next, cap * sizeof *b);
    if (b == NULL)
        return false;
    r->next = b;
    r->cap = cap;
    return true;
}

/* Appends to the next list, or culls for capacity (docs/lightsim.md step 7). */
static bool emit(struct lightsim_ref *r, size_t *n, const struct ls_patch *p)
{
    if (*n >= (size_t)r->set.max_patches) {
        for (int c = 0; c < 3; c++)
            r->st.flux_culled[c] += p->P[c];
        r->st.culled_capacity++;
        return true;
    }
    if (*n >= r->cap && !reserve(r, *n + 1))
        return false;
    r->next[(*n)++] = *p;
    return true;
}

static void swap_lists(struct lightsim_ref *r, size_t n)
{
    struct ls_patch *t = r->list;
    r->list = r->next;
    r->next = t;
    r->count = n;
}

static void update_progress(struct lightsim_ref *r)
{
    r->st.patches_live = (int)r->count;
    if ((int)r->count > r->st.patches_peak)
        r->st.patches_peak = (int)r->count;
    r->st.done = r->count == 0 || r->st.steps >= r->max_steps;
    double t = (double)r->st.steps * r->dt;
    r->st.progress = r->st.done ? 1.0 : fmin(0.99, t / r->t_sweep); /* 1 means done */
}

static enum refract_code oom(struct err *e)
{
    return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                   "out of memory for the light simulation's patch list; lower "
                   "lightsim.max_patches or lightsim.initial_patches");
}

enum refract_code lightsim_ref_begin(const struct lightsim_fields *f, const struct scene_light *l,
                                     const struct scene_lightsim *set, struct lightsim_ref **out,
                                     struct err *e)
{
    *out = NULL;
    struct lightsim_ref *r = calloc(1, sizeof *r);
    if (r == NULL)
        return oom(e);
    r->f = f;
    r->set = *set;
    if (r->set.max_patches < 1)
        r->set.max_patches = 1;
    size_t v = voxel_count(&f->grid);
    r->acc_e = calloc(v * 3, sizeof(double));
    r->acc_d = calloc(v * 3, sizeof(double));
    if (r->acc_e == NULL || r->acc_d == NULL) {
        lightsim_ref_destroy(r);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY,
                       "out of memory for the irradiance accumulators; lower "
                       "lightsim.resolution");
    }
    r->dt = set->step_voxels * f->grid.voxel;
    ls_step_budget(f, r->dt, &r->max_steps, &r->t_sweep);

    struct ls_patch *init = NULL;
    size_t n0 = 0;
    enum refract_code rc = ls_initial_wavefront(f, l, set, &init, &n0, e);
    if (rc != REFRACT_E_OK) {
        lightsim_ref_destroy(r);
        return rc;
    }
    double mean_max = 0.0;
    for (size_t i = 0; i < n0; i++) {
        for (int c = 0; c < 3; c++)
            r->st.flux_in[c] += init[i].P[c];
        mean_max += fmax(init[i].P[0], fmax(init[i].P[1], init[i].P[2]));
    }
    r->energy_floor = n0 > 0 ? set->energy_threshold * mean_max / (double)n0 : 0.0;
    r->st.patches_initial = (int)n0;
    size_t keep = n0 < (size_t)r->set.max_patches ? n0 : (size_t)r->set.max_patches;
    if (!reserve(r, keep > 0 ? keep : 1)) {
        free(init);
        lightsim_ref_destroy(r);
        return oom(e);
    }
    size_t n = 0;
    for (size_t i = 0; i < n0; i++)
        emit(r, &n, &init[i]); /* cannot fail: reserved */
    free(init);
    swap_lists(r, n);
    update_progress(r);
    *out = r;
    return REFRACT_E_OK;
}

enum refract_code lightsim_ref_advance(struct lightsim_ref *r, int max_steps, bool *done,
                                       struct err *e)
{
    vec3 lo, hi;
    ls_grid_box(&r->f->grid, &lo, &hi);
    struct ls_step_ctx ctx = {
        .f = r->f,
        .set = &r->set,
        .dt = r->dt,
        .energy_floor = r->energy_floor,
        .deposit_every = lightsim_deposit_every(&r->set),
        .lo = lo,
        .hi = hi,
        .reach = vec3_length(vec3_sub(hi, lo)),
        .acc_e = r->acc_e,
        .acc_d = r->acc_d,
        .st = &r->st,
    };
    for (int s = 0; s < max_steps && !r->st.done; s++) {
        r->st.patch_steps += (long long)r->count;
        size_t n = 0;
        for (size_t i = 0; i < r->count; i++) {
            struct ls_patch p = r->list[i], child[4], twin;
            enum ls_fate twin_fate;
            enum ls_fate fate = ls_patch_step(&ctx, &p, child, &twin, &twin_fate);
            bool ok = true;
            if (fate == LS_LIVES)
                ok = emit(r, &n, &p);
            else if (fate == LS_SPLITS)
                for (int k = 0; k < 4 && ok; k++)
                    ok = emit(r, &n, &child[k]);
            if (ok && twin_fate == LS_LIVES)
                ok = emit(r, &n, &twin); /* a surface event's reflected twin, after p's */
            if (!ok)
                return oom(e);
        }
        swap_lists(r, n);
        r->st.steps++;
        update_progress(r);
    }
    *done = r->st.done;
    return REFRACT_E_OK;
}

void lightsim_ref_stats(const struct lightsim_ref *r, struct lightsim_stats *out)
{
    *out = r->st;
    memset(out->flux_live, 0, sizeof out->flux_live);
    for (size_t i = 0; i < r->count; i++)
        for (int c = 0; c < 3; c++)
            out->flux_live[c] += r->list[i].P[c];
}

enum refract_code lightsim_ref_read(const struct lightsim_ref *r, struct irradiance_volume *out,
                                    struct err *e)
{
    memset(out, 0, sizeof *out);
    out->grid = r->f->grid;
    size_t v = voxel_count(&out->grid);
    out->irradiance = malloc(v * 4 * sizeof(float));
    out->direction = malloc(v * 4 * sizeof(float));
    if (out->irradiance == NULL || out->direction == NULL) {
        irradiance_volume_free(out);
        return err_set(e, REFRACT_E_OUT_OF_MEMORY, "out of memory for the irradiance volume");
    }
    for (size_t i = 0; i < v; i++) {
        for (int c = 0; c < 3; c++)
            out->irradiance[4 * i + c] = (float)r->acc_e[3 * i + c];
        out->irradiance[4 * i + 3] = 0.0f;
        vec3 d = {r->acc_d[3 * i], r->acc_d[3 * i + 1], r->acc_d[3 * i + 2]};
        double len = vec3_length(d);
        vec3 u = len > 0.0 ? vec3_scale(d, 1.0 / len) : (vec3){0, 0, 0};
        out->direction[4 * i + 0] = (float)u.x;
        out->direction[4 * i + 1] = (float)u.y;
        out->direction[4 * i + 2] = (float)u.z;
        out->direction[4 * i + 3] = len > 0.0 ? 1.0f : 0.0f;
    }
    lightsim_ref_stats(r, &out->stats);
    return REFRACT_E_OK;
}

void lightsim_ref_destroy(struct lightsim_ref *r)
{
    if (r == NULL)
        return;
    free(r->list);
    free(r->next);
    free(r->acc_e);
    free(r->acc_d);
    free(r);
}

enum refract_code lightsim_ref_run(const struct lightsim_fields *f, const struct scene_light *l,
                                   const struct scene_lightsim *set, struct irradiance_volume *out,
                                   struct err *e)
{
    struct lightsim_ref *r = NULL;
    enum refract_code rc = lightsim_ref_begin(f, l, set, &r, e);
    bool done = r == NULL;
    while (rc == REFRACT_E_OK && !done)
        rc = lightsim_ref_advance(r, 64, &done, e);
    if (rc == REFRACT_E_OK)
        rc = lightsim_ref_read(r, out, e);
    lightsim_ref_destroy(r);
    return rc;
}
