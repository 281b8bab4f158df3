/*
 * bench_accuracy.c - refract-accuracy: how far the fixed-step integrators land from the
 * exact ray through a continuous GRIN field, on the CPU double-precision reference
 * (server/core/reftrace.c) and the same voxel fields the GPU uses. It is the measurement
 * behind the README's "Choosing render settings" table; the full speed-against-error
 * report with GPU timings is a later piece of work.
 *
 *     build/refract-accuracy [--scene proto/examples/luneburg_lens.json] [--resolution 128]
 *
 * For a bundle of parallel rays through the object it reports, per integrator and step,
 * the worst and mean exit-direction angle (radians) and exit-position distance (world
 * units) against the adaptive Dormand-Prince trace of the exact field (tolerance 1e-10).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "example_scene.h"
#include "scene/scene_reference.h"

int main(int argc, char **argv)
{
    const char *path = "proto/examples/luneburg_lens.json";
    int res = 128;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--scene"))
            path = argv[i + 1];
        else if (!strcmp(argv[i], "--resolution"))
            res = atoi(argv[i + 1]);
    }
    struct scene *s = bench_load_example("refract-accuracy", path, res);
    if (s == NULL)
        return 1;
    struct scene_reference vox, exact;
    struct err e = {0};
    if (scene_reference_build(s, SCENE_REFERENCE_VOXELS, NULL, NULL, &vox, &e) != REFRACT_E_OK ||
        scene_reference_build(s, SCENE_REFERENCE_ANALYTIC, NULL, NULL, &exact, &e) !=
            REFRACT_E_OK) {
        fprintf(stderr, "refract-accuracy: %s\n", e.msg);
        return 1;
    }
    /* A bundle of parallel rays along +z over the object's cross-section. */
    vec3 lo = s->objects[0].bounds_min, hi = s->objects[0].bounds_max;
    enum { N = 15 };
    vec3 origins[N * N];
    int count = 0;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            double x = lo.x + (hi.x - lo.x) * (i + 0.5) / N * 0.9 + 0.05 * (hi.x - lo.x);
            double y = lo.y + (hi.y - lo.y) * (j + 0.5) / N * 0.9 + 0.05 * (hi.y - lo.y);
            origins[count++] = (vec3){x, y, lo.z - 1.0};
        }
    struct reftrace_settings ref = exact.settings;
    ref.integrator = REFTRACE_ADAPTIVE;
    ref.tolerance = 1e-10;
    struct reftrace_result truth[N * N];
    for (int k = 0; k < count; k++)
        reftrace_ray(exact.objects, exact.count, &ref, origins[k], (vec3){0, 0, 1}, &truth[k]);
    printf("%s at %d^3 (%d rays): exit error against the exact field\n\n", path, res, count);
    printf("| integrator | step (voxels) | direction worst (rad) | direction mean | "
           "position worst | position mean | steps per ray |\n|---|---|---|---|---|---|---|\n");
    const char *names[2] = {"euler", "rk4"};
    const double steps[4] = {2.0, 1.0, 0.5, 0.25};
    for (int it = 0; it < 2; it++) {
        for (int si = 0; si < 4; si++) {
            struct reftrace_settings st = vox.settings;
            st.integrator = it == 0 ? REFTRACE_EULER : REFTRACE_RK4;
            st.step_voxels = steps[si];
            double dmax = 0, dsum = 0, pmax = 0, psum = 0, nsteps = 0;
            for (int k = 0; k < count; k++) {
                struct reftrace_result r;
                reftrace_ray(vox.objects, vox.count, &st, origins[k], (vec3){0, 0, 1}, &r);
                double c = vec3_dot(vec3_normalize(r.exit_direction),
                                    vec3_normalize(truth[k].exit_direction));
                double da = acos(fmax(-1.0, fmin(1.0, c)));
                double dp = vec3_length(vec3_sub(r.exit_origin, truth[k].exit_origin));
                dmax = fmax(dmax, da);
                dsum += da;
                pmax = fmax(pmax, dp);
                psum += dp;
                nsteps += r.steps;
            }
            printf("| %s | %.2f | %.2e | %.2e | %.2e | %.2e | %.0f |\n", names[it], steps[si], dmax,
                   dsum / count, pmax, psum / count, nsteps / count);
        }
    }
    scene_reference_free(&vox);
    scene_reference_free(&exact);
    scene_destroy(s);
    return 0;
}
