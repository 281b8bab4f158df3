/*
 * test_mesh_rt_bvh.c - the ray-tracing hierarchy's invariants (mesh_rt.h) on an icosphere,
 * a random triangle soup, a pile of identical triangles (no SAH plane exists: the median
 * fallback) and a fan of slivers (SAH peels one triangle a level: the depth bound):
 * every triangle in exactly one leaf, leaves of 1..MESH_RT_LEAF_MAX, boxes that contain
 * their triangles' double vertices and float roundings and their children, depth within
 * MESH_RT_MAX_DEPTH, at most 64 GPU bytes per triangle; the octahedral normal coding's
 * error; the generated icosphere's counts, radius and volume.
 */
#include "mesh_rt_test_util.h"
#include "test.h"

struct walk {
    const struct mesh *m;
    int *seen; /* per triangle slot */
    size_t reached;
    int max_depth;
    int bad_box, bad_leaf;
};

static bool box_contains(const struct mesh_rt_node *n, const double *p)
{
    for (int k = 0; k < 3; k++) {
        if (!((double)n->lo[k] <= p[k] && p[k] <= (double)n->hi[k]))
            return false;
        float f = (float)p[k]; /* the GPU's vertex */
        if (!(n->lo[k] <= f && f <= n->hi[k]))
            return false;
    }
    return true;
}

static bool box_inside(const struct mesh_rt_node *in, const struct mesh_rt_node *out)
{
    for (int k = 0; k < 3; k++)
        if (in->lo[k] < out->lo[k] || in->hi[k] > out->hi[k])
            return false;
    return true;
}

static void walk(struct walk *w, uint32_t node, int depth)
{
    const struct mesh_rt *rt = w->m->rt;
    const struct mesh_rt_node *n = &rt->nodes[node];
    w->reached++;
    if (depth > w->max_depth)
        w->max_depth = depth;
    if (n->count == 0) {
        uint32_t l = n->left_or_first;
        if (l + 1 >= rt->node_count || l == 0) {
            w->bad_leaf++;
            return;
        }
        if (!box_inside(&rt->nodes[l], n) || !box_inside(&rt->nodes[l + 1], n))
            w->bad_box++;
        walk(w, l, depth + 1);
        walk(w, l + 1, depth + 1);
        return;
    }
    if (n->count > MESH_RT_LEAF_MAX || n->left_or_first + n->count > rt->tri_count) {
        w->bad_leaf++;
        return;
    }
    for (uint32_t i = n->left_or_first; i < n->left_or_first + n->count; i++) {
        w->seen[i]++;
        const struct mesh_rt_tri *t = &rt->tris[i];
        for (int c = 0; c < 3; c++) {
            if (t->v[c] != w->m->triangles[t->orig][c])
                w->bad_leaf++;
            if (!box_contains(n, w->m->vertices[t->v[c]]))
                w->bad_box++;
        }
    }
}

static void check_invariants(const char *name, const struct mesh *m, bool check_bytes)
{
    const struct mesh_rt *rt = m->rt;
    CHECK(rt != NULL);
    if (rt == NULL)
        return;
    struct walk w = {.m = m, .seen = calloc(rt->tri_count, sizeof(int))};
    walk(&w, 0, 1);
    size_t once = 0;
    int *orig_seen = calloc(m->triangle_count, sizeof(int));
    for (size_t i = 0; i < rt->tri_count; i++) {
        once += w.seen[i] == 1;
        if (rt->tris[i].orig < m->triangle_count)
            orig_seen[rt->tris[i].orig]++;
    }
    size_t orig_once = 0;
    for (size_t i = 0; i < m->triangle_count; i++)
        orig_once += orig_seen[i] == 1;
    struct mesh_rt_gpu g = mesh_rt_gpu_arrays(rt);
    double bpt = (double)g.total_bytes / (double)m->triangle_count;
    printf("%-18s %8zu triangles: %8zu nodes, depth %2d, %.1f GPU bytes/triangle\n", name,
           m->triangle_count, rt->node_count, rt->depth, bpt);
    CHECK_INT(rt->tri_count, m->triangle_count);
    CHECK_INT(once, rt->tri_count);          /* every slot in exactly one leaf */
    CHECK_INT(orig_once, m->triangle_count); /* every triangle exactly once */
    CHECK_INT(w.reached, rt->node_count);    /* no unreachable nodes */
    CHECK_INT(w.bad_box, 0);
    CHECK_INT(w.bad_leaf, 0);
    CHECK_INT(w.max_depth, rt->depth);
    CHECK(rt->depth <= MESH_RT_MAX_DEPTH);
    CHECK_INT(g.node_bytes, 32 * rt->node_count);
    CHECK_INT(g.tri_bytes, 16 * m->triangle_count);
    CHECK_INT(g.vertex_bytes, 16 * m->vertex_count);
    /* nodes and triangles: independent of how vertices are shared */
    double tree = (double)(g.node_bytes + g.tri_bytes) / (double)m->triangle_count;
    CHECK_MSG(tree <= 48.0, "%s: %.1f node + triangle bytes per triangle", name, tree);
    if (check_bytes) /* indexed meshes (vertices shared, V ~ T / 2): the 64-byte budget */
        CHECK_MSG(bpt <= 64.0, "%s: %.1f bytes per triangle", name, bpt);
    free(w.seen);
    free(orig_seen);
}

/* n random triangles in a 10 x 10 x 3 slab, every coordinate times scale. */
static struct mesh *soup(size_t n, uint64_t seed, double scale)
{
    struct rt_rng r = {seed};
    double(*v)[3] = malloc(3 * n * sizeof *v);
    uint32_t(*t)[3] = malloc(n * sizeof *t);
    for (size_t i = 0; i < n; i++) {
        vec3 c = vec3_make(rt_uniform(&r) * 10 - 5, rt_uniform(&r) * 10 - 5, rt_uniform(&r) * 3);
        double size = 0.01 + 0.5 * rt_uniform(&r) * rt_uniform(&r);
        for (int k = 0; k < 3; k++) {
            vec3 p = vec3_madd(c, rt_unit(&r), size);
            v[3 * i + (size_t)k][0] = p.x * scale;
            v[3 * i + (size_t)k][1] = p.y * scale;
            v[3 * i + (size_t)k][2] = p.z * scale;
            t[i][k] = (uint32_t)(3 * i + (size_t)k);
        }
    }
    struct mesh *m = NULL;
    struct err e = {0};
    CHECK_INT(mesh_create(v, 3 * n, t, n, NULL, &m, &e), REFRACT_E_OK);
    return m;
}

/* n copies of one triangle: every centroid equal, so no SAH plane separates any two. */
static struct mesh *pile(size_t n)
{
    double(*v)[3] = malloc(3 * sizeof *v);
    uint32_t(*t)[3] = malloc(n * sizeof *t);
    const double p[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    memcpy(v, p, sizeof p);
    for (size_t i = 0; i < n; i++) {
        t[i][0] = 0;
        t[i][1] = 1;
        t[i][2] = 2;
    }
    struct mesh *m = NULL;
    struct err e = {0};
    CHECK_INT(mesh_create(v, 3, t, n, NULL, &m, &e), REFRACT_E_OK);
    return m;
}

/* Slivers with centroids at x = 2^-i: geometric spacing, so each SAH split peels off
 * about one triangle; without the depth bound the tree would be n / 2 deep. */
static struct mesh *fan(size_t n)
{
    double(*v)[3] = malloc(3 * n * sizeof *v);
    uint32_t(*t)[3] = malloc(n * sizeof *t);
    for (size_t i = 0; i < n; i++) {
        double x = ldexp(1.0, -(int)(i % 900)) + 1e-3 * (double)(i / 900);
        const double p[3][3] = {{x, 0, 0}, {x, 1, 0}, {x, 0, 1}};
        memcpy(v[3 * i], p, sizeof p);
        for (int k = 0; k < 3; k++)
            t[i][k] = (uint32_t)(3 * i + (size_t)k);
    }
    struct mesh *m = NULL;
    struct err e = {0};
    CHECK_INT(mesh_create(v, 3 * n, t, n, NULL, &m, &e), REFRACT_E_OK);
    return m;
}

static void oct_coding_error(void)
{
    struct rt_rng r = {77};
    double worst = 0.0;
    for (int i = 0; i < 200000; i++) {
        vec3 n = rt_unit(&r);
        vec3 back = mesh_rt_oct_decode(mesh_rt_oct_encode(n));
        worst = fmax(worst, acos(fmin(1.0, vec3_dot(n, back))));
    }
    const vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int i = 0; i < 6; i++)
        worst = fmax(
            worst,
            acos(fmin(1.0, vec3_dot(axes[i], mesh_rt_oct_decode(mesh_rt_oct_encode(axes[i]))))));
    printf("octahedral snorm16 normals: worst error %.2e rad\n", worst);
    /* a grid of step 1/32767 over the octahedron's square, stretched up to about twice
     * onto the sphere: half a cell's diagonal, sqrt(2) / 32767 ~ 4.3e-5 rad, at worst */
    CHECK_MSG(worst < 5e-5, "%g", worst);
}

static void icosphere_counts(void)
{
    for (int s = 0; s <= 7; s += (s < 4 ? 1 : 3)) {
        struct mesh *m = NULL;
        struct err e = {0};
        CHECK_INT(mesh_make_icosphere(s, 2.5, &m, &e), REFRACT_E_OK);
        if (m == NULL)
            continue;
        size_t nt = 20u << (2 * s);
        CHECK_INT(m->triangle_count, nt);
        CHECK_INT(m->vertex_count, nt / 2 + 2);
        double worst = 0.0;
        for (size_t i = 0; i < m->vertex_count; i++)
            worst = fmax(worst, fabs(vec3_length(rt_v3(m->vertices[i])) - 2.5));
        CHECK_MSG(worst < 1e-12 * 2.5, "s = %d: radius off by %g", s, worst);
        CHECK(m->closed);
        bool flipped = true;
        CHECK_INT(mesh_check_solid(m, &flipped, &e), REFRACT_E_OK);
        CHECK(!flipped); /* outward as made */
        double vol = mesh_signed_volume(m), sphere = 4.0 / 3.0 * M_PI * 2.5 * 2.5 * 2.5;
        /* inscribed: below the sphere's volume, the deficit shrinking 4 times a level
         * (2.2e-3 of it at s = 4) */
        CHECK(vol > 0.0 && vol < sphere);
        if (s >= 4)
            CHECK_MSG(sphere - vol < 2.5e-3 * pow(0.25, s - 4) * sphere, "s = %d: volume %g of %g",
                      s, vol, sphere);
        if (s == 7)
            CHECK_INT(m->triangle_count, 327680);
        if (s == 7)
            check_invariants("icosphere s=7", m, true);
        mesh_destroy(m);
    }
    struct mesh *m = NULL;
    struct err e = {0};
    CHECK_INT(mesh_make_icosphere(10, 1.0, &m, &e), REFRACT_E_INVALID_FIELD);
    CHECK_INT(mesh_make_icosphere(2, -1.0, &m, &e), REFRACT_E_INVALID_FIELD);
    CHECK_INT(mesh_make_icosphere(2, NAN, &m, &e), REFRACT_E_INVALID_FIELD);
    CHECK(m == NULL);
}

int main(void)
{
    struct mesh *ico = NULL;
    struct err e = {0};
    CHECK_INT(mesh_make_icosphere(4, 1.0, &ico, &e), REFRACT_E_OK);
    check_invariants("icosphere s=4", ico, true);
    mesh_destroy(ico);
    struct mesh *s = soup(50000, 12345, 1.0);
    check_invariants("random soup", s, false); /* 3 own vertices a triangle: 48 B alone */
    mesh_destroy(s);
    /* Extreme scales: float denormals (found by tests/fuzz/fuzz_ply.c: the key extent made
     * the bin scale infinite and 0 * inf gave NaN bins, a conversion UBSan reports) and
     * the largest coordinates mesh_create accepts (1e15). The tree must still hold. */
    s = soup(2000, 7, 1e-44);
    check_invariants("denormal soup", s, false);
    mesh_destroy(s);
    s = soup(2000, 8, 1e14);
    check_invariants("soup at 1e14", s, false);
    mesh_destroy(s);
    struct mesh *box = rt_box_mesh(1.0);
    check_invariants("box", box, false); /* 12 triangles, 8 vertices: bytes are per mesh */
    mesh_destroy(box);
    struct mesh *p = pile(1000);
    check_invariants("identical pile", p, false);
    mesh_destroy(p);
    struct mesh *f = fan(20000);
    check_invariants("sliver fan", f, false);
    CHECK(f->rt->depth > MESH_RT_SAH_DEPTH); /* the fallback was needed and held */
    mesh_destroy(f);
    oct_coding_error();
    icosphere_counts();
    return test_summary("test_mesh_rt_bvh");
}
