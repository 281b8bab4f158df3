/*
 * test_mesh_rt_trace.c - mesh_rt_intersect (double) against brute force over every
 * triangle (Moller-Trumbore, mesh_rt_test_util.h) on random rays at an icosphere, a random
 * triangle soup and a box: the same nearest t to 1e-12 relative (to the mesh's size for
 * hits within 1% of it from the origin) and the same triangle
 * (or a tie at the same t); skip_tri, tmin and tmax select what they say; the hit's
 * barycentrics rebuild the hit point, its geometric normal is the triangle's unit
 * normal, and on a sphere the shading normals are closer to the true normal than the
 * facets'.
 */
#include "mesh_rt_test_util.h"
#include "test.h"

struct stats {
    int rays, hits, mismatch_hit, mismatch_t, mismatch_tri, ties, bad_skip, bad_next, bad_tmax;
    int bad_bary, bad_normal;
    double worst_rel_t;
    double scale; /* the mesh's bounding box diagonal */
};

static vec3 tri_normal(const struct mesh *m, uint32_t t)
{
    const double *a = m->vertices[m->triangles[t][0]], *b = m->vertices[m->triangles[t][1]],
                 *c = m->vertices[m->triangles[t][2]];
    return vec3_normalize(vec3_cross(vec3_make(b[0] - a[0], b[1] - a[1], b[2] - a[2]),
                                     vec3_make(c[0] - a[0], c[1] - a[1], c[2] - a[2])));
}

/* The same hit or none: t to 1e-12 relative, the same triangle unless both are hit at
 * that t (a tie across an edge). */
static bool same(const struct mesh *m, bool hit, const struct mesh_rt_hit *h, double tb,
                 uint32_t tri_b, vec3 o, vec3 d, struct stats *s)
{
    if (hit != (tb >= 0.0)) {
        s->mismatch_hit++;
        return false;
    }
    if (!hit)
        return true;
    /* relative to t, or for hits nearer than 1% of the mesh's size to the origin (whose
     * position alone carries rounding of that size), to that distance */
    double rel = fabs(h->t - tb) / fmax(tb, 0.01 * s->scale / vec3_length(d));
    s->worst_rel_t = fmax(s->worst_rel_t, rel);
    if (rel > 1e-12) {
        s->mismatch_t++;
        return false;
    }
    if (h->tri != tri_b) {
        const uint32_t *t = m->triangles[h->tri];
        double th = rt_mt(o, d, m->vertices[t[0]], m->vertices[t[1]], m->vertices[t[2]]);
        if (fabs(th - tb) <= 1e-12 * tb) {
            s->ties++;
            return true;
        }
        s->mismatch_tri++;
        return false;
    }
    return true;
}

static void check_hit_geometry(const struct mesh *m, vec3 o, vec3 d, const struct mesh_rt_hit *h,
                               double scale, struct stats *s)
{
    const uint32_t *t = m->triangles[h->tri];
    double b0 = 1.0 - h->b1 - h->b2;
    vec3 p = vec3_madd(o, d, h->t);
    vec3 q = vec3_add(vec3_add(vec3_scale(rt_v3(m->vertices[t[0]]), b0),
                               vec3_scale(rt_v3(m->vertices[t[1]]), h->b1)),
                      vec3_scale(rt_v3(m->vertices[t[2]]), h->b2));
    if (vec3_length(vec3_sub(p, q)) > 1e-10 * scale || h->b1 < -1e-12 || h->b2 < -1e-12 ||
        b0 < -1e-12)
        s->bad_bary++;
    if (fabs(vec3_length(h->n_geom) - 1.0) > 1e-12 ||
        vec3_dot(h->n_geom, tri_normal(m, h->tri)) < 1.0 - 1e-12 ||
        fabs(vec3_length(h->n_shade) - 1.0) > 1e-12)
        s->bad_normal++;
}

static void compare(const char *name, const struct mesh *m, int rays, uint64_t seed)
{
    struct rt_rng r = {seed};
    vec3 c = vec3_scale(vec3_add(m->lo, m->hi), 0.5), ext = vec3_sub(m->hi, m->lo);
    double scale = vec3_length(ext);
    struct stats s = {.scale = scale};
    for (int i = 0; i < rays; i++) {
        vec3 o = vec3_madd(c, rt_unit(&r), scale * (0.6 + rt_uniform(&r)));
        if (i % 5 == 0) /* some start inside the bounds */
            o = vec3_madd(c, rt_unit(&r), 0.3 * scale * rt_uniform(&r));
        vec3 target =
            vec3_add(c, vec3_make((rt_uniform(&r) - 0.5) * ext.x, (rt_uniform(&r) - 0.5) * ext.y,
                                  (rt_uniform(&r) - 0.5) * ext.z));
        vec3 d = vec3_sub(target, o);
        if (i % 3 == 0)
            d = vec3_scale(vec3_normalize(d), 0.1 + 10.0 * rt_uniform(&r)); /* t's unit */
        if (i % 7 == 0)
            d = rt_unit(&r);
        s.rays++;
        struct mesh_rt_hit h;
        uint32_t tri_b = 0;
        bool hit = mesh_rt_intersect(m->rt, o, d, 0.0, INFINITY, -1, &h);
        double tb = rt_brute(m, o, d, 0.0, INFINITY, -1, &tri_b);
        if (!same(m, hit, &h, tb, tri_b, o, d, &s) || !hit)
            continue;
        s.hits++;
        check_hit_geometry(m, o, d, &h, scale, &s);
        /* skip the nearest: the brute force's nearest of the others */
        struct mesh_rt_hit h2;
        bool hit2 = mesh_rt_intersect(m->rt, o, d, 0.0, INFINITY, h.tri, &h2);
        double tb2 = rt_brute(m, o, d, 0.0, INFINITY, h.tri, &tri_b);
        if (!same(m, hit2, &h2, tb2, tri_b, o, d, &s))
            s.bad_skip++;
        /* from the hit on: the next surface along the ray */
        bool hit3 = mesh_rt_intersect(m->rt, o, d, h.t, INFINITY, h.tri, &h2);
        double tb3 = rt_brute(m, o, d, h.t, INFINITY, h.tri, &tri_b);
        if (!same(m, hit3, &h2, tb3, tri_b, o, d, &s))
            s.bad_next++;
        /* nothing before the nearest */
        if (mesh_rt_intersect(m->rt, o, d, 0.0, h.t * (1.0 - 1e-9), -1, &h2))
            s.bad_tmax++;
    }
    printf("%-10s %6d rays, %6d hits: hit/miss %d, t %d (worst rel %.1e), triangle %d "
           "(ties %d), skip %d, next %d, tmax %d, barycentrics %d, normals %d\n",
           name, s.rays, s.hits, s.mismatch_hit, s.mismatch_t, s.worst_rel_t, s.mismatch_tri,
           s.ties, s.bad_skip, s.bad_next, s.bad_tmax, s.bad_bary, s.bad_normal);
    CHECK(s.hits > rays / 4); /* the comparison is about hits */
    CHECK_INT(s.mismatch_hit, 0);
    CHECK_INT(s.mismatch_t, 0);
    CHECK_INT(s.mismatch_tri, 0);
    CHECK_INT(s.bad_skip, 0);
    CHECK_INT(s.bad_next, 0);
    CHECK_INT(s.bad_tmax, 0);
    CHECK_INT(s.bad_bary, 0);
    CHECK_INT(s.bad_normal, 0);
}

/* From the centre of an outward icosphere every ray leaves through a front face seen from
 * outside (n_geom . d > 0) at t ~ R, and interpolated normals beat the facets. */
static void sphere_from_inside(void)
{
    struct mesh *m = NULL;
    struct err e = {0};
    CHECK_INT(mesh_make_icosphere(3, 2.0, &m, &e), REFRACT_E_OK);
    struct rt_rng r = {99};
    int wrong_side = 0, missed = 0;
    double err_geom = 0.0, err_shade = 0.0, worst_t = 0.0;
    for (int i = 0; i < 5000; i++) {
        vec3 d = rt_unit(&r);
        struct mesh_rt_hit h;
        if (!mesh_rt_intersect(m->rt, vec3_make(0, 0, 0), d, 0.0, INFINITY, -1, &h)) {
            missed++;
            continue;
        }
        wrong_side += vec3_dot(h.n_geom, d) <= 0.0;
        worst_t = fmax(worst_t, fabs(h.t - 2.0));
        vec3 p = vec3_normalize(vec3_scale(d, h.t)); /* the sphere's normal there */
        err_geom += acos(fmin(1.0, vec3_dot(p, h.n_geom)));
        err_shade += acos(fmin(1.0, vec3_dot(p, h.n_shade)));
    }
    printf("icosphere s=3 from inside: mean normal error facets %.4f rad, shading %.4f rad; "
           "max |t - R| %.4f\n",
           err_geom / 5000, err_shade / 5000, worst_t);
    CHECK_INT(missed, 0);
    CHECK_INT(wrong_side, 0);
    CHECK(worst_t < 0.02 * 2.0); /* the sag of a level-3 icosphere is about 1% of R */
    CHECK(err_shade < 0.5 * err_geom);
    mesh_destroy(m);
}

static struct mesh *soup(size_t n, uint64_t seed)
{
    struct rt_rng r = {seed};
    double(*v)[3] = malloc(3 * n * sizeof *v);
    uint32_t(*t)[3] = malloc(n * sizeof *t);
    for (size_t i = 0; i < n; i++) {
        vec3 c = vec3_make(rt_uniform(&r) * 4 - 2, rt_uniform(&r) * 4 - 2, rt_uniform(&r) * 4 - 2);
        for (int k = 0; k < 3; k++) {
            vec3 p = vec3_madd(c, rt_unit(&r), 0.05 + 0.3 * rt_uniform(&r));
            memcpy(v[3 * i + (size_t)k], (double[3]){p.x, p.y, p.z}, sizeof v[0]);
            t[i][k] = (uint32_t)(3 * i + (size_t)k);
        }
    }
    struct mesh *m = NULL;
    struct err e = {0};
    CHECK_INT(mesh_create(v, 3 * n, t, n, NULL, &m, &e), REFRACT_E_OK);
    return m;
}

int main(void)
{
    struct mesh *ico = NULL;
    struct err e = {0};
    CHECK_INT(mesh_make_icosphere(3, 1.0, &ico, &e), REFRACT_E_OK);
    compare("icosphere", ico, 20000, 1);
    mesh_destroy(ico);
    struct mesh *s = soup(3000, 2);
    compare("soup", s, 20000, 3);
    mesh_destroy(s);
    struct mesh *box = rt_box_mesh(0.75);
    compare("box", box, 20000, 4);
    mesh_destroy(box);
    sphere_from_inside();
    return test_summary("test_mesh_rt_trace");
}
