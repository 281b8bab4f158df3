/*
 * test_scene_field.c - shape SDFs against closed forms and brute force, the layering
 * rule, GRIN profiles at voxel centres, volume resampling and missing volumes.
 */
#include <string.h>
#include <time.h>

#include "scene/font5x7.h"
#include "scene/scene.h"
#include "scene_test_util.h"
#include "test.h"

/* A small deterministic generator for test points. */
static double rnd(unsigned *state)
{
    *state = *state * 1664525u + 1013904223u;
    return (double)(*state >> 8) / (double)(1u << 24);
}

static vec3 rnd_point(unsigned *state, double extent)
{
    return vec3_make((2 * rnd(state) - 1) * extent, (2 * rnd(state) - 1) * extent,
                     (2 * rnd(state) - 1) * extent);
}

/* ---- SDFs ---- */

static void sphere_sdf_is_distance_to_centre_minus_radius(void)
{
    struct scene_shape s = {.kind = SCENE_SHAPE_SPHERE, .center = {0.1, 0.2, 0.3}, .radius = 0.5};
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(0.1, 0.2, 0.3)), -0.5, 1e-15);
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(0.1, 0.2, 1.3)), 0.5, 1e-15);
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(0.4, 0.6, 0.3)), 0.0, 1e-15);
}

static void box_sdf_matches_face_edge_and_corner_distances(void)
{
    struct scene_shape s = {.kind = SCENE_SHAPE_BOX, .center = {0, 0, 0}, .size = {2, 4, 6}};
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(0, 0, 0)), -1.0, 1e-15); /* nearest face x */
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(0.5, 1.5, 2.9)), -0.1, 1e-12);
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(3, 0, 0)), 2.0, 1e-15);
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(4, 5, 0)), sqrt(18.0), 1e-12); /* edge: (3, 3) */
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(2, 3, 4)), sqrt(3.0), 1e-12);  /* corner */
}

static void rounded_box_sdf_matches_its_corner_spheres(void)
{
    struct scene_shape s = {
        .kind = SCENE_SHAPE_ROUNDED_BOX, .center = {0, 0, 0}, .size = {2, 2, 2}, .radius = 0.25};
    /* Faces stay where the box's faces are. */
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(1.5, 0, 0)), 0.5, 1e-15);
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(0, 0, 0)), -1.0, 1e-15);
    /* Near a corner the surface is a sphere of radius 0.25 about (0.75, 0.75, 0.75). */
    vec3 c = {0.75, 0.75, 0.75};
    vec3 p = {1.2, 1.1, 0.9};
    CHECK_NEAR(scene_shape_sdf(&s, p), vec3_length(vec3_sub(p, c)) - 0.25, 1e-12);
    /* radius = half the size is a sphere. */
    struct scene_shape ball = s;
    ball.radius = 1.0;
    CHECK_NEAR(scene_shape_sdf(&ball, vec3_make(1, 1, 1)), sqrt(3.0) - 1.0, 1e-12);
}

static void cylinder_sdf_matches_side_cap_and_rim(void)
{
    struct scene_shape s = {
        .kind = SCENE_SHAPE_CYLINDER, .center = {0, 0, 0}, .radius = 1, .height = 2, .axis = 2};
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(2, 0, 0.5)), 1.0, 1e-15);   /* side */
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(0.3, 0.4, 3)), 2.0, 1e-15); /* cap */
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(0, 4, 5)), 5.0, 1e-12);     /* rim (3, 4) */
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(0, 0, 0.5)), -0.5, 1e-15);  /* inside: cap */
    CHECK_NEAR(scene_shape_sdf(&s, vec3_make(0.8, 0, 0)), -0.2, 1e-12);  /* inside: side */
}

static double box2d(double x, double y, double cx, double cy, double hx, double hy)
{
    double qx = fabs(x - cx) - hx, qy = fabs(y - cy) - hy;
    double ox = fmax(qx, 0), oy = fmax(qy, 0);
    return sqrt(ox * ox + oy * oy) + fmin(fmax(qx, qy), 0.0);
}

static void lathe_of_a_rectangle_equals_a_cylinder(void)
{
    double prof[4][2] = {{0, 0}, {0.6, 0}, {0.6, 1.2}, {0, 1.2}};
    for (int axis = 0; axis < 3; axis++) {
        struct scene_shape lathe = {.kind = SCENE_SHAPE_LATHE,
                                    .base = {0.1, -0.5, 0.2},
                                    .axis = axis,
                                    .profile = prof,
                                    .profile_count = 4};
        struct scene_shape cyl = {.kind = SCENE_SHAPE_CYLINDER,
                                  .center = lathe.base,
                                  .radius = 0.6,
                                  .height = 1.2,
                                  .axis = axis};
        vec3_set(&cyl.center, axis, vec3_get(lathe.base, axis) + 0.6);
        unsigned st = 7;
        double worst = 0;
        for (int i = 0; i < 2000; i++) {
            vec3 p = rnd_point(&st, 2.0);
            worst = fmax(worst, fabs(scene_shape_sdf(&lathe, p) - scene_shape_sdf(&cyl, p)));
        }
        CHECK_NEAR(worst, 0.0, 1e-12);
        /* On the axis inside: the axis edge is not a surface. */
        vec3 on_axis = lathe.base;
        vec3_set(&on_axis, axis, vec3_get(lathe.base, axis) + 0.6);
        CHECK_NEAR(scene_shape_sdf(&lathe, on_axis), -0.6, 1e-12);
    }
}

static void lathe_of_an_offset_rectangle_equals_an_annulus(void)
{
    /* Revolving [0.3, 0.7] x [-0.2, 0.4] gives a tube; its 3D distance is the 2D box
     * distance in (r, h). Listed clockwise, to check orientation does not matter. */
    double prof[4][2] = {{0.3, -0.2}, {0.3, 0.4}, {0.7, 0.4}, {0.7, -0.2}};
    struct scene_shape s = {
        .kind = SCENE_SHAPE_LATHE, .axis = 1, .profile = prof, .profile_count = 4};
    unsigned st = 11;
    double worst = 0;
    for (int i = 0; i < 2000; i++) {
        vec3 p = rnd_point(&st, 1.0);
        double r = sqrt(p.x * p.x + p.z * p.z);
        double expect = box2d(r, p.y, 0.5, 0.1, 0.2, 0.3);
        worst = fmax(worst, fabs(scene_shape_sdf(&s, p) - expect));
    }
    CHECK_NEAR(worst, 0.0, 1e-12);
    CHECK(scene_shape_sdf(&s, vec3_make(0, 0.1, 0)) > 0); /* the hole is outside */
    CHECK(scene_shape_sdf(&s, vec3_make(0.5, 0.1, 0)) < 0);
}

/* Text layout helpers for the tests: pixel size and the centre of pixel (col, row_top)
 * of character index ci, for a text shape centred at the origin. */
static vec3 text_pixel_centre(const struct scene_shape *s, int ci, int col, int row_top)
{
    double px = s->height / 7.0;
    int columns = (int)strlen(s->text) * 6 - 1;
    double x0 = s->center.x - 0.5 * columns * px, y0 = s->center.y - 3.5 * px;
    int c = ci * 6 + col;
    int row_up = 6 - row_top;
    return vec3_make(x0 + (c + 0.5) * px, y0 + (row_up + 0.5) * px, s->center.z);
}

static void text_lit_pixel_centre_is_inside_and_spacing_column_outside(void)
{
    struct scene_shape s = {
        .kind = SCENE_SHAPE_TEXT, .text = "HI", .center = {0, 0, 0}, .height = 0.7, .depth = 0.2};
    /* 'H' column 0 is lit on every row; column 5 is the spacing column. */
    CHECK(scene_shape_sdf(&s, text_pixel_centre(&s, 0, 0, 3)) < 0);
    CHECK_NEAR(scene_shape_sdf(&s, text_pixel_centre(&s, 0, 5, 3)), 0.05, 1e-12);
    /* The middle of the depth is 0.1 from either face; a lit pixel surrounded by lit
     * neighbours (H's crossbar has unlit pixels above and below) is 0.05 from them. */
    CHECK_NEAR(scene_shape_sdf(&s, text_pixel_centre(&s, 0, 2, 3)), -0.05, 1e-12);
    /* In front of the text by 0.3: distance 0.3 - 0.1 straight onto the face. */
    vec3 front = text_pixel_centre(&s, 0, 0, 3);
    front.z = 0.4;
    CHECK_NEAR(scene_shape_sdf(&s, front), 0.3, 1e-12);
}

static void text_i_and_period_differ_at_the_top_centre(void)
{
    struct scene_shape i = {.kind = SCENE_SHAPE_TEXT, .text = "I", .height = 1, .depth = 1};
    struct scene_shape dot = i;
    dot.text = ".";
    vec3 top = text_pixel_centre(&i, 0, 2, 0);
    CHECK(scene_shape_sdf(&i, top) < 0);
    CHECK(scene_shape_sdf(&dot, top) > 0);
    CHECK(scene_font5x7_lit('I', 2, 0));
    CHECK(!scene_font5x7_lit('.', 2, 0));
    CHECK(scene_font5x7_lit('.', 2, 6));
}

static void font_has_a_glyph_for_every_printable_character_but_space(void)
{
    for (int ch = 0x21; ch <= 0x7e; ch++) {
        unsigned any = 0;
        for (int col = 0; col < 5; col++)
            any |= scene_font5x7_column(ch, col);
        CHECK_MSG(any != 0, "glyph 0x%02x is blank", ch);
    }
    for (int col = 0; col < 6; col++)
        CHECK_INT(scene_font5x7_column(' ', col), 0);
    CHECK_INT(scene_font5x7_column('A', 5), 0);
    CHECK_INT(scene_font5x7_column(0x7f, 0), 0);
}

/* Brute force: exact 2D signed distance to the union of lit pixel squares. */
static double text_brute_2d(const char *text, double u, double v)
{
    int columns = (int)strlen(text) * 6 - 1;
    bool inside = false;
    double to_lit = INFINITY, to_unlit = INFINITY;
    for (int c = -1; c <= columns; c++) {
        for (int r = -1; r <= 7; r++) {
            bool lit = c >= 0 && c < columns && r >= 0 && r < 7 &&
                       scene_font5x7_lit((unsigned char)text[c / 6], c % 6, 6 - r);
            double dx = fmax(fmax(c - u, 0), u - (c + 1)), dy = fmax(fmax(r - v, 0), v - (r + 1));
            double d = sqrt(dx * dx + dy * dy);
            if (lit) {
                to_lit = fmin(to_lit, d);
                if (d == 0 && u > c && u < c + 1 && v > r && v < r + 1)
                    inside = true;
            } else {
                to_unlit = fmin(to_unlit, d);
            }
        }
    }
    /* Beyond the ring of cells around the block everything is unlit too. */
    to_unlit = fmin(to_unlit, fmax(0, fmin(fmin(u + 1, columns + 1 - u), fmin(v + 1, 8 - v))));
    return inside ? -to_unlit : to_lit;
}

static void text_sdf_is_exact_against_brute_force(void)
{
    struct scene_shape s = {.kind = SCENE_SHAPE_TEXT,
                            .text = "Rf@ .:#",
                            .center = {0.2, -0.1, 0.3},
                            .height = 0.35,
                            .depth = 0.1};
    double px = s.height / 7;
    int columns = (int)strlen(s.text) * 6 - 1;
    double x0 = s.center.x - 0.5 * columns * px, y0 = s.center.y - 3.5 * px;
    unsigned st = 3;
    double worst = 0;
    for (int i = 0; i < 4000; i++) {
        vec3 p =
            vec3_make(s.center.x + (2 * rnd(&st) - 1) * 1.6, s.center.y + (2 * rnd(&st) - 1) * 0.3,
                      s.center.z + (2 * rnd(&st) - 1) * 0.15);
        double d2 = text_brute_2d(s.text, (p.x - x0) / px, (p.y - y0) / px) * px;
        double dz = fabs(p.z - s.center.z) - 0.5 * s.depth;
        double expect = fmin(fmax(d2, dz), 0.0) + sqrt(pow(fmax(d2, 0), 2) + pow(fmax(dz, 0), 2));
        worst = fmax(worst, fabs(scene_shape_sdf(&s, p) - expect));
    }
    CHECK_NEAR(worst, 0.0, 1e-12);
}

static void text_of_spaces_is_empty(void)
{
    struct scene_shape s = {.kind = SCENE_SHAPE_TEXT, .text = "   ", .height = 1, .depth = 1};
    vec3 lo, hi;
    CHECK(!scene_shape_bounds(&s, &lo, &hi));
    CHECK(scene_shape_sdf(&s, vec3_make(0, 0, 0)) > 1e6);
}

static void shape_bounds_contain_the_solid(void)
{
    double prof[3][2] = {{0, 0}, {0.5, 0.2}, {0.1, 0.9}};
    struct scene_shape shapes[] = {
        {.kind = SCENE_SHAPE_SPHERE, .center = {0.1, 0, 0}, .radius = 0.4},
        {.kind = SCENE_SHAPE_BOX, .center = {0, 0.2, 0}, .size = {0.3, 0.5, 0.7}},
        {.kind = SCENE_SHAPE_ROUNDED_BOX, .size = {0.3, 0.5, 0.7}, .radius = 0.1},
        {.kind = SCENE_SHAPE_CYLINDER, .radius = 0.3, .height = 0.8, .axis = 0},
        {.kind = SCENE_SHAPE_LATHE,
         .base = {0, -0.4, 0},
         .axis = 1,
         .profile = prof,
         .profile_count = 3},
        {.kind = SCENE_SHAPE_TEXT, .text = " x-", .height = 0.3, .depth = 0.2},
    };
    for (size_t k = 0; k < sizeof shapes / sizeof shapes[0]; k++) {
        vec3 lo, hi;
        CHECK(scene_shape_bounds(&shapes[k], &lo, &hi));
        unsigned st = 5;
        int outside_but_inside = 0;
        for (int i = 0; i < 5000; i++) {
            vec3 p = rnd_point(&st, 1.0);
            bool in_box = p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z &&
                          p.z <= hi.z;
            if (!in_box && scene_shape_sdf(&shapes[k], p) < 0)
                outside_but_inside++;
        }
        CHECK_MSG(outside_but_inside == 0, "shape %zu: %d inside points outside its bounds", k,
                  outside_but_inside);
    }
}

/* ---- layering ---- */

static void later_layers_override_earlier_ones(void)
{
    struct scene *s = parse_ok(OBJ("\"resolution\": 8, \"ior\": [1.2, {\"shape\": \"sphere\", "
                                   "\"radius\": 0.5, \"inside\": 1.5}, 1.3, {\"shape\": \"box\", "
                                   "\"center\": [-0.75, -0.75, -0.75], \"size\": [0.5, 0.5, 0.5], "
                                   "\"inside\": 1.7}]"));
    if (s == NULL)
        return;
    float *n = eval(s, SCENE_CH_IOR, NULL, NULL);
    const struct scene_object *o = &s->objects[0];
    /* The constant 1.3 wiped out the sphere; the box covers the corner voxel. */
    CHECK_NEAR(n[voxel_index(o, 4, 4, 4)], 1.3, 1e-6);
    CHECK_NEAR(n[voxel_index(o, 0, 0, 0)], 1.7, 1e-6);
    CHECK_NEAR(n[voxel_index(o, 7, 7, 7)], 1.3, 1e-6);
    free(n);
    scene_destroy(s);
}

static void shape_layer_blends_inside_over_previous_value(void)
{
    struct scene *s = parse_ok(OBJ("\"resolution\": 8, \"ior\": [1.2, {\"shape\": \"sphere\", "
                                   "\"radius\": 0.5, \"inside\": 1.5}]"));
    if (s == NULL)
        return;
    float *n = eval(s, SCENE_CH_IOR, NULL, NULL);
    const struct scene_object *o = &s->objects[0];
    CHECK_NEAR(n[voxel_index(o, 4, 4, 4)], 1.5, 1e-6); /* centre (0.125, ...) */
    CHECK_NEAR(n[voxel_index(o, 0, 0, 0)], 1.2, 1e-6); /* keeps the previous layer */
    free(n);
    scene_destroy(s);
}

static void outside_value_replaces_previous_value_outside_the_shape(void)
{
    struct scene *s = parse_ok(OBJ("\"resolution\": 8, \"ior\": [1.1, {\"shape\": \"sphere\", "
                                   "\"radius\": 0.5, \"inside\": 1.5, \"outside\": 1.3}]"));
    if (s == NULL)
        return;
    float *n = eval(s, SCENE_CH_IOR, NULL, NULL);
    const struct scene_object *o = &s->objects[0];
    CHECK_NEAR(n[voxel_index(o, 4, 4, 4)], 1.5, 1e-6);
    CHECK_NEAR(n[voxel_index(o, 0, 0, 0)], 1.3, 1e-6);
    CHECK_NEAR(n[voxel_index(o, 7, 0, 3)], 1.3, 1e-6);
    free(n);
    scene_destroy(s);
}

static void coverage_is_one_half_at_the_surface(void)
{
    /* Voxels are 0.25 wide; the sphere about voxel centre (0.125, 0.125, 0.125) with
     * radius 0.5 passes exactly through the centre of voxel (6, 4, 4). */
    struct scene *s =
        parse_ok(OBJ("\"resolution\": 8, \"ior\": {\"shape\": \"sphere\", \"center\": "
                     "[0.125, 0.125, 0.125], \"radius\": 0.5, \"inside\": 1.5}, "
                     "\"opaque\": {\"shape\": \"sphere\", \"center\": [0.125, 0.125, "
                     "0.125], \"radius\": 0.5, \"inside\": [1, 0.5, 0]}"));
    if (s == NULL)
        return;
    const struct scene_object *o = &s->objects[0];
    float *n = eval(s, SCENE_CH_IOR, NULL, NULL);
    CHECK_NEAR(n[voxel_index(o, 6, 4, 4)], 1.25, 1e-6);
    /* A quarter voxel inside: c = 0.5 + 0.0625 / 0.25 = 0.75. */
    free(n);
    float *op = eval(s, SCENE_CH_OPAQUE, NULL, NULL);
    size_t v = voxel_index(o, 6, 4, 4) * 4;
    CHECK_NEAR(op[v + 0], 0.5, 1e-6);
    CHECK_NEAR(op[v + 1], 0.25, 1e-6);
    CHECK_NEAR(op[v + 3], 0.5, 1e-6); /* coverage */
    v = voxel_index(o, 4, 4, 4) * 4;
    CHECK_NEAR(op[v + 3], 1.0, 1e-6);
    CHECK_NEAR(op[v + 0], 1.0, 1e-6);
    v = voxel_index(o, 0, 0, 0) * 4;
    CHECK_NEAR(op[v + 3], 0.0, 0);
    free(op);
    scene_destroy(s);
}

static void coverage_ramp_is_linear_in_the_signed_distance(void)
{
    /* A box face at x = 0.3 between voxel centres 0.125 and 0.375 (h = 0.25): the
     * centre at 0.375 is 0.075 outside, so c = 0.5 - 0.075 / 0.25 = 0.2. */
    struct scene *s = parse_ok(OBJ("\"resolution\": 8, \"attenuation\": {\"shape\": \"box\", "
                                   "\"center\": [-0.35, 0, 0], \"size\": [1.3, 4, 4], \"inside\": "
                                   "[10, 20, 30]}"));
    if (s == NULL)
        return;
    const struct scene_object *o = &s->objects[0];
    float *a = eval(s, SCENE_CH_ATTENUATION, NULL, NULL);
    size_t v = voxel_index(o, 5, 3, 3) * 4;
    CHECK_NEAR(a[v + 0], 2.0, 1e-5);
    CHECK_NEAR(a[v + 2], 6.0, 1e-5);
    CHECK_NEAR(a[v + 3], 0.0, 0);
    v = voxel_index(o, 4, 3, 3) * 4; /* 0.175 inside: c = 1 */
    CHECK_NEAR(a[v + 1], 20.0, 1e-5);
    free(a);
    scene_destroy(s);
}

/* Evaluates every voxel with scene_shape_sdf directly and compares with the field,
 * which skips voxels along rows: the skip must never change a value. */
static void row_skipping_matches_per_voxel_evaluation(void)
{
    const char *doc = "{\"objects\": [{\"bounds\": {\"min\": [-1, -0.8, -0.6], \"max\": [1.1, 0.9, "
                      "0.7]}, \"resolution\": [37, 29, 23], \"ior\": [1.0,"
                      " {\"shape\": \"sphere\", \"center\": [0.1, 0, 0], \"radius\": 0.55, "
                      "\"inside\": 1.5},"
                      " {\"shape\": \"rounded_box\", \"size\": [1.2, 0.5, 0.9], \"radius\": 0.2, "
                      "\"inside\": 1.4, \"outside\": 1.1},"
                      " {\"shape\": \"cylinder\", \"radius\": 0.2, \"height\": 1.5, \"axis\": "
                      "\"x\", \"inside\": 1.9},"
                      " {\"shape\": \"lathe\", \"base\": [0.3, -0.7, 0], \"profile\": [[0, 0], "
                      "[0.4, 0], [0.1, 0.3], [0.3, 0.9], [0, 1.1]], \"inside\": 1.6},"
                      " {\"shape\": \"text\", \"text\": \"Ag\", \"center\": [-0.4, 0.3, 0.1], "
                      "\"height\": 0.5, \"depth\": 0.3, \"inside\": 2.0}]}]}";
    struct scene *s = parse_ok(doc);
    if (s == NULL)
        return;
    const struct scene_object *o = &s->objects[0];
    float *n = eval(s, SCENE_CH_IOR, NULL, NULL);
    double h = scene_object_min_voxel(o);
    int bad = 0;
    for (int k = 0; k < o->resolution[2]; k++) {
        for (int j = 0; j < o->resolution[1]; j++) {
            for (int i = 0; i < o->resolution[0]; i++) {
                vec3 p = centre(o, i, j, k);
                double v = 1.0;
                for (size_t l = 1; l < o->fields[SCENE_CH_IOR].count; l++) {
                    const struct scene_layer *L = &o->fields[SCENE_CH_IOR].layers[l];
                    double c = fmin(fmax(0.5 - scene_shape_sdf(&L->shape, p) / h, 0), 1);
                    double prev = L->has_outside ? L->outside[0] : v;
                    v = c * L->inside[0] + (1 - c) * prev;
                }
                if (fabs(n[voxel_index(o, i, j, k)] - v) > 1e-5)
                    bad++;
            }
        }
    }
    CHECK_INT(bad, 0);
    free(n);
    scene_destroy(s);
}

static void unused_channels_evaluate_to_their_base_values(void)
{
    struct scene *s = parse_ok("{\"ambient_ior\": 1.33, \"objects\": [{" BOUNDS ", \"resolution\": "
                               "4, \"emission\": 0.5}]}");
    if (s == NULL)
        return;
    const struct scene_object *o = &s->objects[0];
    CHECK(!scene_channel_used(o, SCENE_CH_IOR));
    CHECK(scene_channel_used(o, SCENE_CH_EMISSION));
    float *n = eval(s, SCENE_CH_IOR, NULL, NULL);
    float *a = eval(s, SCENE_CH_ATTENUATION, NULL, NULL);
    float *op = eval(s, SCENE_CH_OPAQUE, NULL, NULL);
    float *em = eval(s, SCENE_CH_EMISSION, NULL, NULL);
    int wrong = 0;
    for (size_t i = 0; i < 64; i++) {
        wrong += fabsf(n[i] - 1.33f) > 1e-6f;
        for (int c = 0; c < 4; c++) {
            wrong += a[i * 4 + c] != 0.0f;
            wrong += op[i * 4 + c] != 0.0f;
            wrong += em[i * 4 + c] != (c < 3 ? 0.5f : 0.0f);
        }
    }
    CHECK_INT(wrong, 0);
    free(n);
    free(a);
    free(op);
    free(em);
    scene_destroy(s);
}

static void constant_opaque_layer_covers_everything(void)
{
    struct scene *s = parse_ok(OBJ("\"resolution\": 2, \"opaque\": [0.5, 0.25, 1]"));
    if (s == NULL)
        return;
    float *op = eval(s, SCENE_CH_OPAQUE, NULL, NULL);
    CHECK_NEAR(op[4 * 7 + 1], 0.25, 0);
    CHECK_NEAR(op[4 * 7 + 3], 1.0, 0);
    free(op);
    scene_destroy(s);
}

static void luneburg_field_matches_grin_ior_at_voxel_centres(void)
{
    struct scene *s = parse_ok("{\"objects\": [{\"bounds\": {\"min\": [-1.05, -1.05, -1.05], "
                               "\"max\": [1.05, 1.05, 1.05]}, \"resolution\": 33, \"ior\": "
                               "{\"profile\": \"luneburg\", \"radius\": 1}}]}");
    if (s == NULL)
        return;
    const struct scene_object *o = &s->objects[0];
    float *n = eval(s, SCENE_CH_IOR, NULL, NULL);
    struct grin_profile g = {.kind = GRIN_LUNEBURG, .radius = 1};
    double worst = 0;
    for (int k = 0; k < 33; k++)
        for (int j = 0; j < 33; j++)
            for (int i = 0; i < 33; i++)
                worst = fmax(worst, fabs(n[voxel_index(o, i, j, k)] -
                                         grin_ior(&g, centre(o, i, j, k), NULL)));
    CHECK_NEAR(worst, 0.0, 1e-6); /* float rounding */
    CHECK_NEAR(n[voxel_index(o, 16, 16, 16)], sqrt(2.0), 1e-6);
    CHECK_NEAR(n[0], 1.0, 0);
    free(n);
    scene_destroy(s);
}

static void profile_layer_overrides_everything_before_it(void)
{
    struct scene *s =
        parse_ok(OBJ("\"resolution\": 8, \"ior\": [{\"shape\": \"sphere\", \"radius\": "
                     "0.5, \"inside\": 3}, {\"profile\": \"linear\", \"n0\": 1.5, "
                     "\"gradient\": [0.25, 0, 0]}]"));
    if (s == NULL)
        return;
    const struct scene_object *o = &s->objects[0];
    float *n = eval(s, SCENE_CH_IOR, NULL, NULL);
    CHECK_NEAR(n[voxel_index(o, 4, 4, 4)], 1.5 + 0.25 * 0.125, 1e-6);
    CHECK_NEAR(n[voxel_index(o, 0, 4, 4)], 1.5 - 0.25 * 0.875, 1e-6);
    free(n);
    scene_destroy(s);
}

/* ---- volumes ---- */

struct volumes {
    const char *names[4];
    const struct scene_volume *vols[4];
    int lookups;
};

static const struct scene_volume *lookup(void *ctx, const char *name)
{
    struct volumes *v = ctx;
    v->lookups++;
    for (int i = 0; i < 4 && v->names[i] != NULL; i++) {
        if (strcmp(v->names[i], name) == 0)
            return v->vols[i];
    }
    return NULL;
}

static void volume_with_the_object_resolution_is_copied_exactly(void)
{
    struct scene *s =
        parse_ok("{\"objects\": [{\"bounds\": {\"min\": [0, 0, 0], \"max\": [3, 2, 1]}, "
                 "\"resolution\": [6, 5, 4], \"ior\": {\"volume\": \"dens\", \"scale\": "
                 "0.5, \"offset\": 1}}]}");
    if (s == NULL)
        return;
    float data[6 * 5 * 4];
    unsigned st = 1;
    for (int i = 0; i < 120; i++)
        data[i] = (float)rnd(&st);
    struct scene_volume vol = {.dims = {6, 5, 4}, .components = 1, .data = data};
    struct volumes ctx = {.names = {"dens"}, .vols = {&vol}};
    float *n = eval(s, SCENE_CH_IOR, lookup, &ctx);
    double worst = 0;
    for (int i = 0; i < 120; i++)
        worst = fmax(worst, fabs(n[i] - (1.0 + 0.5 * data[i])));
    CHECK_NEAR(worst, 0.0, 1e-6);
    free(n);
    scene_destroy(s);
}

static void volume_of_another_resolution_is_interpolated_trilinearly(void)
{
    struct scene *s = parse_ok(OBJ("\"resolution\": [4, 8, 6], \"attenuation\": {\"volume\": "
                                   "\"rgb\"}, \"emission\": {\"volume\": \"grey\"}"));
    if (s == NULL)
        return;
    const struct scene_object *o = &s->objects[0];
    /* rgb: 2 x 3 x 3 voxels whose components are linear in the source index, so
     * trilinear resampling reproduces the linear function wherever it does not clamp. */
    float rgb[2 * 3 * 3 * 3];
    for (int k = 0; k < 3; k++)
        for (int j = 0; j < 3; j++)
            for (int i = 0; i < 2; i++) {
                float *v = &rgb[((k * 3 + j) * 2 + i) * 3];
                v[0] = (float)i;
                v[1] = (float)(2 * j);
                v[2] = (float)(i + j + k);
            }
    float grey[2] = {0.0f, 1.0f};
    struct scene_volume vrgb = {.dims = {2, 3, 3}, .components = 3, .data = rgb};
    struct scene_volume vgrey = {.dims = {2, 1, 1}, .components = 1, .data = grey};
    struct volumes ctx = {.names = {"rgb", "grey"}, .vols = {&vrgb, &vgrey}};
    float *a = eval(s, SCENE_CH_ATTENUATION, lookup, &ctx);
    /* Target voxel i of 4 maps to source x = (i + 0.5) * 2 / 4 - 0.5: clamp(-0.25) = 0,
     * 0.25, 0.75, clamp(1.25) = 1. Along y (8 -> 3): j = 3 -> (3.5) * 3/8 - 0.5 = 0.8125. */
    static const double ex[4] = {0, 0.25, 0.75, 1};
    for (int i = 0; i < 4; i++)
        CHECK_NEAR(a[voxel_index(o, i, 3, 2) * 4], ex[i], 1e-6);
    CHECK_NEAR(a[voxel_index(o, 1, 3, 2) * 4 + 1], 2 * 0.8125, 1e-6);
    /* z: k = 2 of 6 -> 2.5 * 3/6 - 0.5 = 0.75. */
    CHECK_NEAR(a[voxel_index(o, 1, 3, 2) * 4 + 2], 0.25 + 0.8125 + 0.75, 1e-6);
    CHECK_NEAR(a[voxel_index(o, 1, 3, 2) * 4 + 3], 0.0, 0);
    free(a);
    float *em = eval(s, SCENE_CH_EMISSION, lookup, &ctx);
    /* One component is grey: r = g = b. */
    CHECK_NEAR(em[voxel_index(o, 2, 5, 1) * 4 + 0], 0.75, 1e-6);
    CHECK_NEAR(em[voxel_index(o, 2, 5, 1) * 4 + 2], 0.75, 1e-6);
    free(em);
    scene_destroy(s);
}

static void volume_values_are_clamped_to_the_channel_range(void)
{
    struct scene *s =
        parse_ok(OBJ("\"resolution\": 2, \"attenuation\": {\"volume\": \"v\", \"offset\": -5}"));
    if (s == NULL)
        return;
    float data[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    struct scene_volume vol = {.dims = {2, 2, 2}, .components = 1, .data = data};
    struct volumes ctx = {.names = {"v"}, .vols = {&vol}};
    float *a = eval(s, SCENE_CH_ATTENUATION, lookup, &ctx);
    CHECK_NEAR(a[0], 0.0, 0);     /* 1 - 5 clamps to 0 */
    CHECK_NEAR(a[7 * 4], 3.0, 0); /* 8 - 5 */
    free(a);
    scene_destroy(s);
}

static void missing_volume_is_a_conflict_naming_the_upload(void)
{
    struct scene *s = parse_ok(OBJ("\"resolution\": 2, \"ior\": [1.2, {\"volume\": \"density\"}]"));
    if (s == NULL)
        return;
    float out[8];
    struct err e;
    struct volumes ctx = {.names = {NULL}};
    CHECK_INT(scene_field_eval(s, &s->objects[0], SCENE_CH_IOR, lookup, &ctx, out, &e),
              REFRACT_E_CONFLICT);
    CHECK_CONTAINS(e.msg, "objects[0].ior[1]: volume \"density\"");
    CHECK_CONTAINS(e.msg, "PUT /v1/scenes/{id}/volumes/density");
    /* No lookup function at all is the same as nothing uploaded. */
    CHECK_INT(scene_field_eval(s, &s->objects[0], SCENE_CH_IOR, NULL, NULL, out, &e),
              REFRACT_E_CONFLICT);
    scene_destroy(s);
}

static void volume_with_wrong_components_is_a_conflict(void)
{
    struct scene *s = parse_ok(OBJ("\"resolution\": 2, \"ior\": {\"volume\": \"rgb\"}"));
    if (s == NULL)
        return;
    float data[24] = {0};
    struct scene_volume vol = {.dims = {2, 2, 2}, .components = 3, .data = data};
    struct volumes ctx = {.names = {"rgb"}, .vols = {&vol}};
    float out[8];
    struct err e;
    CHECK_INT(scene_field_eval(s, &s->objects[0], SCENE_CH_IOR, lookup, &ctx, out, &e),
              REFRACT_E_CONFLICT);
    CHECK_CONTAINS(e.msg, "objects[0].ior: volume \"rgb\" has 3 components");
    scene_destroy(s);
}

static void missing_volumes_lists_each_missing_name_once(void)
{
    const char *doc =
        "{\"objects\": [{" BOUNDS ", \"resolution\": 2, \"ior\": [{\"volume\": "
        "\"a\"}, {\"volume\": \"b\"}], \"attenuation\": {\"volume\": \"a\"}}, {" BOUNDS
        ", \"resolution\": 2, \"emission\": {\"volume\": \"c\"}, \"opaque\": "
        "{\"volume\": \"d\"}}]}";
    struct scene *s = parse_ok(doc);
    if (s == NULL)
        return;
    float data[8] = {0};
    struct scene_volume vol = {.dims = {2, 2, 2}, .components = 1, .data = data};
    struct volumes ctx = {.names = {"b", "d"}, .vols = {&vol, &vol}};
    char buf[64];
    CHECK_INT(scene_missing_volumes(s, lookup, &ctx, buf, sizeof buf), 2);
    CHECK_STR(buf, "a,c");
    /* A short buffer shortens the list but not the count. */
    char tiny[2];
    CHECK_INT(scene_missing_volumes(s, lookup, &ctx, tiny, sizeof tiny), 2);
    CHECK_STR(tiny, "a");
    CHECK_INT(scene_missing_volumes(s, NULL, NULL, buf, sizeof buf), 4);
    CHECK_STR(buf, "a,b,c,d");
    struct volumes all = {.names = {"a", "b", "c", "d"}, .vols = {&vol, &vol, &vol, &vol}};
    CHECK_INT(scene_missing_volumes(s, lookup, &all, buf, sizeof buf), 0);
    CHECK_STR(buf, "");
    scene_destroy(s);
}

/* ---- voxel sizes and speed ---- */

static void voxel_size_is_extent_over_resolution(void)
{
    struct scene *s =
        parse_ok("{\"objects\": [{\"bounds\": {\"min\": [0, 0, 0], \"max\": [1, 2, 3]}, "
                 "\"resolution\": [10, 40, 20], \"ior\": 1.5}]}");
    if (s == NULL)
        return;
    vec3 vs = scene_object_voxel_size(&s->objects[0]);
    CHECK_NEAR(vs.x, 0.1, 1e-15);
    CHECK_NEAR(vs.y, 0.05, 1e-15);
    CHECK_NEAR(vs.z, 0.15, 1e-15);
    CHECK_NEAR(scene_object_min_voxel(&s->objects[0]), 0.05, 1e-15);
    CHECK_STR(scene_channel_name(SCENE_CH_OPAQUE), "opaque");
    CHECK_INT(scene_channel_components(SCENE_CH_IOR), 1);
    CHECK_INT(scene_channel_components(SCENE_CH_EMISSION), 4);
    scene_destroy(s);
}

static double seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void evaluates_a_128_cubed_glass_block_with_lettering_quickly(void)
{
    const char *doc =
        "{\"objects\": [{\"bounds\": {\"min\": [-1.25, -0.5, -0.5], \"max\": [1.25, 0.5, 0.5]},"
        " \"resolution\": 128,"
        " \"ior\": {\"shape\": \"rounded_box\", \"size\": [2.4, 0.9, 0.9], \"radius\": 0.08,"
        "   \"inside\": 1.5},"
        " \"attenuation\": [{\"shape\": \"rounded_box\", \"size\": [2.4, 0.9, 0.9], \"radius\": "
        "0.08,"
        "   \"inside\": [1.2, 0.25, 0.35]}, {\"shape\": \"text\", \"text\": \"REFRACT\", "
        "\"height\": "
        "0.35, \"depth\": 0.2, \"inside\": [0.2, 0.9, 2.5]}]}]}";
    struct scene *s = parse_ok(doc);
    if (s == NULL)
        return;
    double t0 = seconds();
    float *n = eval(s, SCENE_CH_IOR, NULL, NULL);
    double t1 = seconds();
    float *a = eval(s, SCENE_CH_ATTENUATION, NULL, NULL);
    double t2 = seconds();
    printf("128^3 glass block: ior %.3f s, attenuation (block + text) %.3f s\n", t1 - t0, t2 - t1);
    /* A loose bound that only catches a pathological slowdown (sanitizer builds are
     * several times slower than release ones). */
    CHECK(t2 - t0 < 10.0);
    const struct scene_object *o = &s->objects[0];
    CHECK_NEAR(n[voxel_index(o, 64, 64, 64)], 1.5, 1e-6);
    CHECK_NEAR(n[voxel_index(o, 0, 0, 0)], 1.0, 1e-6);
    free(n);
    free(a);
    scene_destroy(s);
}

int main(void)
{
    sphere_sdf_is_distance_to_centre_minus_radius();
    box_sdf_matches_face_edge_and_corner_distances();
    rounded_box_sdf_matches_its_corner_spheres();
    cylinder_sdf_matches_side_cap_and_rim();
    lathe_of_a_rectangle_equals_a_cylinder();
    lathe_of_an_offset_rectangle_equals_an_annulus();
    text_lit_pixel_centre_is_inside_and_spacing_column_outside();
    text_i_and_period_differ_at_the_top_centre();
    font_has_a_glyph_for_every_printable_character_but_space();
    text_sdf_is_exact_against_brute_force();
    text_of_spaces_is_empty();
    shape_bounds_contain_the_solid();
    later_layers_override_earlier_ones();
    shape_layer_blends_inside_over_previous_value();
    outside_value_replaces_previous_value_outside_the_shape();
    coverage_is_one_half_at_the_surface();
    coverage_ramp_is_linear_in_the_signed_distance();
    row_skipping_matches_per_voxel_evaluation();
    unused_channels_evaluate_to_their_base_values();
    constant_opaque_layer_covers_everything();
    luneburg_field_matches_grin_ior_at_voxel_centres();
    profile_layer_overrides_everything_before_it();
    volume_with_the_object_resolution_is_copied_exactly();
    volume_of_another_resolution_is_interpolated_trilinearly();
    volume_values_are_clamped_to_the_channel_range();
    missing_volume_is_a_conflict_naming_the_upload();
    volume_with_wrong_components_is_a_conflict();
    missing_volumes_lists_each_missing_name_once();
    voxel_size_is_extent_over_resolution();
    evaluates_a_128_cubed_glass_block_with_lettering_quickly();
    return test_summary("test_scene_field");
}
