/*
 * lathe.c - the exact solid of revolution of a profile polygon (geom.h). Twin:
 * shaders/geom/lathe.glsl.
 *
 * In the frame of the axis a point has height h (along the axis from base) and radius
 * rho (distance from the axis). An edge (r0, h0) -> (r1, h1) of the profile sweeps
 *   - a cone frustum when h0 != h1: rho = r0 + k (h - h0), k = (r1 - r0) / (h1 - h0).
 *     Along the ray h and rho's square are polynomials of t, so rho^2 = (r0 + k (h - h0))^2
 *     is a quadratic in t; a root counts when h lies on the edge and r0 + k (h - h0) >= 0
 *     (the other nappe of the cone is not part of the surface);
 *   - an annulus when h0 == h1: the plane h = h0 between the two radii.
 * The outward normal of an edge in the (rho, h) half-plane is (dh, -dr) for a
 * counter-clockwise polygon (the profile's orientation is read from its signed area),
 * carried into 3D along the radial and axis directions. prim is the edge index.
 */
#include <math.h>

#include "geom.h"

double lathe_orientation(const double (*pts)[2], size_t count)
{
    double area2 = 0.0;
    for (size_t i = 0; i < count; i++) {
        const double *a = pts[i], *b = pts[(i + 1) % count];
        area2 += a[0] * b[1] - b[0] * a[1];
    }
    return area2 >= 0.0 ? 1.0 : -1.0;
}

void lathe_extent(const double (*pts)[2], size_t count, double *r_max, double *h_lo, double *h_hi)
{
    *r_max = 0.0;
    *h_lo = INFINITY;
    *h_hi = -INFINITY;
    for (size_t i = 0; i < count; i++) {
        *r_max = fmax(*r_max, pts[i][0]);
        *h_lo = fmin(*h_lo, pts[i][1]);
        *h_hi = fmax(*h_hi, pts[i][1]);
    }
}

/* The 3D outward normal at (x, y) across the axis and the edge's (n_r, n_h). */
static vec3 edge_normal(int axis, double x, double y, double n_r, double n_h)
{
    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    double rho = sqrt(x * x + y * y);
    vec3 n = vec3_make(0, 0, 0);
    if (rho > 0.0) {
        vec3_set(&n, a1, n_r * x / rho);
        vec3_set(&n, a2, n_r * y / rho);
    }
    vec3_set(&n, axis, n_h);
    return vec3_normalize(n);
}

/* The heights h(t) = oh + t dh that the ray spans while inside the cylinder rho <= r_max,
 * h_lo <= h <= h_hi and tmin < t < tmax, widened by a relative margin for rounding; false
 * when the ray misses that cylinder. */
static bool lathe_span(double ox, double oy, double oh, double dx, double dy, double dh,
                       double r_max, double h_lo, double h_hi, double tmin, double tmax,
                       double *span_lo, double *span_hi)
{
    double margin = 1e-9 * (r_max + fabs(h_lo) + fabs(h_hi));
    double r = r_max + margin;
    double t0 = tmin, t1 = tmax;
    double A = dx * dx + dy * dy;
    if (A > 0.0) {
        double b = (ox * dx + oy * dy) / A;
        double fx = ox - b * dx, fy = oy - b * dy;
        double disc = (r * r - (fx * fx + fy * fy)) / A;
        if (disc < 0.0)
            return false;
        double q = sqrt(disc);
        t0 = fmax(t0, -b - q);
        t1 = fmin(t1, -b + q);
    } else if (ox * ox + oy * oy > r * r) {
        return false;
    }
    if (dh != 0.0) {
        double ta = (h_lo - margin - oh) / dh, tb = (h_hi + margin - oh) / dh;
        t0 = fmax(t0, fmin(ta, tb));
        t1 = fmin(t1, fmax(ta, tb));
    } else if (oh < h_lo - margin || oh > h_hi + margin) {
        return false;
    }
    if (t0 > t1)
        return false;
    double ha = oh + t0 * dh, hb = oh + t1 * dh;
    if (!isfinite(ha) || !isfinite(hb)) { /* an unbounded t range along the axis */
        *span_lo = h_lo - margin;
        *span_hi = h_hi + margin;
        return true;
    }
    *span_lo = fmin(ha, hb) - margin;
    *span_hi = fmax(ha, hb) + margin;
    return true;
}

bool lathe_intersect(vec3 base, int axis, const double (*pts)[2], size_t count, vec3 o, vec3 d,
                     double tmin, double tmax, struct geom_hit *h)
{
    int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
    vec3 v = vec3_sub(o, base);
    double ox = vec3_get(v, a1), oy = vec3_get(v, a2), oh = vec3_get(v, axis);
    double dx = vec3_get(d, a1), dy = vec3_get(d, a2), dh = vec3_get(d, axis);
    double sgn = lathe_orientation(pts, count);
    double best = tmax;
    /* Cull: the part of the ray inside the bounding cylinder (radius r_max, heights
     * h_min..h_max) and the heights it spans there; edges outside those heights cannot be
     * met (the GLSL twin does the same with the bounds packed in surface_params). */
    double r_max, h_lo, h_hi;
    lathe_extent(pts, count, &r_max, &h_lo, &h_hi);
    double span_lo, span_hi;
    if (!lathe_span(ox, oy, oh, dx, dy, dh, r_max, h_lo, h_hi, tmin, tmax, &span_lo, &span_hi))
        return false;
    for (size_t i = 0; i < count; i++) {
        const double *p0 = pts[i], *p1 = pts[(i + 1) % count];
        double r0 = p0[0], h0 = p0[1], r1 = p1[0], h1 = p1[1];
        if (fmax(h0, h1) < span_lo || fmin(h0, h1) > span_hi)
            continue;
        double er = r1 - r0, eh = h1 - h0;
        double n_r = sgn * eh, n_h = -sgn * er;
        if (r0 == 0.0 && r1 == 0.0)
            continue; /* on the axis: sweeps no surface */
        if (eh == 0.0) {
            if (dh == 0.0)
                continue;
            double t = (h0 - oh) / dh;
            double x = ox + t * dx, y = oy + t * dy, rr = x * x + y * y;
            double lo = fmin(r0, r1), hi = fmax(r0, r1);
            if (rr >= lo * lo && rr <= hi * hi)
                geom_hit_consider(t, tmin, &best, edge_normal(axis, x, y, 0.0, n_h), (int64_t)i, h);
            continue;
        }
        double k = er / eh;
        double alpha = r0 + k * (oh - h0), beta = k * dh;
        double A = dx * dx + dy * dy - beta * beta;
        double B = ox * dx + oy * dy - alpha * beta;
        double C = ox * ox + oy * oy - alpha * alpha;
        double roots[2];
        int nroots = 0;
        if (fabs(A) < 1e-300) {
            if (B != 0.0)
                roots[nroots++] = -C / (2.0 * B);
        } else {
            double disc = B * B - A * C;
            if (disc < 0.0)
                continue;
            double q = -B - copysign(sqrt(disc), B);
            roots[nroots++] = q / A;
            if (q != 0.0)
                roots[nroots++] = C / q;
        }
        for (int j = 0; j < nroots; j++) {
            double t = roots[j];
            double hh = oh + t * dh;
            double s = (hh - h0) / eh;
            if (s < 0.0 || s > 1.0 || alpha + beta * t < 0.0)
                continue;
            geom_hit_consider(t, tmin, &best, edge_normal(axis, ox + t * dx, oy + t * dy, n_r, n_h),
                              (int64_t)i, h);
        }
    }
    return best < tmax;
}

bool lathe_inside(vec3 base, int axis, const double (*pts)[2], size_t count, vec3 p)
{
    vec3 v = vec3_sub(p, base);
    double x = vec3_get(v, (axis + 1) % 3), y = vec3_get(v, (axis + 2) % 3);
    double rho = sqrt(x * x + y * y), hh = vec3_get(v, axis);
    bool in = false; /* crossing number of the ray from (rho, hh) towards +r */
    for (size_t i = 0, j = count - 1; i < count; j = i++) {
        const double *a = pts[i], *b = pts[j];
        if ((a[1] > hh) != (b[1] > hh) && rho < (b[0] - a[0]) * (hh - a[1]) / (b[1] - a[1]) + a[0])
            in = !in;
    }
    return in;
}

void lathe_bounds(vec3 base, int axis, const double (*pts)[2], size_t count, vec3 *lo, vec3 *hi)
{
    double rmax, hmin, hmax;
    lathe_extent(pts, count, &rmax, &hmin, &hmax);
    *lo = vec3_make(base.x - rmax, base.y - rmax, base.z - rmax);
    *hi = vec3_make(base.x + rmax, base.y + rmax, base.z + rmax);
    vec3_set(lo, axis, vec3_get(base, axis) + hmin);
    vec3_set(hi, axis, vec3_get(base, axis) + hmax);
}
