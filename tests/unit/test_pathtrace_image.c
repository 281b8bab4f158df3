/*
 * test_pathtrace_image.c - the progressive image (pathtrace_image.h): its variance
 * channel is the variance of the pixel mean, so two renders with independent seeds
 * differ per pixel by z = (m1 - m2) / sqrt(v1 + v2) with E[z^2] = 1 (the z-test that
 * compares the GPU path tracer with this CPU twin); splitting the rows into passes in any
 * order gives the same image bit for bit; more samples lower the variance as 1 / n.
 */
#include <math.h>

#include "core/pathtrace_image.h"
#include "pathtrace_test_util.h"
#include "test.h"

#define W 24
#define H 18

static struct pathtrace_surface ball;

/* A glass ball on a grey floor under a dim sky and a spherical light. */
static struct pathtrace_scene small_scene(void)
{
    struct pathtrace_scene s = pt_scene(0.2);
    s.receiver = (struct pathtrace_receiver){true, -1.0, INFINITY, {0.5, 0.5, 0.5}, {0, 0}};
    ball = pt_sphere(vec3_make(0, 0, 0), 1.0, 1.5);
    s.surfaces = &ball;
    s.surface_count = 1;
    s.lights[0] = (struct pathtrace_light){.kind = PATHTRACE_LIGHT_SPHERE,
                                           .position = {2, 4, 1},
                                           .radius = 0.5,
                                           .value = {5, 5, 5},
                                           .visible = true};
    s.light_count = 1;
    return s;
}

static const struct pathtrace_camera cam = {{0, 2.5, 7}, {0, -0.5, 0}, {0, 1, 0}, 35.0, W, H};

static void render(struct pathtrace_image *img, const struct pathtrace_scene *s, uint64_t seed,
                   int passes)
{
    CHECK(pathtrace_image_init(img, W, H) == 0);
    for (int p = 0; p < passes; p++)
        pathtrace_image_pass(img, s, &cam, seed, 0, H);
}

static void independent_renders_differ_by_their_variance_estimates(void)
{
    struct pathtrace_scene s = small_scene();
    struct pathtrace_image a, b;
    render(&a, &s, 11, 64);
    render(&b, &s, 12, 64);
    double z2 = 0.0;
    int n = 0;
    for (int64_t i = 0; i < W * H; i++) {
        double ma[3], va[3], mb[3], vb[3];
        pathtrace_image_pixel(&a, i, ma, va);
        pathtrace_image_pixel(&b, i, mb, vb);
        if (va[1] + vb[1] <= 0.0)
            continue;
        z2 += (ma[1] - mb[1]) * (ma[1] - mb[1]) / (va[1] + vb[1]);
        n++;
    }
    CHECK(n > W * H / 2);
    /* E[z^2] = 1; over ~400 pixels its spread is about 0.1 (heavier tails make the
     * sample variance an underestimate for a few pixels, hence the upper bound) */
    CHECK_MSG(z2 / n > 0.7 && z2 / n < 1.6, "mean z^2 = %.3f over %d pixels", z2 / n, n);
    pathtrace_image_fini(&a);
    pathtrace_image_fini(&b);
}

static void row_passes_in_any_order_give_the_same_image(void)
{
    struct pathtrace_scene s = small_scene();
    struct pathtrace_image a, b;
    render(&a, &s, 5, 3);
    CHECK(pathtrace_image_init(&b, W, H) == 0);
    for (int p = 0; p < 3; p++) {
        pathtrace_image_pass(&b, &s, &cam, 5, H / 2, H);
        pathtrace_image_pass(&b, &s, &cam, 5, 0, H / 2);
    }
    CHECK(memcmp(a.sum, b.sum, sizeof(double) * 3 * W * H) == 0);
    CHECK(memcmp(a.sum_sq, b.sum_sq, sizeof(double) * 3 * W * H) == 0);
    pathtrace_image_fini(&a);
    pathtrace_image_fini(&b);
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void variance_of_the_mean_falls_as_one_over_n(void)
{
    struct pathtrace_scene s = small_scene();
    struct pathtrace_image a, b;
    render(&a, &s, 21, 16);
    render(&b, &s, 22, 64);
    /* the median of the per-pixel ratios: caustic paths (floor, glass, light) are rare and
     * large, so a sum over pixels follows a few outliers */
    static double ratio[W * H];
    int n = 0;
    for (int64_t i = 0; i < W * H; i++) {
        double m[3], va[3], vb[3];
        pathtrace_image_pixel(&a, i, m, va);
        pathtrace_image_pixel(&b, i, m, vb);
        if (vb[1] > 0.0)
            ratio[n++] = va[1] / vb[1];
    }
    qsort(ratio, (size_t)n, sizeof ratio[0], cmp_double);
    double med = ratio[n / 2];
    CHECK(n > W * H / 2);
    CHECK_MSG(med > 3.0 && med < 5.3, "median ratio %.2f, expected about 4", med);
    pathtrace_image_fini(&a);
    pathtrace_image_fini(&b);
}

int main(void)
{
    independent_renders_differ_by_their_variance_estimates();
    row_passes_in_any_order_give_the_same_image();
    variance_of_the_mean_falls_as_one_over_n();
    return test_summary("test_pathtrace_image");
}
