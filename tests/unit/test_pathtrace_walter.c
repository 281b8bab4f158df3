/*
 * test_pathtrace_walter.c - the path tracer's exact connections through glass
 * (pathtrace_scene.walter, docs/walter.md "In the path tracer") change the estimator, not
 * the expectation: on a scattering glass ball lit from behind by a sphere lamp, camera rays'
 * single-scattered radiance with the connections equals the plain unidirectional estimate
 * (which finds that light only when a scattered ray refracts out onto the lamp) within
 * 4 standard errors, at a fraction of the noise per path. A lamp hit counted as well as
 * the connection that made it (the rule of pt_state.walter) would add the light twice:
 * the comparison fails then.
 */
#include <math.h>

#include "pathtrace_test_util.h"
#include "test.h"

static struct pathtrace_surface ball;

static struct pathtrace_scene backlit_ball(bool walter)
{
    ball = pt_sphere(vec3_make(0, 0, 0), 1.0, 1.5);
    for (int c = 0; c < 3; c++) {
        ball.medium.sigma_s[c] = 0.5;
        ball.medium.sigma_a[c] = 0.05;
    }
    struct pathtrace_scene s = pt_scene(0.0);
    s.surfaces = &ball;
    s.surface_count = 1;
    /* a lamp of radius 0.2 at distance 4: larger than scene B's so that the plain
     * estimator converges in a test's time; connected as a point below 6 % */
    s.lights[0] = (struct pathtrace_light){
        .kind = PATHTRACE_LIGHT_SPHERE, .position = {0, 1, -3.87}, .radius = 0.2, .visible = false};
    for (int c = 0; c < 3; c++)
        s.lights[0].value[c] = 10.0 / (M_PI * 0.2 * 0.2); /* intensity 10 */
    s.light_count = 1;
    s.max_scatter = 1;
    if (walter)
        s.walter = (struct pathtrace_walter){true, 0, {0, 0, 0}, 1.0, 1.5, false, 0.06};
    return s;
}

int main(void)
{
    struct pathtrace_scene plain = backlit_ball(false), exact = backlit_ball(true);
    const vec3 eye = {0, 0.5, 6};
    const vec3 aims[3] = {{0, 0, 0}, {0.4, -0.3, 0}, {-0.2, 0.5, 0}};
    int n_plain = test_sanitized() ? 200000 : 2000000, n_exact = n_plain / 20;
    for (int i = 0; i < 3; i++) {
        vec3 d = vec3_sub(aims[i], eye);
        struct pt_estimate a = pt_estimate_ray(&plain, eye, d, n_plain, 1);
        struct pt_estimate b = pt_estimate_ray(&exact, eye, d, n_exact, 2);
        double se = sqrt(a.stderr_[1] * a.stderr_[1] + b.stderr_[1] * b.stderr_[1]);
        printf("ray %d: plain %.5f +- %.5f (%d paths), with connections %.5f +- %.5f (%d)\n", i,
               a.mean[1], a.stderr_[1], n_plain, b.mean[1], b.stderr_[1], n_exact);
        CHECK(b.mean[1] > 0.0);
        CHECK_MSG(fabs(a.mean[1] - b.mean[1]) < 4.0 * se, "ray %d: %g vs %g (se %g)", i, a.mean[1],
                  b.mean[1], se);
        /* the connections' noise per path is far below the plain estimator's */
        CHECK(b.stderr_[1] * sqrt((double)n_exact) < 0.3 * a.stderr_[1] * sqrt((double)n_plain));
    }
    return test_summary("pathtrace_walter");
}
