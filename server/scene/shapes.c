/*
 * shapes.c - exact signed distance functions of the procedural shapes, and their
 * bounding boxes.
 *
 * Every function returns the Euclidean distance from p to the shape's surface, negative
 * inside, in the object-space units of the owning object. Exactness matters twice: the
 * anti-aliased coverage of a shape layer is 0.5 - sdf / h_min (docs/scenes.md), and
 * scene_field.c skips voxels along a row by the 1-Lipschitz bound |sdf(p) - sdf(q)| <=
 * |p - q|, which only holds for true distances. A lower bound would do for the skip but
 * would blur the boundary, so nothing here returns one.
 *
 * Not here: parsing (scene_parse_field.c) and voxel evaluation (scene_field.c).
 */
#include "scene.h"

#include <float.h>
#include <math.h>

#include "font5x7.h"

/* Inside/outside combination of per-axis signed excesses q (the box formula): exact
 * for any shape that is the intersection of slabs and extrusions. */
static double combine2(double a, double b)
{
    double oa = fmax(a, 0.0), ob = fmax(b, 0.0);
    return fmin(fmax(a, b), 0.0) + sqrt(oa * oa + ob * ob);
}

static double box_sdf(vec3 d, vec3 half)
{
    vec3 q = {fabs(d.x) - half.x, fabs(d.y) - half.y, fabs(d.z) - half.z};
    vec3 o = {fmax(q.x, 0.0), fmax(q.y, 0.0), fmax(q.z, 0.0)};
    return vec3_length(o) + fmin(fmax(q.x, fmax(q.y, q.z)), 0.0);
}

/* Splits d into the coordinate along axis and the distance from the axis line. */
static void axial(vec3 d, int axis, double *h, double *r)
{
    double a = axis == 0 ? d.y : d.x;
    double b = axis == 2 ? d.y : d.z;
    *h = vec3_get(d, axis);
    *r = sqrt(a * a + b * b);
}

/* ---- lathe: a closed polygon in the (r, h) half-plane, revolved about the axis ----
 *
 * For a solid of revolution the nearest surface point lies in the meridian half-plane
 * through p, so the 3D distance is the 2D distance from (r, h) to the polygon. Edges on
 * the axis itself (r = 0 at both ends) are not surfaces after revolving, so they are
 * left out of the distance but still count for the even-odd inside test (where a point
 * on the axis never crosses them: the test ray runs towards +r).
 */
static double lathe_sdf(const struct scene_shape *s, vec3 p)
{
    double h, r;
    axial(vec3_sub(p, s->base), s->axis, &h, &r);
    const double(*pt)[2] = (const double(*)[2])s->profile;
    size_t n = s->profile_count;
    double best2 = INFINITY;
    bool inside = false;
    for (size_t i = 0, j = n - 1; i < n; j = i++) {
        double ar = pt[j][0], ah = pt[j][1], br = pt[i][0], bh = pt[i][1];
        if ((ah > h) != (bh > h)) {
            double rx = ar + (h - ah) * (br - ar) / (bh - ah);
            if (r < rx)
                inside = !inside;
        }
        if (ar == 0.0 && br == 0.0)
            continue;
        double er = br - ar, eh = bh - ah, pr = r - ar, ph = h - ah;
        double len2 = er * er + eh * eh;
        double t = len2 > 0.0 ? fmin(fmax((pr * er + ph * eh) / len2, 0.0), 1.0) : 0.0;
        double dr = pr - t * er, dh = ph - t * eh;
        double d2 = dr * dr + dh * dh;
        if (d2 < best2)
            best2 = d2;
    }
    double d = sqrt(best2);
    return inside ? -d : d;
}

/* ---- text: lit pixels of the 5x7 font, extruded along z ----
 *
 * Layout (pixel units, v up): the block is W = cells * 6 - 1 columns by 7 rows, its
 * lower-left corner at center - (W, 7) * pixel / 2. Column c belongs to character c / 6
 * (glyph column c % 6; column 5 is spacing); pixel row v = 0 is the glyph's bottom row.
 *
 * The 2D distance is exact on both sides: outside, the distance to the nearest lit
 * pixel square; inside, minus the distance to the nearest unlit square, where all of
 * the plane outside the block counts as unlit. Columns are visited outwards from the
 * point and the search stops once a column's horizontal gap alone exceeds the best so
 * far, so a query costs a few columns, not the whole string.
 */
struct text_layout {
    const char *text;
    int columns; /* W */
    double pixel;
    double u, v; /* the point, in pixel units from the block's lower-left corner */
};

/* Lit rows of column c as a bit mask with bit 0 = bottom row (v in [0, 1)). */
static unsigned column_mask(const struct text_layout *t, int c)
{
    if (c < 0 || c >= t->columns)
        return 0;
    unsigned top_down =
        scene_font5x7_column((unsigned char)t->text[c / FONT5X7_CELL_COLS], c % FONT5X7_CELL_COLS);
    unsigned up = 0;
    for (int row = 0; row < FONT5X7_ROWS; row++) {
        if ((top_down >> row) & 1u)
            up |= 1u << (FONT5X7_ROWS - 1 - row);
    }
    return up;
}

static double gap(double x, double lo, double hi)
{
    return fmax(fmax(lo - x, 0.0), x - hi);
}

/* Vertical distance from v to the nearest row in `rows` (bit k = [k, k+1)), where bits
 * 7 and 8 stand for the half-planes below 0 and above 7 when `with_outside`. */
static double row_gap(unsigned rows, double v, bool with_outside)
{
    double best = INFINITY;
    for (int k = 0; k < FONT5X7_ROWS; k++) {
        if ((rows >> k) & 1u)
            best = fmin(best, gap(v, k, k + 1));
    }
    if (with_outside)
        best = fmin(best, fmin(fmax(v, 0.0), fmax(FONT5X7_ROWS - v, 0.0)));
    return best;
}

/* Distance in pixels from (u, v) to the nearest square of the kind asked for: lit
 * squares, or unlit ones (including everything outside the block). */
static double text_nearest(const struct text_layout *t, bool want_lit)
{
    /* Start in the block's column nearest to u (clamped in double before the cast). */
    int start = (int)fmin(fmax(floor(t->u), 0.0), (double)(t->columns - 1));
    double best = INFINITY;
    for (int dir = -1; dir <= 1; dir += 2) {
        for (int c = dir < 0 ? start : start + 1;; c += dir) {
            double dx = gap(t->u, c, c + 1);
            if (dx >= best)
                break;
            double dy;
            if (want_lit) {
                if (c < 0 || c >= t->columns)
                    break;
                dy = row_gap(column_mask(t, c), t->v, false);
            } else if (c < 0 || c >= t->columns) {
                dy = 0.0; /* the whole column outside the block is unlit */
            } else {
                dy = row_gap(~column_mask(t, c) & 0x7fu, t->v, true);
            }
            if (dy < INFINITY)
                best = fmin(best, sqrt(dx * dx + dy * dy));
            if (!want_lit && (c < 0 || c >= t->columns))
                break;
        }
    }
    return best;
}

static struct text_layout text_layout(const struct scene_shape *s, vec3 p)
{
    struct text_layout t = {.text = s->text, .pixel = s->height / FONT5X7_ROWS};
    size_t cells = 0;
    while (s->text[cells] != '\0')
        cells++;
    t.columns = (int)cells * FONT5X7_CELL_COLS - 1;
    double x0 = s->center.x - 0.5 * t.columns * t.pixel;
    double y0 = s->center.y - 0.5 * FONT5X7_ROWS * t.pixel;
    t.u = (p.x - x0) / t.pixel;
    t.v = (p.y - y0) / t.pixel;
    return t;
}

static bool text_lit_at(const struct text_layout *t)
{
    double cu = floor(t->u), cv = floor(t->v);
    if (cu < 0 || cu >= t->columns || cv < 0 || cv >= FONT5X7_ROWS)
        return false;
    return (column_mask(t, (int)cu) >> (int)cv) & 1u;
}

static double text_sdf(const struct scene_shape *s, vec3 p)
{
    struct text_layout t = text_layout(s, p);
    double d2;
    if (text_lit_at(&t))
        d2 = -text_nearest(&t, false) * t.pixel;
    else
        d2 = text_nearest(&t, true) * t.pixel;
    if (isinf(d2))
        return INFINITY; /* no lit pixel at all: the solid is empty */
    double dz = fabs(p.z - s->center.z) - 0.5 * s->depth;
    return combine2(d2, dz);
}

/* r(theta, phi) = R + a sin(f theta) sin(f phi), theta the polar angle from +y, phi the
 * azimuth about y: a hard case for caustics, its cusps (tevs2007 sect. 6.2.4).
 *
 * With g(p) = |d| - r(theta, phi), the value is the first-order distance estimate
 * g / |grad g|, |grad g|^2 = 1 + (dr/dtheta / |d|)^2 + (dr/dphi / (|d| sin theta))^2: close
 * to the true distance near the surface wherever it tilts, so the anti-aliased boundary
 * stays about one voxel wide. It is not a bound on the distance far from the surface
 * (scene_field.c therefore evaluates this shape at every voxel rather than skipping runs),
 * but its sign is exact, and outside the shell R - a <= |d| <= R + a that holds the surface
 * the exact distances to the shell take over, so deep inside reads as inside. */
static double bumpy_sphere_sdf(const struct scene_shape *s, vec3 d)
{
    double len = vec3_length(d);
    double inner = len - (s->radius - s->bump_amplitude),
           outer = len - (s->radius + s->bump_amplitude);
    if (len < 1e-12)
        return inner;
    double theta = acos(fmax(-1.0, fmin(1.0, d.y / len)));
    double phi = atan2(d.z, d.x);
    double f = (double)s->bump_frequency, a = s->bump_amplitude;
    double st = sin(f * theta), sp = sin(f * phi);
    double g = len - (s->radius + a * st * sp);
    double dr_dtheta = a * f * cos(f * theta) * sp;
    double sin_theta = sin(theta);
    /* sin(f theta) / sin(theta) -> f at the poles */
    double ratio = sin_theta > 1e-9 ? st / sin_theta : f;
    double dr_dphi_over_sin = a * f * ratio * cos(f * phi);
    double grad2 =
        1.0 + (dr_dtheta * dr_dtheta + dr_dphi_over_sin * dr_dphi_over_sin) / (len * len);
    double est = g / sqrt(grad2);
    return g < 0.0 ? fmin(est, inner) : fmax(est, outer);
}

double scene_shape_sdf(const struct scene_shape *s, vec3 p)
{
    vec3 d = vec3_sub(p, s->center);
    switch (s->kind) {
    case SCENE_SHAPE_PLANE:
        return vec3_dot(d, s->normal); /* surfaces only: the half-space behind the normal */
    case SCENE_SHAPE_SPHERE:
        return vec3_length(d) - s->radius;
    case SCENE_SHAPE_BOX:
        return box_sdf(d, vec3_scale(s->size, 0.5));
    case SCENE_SHAPE_ROUNDED_BOX: {
        /* A box shrunk by the radius, then dilated by it (exact for rounded boxes). */
        vec3 half = vec3_sub(vec3_scale(s->size, 0.5), vec3_make(s->radius, s->radius, s->radius));
        return box_sdf(d, half) - s->radius;
    }
    case SCENE_SHAPE_CYLINDER: {
        double h, r;
        axial(d, s->axis, &h, &r);
        return combine2(r - s->radius, fabs(h) - 0.5 * s->height);
    }
    case SCENE_SHAPE_LATHE:
        return lathe_sdf(s, p);
    case SCENE_SHAPE_TEXT:
        return text_sdf(s, p);
    case SCENE_SHAPE_BUMPY_SPHERE:
        return bumpy_sphere_sdf(s, d);
    case SCENE_SHAPE_MESH:
        break; /* an upload: voxelized by scene_field.c */
    }
    return INFINITY;
}

static void lathe_bounds(const struct scene_shape *s, vec3 *lo, vec3 *hi)
{
    double rmax = 0.0, hmin = INFINITY, hmax = -INFINITY;
    for (size_t i = 0; i < s->profile_count; i++) {
        rmax = fmax(rmax, s->profile[i][0]);
        hmin = fmin(hmin, s->profile[i][1]);
        hmax = fmax(hmax, s->profile[i][1]);
    }
    *lo = vec3_sub(s->base, vec3_make(rmax, rmax, rmax));
    *hi = vec3_add(s->base, vec3_make(rmax, rmax, rmax));
    vec3_set(lo, s->axis, vec3_get(s->base, s->axis) + hmin);
    vec3_set(hi, s->axis, vec3_get(s->base, s->axis) + hmax);
}

/* The box of the text's lit columns only, so a string with leading or trailing spaces
 * does not widen the region that field evaluation visits. */
static bool text_bounds(const struct scene_shape *s, vec3 *lo, vec3 *hi)
{
    struct text_layout t = text_layout(s, s->center);
    int first = -1, last = -1;
    for (int c = 0; c < t.columns; c++) {
        if (column_mask(&t, c) != 0) {
            if (first < 0)
                first = c;
            last = c;
        }
    }
    if (first < 0)
        return false;
    double x0 = s->center.x - 0.5 * t.columns * t.pixel;
    double half_h = 0.5 * FONT5X7_ROWS * t.pixel;
    *lo = vec3_make(x0 + first * t.pixel, s->center.y - half_h, s->center.z - 0.5 * s->depth);
    *hi = vec3_make(x0 + (last + 1) * t.pixel, s->center.y + half_h, s->center.z + 0.5 * s->depth);
    return true;
}

bool scene_shape_bounds(const struct scene_shape *s, vec3 *lo, vec3 *hi)
{
    vec3 half;
    switch (s->kind) {
    case SCENE_SHAPE_SPHERE:
        half = vec3_make(s->radius, s->radius, s->radius);
        break;
    case SCENE_SHAPE_BUMPY_SPHERE: {
        double r = s->radius + s->bump_amplitude;
        half = vec3_make(r, r, r);
        break;
    }
    case SCENE_SHAPE_BOX:
    case SCENE_SHAPE_ROUNDED_BOX:
        half = vec3_scale(s->size, 0.5);
        break;
    case SCENE_SHAPE_CYLINDER:
        half = vec3_make(s->radius, s->radius, s->radius);
        vec3_set(&half, s->axis, 0.5 * s->height);
        break;
    case SCENE_SHAPE_LATHE:
        lathe_bounds(s, lo, hi);
        return true;
    case SCENE_SHAPE_TEXT:
        return text_bounds(s, lo, hi);
    default:
        return false;
    }
    *lo = vec3_sub(s->center, half);
    *hi = vec3_add(s->center, half);
    return true;
}
