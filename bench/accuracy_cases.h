/*
 * accuracy_cases.h - the analytic cases of the speed-against-error report
 * (docs/accuracy.md): a scene document per case (at a chosen voxel resolution, smoothing
 * and index texture), a bundle of rays, and the exact exits of those rays.
 *
 * The exact exits come from the continuous field, never from voxels: the adaptive
 * Dormand-Prince reference (reftrace REFTRACE_ADAPTIVE, tolerance 1e-10 per step) on the
 * exact GRIN profile for the Luneburg lens, the Maxwell fish-eye, the mirage and the
 * strong Gaussian lens; Snell's law in closed form (optics_exact.h) for the sharp spheres,
 * whose voxels are smoothed. tests/unit/test_grin_analytic.c and test_reftrace.c check
 * these references against closed forms.
 */
#ifndef REFRACT_BENCH_ACCURACY_CASES_H
#define REFRACT_BENCH_ACCURACY_CASES_H

#include <stdbool.h>
#include <stddef.h>

#include "core/vec3.h"
#include "render/render.h"

enum accuracy_reference {
    ACCURACY_REF_DOPRI = 0, /* Dormand-Prince on the exact profile */
    ACCURACY_REF_SNELL = 1, /* closed-form refraction through a homogeneous sphere */
};

struct accuracy_case {
    const char *name;  /* file-name friendly: "luneburg" */
    const char *title; /* for tables and plots */
    const char *what;  /* one line: the field and the rays */
    enum accuracy_reference reference;
    double sphere_n;      /* ACCURACY_REF_SNELL: index inside radius 0.8 */
    double default_sigma; /* smoothing (voxels) when the sweep does not set it */
};

#define ACCURACY_CASE_COUNT 6
extern const struct accuracy_case accuracy_cases[ACCURACY_CASE_COUNT];

/* The scene document at resolution res^3, smoothing sigma (voxels) and the float16 index
 * texture or not. Returns false when buf is too small. */
bool accuracy_case_json(const struct accuracy_case *c, int res, double sigma, bool float16,
                        char *buf, size_t size);

/* side * side rays of the case's bundle. */
void accuracy_case_rays(const struct accuracy_case *c, int side, struct render_trace_ray *rays);

/* The exact exit of a ray: a point on the exit line and its unit direction (world). */
struct accuracy_exit {
    bool valid; /* the reference ray exited (rays it loses are not scored) */
    vec3 point, dir;
};

/* Exact exits of `count` rays. Returns false (message on stderr) when the reference cannot
 * be built. */
bool accuracy_case_reference(const struct accuracy_case *c, const struct render_trace_ray *rays,
                             int count, struct accuracy_exit *out);

/* Errors of one traced exit against the exact one: the angle between the directions
 * (radians) and the distance of the traced exit point from the exact exit line (world). */
void accuracy_exit_error(const struct accuracy_exit *ref, const struct render_trace_hit *hit,
                         double *angle, double *distance);

#endif
