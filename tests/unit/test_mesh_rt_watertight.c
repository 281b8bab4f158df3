/*
 * test_mesh_rt_watertight.c - no ray leaks through a closed mesh (Woop et al. 2013):
 * 1,000,000 rays aimed exactly at the vertices, at edge midpoints and at points along the
 * edges of a closed icosphere (s = 5) and of a closed box whose coordinates, aim points
 * and ray origins are all exact binary fractions (so rays really pass through vertices
 * and edges). Every ray whose line crosses the solid's interior must report an entry hit
 * and then, continuing from it (tmin = t, skip_tri = its triangle), an exit: a hit whose
 * geometric normal faces along the ray (the ray leaves the outward-wound solid). Hits at
 * the entry point on the other triangles sharing its vertex or edge are stepped over (at
 * most 16). Rays that only graze the solid (an uncertain margin around its silhouette)
 * are not counted.
 */
#include "mesh_rt_test_util.h"
#include "test.h"

struct leaks {
    long rays, counted, no_entry, no_exit, wrong_entry, extra_steps;
};

/* Entry and exit of the ray o + t d, counted in l. */
static void trace_through(const struct mesh *m, vec3 o, vec3 d, struct leaks *l)
{
    l->counted++;
    struct mesh_rt_hit h;
    if (!mesh_rt_intersect(m->rt, o, d, 0.0, INFINITY, -1, &h)) {
        l->no_entry++;
        return;
    }
    if (vec3_dot(h.n_geom, d) > 0.0)
        l->wrong_entry++; /* entered through a back face: a front face was missed */
    for (int step = 0; step < 16; step++) {
        struct mesh_rt_hit next;
        if (!mesh_rt_intersect(m->rt, o, d, h.t, INFINITY, h.tri, &next)) {
            l->no_exit++;
            return;
        }
        if (vec3_dot(next.n_geom, d) > 0.0)
            return; /* left */
        l->extra_steps++;
        h = next;
    }
    l->no_exit++;
}

/* Icosphere of radius R about the origin: a line crosses the interior surely when it
 * passes nearer to the centre than the inscribed ball (radius R cos(max facet angle)),
 * and never when further than R; between, it is not counted. */
static void icosphere_rays(long n, struct leaks *l)
{
    struct mesh *m = NULL;
    struct err e = {0};
    CHECK_INT(mesh_make_icosphere(5, 1.0, &m, &e), REFRACT_E_OK);
    if (m == NULL)
        return;
    double r_in = 1.0;
    for (size_t t = 0; t < m->triangle_count; t++) { /* distance of each face plane */
        const double *a = m->vertices[m->triangles[t][0]];
        vec3 nrm =
            vec3_normalize(vec3_cross(vec3_sub(rt_v3(m->vertices[m->triangles[t][1]]), rt_v3(a)),
                                      vec3_sub(rt_v3(m->vertices[m->triangles[t][2]]), rt_v3(a))));
        r_in = fmin(r_in, vec3_dot(nrm, rt_v3(a)));
    }
    struct rt_rng r = {2024};
    for (long i = 0; i < n; i++) {
        vec3 o = vec3_scale(rt_unit(&r), 1.5 + 2.0 * rt_uniform(&r));
        size_t tri = (size_t)(rt_uniform(&r) * (double)m->triangle_count);
        const uint32_t *t = m->triangles[tri];
        vec3 a = rt_v3(m->vertices[t[0]]), b = rt_v3(m->vertices[t[1]]);
        vec3 target;
        switch (i % 3) {
        case 0: /* a vertex, exactly */
            target = a;
            break;
        case 1: /* an edge's midpoint (rounded: on either side of the edge by an ulp) */
            target = vec3_scale(vec3_add(a, b), 0.5);
            break;
        default: /* along an edge */
            target = vec3_madd(a, vec3_sub(b, a), rt_uniform(&r));
            break;
        }
        vec3 d = vec3_sub(target, o);
        l->rays++;
        /* distance of the line from the centre */
        double dist = vec3_length(vec3_cross(o, vec3_normalize(d)));
        if (dist < r_in * (1.0 - 1e-9))
            trace_through(m, o, d, l);
    }
    mesh_destroy(m);
}

/* The line's interior interval in the box [-h, h]^3: true when it crosses the interior
 * by more than a hair (a line along a face or an edge, or through a corner only, is not
 * counted). */
static bool crosses_box(vec3 o, vec3 d, double h)
{
    double t0 = -INFINITY, t1 = INFINITY;
    double ov[3] = {o.x, o.y, o.z}, dv[3] = {d.x, d.y, d.z};
    for (int k = 0; k < 3; k++) {
        if (dv[k] == 0.0) {
            if (!(ov[k] > -h && ov[k] < h))
                return false;
            continue;
        }
        double a = (-h - ov[k]) / dv[k], b = (h - ov[k]) / dv[k];
        t0 = fmax(t0, fmin(a, b));
        t1 = fmin(t1, fmax(a, b));
    }
    return t1 - t0 > 1e-9 * (t1 > 0 ? t1 : 1.0);
}

static double dyadic(struct rt_rng *r, double lo, double hi, int bits)
{
    double steps = ldexp(1.0, bits);
    return lo + floor(rt_uniform(r) * (hi - lo) * steps) / steps;
}

static void box_rays(long n, struct leaks *l)
{
    const double h = 1.0;
    struct mesh *m = rt_box_mesh(h);
    CHECK(m != NULL);
    if (m == NULL)
        return;
    struct rt_rng r = {7};
    for (long i = 0; i < n; i++) {
        vec3 o;
        do { /* a dyadic origin outside the box */
            o = vec3_make(dyadic(&r, -4, 4, 6), dyadic(&r, -4, 4, 6), dyadic(&r, -4, 4, 6));
        } while (fabs(o.x) <= h && fabs(o.y) <= h && fabs(o.z) <= h);
        /* a corner, a point on an edge or on a face diagonal (the edges shared by the two
         * triangles of a face), in steps of 1/64: all exact */
        int axis = (int)(rt_uniform(&r) * 3);
        double s = dyadic(&r, -h, h, 6);
        vec3 c = vec3_make(rt_uniform(&r) < 0.5 ? -h : h, rt_uniform(&r) < 0.5 ? -h : h,
                           rt_uniform(&r) < 0.5 ? -h : h);
        vec3 target = c;
        switch (i % 3) {
        case 0: /* a corner */
            break;
        case 1: /* an edge of the box along axis */
            vec3_set(&target, axis, s);
            break;
        default: { /* the diagonal of a face normal to axis (it runs from the face's
                      lowest corner to its highest, mesh_rt_test_util.h) */
            int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
            vec3_set(&target, a1, s);
            vec3_set(&target, a2, s);
            break;
        }
        }
        vec3 d = vec3_sub(target, o);
        l->rays++;
        if (crosses_box(o, d, h))
            trace_through(m, o, d, l);
    }
    mesh_destroy(m);
}

static void report(const char *name, const struct leaks *l)
{
    printf("%-10s %8ld rays, %8ld cross the interior: %ld without entry, %ld without exit, "
           "%ld entered by a back face; %ld hits stepped over at a shared vertex or edge\n",
           name, l->rays, l->counted, l->no_entry, l->no_exit, l->wrong_entry, l->extra_steps);
    CHECK(l->counted > l->rays / 2); /* most rays test something */
    CHECK_INT(l->no_entry, 0);
    CHECK_INT(l->no_exit, 0);
    CHECK_INT(l->wrong_entry, 0);
}

int main(void)
{
    struct leaks ico = {0}, box = {0};
    icosphere_rays(500000, &ico);
    report("icosphere", &ico);
    box_rays(500000, &box);
    report("box", &box);
    return test_summary("test_mesh_rt_watertight");
}
