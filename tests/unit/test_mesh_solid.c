/*
 * test_mesh_solid.c - mesh_check_solid on a tetrahedron broken in each way it refuses:
 * open (a face missing), non-manifold (a third face on an edge), degenerate (a repeated
 * vertex, collinear vertices), inconsistent winding (one face flipped), no volume (two
 * faces back to back); each message must name the offending element. An inside-out
 * tetrahedron and icosphere are flipped: winding, volume, traced normals and the winding
 * number (exact and hierarchical) all turn outward.
 */
#include "mesh_rt_test_util.h"
#include "test.h"

/* The tetrahedron's faces with some replaced, dropped or added; checked. */
static void expect_refused(const char *what, const uint32_t (*t)[3], size_t nt,
                           const char *const *needles)
{
    struct err e = {0};
    struct mesh *m = rt_mesh_from(rt_tetra_v, 5, t, nt, &e);
    CHECK(m != NULL);
    if (m == NULL)
        return;
    bool flipped = true;
    CHECK_INT(mesh_check_solid(m, &flipped, &e), REFRACT_E_INVALID_MESH);
    CHECK(!flipped);
    printf("%-14s %s\n", what, e.msg);
    for (const char *const *n = needles; *n != NULL; n++)
        CHECK_MSG(strstr(e.msg, *n) != NULL, "%s: \"%s\" not in \"%s\"", what, *n, e.msg);
    mesh_destroy(m);
}

static void refusals(void)
{
    const uint32_t open[3][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}};
    /* triangle 0's edge 2->1 had face 3 (1, 2, 3) on its other side */
    expect_refused("open", open, 3, (const char *const[]){"edge 2-1 of triangle 0", "open", NULL});

    const uint32_t nonmanifold[5][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {1, 2, 4}};
    expect_refused(
        "non-manifold", nonmanifold, 5,
        (const char *const[]){"edge 2-1 is shared by 3 triangles (0, 3, 4)", "non-manifold", NULL});

    const uint32_t repeated[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 2}};
    expect_refused(
        "repeated", repeated, 4,
        (const char *const[]){"triangle 3 (vertices 1, 2, 2)", "zero area", "repeated", NULL});

    /* vertex 4 = (2, 0, 0) lies on the line through vertices 0 and 1 */
    const uint32_t collinear[5][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}, {0, 1, 4}};
    expect_refused(
        "collinear", collinear, 5,
        (const char *const[]){"triangle 4 (vertices 0, 1, 4)", "zero area", "collinear", NULL});

    const uint32_t inconsistent[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 3, 2}};
    expect_refused("inconsistent", inconsistent, 4,
                   (const char *const[]){"edge 2-1", "triangles 0 and 3", "same direction", NULL});

    const uint32_t flat[2][3] = {{0, 1, 2}, {0, 2, 1}};
    expect_refused("no volume", flat, 2, (const char *const[]){"encloses no volume", NULL});
}

static void inside_out_tetrahedron(void)
{
    uint32_t t[4][3];
    for (int i = 0; i < 4; i++) { /* every face reversed */
        t[i][0] = rt_tetra_t[i][0];
        t[i][1] = rt_tetra_t[i][2];
        t[i][2] = rt_tetra_t[i][1];
    }
    struct err e = {0};
    struct mesh *m = rt_mesh_from(rt_tetra_v, 4, (const uint32_t(*)[3])t, 4, &e);
    CHECK(m != NULL);
    if (m == NULL)
        return;
    CHECK_NEAR(mesh_signed_volume(m), -1.0 / 6.0, 1e-15);
    struct mesh_rt_hit h;
    vec3 o = vec3_make(-1, 0.2, 0.3), d = vec3_make(1, 0, 0);
    CHECK(mesh_rt_intersect(m->rt, o, d, 0.0, INFINITY, -1, &h));
    CHECK(vec3_dot(h.n_geom, d) > 0.0); /* inward before */
    bool flipped = false;
    CHECK_INT(mesh_check_solid(m, &flipped, &e), REFRACT_E_OK);
    CHECK(flipped);
    CHECK_NEAR(mesh_signed_volume(m), 1.0 / 6.0, 1e-15);
    for (int i = 0; i < 4; i++) /* the mesh's own triangles now read as the outward ones */
        for (int c = 0; c < 3; c++)
            CHECK_INT(m->triangles[i][c], rt_tetra_t[i][c]);
    CHECK(mesh_rt_intersect(m->rt, o, d, 0.0, INFINITY, -1, &h));
    CHECK_NEAR(h.t, 1.0, 1e-15); /* the face x = 0 */
    CHECK_NEAR(h.n_geom.x, -1.0, 1e-15);
    CHECK(h.n_shade.x < 0.0);
    /* a second check finds nothing to do */
    CHECK_INT(mesh_check_solid(m, &flipped, &e), REFRACT_E_OK);
    CHECK(!flipped);
    mesh_destroy(m);
}

/* An inside-out icosphere big enough that the hierarchical winding number uses its far
 * field (the node area vectors the flip negates), and the packed GPU normals follow. */
static void inside_out_icosphere(void)
{
    struct mesh *ico = NULL, *m = NULL;
    struct err e = {0};
    CHECK_INT(mesh_make_icosphere(4, 1.0, &ico, &e), REFRACT_E_OK);
    if (ico == NULL)
        return;
    uint32_t(*t)[3] = malloc(ico->triangle_count * sizeof *t);
    for (size_t i = 0; i < ico->triangle_count; i++) { /* every face reversed */
        t[i][0] = ico->triangles[i][0];
        t[i][1] = ico->triangles[i][2];
        t[i][2] = ico->triangles[i][1];
    }
    m = rt_mesh_from((const double(*)[3])ico->vertices, ico->vertex_count, (const uint32_t(*)[3])t,
                     ico->triangle_count, &e);
    free(t);
    mesh_destroy(ico);
    CHECK(m != NULL);
    if (m == NULL)
        return;
    vec3 inside = vec3_make(0.1, -0.2, 0.3);
    CHECK_NEAR(mesh_winding_number(m, inside), -1.0, 0.05);
    bool flipped = false;
    CHECK_INT(mesh_check_solid(m, &flipped, &e), REFRACT_E_OK);
    CHECK(flipped);
    CHECK_NEAR(mesh_winding_number_exact(m, inside), 1.0, 1e-9);
    CHECK_NEAR(mesh_winding_number(m, inside), 1.0, 0.05);
    CHECK_NEAR(mesh_winding_number(m, vec3_make(3, 1, 0)), 0.0, 0.05);
    /* every vertex's shading normal, packed or not, points out again */
    int inward = 0;
    for (size_t v = 0; v < m->vertex_count; v++) {
        vec3 p = rt_v3(m->vertices[v]);
        inward += vec3_dot(rt_v3(m->rt->normals[v]), p) < 0.99;
        inward += vec3_dot(mesh_rt_oct_decode(m->rt->verts[v].n_oct), p) < 0.99;
    }
    CHECK_INT(inward, 0);
    mesh_destroy(m);
}

int main(void)
{
    refusals();
    inside_out_tetrahedron();
    inside_out_icosphere();
    return test_summary("test_mesh_solid");
}
