/*
 * bench_accuracy.c - refract-accuracy: the speed-against-error report, docs/accuracy.md
 * and its plots docs/images/accuracy_*.png.
 *
 *     build/refract-accuracy [--quick] [--out docs/accuracy.md] [--images docs/images]
 *
 * For each analytic case (accuracy_cases.h: Luneburg lens, Maxwell fish-eye, mirage,
 * strong Gaussian lens, sharp spheres n = 1.5 and 2.42) it traces a bundle of rays on the
 * GPU path (render_trace: trace_rays.comp, the view renderer's march) under each
 * configuration of four sweeps - integrator x step, voxel resolution, smoothing sigma,
 * float16 against float32 index textures - and scores the exits against the exact
 * continuous-field reference: exit-direction angle and exit-position error (distance of
 * the traced exit point from the exact exit line), and GPU time per ray. It marks the
 * Pareto front of time against error, per case and over all cases, and names the cheapest
 * settings that reach a preview and a final error target.
 *
 * Bounded: --quick traces 144 rays per configuration at 64^3 over a reduced sweep (about a
 * minute on llvmpipe); the full run traces 1024 rays at 128^3 (some minutes). Timing on
 * llvmpipe is CPU time of the software rasterizer and moves with the machine's load; the
 * errors do not depend on it.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "accuracy_cases.h"
#include "accuracy_image.h"
#include "core/ray_status.h"
#include "example_scene.h"
#include "gpu/queue.h"
#include "plot.h"
#include "render/render.h"
#include "scene/scene.h"

#define MAX_CONFIGS 48

enum sweep {
    SWEEP_INTEGRATOR,
    SWEEP_RESOLUTION,
    SWEEP_SIGMA,
    SWEEP_TEXTURE,
    SWEEP_FILTER,
    SWEEP_COUNT
};
static const char *const sweep_names[SWEEP_COUNT] = {
    "integrator x step", "resolution", "smoothing sigma", "float16 texture", "tricubic filter"};
static const char *const integrator_names[4] = {"euler", "rk4", "rk2", "adaptive"};

struct config {
    enum sweep sweep;
    enum scene_integrator integrator;
    double step;      /* voxels (adaptive: the largest step) */
    double tolerance; /* adaptive: voxels per step */
    int res;          /* voxels per axis */
    double sigma;     /* smoothing in voxels; < 0: the case's default */
    bool float16;
    bool tricubic; /* render.ior_filter "tricubic" (else trilinear) */
};

struct result {
    double dir_mean, dir_p90, dir_max; /* radians */
    double pos_mean, pos_max;          /* world units */
    double us_per_ray, steps_per_ray;
    int scored, lost; /* rays with an exact exit; of those, not exited on the GPU */
    bool front;
};

struct options {
    bool quick, no_images; /* --no-images: skip the image sweep (the light simulation) */
    const char *out, *images;
    int side, base_res;
};

struct bench {
    struct options opt;
    struct config configs[MAX_CONFIGS];
    int config_count;
    struct result results[ACCURACY_CASE_COUNT][MAX_CONFIGS];
    bool ok;
};

static void add(struct bench *b, struct config c)
{
    if (b->config_count < MAX_CONFIGS)
        b->configs[b->config_count++] = c;
}

/* The sweeps: one factor at a time from the scene defaults (rk4, step 0.5, float32, the
 * case's smoothing, the base resolution), plus the full integrator x step grid. */
static void build_configs(struct bench *b)
{
    const bool q = b->opt.quick;
    const int base = b->opt.base_res;
    const double steps_full[] = {2.0, 1.0, 0.5, 0.25}, steps_quick[] = {1.0, 0.5};
    const double *steps = q ? steps_quick : steps_full;
    int nsteps = q ? 2 : 4;
    const enum scene_integrator fixed[3] = {SCENE_INTEGRATOR_EULER, SCENE_INTEGRATOR_RK2,
                                            SCENE_INTEGRATOR_RK4};
    for (int i = 0; i < 3; i++)
        for (int s = 0; s < nsteps; s++)
            add(b, (struct config){SWEEP_INTEGRATOR, fixed[i], steps[s], 1e-3, base, -1.0, false,
                                   false});
    const double tols_full[] = {3e-2, 1e-2, 3e-3, 1e-3, 1e-4}, tols_quick[] = {1e-2, 1e-3};
    for (int t = 0; t < (q ? 2 : 5); t++)
        add(b, (struct config){SWEEP_INTEGRATOR, SCENE_INTEGRATOR_ADAPTIVE, 4.0,
                               q ? tols_quick[t] : tols_full[t], base, -1.0, false, false});
    const int res_full[] = {32, 64, 256}, res_quick[] = {32, 128};
    for (int r = 0; r < (q ? 2 : 3); r++)
        add(b, (struct config){SWEEP_RESOLUTION, SCENE_INTEGRATOR_RK4, 0.5, 1e-3,
                               q ? res_quick[r] : res_full[r], -1.0, false, false});
    const double sig_full[] = {0.0, 0.5, 1.0, 2.0}, sig_quick[] = {0.0, 2.0};
    for (int s = 0; s < (q ? 2 : 4); s++)
        add(b, (struct config){SWEEP_SIGMA, SCENE_INTEGRATOR_RK4, 0.5, 1e-3, base,
                               q ? sig_quick[s] : sig_full[s], false, false});
    add(b,
        (struct config){SWEEP_TEXTURE, SCENE_INTEGRATOR_RK4, 0.5, 1e-3, base, -1.0, true, false});
    add(b, (struct config){SWEEP_TEXTURE, SCENE_INTEGRATOR_ADAPTIVE, 4.0, 1e-3, base, -1.0, true,
                           false});
    /* Tricubic against trilinear: the default integrator at every resolution (the
     * trilinear twins are the resolution sweep and the default), and the cheap settings of
     * the front at the base grid. */
    const int fres_full[] = {32, 64, 128, 256}, fres_quick[] = {32, 64, 128};
    for (int r = 0; r < (q ? 3 : 4); r++)
        add(b, (struct config){SWEEP_FILTER, SCENE_INTEGRATOR_RK4, 0.5, 1e-3,
                               q ? fres_quick[r] : fres_full[r], -1.0, false, true});
    add(b, (struct config){SWEEP_FILTER, SCENE_INTEGRATOR_RK4, q ? 1.0 : 2.0, 1e-3, base, -1.0,
                           false, true});
    add(b, (struct config){SWEEP_FILTER, SCENE_INTEGRATOR_ADAPTIVE, 4.0, 1e-2, base, -1.0, false,
                           true});
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* One configuration of one case: a warm-up trace (scene build, program compile), then the
 * faster of two timed traces. */
static bool run_config(struct render *r, const struct accuracy_case *c, const struct config *cfg,
                       const struct render_trace_ray *rays, const struct accuracy_exit *ref,
                       struct render_trace_hit *hits, int count, struct result *out)
{
    double sigma = cfg->sigma < 0.0 ? c->default_sigma : cfg->sigma;
    char json[1024], id[96];
    struct scene *s = NULL;
    struct scene_limits lim = scene_limits_default();
    struct err e = {0};
    if (!accuracy_case_json(c, cfg->res, sigma, cfg->float16, json, sizeof json) ||
        scene_parse(json, strlen(json), &lim, &s, &e) != REFRACT_E_OK) {
        fprintf(stderr, "refract-accuracy: %s: %s\n", c->name, e.msg);
        return false;
    }
    snprintf(id, sizeof id, "%s-%d-%g-%d", c->name, cfg->res, sigma, cfg->float16 ? 16 : 32);
    struct render_scene_source src = {.id = id, .generation = 1, .scene = s};
    struct scene_render_settings st = s->render;
    st.integrator = cfg->integrator;
    st.step_voxels = cfg->step;
    st.tolerance_voxels = cfg->tolerance;
    st.ior_filter = cfg->tricubic ? SCENE_FILTER_TRICUBIC : SCENE_FILTER_TRILINEAR;
    double best = INFINITY;
    for (int rep = 0; rep < 3; rep++) {
        double ms = 0.0;
        if (render_trace(r, &src, &st, rays, (size_t)count, hits, &ms, &e) != REFRACT_E_OK) {
            fprintf(stderr, "refract-accuracy: %s: %s\n", c->name, e.msg);
            scene_destroy(s);
            return false;
        }
        if (rep > 0)
            best = fmin(best, ms);
    }
    double *dirs = malloc(sizeof(double) * (size_t)count);
    memset(out, 0, sizeof *out);
    double steps = 0.0;
    for (int k = 0; dirs && k < count; k++) {
        steps += hits[k].steps;
        if (!ref[k].valid)
            continue;
        if (hits[k].status != RAY_EXITED) {
            out->lost++;
            out->scored++;
            continue;
        }
        double a, d;
        accuracy_exit_error(&ref[k], &hits[k], &a, &d);
        dirs[out->scored - out->lost] = a;
        out->scored++;
        out->dir_mean += a;
        out->dir_max = fmax(out->dir_max, a);
        out->pos_mean += d;
        out->pos_max = fmax(out->pos_max, d);
    }
    int n = out->scored - out->lost;
    if (dirs && n > 0) {
        qsort(dirs, (size_t)n, sizeof *dirs, cmp_double);
        out->dir_p90 = dirs[(int)floor(0.9 * (n - 1))];
        out->dir_mean /= n;
        out->pos_mean /= n;
    }
    free(dirs);
    out->us_per_ray = 1000.0 * best / count;
    out->steps_per_ray = steps / count;
    if (cfg->res >= 256)
        render_scene_forget(r, id); /* 256 MiB of atlas: do not keep it */
    scene_destroy(s);
    return dirs != NULL;
}

/* Rays lost on the GPU (more than 1% of the scored ones) keep a result off the front. */
static bool eligible(const struct result *r)
{
    return r->scored > 0 && r->lost * 100 <= r->scored;
}

static void mark_front(struct result *rs, int n, const double *time, const double *error)
{
    for (int i = 0; i < n; i++) {
        rs[i].front = eligible(&rs[i]);
        for (int j = 0; j < n && rs[i].front; j++) {
            if (j == i || !eligible(&rs[j]))
                continue;
            bool no_worse = time[j] <= time[i] && error[j] <= error[i];
            bool better = time[j] < time[i] || error[j] < error[i];
            if (no_worse && better)
                rs[i].front = false;
        }
    }
}

static void gpu_run(struct gpu_work *w, struct gpu *gpu)
{
    struct bench *b = w->user;
    struct render_desc desc = {.scene_budget_bytes = (size_t)600 << 20};
    struct render *r = render_create(gpu, &desc, &w->err);
    if (r == NULL)
        return;
    int count = b->opt.side * b->opt.side;
    struct render_trace_ray *rays = calloc((size_t)count, sizeof *rays);
    struct render_trace_hit *hits = calloc((size_t)count, sizeof *hits);
    struct accuracy_exit *ref = calloc((size_t)count, sizeof *ref);
    b->ok = rays && hits && ref;
    for (int ci = 0; b->ok && ci < ACCURACY_CASE_COUNT; ci++) {
        const struct accuracy_case *c = &accuracy_cases[ci];
        accuracy_case_rays(c, b->opt.side, rays);
        b->ok = accuracy_case_reference(c, rays, count, ref);
        for (int k = 0; b->ok && k < b->config_count; k++) {
            b->ok = run_config(r, c, &b->configs[k], rays, ref, hits, count, &b->results[ci][k]);
            const struct result *res = &b->results[ci][k];
            fprintf(stderr,
                    "%-10s %-8s step %-4g tol %-6g res %-3d %-9s: dir mean %.2e  pos mean "
                    "%.2e  %.2f us/ray  lost %d\n",
                    c->name, integrator_names[b->configs[k].integrator], b->configs[k].step,
                    b->configs[k].tolerance, b->configs[k].res,
                    b->configs[k].tricubic ? "tricubic" : "trilinear", res->dir_mean, res->pos_mean,
                    res->us_per_ray, res->lost);
        }
    }
    free(rays);
    free(hits);
    free(ref);
    render_destroy(r);
}

/* ---- the report ---------------------------------------------------------------- */

static void config_label(const struct bench *b, const struct config *c, char *buf, size_t n)
{
    char extra[64] = "";
    if (c->integrator == SCENE_INTEGRATOR_ADAPTIVE)
        snprintf(extra, sizeof extra, ", tol %g", c->tolerance);
    char sig[32] = "";
    if (c->sigma >= 0.0)
        snprintf(sig, sizeof sig, ", sigma %g", c->sigma);
    snprintf(buf, n, "%s, step %g%s%s%s%s", integrator_names[c->integrator], c->step, extra, sig,
             c->float16 ? ", float16" : "", c->tricubic ? ", tricubic" : "");
    if (c->res != b->opt.base_res) {
        size_t len = strlen(buf);
        snprintf(buf + len, n - len, ", %d^3", c->res);
    }
}

struct overall {
    double worst_dir[MAX_CONFIGS]; /* worst over cases of the mean direction error */
    double worst_pos[MAX_CONFIGS];
    double mean_us[MAX_CONFIGS];
    int lost[MAX_CONFIGS];
    struct result flags[MAX_CONFIGS]; /* front and eligibility over all cases */
};

/* Worst and mean over the cases; grin_only: the smooth GRIN cases alone (those with a
 * Dormand-Prince reference; the spheres' sharp boundaries set an error of their own). */
static void compute_overall_of(const struct bench *b, bool grin_only, struct overall *o)
{
    int cases = 0;
    for (int ci = 0; ci < ACCURACY_CASE_COUNT; ci++)
        cases += !grin_only || accuracy_cases[ci].reference == ACCURACY_REF_DOPRI;
    for (int k = 0; k < b->config_count; k++) {
        o->worst_dir[k] = o->worst_pos[k] = o->mean_us[k] = 0.0;
        o->lost[k] = 0;
        o->flags[k] = (struct result){.scored = 0};
        for (int ci = 0; ci < ACCURACY_CASE_COUNT; ci++) {
            if (grin_only && accuracy_cases[ci].reference != ACCURACY_REF_DOPRI)
                continue;
            const struct result *r = &b->results[ci][k];
            o->worst_dir[k] = fmax(o->worst_dir[k], r->dir_mean);
            o->worst_pos[k] = fmax(o->worst_pos[k], r->pos_mean);
            o->mean_us[k] += r->us_per_ray / cases;
            o->lost[k] += r->lost;
            o->flags[k].scored += r->scored;
            o->flags[k].lost += r->lost;
        }
    }
    mark_front(o->flags, b->config_count, o->mean_us, o->worst_dir);
}

static void compute_overall(const struct bench *b, struct overall *o)
{
    compute_overall_of(b, false, o);
}

/* The configurations that differ only in integrator settings and filter on the base grid:
 * the candidates of the preview and final choices. */
static bool base_grid_setting(const struct bench *b, int k)
{
    const struct config *c = &b->configs[k];
    return c->sweep == SWEEP_INTEGRATOR || (c->sweep == SWEEP_FILTER && c->res == b->opt.base_res);
}

/* How far configuration k is from the voxel floor: the largest over the cases of its mean
 * direction error divided by the case's best over the integrator x step sweep (at a fixed
 * voxel grid the voxels set an error floor that no integrator goes below). */
static double floor_ratio(const struct bench *b, int k)
{
    double worst = 0.0;
    for (int ci = 0; ci < ACCURACY_CASE_COUNT; ci++) {
        double floor_err = INFINITY;
        for (int j = 0; j < b->config_count; j++)
            if (b->configs[j].sweep == SWEEP_INTEGRATOR && b->results[ci][j].lost == 0)
                floor_err = fmin(floor_err, b->results[ci][j].dir_mean);
        worst = fmax(worst, b->results[ci][k].dir_mean / floor_err);
    }
    return worst;
}

/* The cheapest integrator x step configuration within `factor` of the floor in every case;
 * -1: none. */
static int cheapest_within(const struct bench *b, const struct overall *o, double factor)
{
    int best = -1;
    for (int k = 0; k < b->config_count; k++) {
        if (!base_grid_setting(b, k) || o->lost[k] != 0 || floor_ratio(b, k) > factor)
            continue;
        if (best < 0 || o->mean_us[k] < o->mean_us[best])
            best = k;
    }
    return best;
}

static int find_default(const struct bench *b)
{
    for (int k = 0; k < b->config_count; k++) {
        const struct config *c = &b->configs[k];
        if (c->sweep == SWEEP_INTEGRATOR && c->integrator == SCENE_INTEGRATOR_RK4 && c->step == 0.5)
            return k;
    }
    return -1;
}

static void write_plot(const struct bench *b, const char *name, const char *title, const double *x,
                       const double *y, const struct result *flags)
{
    struct plot_point pts[MAX_CONFIGS];
    for (int k = 0; k < b->config_count; k++) {
        const struct config *c = &b->configs[k];
        int series = c->sweep == SWEEP_INTEGRATOR ? (int)c->integrator : 3 + (int)c->sweep;
        pts[k] = (struct plot_point){x[k], y[k], series, flags[k].front};
    }
    struct plot_desc d = {
        .title = title,
        .x_label = "GPU time per ray (microseconds, llvmpipe)",
        .y_label = "mean exit-direction error (rad)",
        .series_names = {"euler", "rk4", "rk2", "adaptive", "resolution (rk4 0.5)",
                         "sigma (rk4 0.5)", "float16", "tricubic"},
        .series_count = 8,
        .points = pts,
        .count = b->config_count,
        .front_across_series = true,
    };
    char path[512];
    snprintf(path, sizeof path, "%s/accuracy_%s.png", b->opt.images, name);
    struct err e = {0};
    if (plot_write_png(&d, path, &e) != REFRACT_E_OK)
        fprintf(stderr, "refract-accuracy: %s\n", e.msg);
}

static void write_case_table(FILE *f, const struct bench *b, int ci)
{
    const struct accuracy_case *c = &accuracy_cases[ci];
    fprintf(f, "### %s\n\n%s. Reference: %s.\n\n![%s](images/accuracy_%s.png)\n\n", c->title,
            c->what,
            c->reference == ACCURACY_REF_SNELL ? "Snell's law in closed form"
                                               : "Dormand-Prince 5(4) on the exact field",
            c->title, c->name);
    fprintf(f, "| sweep | settings | direction mean (rad) | p90 | max | position mean | max | "
               "us/ray | steps/ray | lost | front |\n|---|---|---|---|---|---|---|---|---|---|"
               "---|\n");
    for (int k = 0; k < b->config_count; k++) {
        const struct result *r = &b->results[ci][k];
        char label[160];
        config_label(b, &b->configs[k], label, sizeof label);
        fprintf(f, "| %s | %s | %.2e | %.2e | %.2e | %.2e | %.2e | %.2f | %.0f | %d | %s |\n",
                sweep_names[b->configs[k].sweep], label, r->dir_mean, r->dir_p90, r->dir_max,
                r->pos_mean, r->pos_max, r->us_per_ray, r->steps_per_ray, r->lost,
                r->front ? "yes" : "");
    }
    fprintf(f, "\n");
}

static void choice_line(FILE *f, const struct bench *b, const struct overall *o, int k,
                        const char *what)
{
    char label[160];
    if (k < 0) {
        fprintf(f, "- %s: none.\n", what);
        return;
    }
    config_label(b, &b->configs[k], label, sizeof label);
    char ratio[48] = "";
    if (base_grid_setting(b, k))
        snprintf(ratio, sizeof ratio, ", %.2fx the floor", floor_ratio(b, k));
    fprintf(f,
            "- %s: **%s**: worst-case mean direction error %.2e rad, position %.2e, %.2f us "
            "per ray%s%s.\n",
            what, label, o->worst_dir[k], o->worst_pos[k], o->mean_us[k], ratio,
            o->flags[k].front ? " (on the overall Pareto front)" : "");
}

static void write_choice(FILE *f, const struct bench *b, const struct overall *o)
{
    fprintf(f,
            "## The choice\n\n"
            "At a given voxel grid the voxels set an error floor (the resolution and sigma "
            "sweeps show it moving); the integrator settings decide how close to that floor "
            "a render gets and at what cost. The floor of a case is the smallest mean "
            "direction error any integrator x step configuration reaches in it at %d^3; a "
            "configuration's distance from the floor (x floor) is the largest over the six "
            "cases of its error divided by the floor.\n\n",
            b->opt.base_res);
    choice_line(f, b, o, find_default(b), "Current default (rk4, step 0.5)");
    choice_line(f, b, o, cheapest_within(b, o, 2.0),
                "Preview: the cheapest within 2x of the floor in every case");
    choice_line(f, b, o, cheapest_within(b, o, 1.25),
                "Final: the cheapest within 25% of the floor in every case");
    int pv = cheapest_within(b, o, 2.0), fi = cheapest_within(b, o, 1.25);
    if (pv >= 0 && fi >= 0)
        fprintf(f,
                "- Index filter (render.ior_filter; both filters were candidates of the two "
                "choices above): preview **%s**, final **%s**.\n",
                b->configs[pv].tricubic ? "tricubic" : "trilinear",
                b->configs[fi].tricubic ? "tricubic" : "trilinear");
    /* Scenes without sharp boundaries: the sharp spheres, which set the worst case above,
     * say nothing about them. */
    struct overall grin;
    compute_overall_of(b, true, &grin);
    int def = find_default(b), best = -1;
    for (int k = 0; def >= 0 && k < b->config_count; k++)
        if (base_grid_setting(b, k) && grin.lost[k] == 0 &&
            grin.worst_dir[k] <= 0.5 * grin.worst_dir[def] &&
            (best < 0 || grin.mean_us[k] < grin.mean_us[best]))
            best = k;
    if (best >= 0) {
        char label[160];
        config_label(b, &b->configs[best], label, sizeof label);
        fprintf(f,
                "- Final for smooth GRIN fields (no sharp boundaries; the four cases with a "
                "Dormand-Prince reference): the cheapest setting on the %d^3 grid with at most "
                "half the default's worst GRIN error (%.2e rad): **%s**: %.2e rad, %.2f us per "
                "ray (the default: %.2f us).\n",
                b->opt.base_res, grin.worst_dir[def], label, grin.worst_dir[best],
                grin.mean_us[best], grin.mean_us[def]);
    }
    int fine = -1;
    for (int k = 0; k < b->config_count; k++)
        if (b->configs[k].sweep == SWEEP_RESOLUTION &&
            (fine < 0 || b->configs[k].res > b->configs[fine].res))
            fine = k;
    choice_line(f, b, o, fine, "Finest grid measured (rk4, step 0.5)");
    fprintf(f, "\n");
}

/* The trilinear configuration that tricubic configuration k is compared with: the same
 * integrator, step, tolerance, grid, smoothing and texture; -1 when the sweeps lack it. */
static int trilinear_twin(const struct bench *b, int k)
{
    const struct config *c = &b->configs[k];
    for (int j = 0; j < b->config_count; j++) {
        const struct config *t = &b->configs[j];
        if (!t->tricubic && t->integrator == c->integrator && t->step == c->step &&
            (c->integrator != SCENE_INTEGRATOR_ADAPTIVE || t->tolerance == c->tolerance) &&
            t->res == c->res && t->sigma == c->sigma && t->float16 == c->float16)
            return j;
    }
    return -1;
}

/* Trilinear against tricubic over the overall worst case: each tricubic configuration and
 * its trilinear twin, one series per filter, each series' front joined. */
static void write_filter_plot(const struct bench *b, const struct overall *o, const char *name,
                              const char *title)
{
    struct plot_point pts[2 * MAX_CONFIGS];
    double x[2 * MAX_CONFIGS], y[2 * MAX_CONFIGS];
    struct result flags[2 * MAX_CONFIGS];
    int n = 0, series[2 * MAX_CONFIGS];
    for (int k = 0; k < b->config_count; k++) {
        int j = b->configs[k].tricubic ? trilinear_twin(b, k) : -1;
        if (j < 0)
            continue;
        const int ks[2] = {j, k};
        for (int s = 0; s < 2; s++) {
            x[n] = o->mean_us[ks[s]];
            y[n] = o->worst_dir[ks[s]];
            flags[n] = o->flags[ks[s]];
            series[n++] = s;
        }
    }
    for (int s = 0; s < 2; s++) { /* one front per filter */
        double xs[2 * MAX_CONFIGS] = {0}, ys[2 * MAX_CONFIGS] = {0};
        struct result fs[2 * MAX_CONFIGS];
        int idx[2 * MAX_CONFIGS], m = 0;
        for (int i = 0; i < n; i++)
            if (series[i] == s) {
                xs[m] = x[i];
                ys[m] = y[i];
                fs[m] = flags[i];
                idx[m++] = i;
            }
        mark_front(fs, m, xs, ys);
        for (int i = 0; i < m; i++)
            pts[idx[i]] = (struct plot_point){x[idx[i]], y[idx[i]], s, fs[i].front};
    }
    struct plot_desc d = {
        .title = title,
        .x_label = "GPU time per ray (microseconds, llvmpipe)",
        .y_label = "worst mean exit-direction error (rad)",
        .series_names = {"trilinear", "tricubic"},
        .series_count = 2,
        .points = pts,
        .count = n,
    };
    char path[512];
    snprintf(path, sizeof path, "%s/accuracy_%s.png", b->opt.images, name);
    struct err e = {0};
    if (plot_write_png(&d, path, &e) != REFRACT_E_OK)
        fprintf(stderr, "refract-accuracy: %s\n", e.msg);
}

static void filter_row(FILE *f, const char *what, const char *label, const struct result *lin,
                       const struct result *cub)
{
    fprintf(f, "| %s | %s | %.2e | %.2e | %.2f | %.2e | %.2e | %.2f | %.2f | %.2f |\n", what, label,
            lin->dir_mean, cub->dir_mean, cub->dir_mean / lin->dir_mean, lin->pos_mean,
            cub->pos_mean, lin->us_per_ray, cub->us_per_ray, cub->us_per_ray / lin->us_per_ray);
}

/* Error per time: for each tricubic configuration, what trilinear needs (a finer grid,
 * other settings) to match it over the cases of o. */
static void write_equal_error(FILE *f, const struct bench *b, const struct overall *o,
                              const char *cases)
{
    fprintf(f,
            "At equal error over %s: for each tricubic configuration, the cheapest trilinear "
            "configuration of the whole report with no larger worst mean direction error "
            "(mean time over those cases).\n\n| tricubic | worst direction | us/ray | "
            "cheapest trilinear as good | worst direction | us/ray |\n"
            "|---|---|---|---|---|---|\n",
            cases);
    for (int k = 0; k < b->config_count; k++) {
        if (!b->configs[k].tricubic)
            continue;
        int best = -1;
        for (int j = 0; j < b->config_count; j++)
            if (!b->configs[j].tricubic && eligible(&o->flags[j]) &&
                o->worst_dir[j] <= o->worst_dir[k] &&
                (best < 0 || o->mean_us[j] < o->mean_us[best]))
                best = j;
        char label[160], other[160] = "none measured";
        config_label(b, &b->configs[k], label, sizeof label);
        if (best >= 0)
            config_label(b, &b->configs[best], other, sizeof other);
        fprintf(f, "| %s | %.2e | %.2f | %s | ", label, o->worst_dir[k], o->mean_us[k], other);
        if (best >= 0)
            fprintf(f, "%.2e | %.2f |\n", o->worst_dir[best], o->mean_us[best]);
        else
            fprintf(f, "- | - |\n");
    }
    fprintf(f, "\n");
}

static void write_filter_section(FILE *f, const struct bench *b, const struct overall *o)
{
    fprintf(f, "\n## Index filter: trilinear against tricubic\n\n"
               "`render.ior_filter` chooses how n and grad n are reconstructed between voxel "
               "centres (docs/tracing.md \"Index filter\"): **trilinear** (one hardware-filtered "
               "fetch of the stored (grad n, n); C0, so grad n has kinks at every plane through "
               "voxel centres, and it is not the gradient of the interpolated n) or "
               "**tricubic**: Catmull-Rom of n per axis (interpolating, exact for quadratics, "
               "C1) with grad n the exact gradient of that interpolant, from 64 texel fetches. "
               "Each row compares a tricubic configuration with its trilinear twin on the same "
               "voxels; ratios below 1 favour tricubic. Measured first and dropped: an "
               "approximating cubic B-spline and Catmull-Rom filtering of the stored gradient "
               "(docs/tracing.md \"Index filter\").\n\n"
               "![filter, all cases](images/accuracy_filter.png) "
               "![filter, smooth GRIN cases](images/accuracy_filter_grin.png)\n\n"
               "| case | settings | trilinear direction | tricubic direction | ratio | trilinear "
               "position | tricubic position | trilinear us/ray | tricubic us/ray | time ratio "
               "|\n|---|---|---|---|---|---|---|---|---|---|\n");
    double log_time = 0.0;
    int timed = 0;
    for (int k = 0; k < b->config_count; k++) {
        int j = b->configs[k].tricubic ? trilinear_twin(b, k) : -1;
        if (j < 0)
            continue;
        char label[160];
        config_label(b, &b->configs[j], label, sizeof label);
        if (b->configs[k].res == b->opt.base_res) {
            size_t len = strlen(label);
            snprintf(label + len, sizeof label - len, ", %d^3", b->opt.base_res);
        }
        for (int ci = 0; ci < ACCURACY_CASE_COUNT; ci++) {
            filter_row(f, accuracy_cases[ci].title, label, &b->results[ci][j], &b->results[ci][k]);
            log_time += log(b->results[ci][k].us_per_ray / b->results[ci][j].us_per_ray);
            timed++;
        }
        struct result lin = {
            .dir_mean = o->worst_dir[j], .pos_mean = o->worst_pos[j], .us_per_ray = o->mean_us[j]};
        struct result cub = {
            .dir_mean = o->worst_dir[k], .pos_mean = o->worst_pos[k], .us_per_ray = o->mean_us[k]};
        filter_row(f, "**worst case**", label, &lin, &cub);
    }
    fprintf(f,
            "\nTricubic costs %.2fx the trilinear time per ray (geometric mean over the rows "
            "above).\n\n",
            timed > 0 ? exp(log_time / timed) : 0.0);
    struct overall grin;
    compute_overall_of(b, true, &grin);
    write_equal_error(f, b, o, "all six cases");
    write_equal_error(f, b, &grin, "the smooth GRIN cases (Luneburg, fish-eye, mirage, Gaussian)");
}

static bool write_report(const struct bench *b, struct gpu *gpu, int argc, char **argv)
{
    FILE *f = fopen(b->opt.out, "w");
    if (f == NULL) {
        fprintf(stderr, "refract-accuracy: cannot write %s\n", b->opt.out);
        return false;
    }
    struct overall o;
    compute_overall((struct bench *)b, &o);
    fprintf(f, "# Speed against error\n\n"
               "Generated by `refract-accuracy` (bench/bench_accuracy.c); do not edit by hand. "
               "Regenerate with `build/refract-accuracy` (full, some minutes on llvmpipe) or "
               "`build/refract-accuracy --quick`.\n\n");
    bench_write_header(f, gpu, argc, argv);
    fprintf(f,
            "%d rays per case and configuration; base resolution %d^3. Errors are measured "
            "against the exact continuous field, never against voxels: **direction** is the "
            "angle between the traced and the exact exit direction, **position** the distance "
            "of the traced exit point from the exact exit line (world units; the objects are "
            "about 2 units across). **us/ray** is the GPU time of one trace_rays dispatch "
            "divided by the rays (the faster of two runs after a warm-up); on llvmpipe it is "
            "CPU time and moves with the machine's load. **lost** counts rays the reference "
            "brings out that the GPU did not (other status); a configuration that loses more "
            "than 1%% is kept off the Pareto front, which is computed on (time, mean direction "
            "error).\n\n",
            b->opt.side * b->opt.side, b->opt.base_res);
    write_choice(f, b, &o);
    fprintf(f, "## Over all cases\n\nPer configuration: the worst over the six cases of the "
               "mean direction and position errors, and the mean time per ray.\n\n"
               "![overall](images/accuracy_overall.png)\n\n"
               "| sweep | settings | worst mean direction (rad) | worst mean position | x floor | "
               "us/ray | lost | front |\n|---|---|---|---|---|---|---|---|\n");
    for (int k = 0; k < b->config_count; k++) {
        char label[160];
        config_label(b, &b->configs[k], label, sizeof label);
        char ratio[32] = "-"; /* the floor is that of the base grid: integrator sweep only */
        if (base_grid_setting(b, k))
            snprintf(ratio, sizeof ratio, "%.2f", floor_ratio(b, k));
        fprintf(f, "| %s | %s | %.2e | %.2e | %s | %.2f | %d | %s |\n",
                sweep_names[b->configs[k].sweep], label, o.worst_dir[k], o.worst_pos[k], ratio,
                o.mean_us[k], o.lost[k], o.flags[k].front ? "yes" : "");
    }
    write_filter_section(f, b, &o);
    fprintf(f, "## Per case\n\n");
    for (int ci = 0; ci < ACCURACY_CASE_COUNT; ci++)
        write_case_table(f, b, ci);
    bool images_ok = b->opt.no_images || accuracy_image_report(gpu, b->opt.quick, b->opt.images, f);
    fclose(f);
    write_plot(b, "overall", "All cases: worst mean error vs time", o.mean_us, o.worst_dir,
               o.flags);
    write_filter_plot(b, &o, "filter", "Index filter, all six cases");
    struct overall grin;
    compute_overall_of(b, true, &grin);
    write_filter_plot(b, &grin, "filter_grin", "Index filter, smooth GRIN cases");
    for (int ci = 0; ci < ACCURACY_CASE_COUNT; ci++) {
        double x[MAX_CONFIGS], y[MAX_CONFIGS];
        for (int k = 0; k < b->config_count; k++) {
            x[k] = b->results[ci][k].us_per_ray;
            y[k] = b->results[ci][k].dir_mean;
        }
        write_plot(b, accuracy_cases[ci].name, accuracy_cases[ci].title, x, y, b->results[ci]);
    }
    return images_ok;
}

static void mark_case_fronts(struct bench *b)
{
    for (int ci = 0; ci < ACCURACY_CASE_COUNT; ci++) {
        double x[MAX_CONFIGS], y[MAX_CONFIGS];
        for (int k = 0; k < b->config_count; k++) {
            x[k] = b->results[ci][k].us_per_ray;
            y[k] = b->results[ci][k].dir_mean;
        }
        mark_front(b->results[ci], b->config_count, x, y);
    }
}

int main(int argc, char **argv)
{
    static struct bench b;
    b.opt = (struct options){.out = "docs/accuracy.md", .images = "docs/images"};
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--quick")) {
            b.opt.quick = true;
        } else if (!strcmp(argv[i], "--no-images")) {
            b.opt.no_images = true;
        } else if (!strcmp(argv[i], "--out") && i + 1 < argc) {
            b.opt.out = argv[++i];
        } else if (!strcmp(argv[i], "--images") && i + 1 < argc) {
            b.opt.images = argv[++i];
        } else {
            fprintf(stderr, "usage: refract-accuracy [--quick] [--no-images] [--out "
                            "docs/accuracy.md] [--images docs/images]\n");
            return 2;
        }
    }
    b.opt.side = b.opt.quick ? 12 : 32;
    b.opt.base_res = b.opt.quick ? 64 : 128;
    build_configs(&b);
    struct gpu_desc desc = {.context = {.device_index = -1}};
    struct err e = {0};
    struct gpu *gpu = gpu_create(&desc, &e);
    if (gpu == NULL) {
        fprintf(stderr, "refract-accuracy: %s\n", e.msg);
        return 1;
    }
    struct gpu_work w = {.priority = GPU_PRIORITY_BATCH, .run = gpu_run, .user = &b};
    enum refract_code rc = gpu_run_sync(gpu, &w);
    if (rc != REFRACT_E_OK || !b.ok) {
        fprintf(stderr, "refract-accuracy: %s\n", rc != REFRACT_E_OK ? w.err.msg : "failed");
        gpu_destroy(gpu, NULL);
        return 1;
    }
    mark_case_fronts(&b);
    bool ok = write_report(&b, gpu, argc, argv);
    gpu_destroy(gpu, NULL);
    return ok ? 0 : 1;
}
